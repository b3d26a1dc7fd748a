#!/usr/bin/env bash
# container.rootfs: the runtime image of docker/Dockerfile, proven without a
# Docker engine. Builds a Debian 12 root (debootstrap --variant=minbase, the
# variant debian:12-slim is made from), runs docker/runtime-setup.sh in it (the
# Dockerfile's runtime stage: exactly scripts/packages/runtime.txt, the user,
# glvnd's NVIDIA vendor file), copies in the binary and the entry point where
# the Dockerfile puts them, and starts the daemon through the entry point as the
# unprivileged user (chroot --userspec) on a free loopback port, with a mounted
# /data and a token. Passes when the HEALTHCHECK command succeeds, the datasets
# of /data are served and a render returns a JPEG on llvmpipe.
#
# The roots are cached in $LUCENT_ROOTFS_CACHE (default
# /var/cache/lucent/rootfs-bookworm): base-HASH (debootstrap, keyed by suite
# and mirror) and runtime-HASH (keyed by the runtime package names and
# runtime-setup.sh), so that a change of the list builds a new root; the three
# most recently used runtime roots are kept.
# Exit 77 (skipped) when not root, or when the mirror cannot be reached to
# build a missing root, unless CI=true, where both fail.
# Usage: test_rootfs.sh LUCENT_BINARY SOURCE_DIR
set -euo pipefail
binary=$(readlink -f "$1")
src=$(readlink -f "$2")
suite=bookworm
mirror=${LUCENT_DEBIAN_MIRROR:-http://deb.debian.org/debian}
security=${LUCENT_DEBIAN_SECURITY_MIRROR:-http://deb.debian.org/debian-security}
cache=${LUCENT_ROOTFS_CACHE:-/var/cache/lucent/rootfs-bookworm}

say() { echo "container: $*"; }
fail() { echo "FAIL: $*" >&2; exit 1; }
skip() {
  [ "${CI:-}" = true ] && fail "$* (CI=true: the container test must run)"
  echo "SKIP: $*"
  exit 77
}
elapsed() { echo $(($(date +%s) - $1)); }

[ "$(id -u)" = 0 ] || skip "needs root (debootstrap, chroot, mount)"
command -v debootstrap >/dev/null || skip "debootstrap is not installed (scripts/setup.sh --test)"

# ---- cleanup: stop the daemon, undo every mount (innermost first), always
mounts=()
daemon=""
work=$(mktemp -d /tmp/lucent-container.XXXXXX)
cleanup() {
  if [ -n "$daemon" ] && kill -0 "$daemon" 2>/dev/null; then
    kill -KILL "$daemon" 2>/dev/null || true
    wait "$daemon" 2>/dev/null || true
  fi
  local i
  for ((i = ${#mounts[@]} - 1; i >= 0; i--)); do
    umount "${mounts[i]}" 2>/dev/null || umount -l "${mounts[i]}" || echo "container: could not unmount ${mounts[i]}" >&2
  done
  mounts=()
  rm -rf "$work"
}
trap cleanup EXIT
trap 'exit 1' INT TERM
mount_at() { # mount_at TARGET MOUNT-ARGS... (remembered for cleanup)
  local target=$1
  shift
  mkdir -p "$target"
  mount "$@" "$target"
  mounts+=("$target")
}
unmount_all() {
  local i
  for ((i = ${#mounts[@]} - 1; i >= 0; i--)); do umount "${mounts[i]}"; done
  mounts=()
}
# Never delete a folder that still has something mounted below it.
remove_tree() {
  if awk -v p="$1/" 'index($2 "/", p) == 1 { found = 1 } END { exit !found }' /proc/self/mounts; then
    fail "$1 has mounts below it; not removing it"
  fi
  rm -rf "$1"
}
mirror_reachable() {
  curl -fsS --max-time 30 -o /dev/null "$mirror/dists/$suite/Release" 2>"$work/probe.log"
}

mkdir -p "$cache"
exec 9>"$cache/.lock"
flock -w 1800 9 || fail "another container test holds $cache/.lock"
# Daemons and mounts left by a run that was killed (a ctest timeout sends
# SIGKILL, which no trap sees): with the lock held nothing else uses the roots,
# so end the processes whose root is one of them, and detach the mounts.
for proc in /proc/[0-9]*; do
  case "$(readlink "$proc/root" 2>/dev/null)" in
    "$cache"/*) say "ending pid ${proc#/proc/}, left in a root by an earlier run"; kill -KILL "${proc#/proc/}" 2>/dev/null || true ;;
  esac
done
awk -v p="$cache/" 'index($2, p) == 1 { print $2 }' /proc/self/mounts | sort -r | while read -r stale; do
  say "detaching $stale, left by an earlier run"
  umount -l "$stale"
done

names() { "$src/scripts/packages/names" "$@"; }
base_key=$({ echo "recipe 1 $suite minbase"; echo "$mirror"; } | sha256sum | cut -c1-12)
runtime_key=$({
  echo "$base_key $security"
  names "$src/scripts/packages/runtime.txt"
  cat "$src/docker/runtime-setup.sh" "$src/scripts/packages/names"
} | sha256sum | cut -c1-12)
base=$cache/base-$base_key
root=$cache/runtime-$runtime_key

# ---- 1. debootstrap (once per suite and mirror)
if [ ! -e "$base/.lucent-complete" ]; then
  mirror_reachable || skip "cannot reach $mirror to build $base: $(cat "$work/probe.log")"
  say "debootstrap --variant=minbase $suite into $base (first run: several minutes)"
  t=$(date +%s)
  remove_tree "$base.tmp"
  debootstrap --variant=minbase "$suite" "$base.tmp" "$mirror" >"$work/debootstrap.log" 2>&1 ||
    { tail -n 40 "$work/debootstrap.log"; fail "debootstrap failed"; }
  touch "$base.tmp/.lucent-complete"
  mv "$base.tmp" "$base"
  say "debootstrap took $(elapsed "$t") s"
fi

# ---- 2. the runtime stage: docker/runtime-setup.sh with the repository's lists
if [ ! -e "$root/.lucent-complete" ]; then
  mirror_reachable || skip "cannot reach $mirror to build $root: $(cat "$work/probe.log")"
  say "runtime root $root: runtime.txt = $(names "$src/scripts/packages/runtime.txt" | tr '\n' ' ')"
  t=$(date +%s)
  remove_tree "$root.tmp"
  cp -a "$base" "$root.tmp"
  rm -f "$root.tmp/.lucent-complete"
  # The sources of the debian:12 images: the release, its updates, security.
  rm -f "$root.tmp/etc/apt/sources.list"
  cat >"$root.tmp/etc/apt/sources.list.d/debian.sources" <<EOF
Types: deb
URIs: $mirror
Suites: $suite $suite-updates
Components: main

Types: deb
URIs: $security
Suites: $suite-security
Components: main
EOF
  cat /etc/resolv.conf >"$root.tmp/etc/resolv.conf"
  mkdir -p "$root.tmp/opt/lucent-setup/scripts" "$root.tmp/opt/lucent-setup/docker"
  cp -a "$src/scripts/packages" "$root.tmp/opt/lucent-setup/scripts/"
  cp -a "$src/docker/runtime-setup.sh" "$root.tmp/opt/lucent-setup/docker/"
  mount_at "$root.tmp/proc" -t proc proc
  if ! chroot "$root.tmp" /opt/lucent-setup/docker/runtime-setup.sh >"$work/setup.log" 2>&1; then
    tail -n 40 "$work/setup.log"
    fail "docker/runtime-setup.sh failed in the root"
  fi
  unmount_all
  rm -rf "$root.tmp/opt/lucent-setup"
  touch "$root.tmp/.lucent-complete"
  mv "$root.tmp" "$root"
  say "runtime-setup.sh took $(elapsed "$t") s ($(du -sm "$root" | cut -f1) MiB)"
fi
say "root $root"
# Keep the three most recently used roots (branches with other lists share the
# cache), remove older ones and leftovers of interrupted builds.
touch "$root/.lucent-complete"
for old in $(ls -1t "$cache"/runtime-*/.lucent-complete | tail -n +4 | xargs -r -n1 dirname) \
           $(ls -1d "$cache"/*.tmp 2>/dev/null); do
  say "removing the unused root $old"
  remove_tree "$old"
done

# glvnd's vendor files: NVIDIA's first (its library is absent here, so glvnd
# must fall through to Mesa, which the render below proves), then Mesa's.
for vendor in 10_nvidia.json 50_mesa.json; do
  [ -f "$root/usr/share/glvnd/egl_vendor.d/$vendor" ] || fail "no /usr/share/glvnd/egl_vendor.d/$vendor in the root"
done

# ---- 3. the image's files, a /data folder and a Docker-like /dev and /proc
t=$(date +%s)
install -m 0755 "$binary" "$root/usr/local/bin/lucent"
install -m 0755 "$src/docker/entrypoint.sh" "$root/usr/local/bin/lucent-entrypoint"
mkdir -p "$work/data"
"$binary" gen tornado --count 10 -o "$work/data/tracts.ply" >/dev/null
echo "not a dataset: the entry point passes only dataset files" >"$work/data/README.txt"
chmod -R a+rX "$work"
mount_at "$root/data" --bind "$work/data"
mount -o remount,bind,ro "$root/data"
mount_at "$root/proc" -t proc proc
mount_at "$root/sys" -t sysfs -o ro sysfs
mount_at "$root/dev" -t tmpfs -o mode=0755,nosuid tmpfs
for node in "null c 1 3" "zero c 1 5" "full c 1 7" "random c 1 8" "urandom c 1 9" "tty c 5 0"; do
  set -- $node
  mknod -m 0666 "$root/dev/$1" "$2" "$3" "$4"
done
mount_at "$root/dev/shm" -t tmpfs -o mode=1777,nosuid,nodev tmpfs
mount_at "$root/tmp" -t tmpfs -o mode=1777,nosuid,nodev tmpfs

# ---- 4. the daemon, as the image runs it: entry point, user lucent, env only
token=container-test-$RANDOM$RANDOM
# shellcheck disable=SC2054  # the commas are NVIDIA_DRIVER_CAPABILITIES's own
as_user=(chroot --userspec=lucent:lucent "$root" /usr/bin/env -i
         PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin HOME=/nonexistent
         NVIDIA_VISIBLE_DEVICES=all NVIDIA_DRIVER_CAPABILITIES=graphics,compute,utility LUCENT_DATA=/data)
"${as_user[@]}" LUCENT_LISTEN=127.0.0.1:0 LUCENT_TOKEN="$token" LUCENT_DEMO=1 LUCENT_DEMO_SIZE=200 \
  /usr/local/bin/lucent-entrypoint >"$work/daemon.log" 2>&1 &
daemon=$!
port=""
for _ in $(seq 1 600); do
  port=$(sed -n 's|.*listening on http://127\.0\.0\.1:\([0-9]*\)/.*|\1|p; T; q' "$work/daemon.log")
  [ -n "$port" ] && break
  kill -0 "$daemon" 2>/dev/null || break
  sleep 0.1
done
[ -n "$port" ] || { cat "$work/daemon.log"; fail "the daemon did not start in the root"; }
say "daemon up on 127.0.0.1:$port in $(elapsed "$t") s"

# The image's HEALTHCHECK command, run the way Docker runs it (in the container).
"${as_user[@]}" LUCENT_LISTEN=127.0.0.1:$port /usr/local/bin/lucent-entrypoint health ||
  { cat "$work/daemon.log"; fail "lucent-entrypoint health failed"; }

base_url=http://127.0.0.1:$port
auth=(-H "Authorization: Bearer $token")
get() { curl -sS --max-time 120 "$@"; }
health=$(get "$base_url/api/v1/health")
grep -q '"status":"ok"' <<<"$health" || fail "health: $health"
say "health: $health"
grep -qi 'llvmpipe' <<<"$health" || fail "expected Mesa llvmpipe on this host: $health"

uid=$(stat -c %u "/proc/$daemon")
[ "$uid" = "$(chroot "$root" id -u lucent)" ] && [ "$uid" != 0 ] || fail "the daemon runs as uid $uid, not as lucent"

code=$(get -o /dev/null -w '%{http_code}' "$base_url/api/v1/datasets")
[ "$code" = 401 ] || fail "without the token /api/v1/datasets answered $code, expected 401"
datasets=$(get "${auth[@]}" "$base_url/api/v1/datasets")
grep -q '"tracts"' <<<"$datasets" || fail "/data/tracts.ply is not served: $datasets"
grep -q '"README' <<<"$datasets" && fail "/data/README.txt was passed as a dataset: $datasets"

# render QUERY OUT TYPE MAGIC-START [MAGIC-END]: checks the status, the type and
# the image's magic bytes (JPEG: FF D8 ... FF D9; PNG: 89 'PNG'), so that both
# encoders' libraries (libturbojpeg, libpng) are proven present.
render() {
  local got
  got=$(get "${auth[@]}" -o "$2" -w '%{http_code} %{content_type}' "$base_url/api/v1/render?$1")
  [ "$got" = "200 $3" ] || fail "render $1: $got: $(head -c 300 "$2" | tr -d '\0')"
  [ "$(head -c $((${#4} / 2)) "$2" | od -An -tx1 | tr -d ' \n')" = "$4" ] || fail "render $1: not a $3 (magic)"
  [ -z "${5:-}" ] || [ "$(tail -c $((${#5} / 2)) "$2" | od -An -tx1 | tr -d ' \n')" = "$5" ] ||
    fail "render $1: $3 is cut short"
  say "render $1: $(stat -c %s "$2") bytes of $3"
}
render "dataset=demo:tornado&width=64&height=64&format=jpeg" "$work/tornado.jpg" image/jpeg ffd8 ffd9
render "dataset=tracts&width=64&height=64" "$work/tracts.png" image/png 89504e47
# (Whole answers into variables: grep -q would end a pipe early, and pipefail fail it.)
metrics=$(get "${auth[@]}" "$base_url/metrics")
grep -q '^lucent_frames_rendered_total' <<<"$metrics" || fail "/metrics has no lucent_frames_rendered_total"
page=$(get "$base_url/")
grep -qi '<html' <<<"$page" || fail "the embedded web client is not served"

# A docker stop: SIGTERM, then the daemon exits 0 within its grace period.
kill -TERM "$daemon"
rc=0
for _ in $(seq 1 100); do kill -0 "$daemon" 2>/dev/null || break; sleep 0.1; done
kill -0 "$daemon" 2>/dev/null && fail "the daemon did not stop within 10 s of SIGTERM"
wait "$daemon" || rc=$?
daemon=""
[ "$rc" = 0 ] || { cat "$work/daemon.log"; fail "the daemon exited $rc after SIGTERM"; }
say "passed (serve + checks $(elapsed "$t") s)"
