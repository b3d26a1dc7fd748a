#!/usr/bin/env bash
# Regenerates the reference renders of tests/data/reference/ from cases.txt with
# the built binary (build/lucent or $1). Run it only when a change is meant to
# alter images, and say so in the commit: test_references requires identical pixels
# (with --exact-positions, the float vertex buffers).
set -euo pipefail
cd "$(dirname "$0")/.."
lucent=${1:-build/lucent}
dir=tests/data/reference
grep -v '^#' "$dir/cases.txt" | grep -v '^[[:space:]]*$' | while read -r name args; do
  # shellcheck disable=SC2086 # args are a word list by design
  "$lucent" render $args --exact-positions --out "$dir/$name.png"
  echo "$dir/$name.png"
done
