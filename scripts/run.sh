#!/usr/bin/env bash
# One command to see Lucent: install, build, and serve the built-in demo data
# on http://127.0.0.1:8080/ (extra arguments go to `lucent serve`).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh build
exec build/lucent serve --listen 127.0.0.1:8080 "$@"
