#!/bin/sh
# The runtime stage of docker/Dockerfile, as one script so that tests/container
# runs the very same steps in a debootstrap'd Debian 12 root: installs exactly
# scripts/packages/runtime.txt (no recommends), creates the unprivileged user
# and the /data mount point, and registers NVIDIA's EGL library with glvnd.
# Expects the repository's scripts/packages/ and docker/ next to each other:
#   <dir>/docker/runtime-setup.sh  reads  <dir>/scripts/packages/runtime.txt
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
pkgs=$("$root/scripts/packages/names" "$root/scripts/packages/runtime.txt")

export DEBIAN_FRONTEND=noninteractive
apt-get update -q
# shellcheck disable=SC2086  # one word per package
apt-get install -y -q --no-install-recommends $pkgs
apt-get clean
rm -rf /var/lib/apt/lists/*

# A fixed uid, so that files on a mounted /data can be granted to it.
getent passwd lucent >/dev/null ||
  useradd --system --user-group --uid 10001 --home-dir /nonexistent --no-create-home \
          --shell /usr/sbin/nologin lucent
mkdir -p /data

# glvnd loads every vendor listed here in file-name order and skips those whose
# library does not load. The NVIDIA container toolkit (capability "graphics")
# mounts libEGL_nvidia.so.0 and its dependencies; with this file NVIDIA's EGL
# is found even where the toolkit does not mount a vendor file of its own.
# Without a driver, glvnd falls through to Mesa's 50_mesa.json (llvmpipe).
vendor=/usr/share/glvnd/egl_vendor.d/10_nvidia.json
mkdir -p "$(dirname "$vendor")"
[ -e "$vendor" ] || cat >"$vendor" <<'JSON'
{
    "file_format_version" : "1.0.0",
    "ICD" : {
        "library_path" : "libEGL_nvidia.so.0"
    }
}
JSON
