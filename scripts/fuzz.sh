#!/usr/bin/env bash
# Builds the libFuzzer harnesses of tests/fuzz (clang, ASan + UBSan) and runs
# each one for SECONDS, then prints executions and findings per harness.
#
#   scripts/fuzz.sh SECONDS [HARNESS...]     e.g. scripts/fuzz.sh 60, scripts/fuzz.sh 600 trk ply
#
# HARNESS: a tests/fuzz/fuzz_NAME.c name, e.g. ply trk tck protocol (default: all). Environment:
#   LUCENT_FUZZ_BUILD  build folder (default build-fuzz)
#   LUCENT_FUZZ_JOBS   harnesses run at once (default 1; each is one process)
# Seeds are tests/fuzz/corpus/NAME (and tests/data/loaders for the readers);
# new inputs go to BUILD/fuzz-corpus/NAME (the checked-in corpus is never
# written), crashes, leaks, timeouts and OOMs to BUILD/fuzz-findings/NAME/.
# Exit status: 0 without findings, 1 with, 2 on usage or build errors.
# Needs clang and libclang-rt-14-dev (scripts/setup.sh installs both).
set -euo pipefail
cd "$(dirname "$0")/.."

usage() {
    sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'
    exit 2
}
[[ $# -ge 1 && "$1" =~ ^[0-9]+$ && "$1" -gt 0 ]] || usage
seconds=$1
shift
all=()
for f in tests/fuzz/fuzz_*.c; do n=${f##*/fuzz_}; all+=("${n%.c}"); done
harnesses=("${@:-${all[@]}}")
for h in "${harnesses[@]}"; do
    [[ " ${all[*]} " == *" $h "* ]] || { echo "fuzz.sh: unknown harness '$h' (have: ${all[*]})" >&2; exit 2; }
done
build="${LUCENT_FUZZ_BUILD:-build-fuzz}"
jobs="${LUCENT_FUZZ_JOBS:-1}"
cc="${CC:-$(command -v clang || command -v clang-14 || true)}"
[[ -n "$cc" ]] || { echo "fuzz.sh: clang not found (apt-get install clang libclang-rt-14-dev)" >&2; exit 2; }

echo "== building ${harnesses[*]} in $build with $cc"
cmake -S . -B "$build" -DCMAKE_C_COMPILER="$cc" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLUCENT_FUZZ=ON >/dev/null
targets=()
for h in "${harnesses[@]}"; do targets+=("fuzz_$h"); done
if ! cmake --build "$build" -j"$(nproc)" --target "${targets[@]}" >"$build/fuzz-build.log" 2>&1; then
    tail -30 "$build/fuzz-build.log" >&2
    echo "fuzz.sh: build failed (log: $build/fuzz-build.log)" >&2
    exit 2
fi

run_one() {
    local h=$1 bin="$build/tests/fuzz/fuzz_$1"
    local work="$build/fuzz-corpus/$h" found="$build/fuzz-findings/$h" log="$build/fuzz-$h.log"
    rm -rf "$found" # findings of this run only; copy them away to keep them
    mkdir -p "$work" "$found"
    local seeds=(tests/fuzz/corpus/"$h")
    [[ "$h" == protocol ]] || seeds+=(tests/data/loaders)
    # -timeout: one input slower than 10 s is a finding (a hang); -rss_limit_mb: an OOM is one too.
    "$bin" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
        -artifact_prefix="$found/" "$work" "${seeds[@]}" >"$log" 2>&1 || true
}

echo "== fuzzing ${#harnesses[@]} harness(es) for $seconds s each, $jobs at a time"
running=0
for h in "${harnesses[@]}"; do
    run_one "$h" &
    running=$((running + 1))
    if [[ $running -ge $jobs ]]; then
        wait -n || true
        running=$((running - 1))
    fi
done
wait || true

total_execs=0
total_findings=0
printf '%-10s %14s %10s %8s  %s\n' harness executions exec/s corpus findings
for h in "${harnesses[@]}"; do
    log="$build/fuzz-$h.log"
    execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1 || true)
    rate=$(grep -o 'stat::average_exec_per_sec: *[0-9]*' "$log" | grep -o '[0-9]*$' | tail -1 || true)
    corpus=$(find "$build/fuzz-corpus/$h" -type f | wc -l)
    findings=$(find "$build/fuzz-findings/$h" -type f \( -name 'crash-*' -o -name 'leak-*' -o -name 'timeout-*' \
        -o -name 'oom-*' -o -name 'slow-unit-*' \) | wc -l)
    if [[ -z "$execs" ]]; then # no final stats: the fuzzer stopped on a finding or failed to start
        execs=0
        [[ "$findings" -gt 0 ]] || { findings=1; echo "fuzz.sh: $h ended without stats, see $log" >&2; }
    fi
    total_execs=$((total_execs + execs))
    total_findings=$((total_findings + findings))
    list=$(find "$build/fuzz-findings/$h" -type f | head -3 | tr '\n' ' ')
    printf '%-10s %14s %10s %8s  %s %s\n' "$h" "$execs" "${rate:-0}" "$corpus" "$findings" "$list"
done
printf '%-10s %14s %21s  %s\n' total "$total_execs" "" "$total_findings"
[[ $total_findings -eq 0 ]]
