#!/usr/bin/env bash
# The whole suite (scripts/test.sh) while busy processes keep every core
# loaded, twice in a row: a test that assumes the machine's speed fails here.
# Prints each run's time and result; exits non-zero when either run failed.
#   scripts/test_under_load.sh [RUNS]     (default 2)
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-2}
hogs=()
stop_hogs() {
  for p in "${hogs[@]+"${hogs[@]}"}"; do kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
}
trap stop_hogs EXIT
# One busy loop per core, at the suite's own priority: the tests compete for
# the CPU as they would beside another job on a shared machine.
for _ in $(seq "$(nproc)"); do
  sh -c 'while :; do :; done' &
  hogs+=($!)
done
echo "== $(nproc) busy loops: ${hogs[*]}"
status=0
results=()
for i in $(seq "$runs"); do
  t0=$SECONDS
  if scripts/test.sh; then r=passed; else r=FAILED; status=1; fi
  results+=("run $i: $r in $((SECONDS - t0)) s")
  echo "== ${results[-1]}"
done
printf '%s\n' "${results[@]}"
exit $status
