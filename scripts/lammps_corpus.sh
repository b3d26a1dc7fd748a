#!/usr/bin/env bash
# Generates the LAMMPS simulations of the real-data corpus (docs/EVALUATION.md
# "The real-data corpus with defaults") into DIR (default
# build/real-data/lammps): one dump per input of scripts/lammps/, each with
# unwrapped positions (xu yu zu) and velocities, 1-3 M segments (atoms x
# (frames - 1)); the inputs' headers say the physics and the sizes.
#   lj_melt     dense LJ liquid, 16,384 atoms x 126 frames   2,048,000 segments
#   ka_liquid   Kob-Andersen binary liquid, 8,788 x 141      1,230,320
#   indent      3D crystal under a spherical indenter,
#               16,800 x 121                                 2,016,000
#   obstacle    3D flow past a sphere between walls,
#               7,721 x 161                                  1,235,360
#   polymer     bead-spring chain melt, 32,000 x 61          1,920,000
#   shock       shock in a crystal bar, 20,200 x 101         2,020,000
#   crack       2D crack, 8,141 x 151                        1,221,150
#   gas         dilute gas, 8,000 x 151                      1,200,000
#   pour        granular pour and chute flow, 6,000 grains
#               inserted during 251 frames                   1,129,918
#   friction    2D sliding asperities, 3,448 x 301           1,034,400
# Installs LAMMPS with apt-get (scripts/packages/lammps.txt) when lmp or the
# examples are missing. Idempotent: a dump that exists is kept (a run writes
# NAME.dump.part and renames it when LAMMPS ends well). Deterministic: fixed
# seeds, serial lmp. Each run takes 5-75 s on one core of the 2-core host
# (all ten about six minutes) and is started with nice -n 19; NAME.log is LAMMPS' log.
# usage: scripts/lammps_corpus.sh [DIR]   prints DIR
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
DIR=${1:-$ROOT/build/real-data/lammps}
RUNS="lj_melt ka_liquid indent obstacle polymer shock crack gas pour friction"
CHAIN=/usr/share/lammps/examples/COUPLE/multiple/data.chain

if ! command -v lmp >/dev/null || [ ! -s "$CHAIN" ]; then
    mapfile -t pkgs < <("$ROOT/scripts/packages/names" "$ROOT/scripts/packages/lammps.txt")
    echo "lammps_corpus: installing ${pkgs[*]}" >&2
    SUDO=""
    [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    $SUDO apt-get update -q >&2
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${pkgs[@]}" >&2
fi

mkdir -p "$DIR"
DIR=$(cd "$DIR" && pwd)
for run in $RUNS; do
    [ -s "$DIR/$run.dump" ] && continue
    rm -f "$DIR/$run.dump.part"
    start=$(date +%s%N)
    if ! (cd "$DIR" && nice -n 19 lmp -nocite -screen none -log "$run.log" -var out "$run.dump.part" \
        -var data "$CHAIN" -in "$ROOT/scripts/lammps/in.$run"); then
        echo "lammps_corpus: $run failed; the end of $DIR/$run.log:" >&2
        tail -5 "$DIR/$run.log" >&2
        rm -f "$DIR/$run.dump.part"
        exit 1
    fi
    mv "$DIR/$run.dump.part" "$DIR/$run.dump"
    echo "lammps_corpus: $run.dump in $((($(date +%s%N) - start) / 1000000)) ms" >&2
done
echo "$DIR"
