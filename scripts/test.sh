#!/usr/bin/env bash
# One command for the whole suite: install, build (plain and ASan+UBSan), run
# every ctest label. Used by .ci/run. Set LUCENT_SKIP_SANITIZE=1 to skip the
# sanitizer pass locally.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --test
scripts/build.sh build
jobs=$(nproc)

echo "== ctest (all labels)"
(cd build && ctest --output-on-failure -j"$jobs" --timeout 900)

if [ "${LUCENT_SKIP_SANITIZE:-0}" != "1" ]; then
  echo "== ASan + UBSan build: parsers, formulas, fuzz corpora, CLI"
  scripts/build.sh build-asan -DLUCENT_SANITIZE=ON
  # Mesa's llvmpipe keeps allocations alive for the process lifetime; leak
  # checks cover our code in the GL-free labels.
  (cd build-asan && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
     ctest --output-on-failure -j"$jobs" -L 'unit|fuzz' --timeout 900)
fi
