#!/usr/bin/env bash
# One command for the whole suite: install, build (plain and ASan+UBSan), run
# every ctest label. Used by .ci/run. Set LUCENT_SKIP_SANITIZE=1 to skip the
# sanitizer pass locally.
#
# Every phase runs even when an earlier one failed, so that one run shows every
# failing test; the end prints each phase's time, ctest's label times and the
# failing tests with the log that holds their output, and the exit status is
# non-zero when any test failed.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --test
scripts/build.sh build
jobs=$(nproc)
logs=$(mktemp -d "${TMPDIR:-/tmp}/lucent-test.XXXXXX")
failed=0
summary=()

# phase NAME DIR [VAR=VALUE...] -- CTEST-ARGS...
phase() {
  local name=$1 dir=$2
  shift 2
  local env=()
  while [ "$1" != "--" ]; do env+=("$1"); shift; done
  shift
  local log="$logs/$name.log" t0=$SECONDS rc=0
  echo "== ctest: $name"
  (cd "$dir" && env "${env[@]+"${env[@]}"}" ctest --output-on-failure "$@") 2>&1 | tee "$log" || rc=$?
  summary+=("$(printf '%-22s %4d s  %s' "$name" $((SECONDS - t0)) "$([ $rc = 0 ] && echo passed || echo FAILED)")")
  if [ $rc != 0 ]; then
    failed=1
    sed -n '/The following tests FAILED:/,/^Errors while running/p' "$log" | grep -E '^\s+[0-9]+ - ' |
      sed "s|\$|   (output in $log)|" >>"$logs/failures"
  fi
}

phase plain build -- -j"$jobs"

if [ "${LUCENT_SKIP_SANITIZE:-0}" != "1" ]; then
  echo "== ASan + UBSan build"
  scripts/build.sh build-asan -DLUCENT_SANITIZE=ON
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  # GL-free code: full leak checking.
  phase asan-unit-fuzz build-asan ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 -- -j"$jobs" -L 'unit|fuzz'
  # GL code: only the tests labelled asan (tests/CMakeLists.txt: the renders
  # that exercise our memory handling, not the long ones that repeat the plain
  # phase's pictures). Mesa's llvmpipe keeps driver allocations for the process
  # lifetime, so leak reports there are not ours; memory errors still fail.
  phase asan-render build-asan ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 -- -j"$jobs" -L asan -LE 'unit|fuzz|server'
  # The daemon: the server tests read LeakSanitizer's report themselves and
  # fail on leaks in our code.
  phase asan-server build-asan ASAN_OPTIONS=detect_leaks=1 -- -j"$jobs" -L server
fi

echo
echo "== summary"
printf '%s\n' "${summary[@]}"
for log in "$logs"/*.log; do
  echo "-- label times, $(basename "$log" .log):"
  sed -n '/^Label Time Summary:/,/^$/p' "$log" | tail -n +2
done
if [ "$failed" != 0 ]; then
  echo "FAILED tests (each failed once; a test that passes on rerun is still a defect):"
  cat "$logs/failures"
  exit 1
fi
echo "all phases passed"
