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
  echo "== ASan + UBSan build"
  scripts/build.sh build-asan -DLUCENT_SANITIZE=ON
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  # GL-free code: full leak checking.
  (cd build-asan && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
     ctest --output-on-failure -j"$jobs" -L 'unit|fuzz' --timeout 900)
  # GL code: Mesa's llvmpipe keeps driver allocations for the process lifetime,
  # so leak reports there are not ours; memory errors still fail. The server
  # tests read LeakSanitizer's report themselves and fail on leaks in our code.
  (cd build-asan && ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 \
     ctest --output-on-failure -j"$jobs" -L 'render|cli' --timeout 900)
  (cd build-asan && ASAN_OPTIONS=detect_leaks=1 ctest --output-on-failure -L server --timeout 900)
fi
