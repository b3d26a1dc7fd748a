#!/usr/bin/env bash
# Formats the tree the one way the house writes it: clang-format (.clang-format)
# for every tracked C file, prettier (.prettierrc.json, from tests/browser's
# npm packages) for the page and its tests. With --check, changes nothing and
# lists the files that differ; exits 1 when any does (the unit.format test).
#   scripts/format.sh [--check]
set -euo pipefail
cd "$(dirname "$0")/.."
check=0
[ "${1:-}" = "--check" ] && check=1
CLANG_FORMAT=${CLANG_FORMAT:-clang-format}
PRETTIER=tests/browser/node_modules/.bin/prettier
# A tool missing: 77 (the test's "skipped") on a developer's machine, an error under CI, which installs both.
missing=$([ -n "${CI:-}" ] && echo 2 || echo 77)
command -v "$CLANG_FORMAT" >/dev/null || { echo "format.sh: $CLANG_FORMAT not found (apt-get install clang-format)" >&2; exit "$missing"; }
[ -x "$PRETTIER" ] || { echo "format.sh: $PRETTIER not found (cd tests/browser && npm ci)" >&2; exit "$missing"; }
mapfile -t c_files < <(git ls-files '*.c' '*.h')
mapfile -t web_files < <(git ls-files 'web/*.js' 'web/*.mjs' 'web/*.css' 'web/*.html' 'tests/browser/*.mjs')
if [ "$check" = 0 ]; then
    "$CLANG_FORMAT" -i "${c_files[@]}"
    "$PRETTIER" --log-level warn --write "${web_files[@]}"
    exit 0
fi
bad=0
for f in "${c_files[@]}"; do
    if ! "$CLANG_FORMAT" --dry-run --Werror "$f" >/dev/null 2>&1; then
        echo "not formatted (clang-format): $f"
        bad=1
    fi
done
if ! "$PRETTIER" --log-level warn --list-different "${web_files[@]}"; then
    bad=1
fi
[ "$bad" = 0 ] && echo "format.sh: ${#c_files[@]} C files and ${#web_files[@]} web files formatted"
if [ "$bad" != 0 ]; then
    echo "format.sh: run scripts/format.sh to format them" >&2
fi
exit "$bad"
