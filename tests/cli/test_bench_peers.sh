#!/bin/sh
# scripts/bench_peers.sh on a tiny line file, one round: it completes, prints
# Lucent's three rows with figures and either ParaView's row (where pvpython and
# xvfb-run are installed; the .obj input also takes the conversion path) or the
# line that says how to install the peer; --no-peer --doc writes the section
# into a document and replaces it on a second run. Times are not checked.
set -u
LUCENT=$1
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
num='[0-9][0-9]*\.[0-9]'

"$LUCENT" gen 'demo:abc?count=12' -o "$TMP/lines.obj" >/dev/null || fail "lucent gen failed"
LUCENT=$LUCENT "$ROOT/scripts/bench_peers.sh" --warmup 0 --frames 1 "$TMP/lines.obj" 64 48 1 >"$TMP/out" 2>"$TMP/err"
rc=$?
cat "$TMP/out"
if [ $rc -ne 0 ] && grep -qi 'egl\|opengl' "$TMP/err" && [ "${CI:-}" != true ]; then
    cat "$TMP/err"; echo "SKIP: no OpenGL 4.5 context"; exit 77
fi
[ $rc -eq 0 ] || { cat "$TMP/err"; fail "bench_peers.sh exited with $rc"; }
for m in fourier exact opaque; do
    grep -q "^Lucent $m  *$num" "$TMP/out" || fail "no row for Lucent $m"
done
grep -q '^fourier / exact time: [0-9]' "$TMP/out" || fail "no fourier / exact ratio"
if command -v "${PVPYTHON:-pvpython}" >/dev/null && command -v xvfb-run >/dev/null; then
    grep -q "^ParaView depth peeling (8 peels, opacity 0.3)  *$num" "$TMP/out" || fail "no ParaView row"
    grep -q '^ParaView depth peeling / Lucent fourier time: [0-9]' "$TMP/out" || fail "no ParaView ratio"
else
    grep -q 'scripts/setup.sh --peers' "$TMP/out" || fail "no line saying how to install the peer"
fi

printf '# Doc\n\n## 7. Before\n\nkept\n' >"$TMP/doc.md"
for run in 1 2; do
    LUCENT=$LUCENT "$ROOT/scripts/bench_peers.sh" --no-peer --doc "$TMP/doc.md" --warmup 0 --frames 1 \
        "$TMP/lines.obj" 32 32 1 2>"$TMP/err" || { cat "$TMP/err"; fail "--doc run $run failed"; }
done
[ "$(grep -c '^## 8. Peers' "$TMP/doc.md")" = 1 ] || fail "--doc did not keep exactly one Peers section"
grep -q '^kept$' "$TMP/doc.md" || fail "--doc lost the text before the section"
grep -q "^| Lucent fourier | $num" "$TMP/doc.md" || fail "no markdown row for Lucent fourier"
grep -q '^| ParaView' "$TMP/doc.md" && fail "--no-peer still ran ParaView"
echo "bench_peers.sh: ok"
