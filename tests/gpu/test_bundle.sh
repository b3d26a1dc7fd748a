#!/usr/bin/env bash
# container.gpu_bundle: the GPU bundle proven on this host in every run of the suite (docs/TESTING.md "The GPU
# check"). scripts/gpu_bundle.sh packs the suite's own binary (--binary: no second build) into a scratch folder;
# scripts/gpu_check.sh --quick then runs from the bundle under `env -i` with only PATH and HOME (a scratch home),
# so that the process sees the bundle's libraries, glvnd's loaders from the bundle and the system's Mesa driver,
# and the benchmark clients the bundle's websockets (LUCENT_CHECK_PYTHON=bundle). Checks report.json: every
# part present and "ok", the renderer and EGL strings, no library of the bundle loaded from elsewhere, the
# compare SSIMs numbers within 0.001 of the bundle's reference, bench rows for every size and method, the
# orbit's and the sessions' figures. Also runs the bundle's glibc fallback (LUCENT_BUNDLE_GLIBC=1) once.
# When `apt-get download` cannot fetch glvnd's packages (no mirror) the bundle is made without them and the
# check runs on the system's glvnd: the test says so in its output and still checks everything else.
# Exit 77 (skipped) when there is no EGL/OpenGL 4.5 here, unless CI=true.
# Usage: test_bundle.sh LUCENT_BINARY SOURCE_DIR
set -euo pipefail
binary=$(readlink -f "$1")
src=$(readlink -f "$2")
scratch=$(mktemp -d "${TMPDIR:-/tmp}/lucent-gpu-bundle.XXXXXX")
trap 'rm -rf "$scratch"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
say() { echo "gpu_bundle test: $*"; }
clean_path=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin

if ! "$binary" bench --dataset 'demo:points?count=100' --size 16x16 --frames 1 --warmup 0 >"$scratch/probe.log" 2>&1
then
  cat "$scratch/probe.log"
  if grep -qi 'egl\|opengl' "$scratch/probe.log" && [ "${CI:-}" != true ]; then
    echo "SKIP: no OpenGL 4.5 context"
    exit 77
  fi
  fail "lucent bench does not run here"
fi

# ---- 1. the bundle, from the suite's binary (its own HOME: the cache of glvnd's packages lives there)
t=$SECONDS
env -i PATH="$clean_path" HOME="${HOME:-$scratch}" "$src/scripts/gpu_bundle.sh" "$scratch/bundle" \
  --binary "$binary" --max-mib 0 --reference quick >"$scratch/bundle.log" 2>&1 ||
  { cat "$scratch/bundle.log"; fail "gpu_bundle.sh failed"; }
cat "$scratch/bundle.log"
say "bundle made in $((SECONDS - t)) s"

# ---- 2. the check, in a clean environment
mkdir -p "$scratch/home"
t=$SECONDS
env -i PATH="$clean_path" HOME="$scratch/home" LUCENT_CHECK_PYTHON=bundle \
  "$scratch/bundle/gpu_check.sh" "$scratch/bundle" "$scratch/report" --quick >"$scratch/check.log" 2>&1 ||
  { cat "$scratch/check.log"; fail "gpu_check.sh --quick exited non-zero"; }
cat "$scratch/check.log"
say "gpu_check.sh --quick took $((SECONDS - t)) s"

# ---- 3. the bundle's glibc, forced (what a host with an older glibc runs)
setup=$(env -i PATH="$clean_path" HOME="$scratch/home" LUCENT_BUNDLE_GLIBC=1 "$scratch/bundle/lucent" --bundle-env)
grep -qx 'glibc_bundled=1' <<<"$setup" || fail "LUCENT_BUNDLE_GLIBC=1 does not select the bundle's glibc: $setup"
env -i PATH="$clean_path" HOME="$scratch/home" LUCENT_BUNDLE_GLIBC=1 LD_DEBUG=libs "$scratch/bundle/lucent" bench \
  --dataset 'demo:points?count=500' --size 32x32 --frames 1 --warmup 0 >"$scratch/glibc.log" 2>&1 ||
  { tail -n 40 "$scratch/glibc.log"; fail "the bundle's lucent does not render through the bundle's glibc"; }
grep -q "calling init: $scratch/bundle/glibc/libc.so.6" "$scratch/glibc.log" ||
  fail "LUCENT_BUNDLE_GLIBC=1 did not load the bundle's libc.so.6"
grep -q '^renderer: ' "$scratch/glibc.log" || fail "no renderer line through the bundle's glibc"
say "the bundle's glibc (LUCENT_BUNDLE_GLIBC=1) renders"

# ---- 4. the report
python3 - "$scratch/bundle" "$scratch/report" <<'EOF'
import json, os, sys

bundle, report = sys.argv[1:]
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL: " + what)


def is_num(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool)


files = sorted(os.listdir(report))
check(files == ["logs.tar.gz", "report.json", "report.md"], "OUTDIR holds %s, not the report's three files" % files)
with open(os.path.join(report, "report.json")) as f:
    r = json.load(f)
with open(os.path.join(report, "report.md")) as f:
    md = f.read()
with open(os.path.join(bundle, "manifest.json")) as f:
    m = json.load(f)
check(r.get("schema") == 1 and r.get("mode") == "quick", "schema 1, quick mode")
parts = r.get("parts", {})
for name in ("environment", "compare", "bench", "orbit", "sessions", "breakdown"):
    check(name in parts, "part %s present" % name)
    check(parts.get(name, {}).get("status") == "ok",
          "part %s: %s (%s)" % (name, parts.get(name, {}).get("status"), parts.get(name, {}).get("reason")))

env = parts.get("environment", {})
check(isinstance(env.get("renderer"), str) and env["renderer"] != "", "a renderer string")
check(env.get("renderer", "") in md, "report.md names the renderer")
check("EGL_EXT_platform_device" in (env.get("egl_platform") or "") or "surfaceless" in (env.get("egl_platform") or ""),
      "an EGL platform string: %r" % env.get("egl_platform"))
check((env.get("egl") or "").startswith("EGL "), "the EGL version: %r" % env.get("egl"))
check(env.get("outside_bundle_shadowed") == [], "bundle libraries loaded from elsewhere: %s"
      % env.get("outside_bundle_shadowed"))
check(any(p.startswith("lib/") for p in env.get("libraries", {}).get("bundle", [])), "libraries loaded from lib/")
print("libraries from the system besides glibc and the GL driver (the driver's own dependencies): %s" % ", ".join(
    os.path.basename(p) for p in env.get("libraries", {}).get("system_other", [])))
if m["glvnd"]["packed"]:
    check((env.get("egl_loader") or "").startswith(os.path.join(bundle, "glvnd") + "/"),
          "libEGL.so.1 from the bundle's glvnd: %r" % env.get("egl_loader"))
else:
    print("NOTE: glvnd's loaders were NOT packed (%s); the check ran on the system's %s"
          % (m["glvnd"]["note"], env.get("egl_loader")))
check(env.get("egl_vendor_libraries"), "an EGL vendor library (libEGL_mesa.so.0 here)")
check(len(env.get("data", [])) == 4 and all(d["ok"] for d in env["data"]), "the bundle's four data files read")
check(r["host"].get("websockets") == "bundle", "the benchmark clients used the bundle's websockets")

demos = parts.get("compare", {}).get("demos", {})
check(sorted(demos) == ["abc", "points", "surface", "tornado"], "compare ran every demo")
for d, c in demos.items():
    check(is_num(c.get("ssim")) and 0.9 < c["ssim"] <= 1, "compare %s: SSIM %r" % (d, c.get("ssim")))
    check(is_num(c.get("rmse")) and is_num(c.get("fourier_ms")) and is_num(c.get("exact_ms")),
          "compare %s: RMSE and times" % d)
    check(is_num(c.get("reference_ssim")) and c.get("within_0_001") is True,
          "compare %s: SSIM %r within 0.001 of this host's %r" % (d, c.get("ssim"), c.get("reference_ssim")))

runs = parts.get("bench", {}).get("runs", {})
check(sorted(runs) == ["points-16M", "surface-10M", "surface-1M", "tornado-10M", "tornado-1M"], "bench runs: %s"
      % sorted(runs))
for key, run in runs.items():
    combos = sorted((x["size"], x["method"]) for x in run.get("rows", []))
    check(combos == sorted((s, mt) for s in ("96x96", "128x72") for mt in ("fourier", "exact", "opaque")),
          "bench %s: a row per size and method, %s" % (key, combos))
    for x in run.get("rows", []):
        check(is_num(x["gpu_ms"]) and is_num(x["wall_ms"]) and is_num(x["passes_ms"].get("readback")),
              "bench %s %s %s: times" % (key, x["size"], x["method"]))
    fourier = [x for x in run.get("rows", []) if x["method"] == "fourier"]
    check(all("importance" in x["passes_ms"] and "resolve" in x["passes_ms"] for x in fourier),
          "bench %s: Fourier rows have the passes" % key)

orbit = parts.get("orbit", {})
check(is_num(orbit.get("frames_per_s")) and orbit["frames_per_s"] > 0, "orbit frames/s: %r"
      % orbit.get("frames_per_s"))
lat = orbit.get("input_to_frame_ms") or {}
check(is_num(lat.get("p50")) and is_num(lat.get("p95")), "orbit input-to-frame p50/p95")
check(is_num(((orbit.get("moving") or {}).get("encode_ms") or {}).get("mean")), "orbit JPEG encode ms")
sess = parts.get("sessions", {})
check([x["sessions"] for x in sess.get("runs", [])] == [1, 2], "sessions runs 1 and 2")
check(isinstance(sess.get("sessions_at_rate"), int), "sessions at 30 frames/s: %r" % sess.get("sessions_at_rate"))
check(len(sess.get("jpeg_encode") or []) == 2, "JPEG encode rates")
bd = parts.get("breakdown", {})
check(bd.get("orbit") and is_num(bd["orbit"].get("readback_ms")) and len(bd.get("bench", [])) == 5,
      "read-back/encode breakdown")
check(len(r.get("goals", [])) == 3, "three goals listed")
for section in ("## Device", "## Fourier against exact", "## Per pass", "## WebSocket orbit", "## Sessions",
                "## Read-back and encode"):
    check(section in md, "report.md has %s" % section)

print("report: %s, %s, %d s; bundle %.1f MiB (%.1f MiB without the libraries only movies and MPI need: the "
      "default build's size), glvnd %s" % (
          env.get("renderer"), env.get("egl_platform"), r.get("seconds", 0), m["bytes"] / 1048576,
          m["bytes_without_movies_and_mpi"] / 1048576, "packed" if m["glvnd"]["packed"] else "NOT packed"))
check(m["bytes_without_movies_and_mpi"] < 64 * 1048576, "the default bundle would stay under 64 MiB")
sys.exit(1 if failures else 0)
EOF
echo "PASS"
