#!/usr/bin/env bash
# Builds docker/Dockerfile for real with podman (no Docker engine needed) and
# runs the image: the HEALTHCHECK, a token-protected JPEG render of a dataset
# mounted at /data, the user, and a clean stop. A manual check, not part of
# ctest (podman is not in the package lists, and a build takes minutes);
# container.rootfs proves the runtime stage in the suite.
#
# Where no registry can be reached, the base images are imported from the
# Debian 12 minbase root that container.rootfs caches (debian:12-slim is made
# from the same variant): run `ctest -L container` once first, or set
# LUCENT_PODMAN_PULL=1 to pull debian:12 and debian:12-slim instead.
# Works around what this kind of host lacks: RUN steps isolated by chroot (no
# cgroup v2 for crun), runc with explicit ulimits for `podman run`.
# Usage (root, from anywhere): docker/podman-check.sh [TAG]
set -euo pipefail
cd "$(dirname "$0")/.."
tag=${1:-localhost/lucent:check}
cache=${LUCENT_ROOTFS_CACHE:-/var/cache/lucent/rootfs-bookworm}
name=lucent-check-$$
data=$(mktemp -d /tmp/lucent-podman.XXXXXX)
cleanup() {
  podman rm -f "$name" >/dev/null 2>&1 || true
  rm -rf "$data"
}
trap cleanup EXIT
command -v podman >/dev/null || { echo "podman-check: apt-get install podman runc" >&2; exit 2; }

if [ "${LUCENT_PODMAN_PULL:-0}" != 1 ]; then
  base=$(ls -1d "$cache"/base-*/ 2>/dev/null | head -n 1)
  [ -n "$base" ] || { echo "podman-check: no base root in $cache (run ctest -L container first)" >&2; exit 2; }
  if ! podman image exists docker.io/library/debian:12; then
    tar --exclude=./.lucent-complete -C "$base" -c . | podman import --change 'CMD ["bash"]' - docker.io/library/debian:12
  fi
  podman tag docker.io/library/debian:12 docker.io/library/debian:12-slim
fi

t=$(date +%s)
podman build --format docker --isolation chroot --network host \
  --ignorefile docker/Dockerfile.dockerignore -f docker/Dockerfile -t "$tag" .
echo "podman-check: built $tag in $(($(date +%s) - t)) s ($(podman image inspect "$tag" --format '{{.Size}}') bytes)"

[ -x build/lucent ] || { echo "podman-check: build/lucent makes the test data (scripts/build.sh)" >&2; exit 2; }
build/lucent gen tornado --count 10 -o "$data/tracts.ply" >/dev/null
chmod -R a+rX "$data"
port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
podman run -d --name "$name" --runtime runc --ulimit nofile=1024:1024 --ulimit nproc=4096:4096 \
  -p "127.0.0.1:$port:8080" -v "$data:/data:ro" -e LUCENT_TOKEN=check "$tag" >/dev/null
for _ in $(seq 1 120); do
  podman healthcheck run "$name" >/dev/null 2>&1 && break
  sleep 1
done
podman healthcheck run "$name" || { podman logs "$name"; echo "podman-check: FAIL: unhealthy" >&2; exit 1; }
echo "podman-check: $(curl -s "127.0.0.1:$port/api/v1/health")"
echo "podman-check: runs as $(podman top "$name" user | tail -n 1)"
got=$(curl -s -H 'Authorization: Bearer check' -o "$data/f.jpg" -w '%{http_code} %{content_type}' \
  "127.0.0.1:$port/api/v1/render?dataset=tracts&width=64&height=64&format=jpeg")
magic=$(head -c 2 "$data/f.jpg" | od -An -tx1 | tr -d ' \n')
[ "$got" = "200 image/jpeg" ] && [ "$magic" = ffd8 ] || { echo "podman-check: FAIL: render: $got $magic" >&2; exit 1; }
podman stop -t 15 "$name" >/dev/null
rc=$(podman inspect "$name" --format '{{.State.ExitCode}}')
[ "$rc" = 0 ] || { podman logs "$name"; echo "podman-check: FAIL: exit $rc after stop" >&2; exit 1; }
echo "podman-check: passed (health, /data render as JPEG, stop exits 0)"
