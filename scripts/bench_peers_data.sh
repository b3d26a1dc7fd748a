#!/bin/sh
# Writes the large line file of the peer benchmark (scripts/bench_peers.sh,
# docs/EVALUATION.md "Peers"): demo:tornado?count=1700, 1,700 RK4 streamlines of
# Crawfis' tornado with 896,481 segments, as binary VTK legacy polydata that
# both Lucent and ParaView read. Deterministic (the demo's default seed), so
# every machine benches the same bytes; nothing is downloaded.
#
# No real line data set near a million segments ships in Debian 12's packages:
# the MD and tractography packages hold only small test files (python3-dipy's
# bundles of a few hundred streamlines, python-mdtraj-doc's 22-atom frame0.xtc,
# pymol-data's single PDB models), so the benchmark uses this demo. A real file
# of your own (.trk, .tck, .trx, .nc, ...) works as well: bench_peers.sh FILE.
#
# usage: scripts/bench_peers_data.sh [OUT.vtk]    (default build/peers/tornado-1700.vtk)
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
LUCENT=${LUCENT:-$ROOT/build/lucent}
OUT=${1:-$ROOT/build/peers/tornado-1700.vtk}
[ -x "$LUCENT" ] || { echo "bench_peers_data.sh: $LUCENT is not built (scripts/build.sh)" >&2; exit 1; }
mkdir -p "$(dirname "$OUT")"
"$LUCENT" gen tornado --count 1700 -o "$OUT"
