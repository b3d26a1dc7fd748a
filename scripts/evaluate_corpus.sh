#!/usr/bin/env bash
# Prints the real-data corpus subsection of docs/EVALUATION.md §7 (scripts/evaluate.sh
# includes it): every file of scripts/real_data.sh and the demos rendered at 512x512
# with defaults (fourier, and exact), their visibility report (topDecileAlpha,
# bottomHalfAlpha, occluderAlpha) against the goal of issue 26, and a few images
# (docs/corpus-*.jpg).
# Usage: evaluate_corpus.sh [LUCENT] [DOCS_DIR]   (prints nothing when the corpus cannot be fetched)
set -euo pipefail
cd "$(dirname "$0")/.."
lucent=${1:-build/lucent}
docs=${2:-docs}
real=$(scripts/real_data.sh 2>/dev/null) || exit 0
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
row() { # stats.json [short]: the table cells after the importance (short: one cell, top / bottom / occluder)
    python3 -c 'import json,sys
v = json.load(open(sys.argv[1]))["visibility"]
t, b, o = v["topDecileAlpha"], v["bottomHalfAlpha"], v["occluderAlpha"]
met = "yes" if t >= 0.5 and t >= b - 0.05 and o <= 0.5 * t else "no"
print(("%.3f / %.3f / %.3f | %s" if len(sys.argv) > 2 else "%.3f | %.3f | %.3f | %s") % (t, b, o, met))' "$@"
}
cat <<'MD'

### The real-data corpus with defaults

Every file of `scripts/real_data.sh` (CGAL's point sets and meshes, the thiophene LAMMPS dump of
votca-tutorials read directly, the Hipparcos stars of kstars-data converted to a point table) and the demos,
rendered as a new user would: 512x512, every parameter at its default, the file's default importance and colour
(docs/GUIDE.md "Default attributes"), with the default method (fourier) and with `method: "exact"`. The goal
(issue 26): topDecileAlpha >= 0.5, no inversion (topDecileAlpha >= bottomHalfAlpha - 0.05) and the unimportant
elements that hide importance faded (occluderAlpha <= 0.5 x topDecileAlpha; docs/ALGORITHM.md §8).

| data | default importance | default colour | top decile | bottom half | occluder | goal met | exact: top / bottom / occluder | exact: goal met |
|---|---|---|---|---|---|---|---|---|
MD
specs="thiophene.dump stars.csv building.ply ball.ply b9_training.ply radar.xyz bunny.ply elephant.ply armadillo.ply"
for spec in $specs demo:tornado demo:abc demo:points demo:surface; do
    path=$spec
    [ "${spec#demo:}" = "$spec" ] && path="$real/$spec"
    "$lucent" render --dataset "$path" --size 512x512 --stats "$TMP/d.json" --out "$TMP/d.png" >/dev/null 2>&1
    "$lucent" render --dataset "$path" --size 512x512 --method exact --stats "$TMP/e.json" --out "$TMP/e.png" \
        >/dev/null 2>&1
    info=$("$lucent" info "$path" 2>/dev/null)
    imp=$(echo "$info" | awk '$1 == "importance" { print $2 }')
    col=$(echo "$info" | awk '$1 == "color" { print $2 }')
    echo "| $spec | $imp | $col | $(row "$TMP/d.json") | $(row "$TMP/e.json" short) |"
done
for f in thiophene.dump armadillo.ply stars.csv; do
    "$lucent" render --dataset "$real/$f" --size 320x320 --quality 80 --out "$docs/corpus-${f%.*}.jpg" >/dev/null 2>&1
done
cat <<'MD'

| thiophene.dump (speed) | armadillo.ply (mean curvature) | stars.csv (magnitude) |
|---|---|---|
| ![](corpus-thiophene.jpg) | ![](corpus-armadillo.jpg) | ![](corpus-stars.jpg) |
MD
