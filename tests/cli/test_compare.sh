#!/bin/sh
# `lucent compare` on tiny demos: a request file plus flags, Fourier against
# the exact reference. Checks the exit status, the "SSIM x" / "RMSE y" lines
# and their ranges, the exact method's statistics and the written images.
set -u
LUCENT=$1
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

run() { # name, args...: runs lucent compare, output in $TMP/$name.out
    name=$1; shift
    "$LUCENT" compare "$@" >"$TMP/$name.out" 2>"$TMP/$name.err"
    rc=$?
    cat "$TMP/$name.out"
    if [ $rc -ne 0 ] && grep -qi 'egl\|opengl' "$TMP/$name.err" && [ "${CI:-}" != true ]; then
        cat "$TMP/$name.err"; echo "SKIP: no OpenGL 4.5 context"; exit 77
    fi
    [ $rc -eq 0 ] || { cat "$TMP/$name.err"; fail "$name: lucent compare exited with $rc"; }
}
value() { awk -v k="$1" '$1 == k { print $2; exit }' "$TMP/$2.out"; }
in_range() { awk -v v="$1" -v lo="$2" -v hi="$3" 'BEGIN { exit !(v != "" && v + 0 >= lo && v + 0 <= hi) }'; }

# 1. A request file (dataset, size, bands) with flags on top.
cat >"$TMP/req.json" <<'JSON'
{ "dataset": "demo:abc?count=30", "width": 64, "height": 64, "method": "fourier", "params": { "bands": 3 } }
JSON
run req --request "$TMP/req.json" --size 80x72 --repeat 1 --out-dir "$TMP/img"
grep -q '^SSIM [0-9.]*$' "$TMP/req.out" || fail "no 'SSIM x' line"
grep -q '^RMSE [0-9.]*$' "$TMP/req.out" || fail "no 'RMSE y' line"
in_range "$(value SSIM req)" 0.85 1 || fail "SSIM $(value SSIM req) outside [0.85, 1]"
in_range "$(value RMSE req)" 0 0.1 || fail "RMSE $(value RMSE req) outside [0, 0.1]"
[ "$(value size req)" = 80x72 ] || fail "--size did not override the request"
[ "$(value bands req)" = 3 ] || fail "bands from the request file were not used"
[ "$(value against req)" = exact ] || fail "the default reference is not exact"
in_range "$(value fragments req)" 1 1e12 || fail "no fragments reported"
in_range "$(value max_layers req)" 1 1e9 || fail "no max_layers reported"
[ "$(value dropped_fragments req)" = 0 ] || fail "fragments dropped with the default pool"
for m in fourier exact; do
    in_range "$(value gpu_ms.$m req)" 0 1e9 || fail "no gpu_ms.$m"
    in_range "$(value memory_mib.$m req)" 0.001 1e9 || fail "no memory_mib.$m"
done
for f in fourier exact difference; do
    [ -s "$TMP/img/$f.png" ] || fail "$f.png was not written"
done

# 2. Points against WBOIT, and a pool too small for the exact method: reported, still exit 0.
run points --dataset 'demo:points?count=2000' --size 64x64 --repeat 1 --method wboit
[ "$(value method points)" = wboit ] || fail "--method wboit ignored"
in_range "$(value SSIM points)" 0 1 || fail "points: SSIM outside [0, 1]"
run pool --dataset 'demo:surface?count=24' --size 64x64 --repeat 1 --pool-mib 1 --against exact
in_range "$(value SSIM pool)" 0 1 || fail "pool: SSIM outside [0, 1]"

# 3. FOO Fig. 7 on the tornado (q 10, r 500, lambda 2, the default depth normalization): the Fourier
# compositing is closer to the exact reference than each baseline at equal memory, in SSIM and RMSE, and
# binning closer than WBOIT and the weighted average (SSIM 0.987 > 0.973 > 0.960, 0.960). WBOIT against the
# weighted average (0.0002 apart) and the orders under other normalizations and data are not checked
# (docs/EVALUATION.md "Baselines at equal memory").
fig7="--dataset demo:tornado --size 256x256 --repeat 0 --q 10 --r 500 --lambda 2"
run fig7_fourier $fig7 --method fourier
for m in binning wboit weighted-average; do
    run "fig7_$m" $fig7 --method $m
    [ "$(value method "fig7_$m")" = "$m" ] || fail "--method $m ignored"
    awk -v f="$(value SSIM fig7_fourier)" -v b="$(value SSIM "fig7_$m")" 'BEGIN { exit !(f > b + 0.01) }' ||
        fail "tornado: fourier SSIM $(value SSIM fig7_fourier) not above $m's $(value SSIM "fig7_$m") + 0.01"
    awk -v f="$(value RMSE fig7_fourier)" -v b="$(value RMSE "fig7_$m")" 'BEGIN { exit !(f < b) }' ||
        fail "tornado: fourier RMSE $(value RMSE fig7_fourier) not below $m's $(value RMSE "fig7_$m")"
done
for m in wboit weighted-average; do
    awk -v f="$(value SSIM fig7_binning)" -v b="$(value SSIM "fig7_$m")" 'BEGIN { exit !(f > b + 0.005) }' ||
        fail "tornado: binning SSIM $(value SSIM fig7_binning) not above $m's $(value SSIM "fig7_$m") + 0.005"
done

# 4. Bad usage is an error with a message, not a crash.
"$LUCENT" compare --against nosuchmethod >/dev/null 2>&1 && fail "unknown --against accepted"
echo "PASS"
