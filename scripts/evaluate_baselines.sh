#!/usr/bin/env bash
# Prints the "Baselines at equal memory" section of docs/EVALUATION.md: FOO
# Fig. 7's comparison, each compositing method against the exact method
# (linked lists) by `lucent compare` (SSIM, RMSE, GPU memory of the method) on
# the demos; the tornado with Fig. 7's q = 10, r = 500, lambda = 2 at m = 5
# and m = 2 bands, and with each depth normalization. Usage: evaluate_baselines.sh [LUCENT] [SIZE]
set -euo pipefail
cd "$(dirname "$0")/.."
lucent=${1:-build/lucent}
size=${2:-512x512}
methods="fourier binning wboit weighted-average"
value() { awk -v k="$1" '$1 == k { print $2 }'; }
row() { # label dataset flags...
    local label=$1 ds=$2
    shift 2
    local cells="" order=""
    for m in $methods; do
        out=$("$lucent" compare --dataset "$ds" --size "$size" --method "$m" --against exact --repeat 0 "$@" 2>/dev/null)
        ssim=$(value SSIM <<<"$out")
        cells="$cells $ssim / $(value RMSE <<<"$out") / $(value "memory_mib.$m" <<<"$out") |"
        order="$order $ssim:$m"
    done
    echo "| $label |$cells $(tr ' ' '\n' <<<"${order# }" | sort -t: -k1,1 -gr | cut -d: -f2 | paste -sd'>' | sed 's/>/ > /g') |"
}
echo "| data | fourier | binning | wboit | weighted-average | order by SSIM |"
echo "|---|---|---|---|---|---|"
row "\`demo:tornado\` q 10, r 500, λ 2, m 5" demo:tornado --q 10 --r 500 --lambda 2
row "\`demo:tornado\` q 10, r 500, λ 2, m 2" demo:tornado --q 10 --r 500 --lambda 2 --bands 2
row "\`demo:tornado\` q 10, r 500, λ 2, m 5, depthRange global" demo:tornado --q 10 --r 500 --lambda 2 --depth-range global
row "\`demo:tornado\` q 10, r 500, λ 2, m 5, depthRange pixel" demo:tornado --q 10 --r 500 --lambda 2 --depth-range pixel
row "\`demo:tornado\` defaults" demo:tornado
row "\`demo:abc\` defaults" demo:abc
row "\`demo:points\` defaults" demo:points
row "\`demo:surface\` defaults" demo:surface
