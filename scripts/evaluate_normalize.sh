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
cat <<'MD'

Fourier against exact (`lucent compare --size 512x512 --repeat 0`; both methods use the same normalization):

| demo | SSIM off | SSIM auto |
|---|---|---|
MD
for d in tornado abc points surface; do
    s_off=$("$lucent" compare --dataset "demo:$d" --size 512x512 --normalize off --repeat 0 2>/dev/null | awk '$1 == "SSIM" { print $2 }')
    s_auto=$("$lucent" compare --dataset "demo:$d" --size 512x512 --normalize auto --repeat 0 2>/dev/null | awk '$1 == "SSIM" { print $2 }')
    echo "| $d | $s_off | $s_auto |"
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

**How it was chosen.** q and r scaled by one global factor (from the 95th percentile of the per-pixel mass)
could not lift the point demos: their important points sit in dense clusters while the unimportant noise is
alone in its pixels, so with λ = 1 the noise stayed more opaque than the clusters at every factor tried
(top decile 0.12-0.45 against bottom half 0.18-0.62). Scaling each pixel's sums by its own mass (k = min(1,
M_ref / M)) lifts the clusters without lifting the sparse noise; a stronger emphasis then separates the
important from the unimportant in the dense pixels. We swept M_ref from 0.02 to 2 and λ' from λ to 2.5λ on
the four demos and the two dense variants; a constant λ' = 2λ with M_ref = 0.35 met the goal on all six (the
million points are the binding case). The emphasis now rises with the density instead, λ' = (2 - k) λ: the
paper's λ in pixels whose sums are not scaled, 2λ in the densest, which kept the goal on all six and moved the
line demos less (SSIM auto/off 0.908 -> 0.940 on the tornado, 0.867 -> 0.908 on abc). It is still below the 0.95
we aimed for: the two aims pull apart on the tornado, where M_ref = 0.5 reaches SSIM 0.953 but drops its top
decile to 0.478 (and the million points to 0.491), under the goal. `"normalize": "off"` keeps the paper's images
bit for bit (the reference renders check it). On the 3,000 tornado lines the paper's formula isolates the vortex core more
sharply, while auto shows more of the surrounding flow: the report favours auto, the eye may not.
MD
