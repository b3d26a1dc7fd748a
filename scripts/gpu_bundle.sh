#!/usr/bin/env bash
# Packs Lucent for a GPU machine that has no Debian packages (a bare CUDA
# image: a compiler, CMake, python3, NVIDIA's driver): one folder, under
# 64 MiB, that scripts/gpu_check.sh runs from (docs/TESTING.md "The GPU check").
#
#   scripts/gpu_bundle.sh [OUTDIR] [--binary PATH] [--build-dir DIR] [--reference full|quick|both|none] [--full-icu]
#                         [--max-mib N]
#
# OUTDIR (default out/gpu-bundle, replaced) holds:
#   lucent          the loader script: runs bin/lucent with LD_LIBRARY_PATH on the bundle's libraries, glvnd's
#                   EGL vendor folders plus the bundle's NVIDIA vendor file, and the bundle's glibc when the
#                   host's is older than the libraries need; `lucent --bundle-env` prints what it would do
#   bin/lucent      the binary: built here in --build-dir (default build-gpu-release: RelWithDebInfo, no MPI,
#                   no libavcodec, no tests), or --binary PATH as it is (the test suite passes its own build)
#   lib/            every shared library `ldd bin/lucent` resolves, but glibc and the GL loaders; libicudata
#                   (31 MB, reached through libnetcdf -> libxml2 -> ICU) is ICU's stub data unless --full-icu:
#                   only encoding conversions for remote NetCDF (DAP, NCZarr) would read it
#   glibc/          this host's glibc (ld.so, libc, libm, ...), used only where the host's glibc is older
#   glvnd/          glvnd's loaders (libEGL.so.1, libOpenGL.so.0, libGL.so.1, ...) from the Debian packages of
#                   scripts/packages/gpu-bundle.txt (apt-get download, dpkg -x), with their copyright files; when
#                   the download fails and no earlier download is cached, the folder is absent and the host's
#                   own glvnd is used (manifest.json says so)
#   egl_vendor.d/   a glvnd vendor file for libEGL_nvidia.so.0, for hosts whose driver has none registered
#   python/         tests/bench/*.py (browse_bench.py and server_bench.py run in the check), the helpers of
#                   tests/server (lucent_server.py), the Python client (clients/python/lucent) and
#                   python3-websockets (site/, used where the host's python3 has no websockets module)
#   data/           small files of four formats (NetCDF, TRX, TrackVis, PLY); the demos are generated
#   reference/      `lucent compare` of every demo on this host, at the check's size (full: the default request,
#                   1024x768) and at --quick's (256x192): the SSIMs the check compares against (--reference: which)
#   gpu_check.sh, manifest.json (what was packed, from where, sizes), README.txt
# The web page is embedded in the binary. Exit 1 when the bundle exceeds --max-mib (default 64; 0 = no limit).
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)

out=""
binary=""
build_dir=build-gpu-release
reference=both
full_icu=0
max_mib=64
usage() {
  sed -n '6p' "$0" | sed 's/^# *//' >&2
  exit 2
}
while [ $# -gt 0 ]; do
  case "$1" in
    --binary) binary=${2:?--binary PATH}; shift 2 ;;
    --build-dir) build_dir=${2:?--build-dir DIR}; shift 2 ;;
    --reference) reference=${2:?--reference full|quick|both|none}; shift 2 ;;
    --full-icu) full_icu=1; shift ;;
    --max-mib) max_mib=${2:?--max-mib N}; shift 2 ;;
    -h | --help) usage ;;
    -*) echo "gpu_bundle: unknown option $1" >&2; usage ;;
    *) [ -z "$out" ] || usage; out=$1; shift ;;
  esac
done
out=${out:-$src/out/gpu-bundle}
case "$reference" in
  full | quick | both | none) ;;
  *) echo "gpu_bundle: --reference full|quick|both|none" >&2; exit 2 ;;
esac
case "$max_mib" in '' | *[!0-9]*) echo "gpu_bundle: --max-mib takes a whole number" >&2; exit 2 ;; esac
say() { echo "gpu_bundle: $*"; }
die() { echo "gpu_bundle: $*" >&2; exit 1; }
for tool in ldd objdump python3; do
  command -v "$tool" >/dev/null || die "needs $tool"
done

work=$(mktemp -d "${TMPDIR:-/tmp}/lucent-bundle.XXXXXX")
trap 'rm -rf "$work"' EXIT

# ---- 1. the binary
if [ -z "$binary" ]; then
  # libavcodec (movies) and its codecs would add 120 MB; MPI is not used on one GPU. pkg-config sees
  # every .pc file but libav*'s and libsw*'s, so CMake's optional check does not find them.
  mkdir -p "$work/pc"
  IFS=: read -r -a pc_dirs <<<"$(pkg-config --variable pc_path pkg-config)"
  for d in "${pc_dirs[@]}"; do
    [ -d "$d" ] || continue
    for pc in "$d"/*.pc; do
      [ -e "$pc" ] || continue
      case "$(basename "$pc")" in libav* | libsw* | libpostproc*) continue ;; esac
      [ -e "$work/pc/$(basename "$pc")" ] || ln -s "$pc" "$work/pc/"
    done
  done
  say "building $build_dir (RelWithDebInfo, -DLUCENT_MPI=OFF -DLUCENT_TESTS=OFF, without libavcodec)"
  (cd "$src" && PKG_CONFIG_LIBDIR="$work/pc" PKG_CONFIG_PATH="" \
    scripts/build.sh "$build_dir" -DLUCENT_MPI=OFF -DLUCENT_TESTS=OFF)
  binary=$src/$build_dir/lucent
fi
[ -x "$binary" ] || die "no binary at $binary"
binary=$(readlink -f "$binary")

rm -rf "$out"
mkdir -p "$out"/{bin,lib,glibc,egl_vendor.d,data,reference} "$out"/python/{site,tests/bench,tests/server,clients}
out=$(cd "$out" && pwd)
cp "$binary" "$out/bin/lucent"

# ---- 2. shared libraries (ldd), glibc apart, GL loaders left out
glibc_names=" ld-linux-x86-64.so.2 libc.so.6 libm.so.6 libmvec.so.1 libdl.so.2 libpthread.so.0 librt.so.1"
glibc_names+=" libresolv.so.2 libutil.so.1 libanl.so.1 "
gl_names=" libEGL.so.1 libGL.so.1 libOpenGL.so.0 libGLX.so.0 libGLdispatch.so.0 libGLESv2.so.2 libGLESv1_CM.so.1 "
ldd "$binary" >"$work/ldd.txt" || die "ldd $binary failed"
if grep -q "not found" "$work/ldd.txt"; then
  die "$(grep "not found" "$work/ldd.txt")"
fi
libc_dir=""
: >"$work/libs.tsv" # name, source path, how packed
while read -r name arrow path _; do
  [ "$arrow" = "=>" ] || continue
  if [[ "$glibc_names" == *" $name "* ]]; then
    [ "$name" != libc.so.6 ] || libc_dir=$(dirname "$(readlink -f "$path")")
    continue
  fi
  case "$gl_names" in *" $name "*) continue ;; esac
  real=$(readlink -f "$path")
  how=copied
  if [[ "$name" == libicudata.so.* ]] && [ "$full_icu" = 0 ] && command -v cc >/dev/null; then
    sym=$(objdump -T "$real" | grep -o -m1 'icudt[0-9]*_dat' || true)
    # ICU's stubdata (icu4c source/stubdata): an empty common data package, 32-byte header, no entries.
    cat >"$work/icustub.c" <<EOF
struct stub_info {
    unsigned short size, reserved_word;
    unsigned char big_endian, charset_family, sizeof_uchar, reserved_byte;
    unsigned char data_format[4], format_version[4], data_version[4];
};
struct stub_header {
    unsigned short header_size;
    unsigned char magic1, magic2;
    struct stub_info info;
    char padding[8];
    unsigned int count, reserved;
    unsigned int toc[2];
};
__attribute__((visibility("default"))) const struct stub_header ${sym} = {
    32, 0xda, 0x27, {sizeof(struct stub_info), 0, 0, 0, 2, 0, {0x54, 0x6f, 0x43, 0x50}, {1, 0, 0, 0}, {0, 0, 0, 0}},
    {0}, 0, 0, {0, 0}};
EOF
    if [ -n "$sym" ] && cc -shared -fPIC -O2 -Wl,-soname,"$name" -o "$out/lib/$name" "$work/icustub.c"; then
      how="ICU stub data ($sym)"
    else
      cp "$real" "$out/lib/$name"
    fi
  else
    cp "$real" "$out/lib/$name"
  fi
  printf '%s\t%s\t%s\n' "$name" "$real" "$how" >>"$work/libs.tsv"
done <"$work/ldd.txt"
[ -n "$libc_dir" ] || die "ldd did not list libc.so.6"
for name in $glibc_names; do
  for dir in "$libc_dir" /lib64 /lib/x86_64-linux-gnu; do
    if [ -e "$dir/$name" ]; then
      cp "$(readlink -f "$dir/$name")" "$out/glibc/$name"
      break
    fi
  done
done
[ -e "$out/glibc/ld-linux-x86-64.so.2" ] || die "no ld-linux-x86-64.so.2 next to $libc_dir/libc.so.6"

# ---- 3. glvnd's loaders from Debian packages (fetched, unpacked, never installed)
mapfile -t glvnd_pkgs < <("$src/scripts/packages/names" "$src/scripts/packages/gpu-bundle.txt")
cache=${LUCENT_GPU_DEB_CACHE:-${XDG_CACHE_HOME:-${HOME:-/tmp}/.cache}/lucent/gpu-debs}
mkdir -p "$work/debs"
glvnd_source=""
glvnd_note=""
if (cd "$work/debs" && timeout 120 apt-get download "${glvnd_pkgs[@]}") >"$work/apt.log" 2>&1; then
  glvnd_source="apt-get download"
  if mkdir -p "$cache" 2>/dev/null; then
    for p in "${glvnd_pkgs[@]}"; do rm -f "$cache/${p}"_*.deb; done
    cp "$work"/debs/*.deb "$cache/" || true
  fi
else
  glvnd_note="apt-get download failed: $(grep -E '^(E|W):' "$work/apt.log" | head -n 2 | tr '\n' ' ')"
  rm -f "$work"/debs/*.deb
  have_all=1
  for p in "${glvnd_pkgs[@]}"; do compgen -G "$cache/${p}_*.deb" >/dev/null || have_all=0; done
  if [ "$have_all" = 1 ]; then
    for p in "${glvnd_pkgs[@]}"; do cp "$cache/${p}"_*.deb "$work/debs/"; done # one version each (see above)
    glvnd_source="cached packages ($cache)"
  fi
fi
if [ -n "$glvnd_source" ]; then
  mkdir -p "$out/glvnd/copyright"
  for deb in "$work"/debs/*.deb; do
    pkg=$(dpkg-deb -f "$deb" Package)
    printf '%s\t%s\n' "$pkg" "$(dpkg-deb -f "$deb" Version)" >>"$work/debs.tsv"
    rm -rf "$work/x"
    dpkg -x "$deb" "$work/x"
    # The sonames (links in the package) as plain files: the bundle holds no links, which some ways of
    # copying a folder drop. A library no link names is copied under its own name.
    for f in "$work"/x/usr/lib/*/lib*.so*; do
      if [ -L "$f" ]; then
        cp -L "$f" "$out/glvnd/"
      elif ! find "$(dirname "$f")" -maxdepth 1 -type l -lname "$(basename "$f")" | grep -q .; then
        cp "$f" "$out/glvnd/"
      fi
    done
    if [ -f "$work/x/usr/share/doc/$pkg/copyright" ]; then
      cp "$work/x/usr/share/doc/$pkg/copyright" "$out/glvnd/copyright/$pkg"
    fi
  done
  say "glvnd loaders packed from $glvnd_source: $(cut -f1 "$work/debs.tsv" | tr '\n' ' ')"
else
  : >"$work/debs.tsv"
  say "NOTE: glvnd's loaders are NOT packed ($glvnd_note); the bundle will use the host's own libEGL.so.1"
fi
cat >"$out/egl_vendor.d/10_nvidia.json" <<'EOF'
{
    "file_format_version" : "1.0.0",
    "ICD" : {
        "library_path" : "libEGL_nvidia.so.0"
    }
}
EOF

# The newest glibc symbol version any packed file needs: older hosts run through glibc/.
elf_files=("$out/bin/lucent" "$out"/lib/*)
[ -d "$out/glvnd" ] && elf_files+=("$out"/glvnd/*.so*)
objdump -T "${elf_files[@]}" | grep -o 'GLIBC_[0-9][0-9.]*' | sed 's/GLIBC_//' | sort -V |
  tail -n1 >"$out/glibc/REQUIRED"
glibc_here=$(getconf GNU_LIBC_VERSION | awk '{print $2}')

# ---- 4. the loader script
cat >"$out/lucent" <<'EOF'
#!/usr/bin/env bash
# Runs the bundle's lucent (scripts/gpu_bundle.sh): the bundle's libraries first, glvnd's loaders from the
# bundle when packed, the host's EGL vendors (NVIDIA, Mesa) plus the bundle's NVIDIA vendor file when the host
# registers none, and the bundle's glibc when the host's is older than the libraries need
# (LUCENT_BUNDLE_GLIBC=1 forces it, 0 never). `lucent --bundle-env` prints the set-up and exits.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd -P)
libs=$here/lib
[ -d "$here/glvnd" ] && libs=$here/glvnd:$libs
if [ -z "${__EGL_VENDOR_LIBRARY_FILENAMES:-}" ] && [ -z "${__EGL_VENDOR_LIBRARY_DIRS:-}" ] &&
  ! compgen -G '/etc/glvnd/egl_vendor.d/*nvidia*.json' >/dev/null &&
  ! compgen -G '/usr/share/glvnd/egl_vendor.d/*nvidia*.json' >/dev/null; then
  export __EGL_VENDOR_LIBRARY_DIRS=/etc/glvnd/egl_vendor.d:/usr/share/glvnd/egl_vendor.d:$here/egl_vendor.d
fi
need=$(cat "$here/glibc/REQUIRED" 2>/dev/null || echo 0)
have=$(getconf GNU_LIBC_VERSION 2>/dev/null | awk '{print $2}')
glibc=${LUCENT_BUNDLE_GLIBC:-auto}
if [ "$glibc" = auto ]; then
  glibc=0
  if [ -x "$here/glibc/ld-linux-x86-64.so.2" ] && [ "$have" != "$need" ] &&
    [ "$(printf '%s\n%s\n' "$have" "$need" | sort -V | head -n1)" = "$have" ]; then
    glibc=1
  fi
fi
if [ "${1:-}" = --bundle-env ]; then
  echo "bundle=$here"
  echo "glibc_host=$have"
  echo "glibc_needed=$need"
  echo "glibc_bundled=$glibc"
  echo "library_path=$libs"
  echo "egl_vendor_dirs=${__EGL_VENDOR_LIBRARY_DIRS:-glvnd defaults}"
  echo "glvnd=$([ -d "$here/glvnd" ] && echo bundle || echo host)"
  exit 0
fi
if [ "$glibc" = 1 ]; then
  exec "$here/glibc/ld-linux-x86-64.so.2" --library-path "$here/glibc:$libs" "$here/bin/lucent" "$@"
fi
export LD_LIBRARY_PATH=$libs${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
exec "$here/bin/lucent" "$@"
EOF
chmod +x "$out/lucent"

# ---- 5. Python clients, the check, data
# The benchmark clients with their helpers: every module of tests/bench, the helpers (not the tests) of tests/server.
cp "$src"/tests/bench/*.py "$out/python/tests/bench/"
for f in "$src"/tests/server/*.py; do
  case "$(basename "$f")" in test_*) ;; *) cp "$f" "$out/python/tests/server/" ;; esac
done
cp -r "$src/clients/python/lucent" "$out/python/clients/"
cp "$src/scripts/gpu_check.sh" "$out/"
ws_dir=""
for py in python3 /usr/bin/python3; do
  command -v "$py" >/dev/null || continue
  ws_dir=$("$py" -c 'import os, websockets; print(os.path.dirname(websockets.__file__))' 2>/dev/null) && break
done
ws_version=""
if [ -n "$ws_dir" ] && [ -d "$ws_dir" ]; then
  cp -r "$ws_dir" "$out/python/site/websockets"
  ws_version=$(sed -n 's/^version = "\(.*\)"/\1/p' "$ws_dir/version.py" 2>/dev/null | head -n1)
else
  say "NOTE: no python3 here has websockets (python3-websockets); the bundle has none"
fi
find "$out/python" -name __pycache__ -type d -prune -exec rm -rf {} +
for f in nc/valid/trajectories.nc trx/valid/f16_deflated.trx trk/valid/tracts_le.trk valid/tetra_le.ply; do
  cp "$src/tests/data/loaders/$f" "$out/data/"
done

# ---- 6. this host's figures, through the loader script (which proves it here)
# The sizes are gpu_check.sh's: the default request's for the full check, 256x192 for --quick.
compare_reference() { # PREFIX [FLAGS...]
  local prefix=$1 d
  shift
  for d in tornado abc points surface; do
    "$out/lucent" compare --input "demo:$d" --repeat 0 "$@" >"$out/reference/$prefix$d.txt" 2>"$work/compare.err" ||
      die "lucent compare demo:$d $* failed: $(tail -n 5 "$work/compare.err")"
  done
}
if [ "$reference" != none ]; then
  say "lucent compare of every demo on this host (reference/: $reference)"
  [ "$reference" = quick ] || compare_reference compare-
  [ "$reference" = full ] || compare_reference quick-compare- --size 256x192
fi

# ---- 7. manifest and README
commit=$(git -C "$src" rev-parse HEAD 2>/dev/null || echo unknown)
dirty=$(git -C "$src" status --porcelain --untracked-files=no 2>/dev/null | wc -l)
python3 - "$out" "$work/libs.tsv" "$work/debs.tsv" "$binary" "$commit" "$dirty" "$glvnd_source" "$glvnd_note" \
  "$ws_version" "$glibc_here" "$reference" <<'EOF'
import datetime, hashlib, json, os, platform, re, subprocess, sys
out, libs_tsv, debs_tsv, binary, commit, dirty, glvnd_source, glvnd_note, ws_version, glibc_here, ref = sys.argv[1:]


def size(path):
    total = 0
    for root, _, files in os.walk(path):
        for f in files:
            p = os.path.join(root, f)
            if not os.path.islink(p):
                total += os.path.getsize(p)
    return total


def rows(path):
    with open(path) as f:
        return [line.rstrip("\n").split("\t") for line in f if line.strip()]


ldd = subprocess.run(["ldd", binary], capture_output=True, text=True).stdout
resolved = dict(re.findall(r"^\s*(\S+) => (/\S+)", ldd, re.M))
# The libraries only movies (libavcodec and friends) and MPI bring: what the default build (without them)
# leaves out, so that a bundle of the suite's build can tell the size of the default one.
needed = re.findall(r"NEEDED\s+(\S+)", subprocess.run(["objdump", "-p", binary], capture_output=True,
                                                         text=True).stdout)
optional = re.compile(r"lib(avcodec|avformat|avutil|swscale|swresample|mpi)\.so")
keep = set()
for n in needed:
    if not optional.match(n) and n in resolved:
        keep.add(n)
        keep.update(re.findall(r"^\s*(\S+) => /", subprocess.run(["ldd", resolved[n]], capture_output=True,
                                                                   text=True).stdout, re.M))
with open(os.path.join(out, "bin", "lucent"), "rb") as f:
    digest = hashlib.sha256(f.read()).hexdigest()
with open(os.path.join(out, "glibc", "REQUIRED")) as f:
    needed = f.read().strip()
m = {
    "created": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
    "host": platform.node(), "commit": commit,
    "working_tree_changes": int(dirty),
    "binary": {"from": binary, "sha256": digest, "bytes": os.path.getsize(os.path.join(out, "bin", "lucent")),
               "links_libavcodec": "libavcodec" in ldd, "links_mpi": "libmpi" in ldd},
    "libraries": [{"name": n, "from": p, "packed": how, "bytes": os.path.getsize(os.path.join(out, "lib", n)),
                   "only_for_movies_or_mpi": n not in keep} for n, p, how in rows(libs_tsv)],
    "glibc": {"host": glibc_here, "needed": needed, "files": sorted(os.listdir(os.path.join(out, "glibc")))},
    "glvnd": {"packed": bool(glvnd_source), "source": glvnd_source or None, "note": glvnd_note or None,
              "packages": {p: v for p, v in rows(debs_tsv)}},
    "python": {"websockets": ws_version or None},
    "data": sorted(os.listdir(os.path.join(out, "data"))),
    "reference": {"sizes": ref, "files": sorted(os.listdir(os.path.join(out, "reference")))},
    "web": "embedded in the binary",
    "folders_bytes": {d: size(os.path.join(out, d)) for d in sorted(os.listdir(out))
                      if os.path.isdir(os.path.join(out, d))},
}
m["bytes"] = size(out)
m["bytes_without_movies_and_mpi"] = m["bytes"] - sum(x["bytes"] for x in m["libraries"]
                                                     if x["only_for_movies_or_mpi"])
with open(os.path.join(out, "manifest.json"), "w") as f:
    json.dump(m, f, indent=1)
EOF
cat >"$out/README.txt" <<EOF
Lucent GPU bundle, made by scripts/gpu_bundle.sh from commit $commit.
  ./lucent --help                       the binary, through the loader script (./lucent --bundle-env: its set-up)
  ./gpu_check.sh . OUTDIR [--quick]     the GPU check: OUTDIR/report.md, report.json, logs.tar.gz
manifest.json lists what was packed and from where; docs/TESTING.md "The GPU check" explains the report.
EOF

bytes=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["bytes"])' "$out/manifest.json")
mib=$(awk -v b="$bytes" 'BEGIN { printf "%.1f", b / 1048576 }')
say "$out: $mib MiB ($(find "$out" -type f | wc -l) files); glibc needed $(cat "$out/glibc/REQUIRED"), here $glibc_here"
if grep -q '"only_for_movies_or_mpi": true' "$out/manifest.json"; then
  say "the binary links libavcodec or MPI: $(python3 -c 'import json, sys
m = json.load(open(sys.argv[1]))
print("%.1f MiB without the libraries only they need (the default build leaves them out)"
      % (m["bytes_without_movies_and_mpi"] / 1048576))' "$out/manifest.json")"
fi
if [ "$max_mib" -gt 0 ] && [ "$bytes" -gt $((max_mib * 1048576)) ]; then
  die "the bundle is $mib MiB, over --max-mib $max_mib (manifest.json has the sizes)"
fi
