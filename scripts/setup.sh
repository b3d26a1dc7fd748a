#!/usr/bin/env bash
# Installs what Lucent needs on Debian 12 (apt only), for building and running
# (default) or also for the whole test suite (--test: Chromium, Node, Python
# WebSocket client, clang for the fuzzers, debootstrap for the container test)
# and/or the peer renderers of scripts/bench_peers.sh (--peers: ParaView and
# Xvfb, about a gigabyte; opt-in, never needed by the tests).
# Skips apt when everything is there.
#   scripts/setup.sh [--test] [--peers]
set -euo pipefail
cd "$(dirname "$0")/.."

# One list per purpose under scripts/packages/ (also read by docker/Dockerfile
# and tests/container): build tools and -dev packages, the runtime shared
# libraries (the container image installs exactly these), test tools, peers.
lists=(scripts/packages/build.txt scripts/packages/runtime.txt)
test=0
for arg in "$@"; do
  case "$arg" in
    --test) test=1; lists+=(scripts/packages/test.txt) ;;
    --peers) lists+=(scripts/packages/peers.txt) ;;
    *) echo "usage: scripts/setup.sh [--test] [--peers]" >&2; exit 2 ;;
  esac
done
mapfile -t want < <(scripts/packages/names "${lists[@]}")
[ "${#want[@]}" -gt 0 ] || { echo "setup: no packages read from ${lists[*]}" >&2; exit 1; }

missing=()
for p in "${want[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Node and npm may come from elsewhere than Debian (e.g. a preinstalled Node.js); accept those.
if [ "${#missing[@]}" -gt 0 ]; then
  filtered=()
  for p in "${missing[@]}"; do
    case "$p" in
      nodejs) command -v node >/dev/null || filtered+=("$p") ;;
      npm) command -v npm >/dev/null || filtered+=("$p") ;;
      *) filtered+=("$p") ;;
    esac
  done
  missing=("${filtered[@]+"${filtered[@]}"}")
fi
if [ "${#missing[@]}" -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

if [ "$test" = 1 ] && [ -f tests/browser/package.json ]; then
  # playwright-core drives Debian's Chromium; it never downloads a browser.
  if [ ! -d tests/browser/node_modules/playwright-core ]; then
    echo "setup: npm ci in tests/browser"
    (cd tests/browser && npm ci --no-audit --no-fund --loglevel=error)
  fi
fi
