#!/usr/bin/env bash
# Prints the "Density normalization" section of docs/EVALUATION.md (scripts/evaluate.sh
# includes it): the visibility report with normalize off and auto on the demos and
# dense variants at 512x512, SSIM of auto against off (how far the paper's look
# moves), Fourier-vs-exact SSIM in both modes, and the before/after images
# (docs/normalize-*.jpg). Usage: evaluate_normalize.sh [LUCENT] [DOCS_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
lucent=${1:-build/lucent}
docs=${2:-docs}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
vis() { # file key
    python3 -c 'import json,sys; print("%.3f" % json.load(open(sys.argv[1]))["visibility"][sys.argv[2]])' "$1" "$2"
}
goal() { # file: is the goal met?
    python3 -c 'import json,sys; v = json.load(open(sys.argv[1]))["visibility"]
print("yes" if v["topDecileAlpha"] >= 0.5 and v["bottomHalfAlpha"] <= 0.6 * v["topDecileAlpha"] else "no")' "$1"
}
cat <<'MD'
## 7. Density normalization (`params.normalize`)

Visibility report (docs/ALGORITHM.md §8) at 512x512 with default parameters, `"normalize": "off"` (the paper's
formula) against `"auto"` (the default). The goal for a useful first picture: topDecileAlpha >= 0.5 (the 10% most
important elements in view are at least half opaque) and bottomHalfAlpha <= 0.6 x topDecileAlpha;
`tests/cli/test_visibility.py` asserts it. "SSIM auto/off" is how far auto moves the image from the paper's.

| data | off: top decile | off: bottom half | auto: top decile | auto: bottom half | SSIM auto/off |
|---|---|---|---|---|---|
MD
for spec in tornado abc points surface 'points?count=1000000' 'tornado?count=3000'; do
    n=${spec/\?count=/-}
    for m in off auto; do
        "$lucent" render --dataset "demo:$spec" --size 512x512 --normalize $m --stats "$TMP/$n.$m.json" \
            --out "$TMP/$n.$m.png" >/dev/null
    done
    ssim=$("$lucent" ssim "$TMP/$n.off.png" "$TMP/$n.auto.png" | awk '$1 == "ssim" { printf "%.3f", $2 }')
    echo "| \`demo:$spec\` | $(vis "$TMP/$n.off.json" topDecileAlpha) | $(vis "$TMP/$n.off.json" bottomHalfAlpha) |" \
         "$(vis "$TMP/$n.auto.json" topDecileAlpha) | $(vis "$TMP/$n.auto.json" bottomHalfAlpha) | $ssim |"
done
real=$(scripts/real_data.sh 2>/dev/null) || real=""
if [ -n "$real" ]; then
    # bunny with its height (y) as importance: a smooth attribute on the same closed surface.
    awk '/^end_header/ { print; body = 1; next }
         !body { print; if ($0 == "property float z") print "property float height"; if ($1 == "element" && $2 == "vertex") nv = $3; next }
         v < nv { print $1, $2, $3, $2; v++; next }
         { print }' "$real/bunny.ply" > "$TMP/bunny-height.ply"
    cat <<'MD'

Real files (`scripts/real_data.sh`: CGAL's point sets and meshes from Debian's libcgal-demo; the corpus
subsection below adds real trajectories and stars), each with its default importance attribute, at 512x512:

| file | what | importance | off: top decile | off: bottom half | auto: top decile | auto: bottom half | goal met (off / auto) | SSIM auto/off |
|---|---|---|---|---|---|---|---|---|
MD
    while read -r file what imp; do
        path="$real/$file"
        [ "$file" = bunny-height.ply ] && path="$TMP/bunny-height.ply"
        flag=""
        [ "$imp" = height ] && flag="--importance height"
        for m in off auto; do
            # shellcheck disable=SC2086 # flag is empty or two words
            "$lucent" render --dataset "$path" $flag --size 512x512 --normalize $m --stats "$TMP/r.$m.json" \
                --out "$TMP/r.$m.png" >/dev/null
        done
        ssim=$("$lucent" ssim "$TMP/r.off.png" "$TMP/r.auto.png" | awk '$1 == "ssim" { printf "%.3f", $2 }')
        echo "| $file | ${what//_/ } | ${imp/_(/ (} | $(vis "$TMP/r.off.json" topDecileAlpha) | $(vis "$TMP/r.off.json" bottomHalfAlpha) |" \
             "$(vis "$TMP/r.auto.json" topDecileAlpha) | $(vis "$TMP/r.auto.json" bottomHalfAlpha) |" \
             "$(goal "$TMP/r.off.json") / $(goal "$TMP/r.auto.json") | $ssim |"
    done <<'LIST'
building.ply 100k_points_of_a_building segment_index
ball.ply 31k_points segment_index
b9_training.ply 22k_airborne_LIDAR_points,_RGB label
radar.xyz 21k_points density_(derived)
bunny.ply Stanford_bunny,_75k_triangles mean_curvature
elephant.ply elephant,_89k_triangles mean_curvature
armadillo.ply armadillo,_52k_triangles mean_curvature
bunny-height.ply the_bunny height
LIST
    for m in off auto; do
        "$lucent" render --dataset "$real/building.ply" --size 320x320 --normalize $m --quality 80 \
            --out "$docs/normalize-building-$m.jpg" >/dev/null
    done
fi
cat <<'MD'

Fourier against exact (`lucent compare --size 512x512 --repeat 0`; both methods use the same normalization).
"off" is the paper's method (its formula, the bounds' depth range); "auto" the defaults (density normalization,
depth warped by the moments); the last column auto with the bounds' range (`--depth-range global`):

| data | SSIM off | SSIM auto | SSIM auto, bounds' range |
|---|---|---|---|
MD
ssim_of() { "$lucent" compare --size 512x512 --repeat 0 "$@" 2>/dev/null | awk '$1 == "SSIM" { print $2 }'; }
for spec in tornado abc points surface 'tornado?count=3000' 'points?count=1000000'; do
    echo "| \`demo:$spec\` | $(ssim_of --dataset "demo:$spec" --normalize off) | $(ssim_of --dataset "demo:$spec") |" \
         "$(ssim_of --dataset "demo:$spec" --depth-range global) |"
done
for spec in tornado 'points?count=1000000' 'tornado?count=3000'; do
    n=${spec/\?count=/-}
    for m in off auto; do
        "$lucent" render --dataset "demo:$spec" --size 320x320 --normalize $m --quality 80 \
            --out "$docs/normalize-$n-$m.jpg" >/dev/null
    done
done
cat <<'MD'

| | off (the paper's formula) | auto (default) |
|---|---|---|
| tornado | ![](normalize-tornado-off.jpg) | ![](normalize-tornado-auto.jpg) |
| a million points | ![](normalize-points-1000000-off.jpg) | ![](normalize-points-1000000-auto.jpg) |
| 3,000 tornado lines | ![](normalize-tornado-3000-off.jpg) | ![](normalize-tornado-3000-auto.jpg) |
MD
[ -n "$real" ] && echo '| building.ply (real, 100k points) | ![](normalize-building-off.jpg) | ![](normalize-building-auto.jpg) |'
cat <<'MD'

**How the constants were chosen.** q and r scaled by one global factor (from the 95th percentile of the per-pixel
mass) could not lift the point demos: their important points sit in dense clusters while the unimportant noise is
alone in its pixels, so with λ = 1 the noise stayed more opaque than the clusters at every factor tried (top decile
0.12-0.45 against bottom half 0.18-0.62). Scaling each pixel's sums by its own mass (k = min(1, M_ref / M)) lifts
the clusters without lifting the sparse noise; a stronger emphasis (1 + 3(1-k)²) λ then separates the important from
the unimportant in the dense pixels, while the squared term keeps it near the paper's in moderately dense pixels.
Two aims constrain the constants: the goal above on all six data sets, and SSIM ≥ 0.95 of auto against the paper's
image on the sparse line demos (tornado, abc), which should keep their look. A sweep with temporary switches at
512x512, depth warped by the moments (SSIM auto/off, top decile; "fails" where the goal is missed):

| M_ref | tornado | abc | points | a million points | verdict |
|---|---|---|---|---|---|
| 0.55 | 0.961, 0.533 | 0.945, 0.562 | 0.950, 0.853 | 0.930, 0.723 | abc SSIM low |
| 0.58 | 0.964, 0.521 | 0.950, 0.531 | | | at the limit |
| 0.6 | 0.966, 0.514 | 0.954, 0.513 | 0.951, 0.843 | 0.930, 0.714 | **chosen** |
| 0.65 | 0.970, 0.498 fails | 0.961, 0.471 fails | 0.952, 0.833 | 0.931, 0.705 | |
| 0.8 | 0.978, 0.460 fails | 0.976, 0.380 fails | 0.955, 0.807 | 0.933, 0.684 | |

The margins are narrow on the line demos in both directions. The importance range is the auto range: it cuts only
outliers (beyond both the 2nd-98th percentile and Tukey's far-out fence), which is min/max on the tornado and abc
and the 98th percentile on the million points; the percentiles alone cut the tornado's lower end (line_curvature
from 0.078 to 0.148) and moved its image to SSIM 0.940, min/max alone let the million points' top end squash the
clusters (top decile 0.326). `"normalize": "off"` keeps the paper's images bit for bit (the reference renders check
it). On the 3,000 tornado lines the paper's formula isolates the vortex core more sharply, while auto shows more of
the surrounding flow: the report favours auto, the eye may not.

**Fourier against exact.** With the bounds' depth range auto agrees with the exact method slightly less than the
paper's formula (last column of the table above, by 0.001-0.004): it makes the layers of dense pixels semi-opaque,
and the series of the optical depth cannot tell apart semi-opaque layers closer than about 1/(2m) of the depth
range (a temporary build that gave the exact method's opacities to the Fourier compositing kept most of the gap:
points 0.9950 against exact, 0.9994 with the paper's formula). More bands, the per-pixel range and σ-factors did
not close it on the points. The moments pass (`depthRange: "moments"`, docs/ALGORITHM.md §2), the default with
density normalization, does: with it auto agrees with exact better than the paper's formula on every row of the
table above; it lifts the paper's formula too (`--normalize off --depth-range moments`: tornado 0.9909, abc 0.9993,
points 0.9990, surface 0.9992, the 3,000 tornado lines 0.9638 against 0.9546), but "off" keeps the bounds so that it
stays the paper's method bit for bit. On the real files at 512x512 (auto: bounds' range → moments): building.ply
0.9573 → 0.9889, ball.ply 0.9853 → 0.9946, radar.xyz 0.9737 → 0.9979, bunny.ply 0.9940 → 0.9971, armadillo.ply
0.9978 → 0.9990; on the 896k-segment peer file 0.9572 → 0.9689. Against the paper's formula on the same files (off
0.9580, 0.9811, 0.9766, 0.9977, 0.9987) auto is higher on four and lower on the bunny (0.9971 against 0.9977); the
other case measured where auto stays below it is 50,000 points at 256x256 (0.9937 against 0.9950), where 2-pixel
splats leave clusters of layers that even the warped series does not resolve. `tests/render/test_demo_ssim.c` holds
the defaults to the paper's agreement at 512x512 on the four demos. The warp's choices, each measured against
alternatives on the demos: the spread scale s = σ (0.55σ, 0.7σ and 1.4σ were each lower on some demo), weights g²
(1, g and g⁴ lower on some demo), the warp spanning the bounds' margins, moments at the optimization resolution only
(within 0.0003 of both resolutions, one pass fewer; at a quarter of it the line demos lose, tornado 0.9625). Cost:
on the 896k-segment peer file at 1024x1024 (`lucent bench --frames 4 --warmup 1`, alternated) a still took
1030-1094 ms against 861-879 ms with the bounds' range (+19-25%): P0 93-104 ms, P4 and P5 together +35-70 ms, P1 and
P2 +5-20 ms. Interactive frames that reuse opacities skip the pass; `depthRange: "global"` keeps the faster frame.

**Real files.** On the real point sets auto meets the goal where the paper's formula does not (the building) or
keeps it (the ball). radar.xyz has no attribute and gets a derived `density` (points per grid cell over their
neighbourhood), with which auto meets the goal. b9_training.ply cannot in either mode with its class label as the
importance: four values on sparse points (5% of the pixels covered), so its unimportant points hide nothing and
stay opaque (bottom half 0.98); section 10 has the class-label rule that fixes its default. The meshes with their
curvature as importance miss the goal in both modes: curvature is high on thin features (the bunny's ears, the
armadillo's claws) whose front and back sides cover each other, and a patch's opacity is its least important
fragment's, so the flat, unimportant patches stay opaque. Smoothing the curvature (5 or 20 one-ring iterations)
does not change that; one patch per vertex (`lucent render --elements` at the vertex count) lifts both figures
(auto: bunny 0.507 / 0.449, elephant 0.478 / 0.455, armadillo 0.273 / 0.238). With a smooth attribute on the same
surface (the bunny's height) auto meets the goal and the paper's formula does not. The clarity loop (the corpus
below, and section 10) is what lifts the curvature meshes. nibabel's test tractograms (`standard.trk`,
`standard.tck`: 120 straight lines of 3 points, constant importance; `complex.trk`: 3 tracks) load and render but
are too small to say anything.
MD
