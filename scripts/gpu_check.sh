#!/usr/bin/env bash
# The GPU check (docs/TESTING.md "The GPU check"): runs a bundle of scripts/gpu_bundle.sh on this machine and
# writes one report, OUTDIR/report.md and OUTDIR/report.json, with the raw logs in OUTDIR/logs.tar.gz:
#   environment  the EGL device, renderer and GL strings, the libraries the process loaded (LD_DEBUG), the
#                bundle's data files read, the host (nvidia-smi where present)
#   compare      `lucent compare` of Fourier against exact on every demo, SSIM against the bundle's reference
#   bench        `lucent bench` per pass at 1000x1000 and 1920x1080, Fourier, exact and opaque: the tornado at
#                1 M and 10 M segments, 16 M points, the surface demo at 1 M and 10 M vertices; GPU memory
#   orbit        a WebSocket orbit at 1920x1080 (tests/bench/browse_bench.py): frames/s, input-to-frame
#                p50/p95, render, read-back and JPEG encode ms per frame
#   sessions     sessions at 1920x1080 orbiting at 30 updates/s (tests/bench/server_bench.py): how many keep
#                30 frames/s each; JPEG encode rate
#   breakdown    read-back and encode against the frame time, from the parts above
# Each run has its own time limit and the whole a budget (default 450 s; --budget S): a run that does not end
# in time is recorded as "not reached", one that fails as "failed" with its log's end; the report is always
# written and the exit status is 0 when it was. --quick runs every part at tiny sizes (under a minute on
# llvmpipe; budget 270 s, for a busy host): the suite's container.gpu_bundle test.
#
#   scripts/gpu_check.sh BUNDLE OUTDIR [--quick] [--budget S]
#
# LUCENT_CHECK_PYTHON=bundle makes the benchmark clients use the bundle's websockets even where python3 has its
# own (the test proves the bundled copy that way).
set -euo pipefail

bundle=""
out=""
quick=0
budget=""
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1; shift ;;
    --budget) budget=${2:?--budget S}; shift 2 ;;
    -h | --help) sed -n '19p' "$0" | sed 's/^# *//'; exit 0 ;;
    -*) echo "gpu_check: unknown option $1" >&2; exit 2 ;;
    *)
      if [ -z "$bundle" ]; then bundle=$1; elif [ -z "$out" ]; then out=$1; else
        echo "gpu_check: one BUNDLE and one OUTDIR" >&2; exit 2
      fi
      shift
      ;;
  esac
done
if [ -z "$bundle" ] || [ -z "$out" ]; then
  sed -n '19p' "$0" | sed 's/^# */usage: /' >&2
  exit 2
fi
if [ ! -x "$bundle/lucent" ]; then
  echo "gpu_check: $bundle has no lucent loader script (scripts/gpu_bundle.sh)" >&2
  exit 2
fi
B=$(cd "$bundle" && pwd -P)
mkdir -p "$out"
out=$(cd "$out" && pwd -P)
[ -n "$budget" ] || budget=$([ "$quick" = 1 ] && echo 270 || echo 450)
case "$budget" in '' | *[!0-9]*) echo "gpu_check: --budget takes whole seconds" >&2; exit 2 ;; esac
rm -f "$out/report.md" "$out/report.json" "$out/logs.tar.gz"
work=$(mktemp -d "${TMPDIR:-/tmp}/lucent-gpu-check.XXXXXX")
logs=$work/logs
mkdir -p "$logs"
smi_pid=""
cleanup() {
  [ -z "$smi_pid" ] || kill "$smi_pid" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
export PYTHONDONTWRITEBYTECODE=1
started=$(date -u +%Y-%m-%dT%H:%M:%SZ)
t0=$SECONDS
say() { echo "gpu_check: $*"; }

# ---- the sizes of the parts
if [ "$quick" = 1 ]; then
  sizes=96x96,128x72
  frames=(--frames 1 --warmup 1)
  # each run takes a second or two; the limits leave room for a busy two-core host
  sets=("tornado-1M demo:tornado?count=8 120" "points-16M demo:points?count=5000 120"
    "surface-1M demo:surface?count=16 120" "tornado-10M demo:tornado?count=16 120"
    "surface-10M demo:surface?count=20 120")
  limit=120
  orbit=(--dataset 'demo:tornado?count=8' --width 320 --height 180 --seconds 2 --rate 30)
  sessions=(--dataset 'demo:tornado?count=8' --width 320 --height 180 --seconds 2 --rate 30 --sessions "1,2")
  compare=(--repeat 0 --size 256x192)
  reference="quick-compare-"
else
  sizes=1000x1000,1920x1080
  frames=(--frames 5 --warmup 2)
  # 1880 tornado lines are 0.99 M segments, 18800 are 9.9 M; surface resolution 577 is 1.0 M vertices, 1826 10.0 M
  sets=("tornado-1M demo:tornado?count=1880 90" "points-16M demo:points?count=16000000 120"
    "surface-1M demo:surface?count=577 90" "tornado-10M demo:tornado?count=18800 120"
    "surface-10M demo:surface?count=1826 240")
  orbit=(--dataset demo:tornado --width 1920 --height 1080 --seconds 8 --rate 120)
  sessions=(--dataset demo:tornado --width 1920 --height 1080 --seconds 5 --rate 30 --sessions "1,2,4,8,16")
  compare=(--repeat 3)
  reference="compare-"
  limit=60
fi

# ---- python3 and websockets for the benchmark clients
py=$(command -v python3 || true)
ws_from=none
if [ -n "$py" ]; then
  if [ "${LUCENT_CHECK_PYTHON:-}" != bundle ] && "$py" -c 'import websockets' 2>/dev/null; then
    ws_from=host
  elif PYTHONPATH=$B/python/site${PYTHONPATH:+:$PYTHONPATH} "$py" -c 'import websockets' 2>/dev/null; then
    export PYTHONPATH=$B/python/site${PYTHONPATH:+:$PYTHONPATH}
    ws_from=bundle
  fi
fi

# ---- running a part: its own limit, within what is left of the budget
smi_start() {
  command -v nvidia-smi >/dev/null || return 0
  nvidia-smi --query-gpu=index,memory.used,memory.total,utilization.gpu --format=csv,noheader,nounits -lms 250 \
    >"$logs/$1.smi" 2>&1 &
  smi_pid=$!
}
smi_stop() {
  [ -n "$smi_pid" ] || return 0
  kill "$smi_pid" 2>/dev/null || true
  wait "$smi_pid" 2>/dev/null || true
  smi_pid=""
}
record() { # NAME STATUS SECONDS LIMIT RC REASON
  printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$@" >>"$work/parts.tsv"
  say "$1: $2 ($3 s)${6:+: $6}"
}
run_part() { # NAME LIMIT COMMAND...
  local name=$1 limit=$2 left t rc=0 start status=ok reason=""
  shift 2
  left=$((budget - (SECONDS - t0) - 10))
  t=$((limit < left ? limit : left))
  if [ "$t" -lt 5 ]; then
    record "$name" "not reached" 0 "$limit" "" "the check's budget of $budget s was spent"
    return 0
  fi
  say "$name (limit $t s)"
  start=$SECONDS
  smi_start "$name"
  timeout -k 5 "$t" "$@" >"$logs/$name.log" 2>&1 || rc=$?
  smi_stop
  if [ "$rc" = 124 ] || [ "$rc" = 137 ]; then
    status="not reached" reason="stopped at its time limit of $t s"
  elif [ "$rc" != 0 ]; then
    status=failed reason="exit $rc: $(tail -n 4 "$logs/$name.log" | tr '\t\n' '  ' | cut -c1-400)"
  fi
  record "$name" "$status" $((SECONDS - start)) "$t" "$rc" "$reason"
}
skip_part() { record "$1" "not reached" 0 0 "" "$2"; }

say "bundle $B, report in $out, $([ "$quick" = 1 ] && echo quick || echo full), budget $budget s"
"$B/lucent" --bundle-env >"$logs/bundle-env.txt" 2>&1 || true

# ---- environment: EGL device and renderer, the libraries loaded, the data files
run_part environment "$limit" env LD_DEBUG=libs LUCENT_LOG_LEVEL=debug "$B/lucent" bench \
  --dataset 'demo:points?count=1000' --size 64x64 --frames 1 --warmup 0
# shellcheck disable=SC2016 # the inner script's own arguments
run_part data "$limit" bash -c \
  'for f in "$1"/data/*; do echo "== $(basename "$f")"; "$1/lucent" info "$f" || exit; done' _ "$B"

# ---- compare: Fourier against exact on every demo (the default request: 1024x768, m = 5, midpoint; 256x192 quick)
for d in tornado abc points surface; do
  run_part "compare.$d" "$limit" "$B/lucent" compare --input "demo:$d" "${compare[@]}"
done

# ---- bench, orbit and sessions: the small datasets first, the 10 M ones last (the longest to generate)
bench_set() { # KEY SPEC LIMIT
  run_part "bench.$1" "$3" "$B/lucent" bench --dataset "$2" --sizes "$sizes" --methods fourier,exact,opaque \
    "${frames[@]}"
}
for s in "${sets[@]:0:3}"; do
  read -r key spec set_limit <<<"$s"
  bench_set "$key" "$spec" "$set_limit"
done
if [ "$ws_from" = none ]; then
  why="no python3 with websockets here, and the bundle's copy does not import"
  [ -n "$py" ] || why="no python3 here"
  skip_part orbit "$why"
  skip_part sessions "$why"
else
  run_part orbit $((limit + 30)) "$py" "$B/python/tests/bench/browse_bench.py" --binary "$B/lucent" "${orbit[@]}" \
    --timeout 60 --json "$work/orbit.json"
  run_part sessions 150 "$py" "$B/python/tests/bench/server_bench.py" --binary "$B/lucent" "${sessions[@]}" \
    --json "$work/sessions.json"
fi
for s in "${sets[@]:3}"; do
  read -r key spec set_limit <<<"$s"
  bench_set "$key" "$spec" "$set_limit"
done
for s in "${sets[@]}"; do
  read -r key spec _ <<<"$s"
  printf '%s\t%s\n' "$key" "$spec" >>"$work/sets.tsv"
done

# ---- the report
total=$((SECONDS - t0))
tar -czf "$out/logs.tar.gz" -C "$work" logs
if [ -z "$py" ]; then
  {
    echo "# Lucent GPU check: no python3 on this machine, so no tables; the runs and their logs"
    echo
    sed 's/^/    /' "$work/parts.tsv"
    for f in "$logs"/*.log; do
      echo
      echo "## $(basename "$f" .log)"
      tail -n 60 "$f" | sed 's/^/    /'
    done
  } >"$out/report.md"
  echo '{"schema": 1, "error": "no python3 on this machine: report.md has the raw runs"}' >"$out/report.json"
  say "wrote $out/report.md (raw: no python3)"
  exit 0
fi
"$py" - "$B" "$work" "$out" "$quick" "$budget" "$ws_from" "$started" "$total" "$sizes" "$reference" <<'PYEOF'
import glob, json, os, platform, re, subprocess, sys

B, work, out, quick, budget, ws_from, started, total, sizes, reference = sys.argv[1:]
quick, logs = quick == "1", os.path.join(work, "logs")
DEMOS = ("tornado", "abc", "points", "surface")
GLIBC = {"ld-linux-x86-64.so.2", "libc.so.6", "libm.so.6", "libmvec.so.1", "libdl.so.2", "libpthread.so.0",
         "librt.so.1", "libresolv.so.2", "libutil.so.1", "libanl.so.1"}
GL = re.compile(r"^(libEGL|libGL|libOpenGL|libGLX|libGLdispatch|libGLES|libnvidia|libcuda|libgbm|libglapi|libdrm|"
                r"libLLVM|libwayland|libxcb|libX|swrast_dri|.*_dri\.so|libvulkan|libxshmfence|libsensors|libelf)")


def read(path, default=""):
    try:
        with open(path, errors="replace") as f:
            return f.read()
    except OSError:
        return default


def num(s):
    try:
        return float(s)
    except (TypeError, ValueError):
        return None


parts = {}
for line in read(os.path.join(work, "parts.tsv")).splitlines():
    name, status, seconds, limit, rc, reason = (line.split("\t") + [""] * 6)[:6]
    parts[name] = {"status": status, "seconds": int(seconds or 0), "limit_s": int(limit or 0),
                   "reason": reason or None}


def part(name, **extra):
    p = dict(parts.get(name, {"status": "not reached", "seconds": 0, "limit_s": 0, "reason": "not run"}))
    p.update(extra)
    return p


def log(name):
    return read(os.path.join(logs, name + ".log"))


def smi_peak(name):
    """Peak memory.used (MiB) per GPU index over the run's nvidia-smi samples, and the total."""
    peak = {}
    for line in read(os.path.join(logs, name + ".smi")).splitlines():
        f = [x.strip() for x in line.split(",")]
        if len(f) >= 3 and num(f[1]) is not None:
            i = f[0]
            peak[i] = {"used_mib": max(num(f[1]), peak.get(i, {}).get("used_mib", 0)), "total_mib": num(f[2])}
    return peak or None


def group(status_list):
    if not status_list:
        return "not reached"
    if all(s == "ok" for s in status_list):
        return "ok"
    if any(s == "ok" for s in status_list):
        return "partial"
    return "failed" if any(s == "failed" for s in status_list) else "not reached"


# ---- host and environment
def sh(cmd):
    try:
        return subprocess.run(cmd, capture_output=True, text=True, timeout=20).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return ""


osr = dict(re.findall(r'^(\w+)="?([^"\n]*)"?$', read("/etc/os-release"), re.M))
mem = re.search(r"MemTotal:\s+(\d+)", read("/proc/meminfo"))
cpu = re.search(r"model name\s*:\s*(.*)", read("/proc/cpuinfo"))
gpus = []
for line in sh(["nvidia-smi", "--query-gpu=index,name,driver_version,memory.total,pci.bus_id",
                "--format=csv,noheader,nounits"]).splitlines():
    f = [x.strip() for x in line.split(",")]
    if len(f) >= 5:
        gpus.append({"index": f[0], "name": f[1], "driver": f[2], "memory_mib": num(f[3]), "pci": f[4]})
vendors = {}
for d in ("/etc/glvnd/egl_vendor.d", "/usr/share/glvnd/egl_vendor.d", os.path.join(B, "egl_vendor.d")):
    for f in sorted(glob.glob(os.path.join(d, "*.json"))):
        m = re.search(r'"library_path"\s*:\s*"([^"]+)"', read(f))
        vendors[f] = m.group(1) if m else None
host = {"os": osr.get("PRETTY_NAME"), "kernel": platform.release(), "cpu": cpu.group(1) if cpu else None,
        "cpus": os.cpu_count(), "memory_gib": round(int(mem.group(1)) / 1048576, 1) if mem else None,
        "python": platform.python_version(), "websockets": ws_from, "gpus": gpus, "egl_vendor_files": vendors,
        "bundle_env": dict(l.split("=", 1) for l in read(os.path.join(logs, "bundle-env.txt")).splitlines()
                           if "=" in l)}
manifest = json.loads(read(os.path.join(B, "manifest.json"), "{}") or "{}")

env_log = log("environment")
rend = re.search(r"^renderer: (.*?) \| (.*?) \| (.*)$", env_log, re.M)
egl = re.search(r"initialized (EGL [\d.]+) on (.*)$", env_log, re.M)
# The libraries of the lucent process: LD_DEBUG also traces env and the loader script (and what they run), in
# the same process until the exec that transfers control to lucent.
pending, lucent_pid, loaded = {}, None, []
for m in re.finditer(r"^\s*(\d+):\s+(calling init|transferring control): (\S+)$", env_log, re.M):
    pid, kind, path = m.groups()
    if kind == "calling init":
        (loaded if pid == lucent_pid else pending.setdefault(pid, [])).append(path)
    elif os.path.basename(path) == "lucent":
        lucent_pid, loaded = pid, pending.pop(pid, [])
    else:
        pending[pid] = []
loaded = sorted(set(loaded))
bundle_libs = set(os.listdir(os.path.join(B, "lib"))) | set(
    os.listdir(os.path.join(B, "glvnd")) if os.path.isdir(os.path.join(B, "glvnd")) else [])
libs = {"bundle": [], "glibc": [], "gl_driver": [], "system_other": []}
for p in loaded:
    name = os.path.basename(p)
    if p.startswith(B + os.sep):
        libs["bundle"].append(os.path.relpath(p, B))
    elif name in GLIBC:
        libs["glibc"].append(p)
    elif GL.match(name):
        libs["gl_driver"].append(p)
    else:
        libs["system_other"].append(p)
shadowed = sorted(p for p in loaded if not p.startswith(B + os.sep) and os.path.basename(p) in bundle_libs)
egl_loader = next((p for p in loaded if os.path.basename(p) == "libEGL.so.1"), None)
egl_vendor_libs = [p for p in loaded if re.match(r"libEGL_\w+\.so", os.path.basename(p))]
data_log = log("data")
data = [{"file": m.group(1), "ok": True} for m in re.finditer(r"^== (.*)$", data_log, re.M)]
if data and parts.get("data", {}).get("status") != "ok":
    data[-1]["ok"] = False
environment = part("environment",
                   renderer=rend.group(1) if rend else None, gl_version=rend.group(2) if rend else None,
                   egl_platform=rend.group(3) if rend else None, egl=egl.group(1) if egl else None,
                   egl_display=egl.group(2) if egl else None,
                   software=bool(rend and re.search(r"llvmpipe|softpipe|swrast|software", rend.group(0))),
                   egl_loader=egl_loader, egl_vendor_libraries=egl_vendor_libs, libraries=libs,
                   outside_bundle_shadowed=shadowed, data=data, data_status=parts.get("data", {}).get("status"))


# ---- compare
def compare_values(text):
    v = {}
    for line in text.splitlines():
        k, _, rest = line.partition(" ")
        if k and rest:
            v[k] = num(rest) if num(rest) is not None else rest.strip()
    return v


demos = {}
for d in DEMOS:
    v = compare_values(log("compare." + d))
    ref = compare_values(read(os.path.join(B, "reference", reference + d + ".txt")))
    ssim, rssim = v.get("SSIM"), ref.get("SSIM")
    delta = ssim - rssim if isinstance(ssim, float) and isinstance(rssim, float) else None
    demos[d] = part("compare." + d, size=v.get("size"), primitives=v.get("primitives"), ssim=ssim, rmse=v.get("RMSE"),
                    reference_ssim=rssim, reference_renderer=ref.get("renderer"), ssim_delta=delta,
                    within_0_001=abs(delta) <= 0.001 if delta is not None else None,
                    fourier_ms=v.get("wall_ms.fourier"), exact_ms=v.get("wall_ms.exact"),
                    fourier_gpu_ms=v.get("gpu_ms.fourier"), exact_gpu_ms=v.get("gpu_ms.exact"),
                    fourier_mib=v.get("memory_mib.fourier"), exact_mib=v.get("memory_mib.exact"),
                    fragments=v.get("fragments"), dropped_fragments=v.get("dropped_fragments"),
                    passes={k.split(".", 2)[1] + "." + k.split(".", 2)[2]: x for k, x in v.items()
                            if k.startswith("pass_ms.")})
compare = {"status": group([demos[d]["status"] for d in DEMOS]), "demos": demos}


# ---- bench
def bench_rows(text):
    rows, cols = [], None
    for line in text.splitlines():
        t = line.split()
        if t[:2] == ["dataset", "size"]:
            cols = t[5:t.index("gpu")]  # the passes, between "elements" and "gpu ms"
            continue
        if cols and len(t) == 5 + len(cols) + 9 and re.match(r"\d+x\d+$", t[1]):
            vals = [num(x) for x in t[5 + len(cols):]]
            rows.append({"dataset": t[0], "size": t[1], "method": t[2], "primitives": num(t[3]),
                         "elements": num(t[4]), "passes_ms": {c: num(x) for c, x in zip(cols, t[5:5 + len(cols)])
                                                             if num(x) is not None},
                         "gpu_ms": vals[0], "wall_ms": vals[1], "fps": vals[2], "pipeline_mib": vals[3],
                         "scene_mib": vals[4], "drawn": vals[5], "load_s": vals[6], "rss_mib": vals[7]})
    return rows


sets = [line.split("\t") for line in read(os.path.join(work, "sets.tsv")).splitlines() if line]
runs = {}
for key, spec in sets:
    text = log("bench." + key)
    rows = bench_rows(text)
    errors = re.findall(r"^lucent bench: (.*)$", text, re.M)
    runs[key] = part("bench." + key, spec=spec, rows=rows, errors=errors, gpu_memory=smi_peak("bench." + key))
    if runs[key]["status"] == "ok" and errors:
        runs[key]["status"] = "partial"
bench = {"status": group([r["status"] for r in runs.values()]), "sizes": sizes.split(","),
         "methods": ["fourier", "exact", "opaque"], "runs": runs}


def row(key, size, method):
    return next((r for r in runs.get(key, {}).get("rows", []) if r["size"] == size and r["method"] == method), None)


# ---- orbit, sessions
orbit = part("orbit", **json.loads(read(os.path.join(work, "orbit.json"), "{}") or "{}"))
sess = json.loads(read(os.path.join(work, "sessions.json"), "{}") or "{}")
rate = sess.get("rate") or 30
at_rate, keeps = 0, True
for r in sess.get("runs", []):  # the most sessions that, like every smaller count run, keep the rate
    keeps = keeps and r["per_session_frames_per_s"] >= 0.9 * rate
    if keeps:
        at_rate = r["sessions"]
sessions = part("sessions", **sess)
sessions["sessions_at_rate"] = at_rate if sess.get("runs") else None
sessions["criterion"] = "each session >= %.0f frames/s (90 %% of %g camera updates/s)" % (0.9 * rate, rate)

# ---- read-back and encode against the frame
big = sizes.split(",")[-1]
breakdown = {"bench": [], "orbit": None, "jpeg_encode": sess.get("jpeg_encode")}
for key in runs:
    r = row(key, big, "fourier")
    if r and r["wall_ms"]:
        rb = r["passes_ms"].get("readback")
        breakdown["bench"].append({"run": key, "size": big, "wall_ms": r["wall_ms"], "readback_ms": rb,
                                   "readback_share": rb / r["wall_ms"] if rb is not None else None})
mv = orbit.get("moving") or {}
if mv.get("count"):
    def mean(k):
        return (mv.get(k) or {}).get("mean")
    breakdown["orbit"] = {"size": mv.get("size"), "frames": mv.get("count"), "render_ms": mean("render_ms"),
                          "gpu_ms": mean("gpu_ms"), "readback_ms": mean("readback_ms"),
                          "encode_ms": mean("encode_ms"), "still": orbit.get("still_frame")}
    tot = (mean("render_ms") or 0) + (mean("encode_ms") or 0)
    if tot > 0:
        breakdown["orbit"]["readback_share"] = (mean("readback_ms") or 0) / tot
        breakdown["orbit"]["encode_share"] = (mean("encode_ms") or 0) / tot
breakdown["status"] = "ok" if breakdown["bench"] or breakdown["orbit"] else "not reached"


# ---- goals (issue 45) and the paper's figures (FOO, Table 1)
def goal(text, value, unit, limit, above=False):
    met = None if value is None or quick else (value >= limit if above else value <= limit)
    return {"goal": text, "value": value, "unit": unit, "met": met}


t1 = row("tornado-1M", "1000x1000", "fourier")
p16 = row("points-16M", "1000x1000", "fourier")
goals = [goal("1 M segments at 1000x1000: a Fourier frame <= 10 ms (wall, read-back included)",
              t1 and t1["wall_ms"], "ms", 10),
         goal("16 M points at 1000x1000: a Fourier frame <= 100 ms", p16 and p16["wall_ms"], "ms", 100),
         goal("an orbit at 1920x1080 >= 60 frames/s", orbit.get("frames_per_s") if not quick else None,
              "frames/s", 60, above=True)]
paper = {"source": "Baeza Rojo, Gross, Guenther, TVCG 2020 (FOO), Table 1",
         "tornado_1000x1000_ms": 1.46, "dark_sky_16_3M_points_ms": 106.7, "gpu": "Quadro P6000"}

report = {"schema": 1, "mode": "quick" if quick else "full", "started": started, "seconds": int(total),
          "budget_s": int(budget), "host": host,
          "bundle": {k: manifest.get(k) for k in ("created", "commit", "working_tree_changes", "binary", "glibc",
                                                  "glvnd", "python", "bytes")},
          "parts": {"environment": environment, "compare": compare, "bench": bench, "orbit": orbit,
                    "sessions": sessions, "breakdown": breakdown},
          "goals": goals, "paper": paper}
with open(os.path.join(out, "report.json"), "w") as f:
    json.dump(report, f, indent=1)


# ---- report.md
def fmt(x, spec="%.2f"):
    return "-" if x is None else (spec % x if isinstance(x, (int, float)) else str(x))


md = ["# Lucent GPU check (%s)" % report["mode"], ""]
gpu_line = "; ".join("GPU %s: %s, driver %s, %s MiB" % (
    g["index"], g["name"], g["driver"], fmt(g["memory_mib"], "%.0f")) for g in gpus) or "no nvidia-smi"
md += ["Started %s, %d s of a %s s budget. Host: %s, %s CPUs, %s GiB, %s. %s." % (
    started, int(total), budget, host["os"], host["cpus"], host["memory_gib"], host["cpu"], gpu_line), ""]
if quick:
    md += ["**Quick mode**: every part at tiny sizes (the part names give the full sizes); the figures test the "
           "script, they measure nothing.", ""]
md += ["Bundle: commit %s%s, glvnd %s, glibc %s (%s), websockets from %s." % (
    (manifest.get("commit") or "?")[:12],
    " with %d changed files" % manifest["working_tree_changes"] if manifest.get("working_tree_changes") else "",
    "packed" if (manifest.get("glvnd") or {}).get("packed") else "NOT packed (the host's)",
    "bundled" if host["bundle_env"].get("glibc_bundled") == "1" else "the host's",
    host["bundle_env"].get("glibc_host"), ws_from), ""]
md += ["## Device", "", "| | |", "|---|---|",
       "| renderer | %s |" % fmt(environment["renderer"]), "| OpenGL | %s |" % fmt(environment["gl_version"]),
       "| EGL | %s on %s |" % (fmt(environment["egl"]), fmt(environment["egl_display"])),
       "| platform | %s |" % fmt(environment["egl_platform"]),
       "| EGL loader | %s |" % fmt(environment["egl_loader"]),
       "| EGL vendor libraries | %s |" % (", ".join(egl_vendor_libs) or "-"),
       "| driver libraries | %s |" % (", ".join(os.path.basename(p) for p in libs["gl_driver"]) or "-"),
       "| bundle libraries loaded from elsewhere | %s |" % (", ".join(shadowed) or "none"),
       "| data files read | %s |" % (", ".join("%s%s" % (d["file"], "" if d["ok"] else " (FAILED)") for d in data)
                                    or "-"), ""]
md += ["## Runs", "", "| run | status | s | limit s | note |", "|---|---|---|---|---|"]
for name, p in parts.items():
    md.append("| %s | %s | %d | %d | %s |" % (name, p["status"], p["seconds"], p["limit_s"],
                                             (p["reason"] or "").replace("|", "/")))
md += ["", "## Goals", "", "| goal | measured | met |", "|---|---|---|"]
for g in goals:
    md.append("| %s | %s %s | %s |" % (g["goal"], fmt(g["value"]), g["unit"],
                                      {True: "yes", False: "NO", None: "-"}[g["met"]]))
if environment["software"]:
    md += ["", "The renderer is a software one (llvmpipe): these are not a GPU's figures."]
md += ["", "The paper (%s, %s): TORNADO %.2f ms at 1000x1000, DARK SKY 16.3 M points %.1f ms." % (
    paper["source"], paper["gpu"], paper["tornado_1000x1000_ms"], paper["dark_sky_16_3M_points_ms"]), ""]
md += ["## Fourier against exact (lucent compare, repeat %s)" % ("0" if quick else "3"), "",
       "| demo | size | SSIM | this host's | difference | within 0.001 | RMSE | fourier ms | exact ms | "
       "fourier MiB | exact MiB | fragments |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
for d in DEMOS:
    c = demos[d]
    md.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
        d if c["status"] == "ok" else "%s (%s)" % (d, c["status"]), fmt(c["size"]), fmt(c["ssim"], "%.4f"),
        fmt(c["reference_ssim"], "%.4f"), fmt(c["ssim_delta"], "%+.4f"),
        {True: "yes", False: "NO", None: "-"}[c["within_0_001"]], fmt(c["rmse"], "%.4f"), fmt(c["fourier_ms"]),
        fmt(c["exact_ms"]), fmt(c["fourier_mib"], "%.1f"), fmt(c["exact_mib"], "%.1f"), fmt(c["fragments"], "%.0f")))
md += ["", "The reference is `lucent compare` of the same binary where the bundle was made (%s)." % (
    demos["tornado"]["reference_renderer"] or "none packed"), ""]
md += ["## Per pass (lucent bench, ms a frame, mean of the timed frames)", ""]
for key, r in runs.items():
    md += ["### %s: `%s` (%s, %d s)" % (key, r["spec"], r["status"], r["seconds"]), ""]
    if r["rows"]:
        passes = []
        for x in r["rows"]:
            passes += [p for p in x["passes_ms"] if p not in passes]
        md += ["| size | method | primitives | " + " | ".join(passes) +
               " | gpu ms | wall ms | fps | pipeline MiB | scene MiB | drawn | load s |",
               "|" + "---|" * (len(passes) + 10)]
        for x in r["rows"]:
            md.append("| %s | %s | %.0f | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                x["size"], x["method"], x["primitives"] or 0,
                " | ".join(fmt(x["passes_ms"].get(p)) for p in passes), fmt(x["gpu_ms"]), fmt(x["wall_ms"]),
                fmt(x["fps"], "%.1f"), fmt(x["pipeline_mib"], "%.1f"), fmt(x["scene_mib"], "%.1f"),
                fmt(x["drawn"], "%.0f"), fmt(x["load_s"])))
    for e in r["errors"]:
        md.append("- error: %s" % e)
    if r["gpu_memory"]:
        md.append("- GPU memory used at most (nvidia-smi): " + ", ".join(
            "GPU %s %.0f of %.0f MiB" % (i, g["used_mib"], g["total_mib"] or 0) for i, g in r["gpu_memory"].items()))
    if r["reason"]:
        md.append("- %s" % r["reason"])
    md.append("")
md += ["## WebSocket orbit (tests/bench/browse_bench.py)", ""]
if orbit.get("frames_per_s") is not None:
    lat = orbit.get("input_to_frame_ms") or {}
    md += ["`%s` at %sx%s, camera updates at %s/s for %s s: **%.1f frames/s**, input-to-frame p50 %s ms, p95 %s ms "
           "(%s samples); first frame %s s after hello, the still %s s after the last input." % (
               orbit["dataset"], orbit["width"], orbit["height"], orbit["rate"], orbit["seconds"],
               orbit["frames_per_s"], fmt(lat.get("p50"), "%.0f"), fmt(lat.get("p95"), "%.0f"), lat.get("samples"),
               fmt(orbit.get("first_s")), fmt(orbit.get("still_s"))), ""]
else:
    md += ["%s: %s" % (orbit["status"], orbit.get("reason") or ""), ""]
md += ["## Sessions (tests/bench/server_bench.py)", ""]
if sess.get("runs"):
    md += ["`%s` at %sx%s, each session orbiting at %s camera updates/s for %s s. **%s session(s) keep %s**." % (
        sess["dataset"], sess["width"], sess["height"], sess["rate"], sess["seconds"], at_rate,
        sessions["criterion"]), "", "| sessions | frames/s | per session | latency p50 ms | p99 ms | render p50 ms | "
                                    "encode MP/s | stills |", "|---|---|---|---|---|---|---|---|"]
    for r in sess["runs"]:
        lat = r.get("latency_ms") or {}
        md.append("| %d | %.1f | %.1f | %s | %s | %s | %s | %s |" % (
            r["sessions"], r["frames_per_s"], r["per_session_frames_per_s"], fmt(lat.get("p50"), "%.0f"),
            fmt(lat.get("p99"), "%.0f"), fmt(r.get("render_ms_p50"), "%.1f"), fmt(r.get("encode_mp_per_s"), "%.0f"),
            ",".join(r.get("stills") or [])))
    md.append("")
else:
    md += ["%s: %s" % (sessions["status"], sessions.get("reason") or ""), ""]
md += ["## Read-back and encode", ""]
o = breakdown["orbit"]
if o:
    md += ["Orbit, moving frames (%s, %d frames), mean ms: render %s (GPU passes %s, read-back %s), JPEG encode %s; "
           "read-back is %s and encoding %s of render + encode." % (
               o["size"], o["frames"], fmt(o["render_ms"]), fmt(o["gpu_ms"]), fmt(o["readback_ms"]),
               fmt(o["encode_ms"]), fmt(100 * o.get("readback_share", 0), "%.0f %%"),
               fmt(100 * o.get("encode_share", 0), "%.0f %%")), ""]
    st = o.get("still") or {}
    if st:
        md += ["The still (%s): render %s ms, read-back %s ms, encode %s ms." % (
            st.get("size"), fmt(st.get("render_ms")), fmt(st.get("readback_ms")), fmt(st.get("encode_ms"))), ""]
for b in breakdown["bench"]:
    md.append("- bench %s, %s, fourier: read-back %s of %s ms (%s)" % (
        b["run"], b["size"], fmt(b["readback_ms"]), fmt(b["wall_ms"]),
        fmt(100 * b["readback_share"] if b["readback_share"] is not None else None, "%.1f %%")))
for e in breakdown["jpeg_encode"] or []:
    md.append("- JPEG encode %s quality %d: %.0f MP/s, %.1f ms a 1920x1080 frame" % (
        e["size"], e["quality"], e["mp_per_s"], 1920 * 1080 / 1e6 / e["mp_per_s"] * 1000))
md += ["", "Raw output of every run: logs.tar.gz (logs/NAME.log; NAME.smi are nvidia-smi samples)."]
with open(os.path.join(out, "report.md"), "w") as f:
    f.write("\n".join(md) + "\n")
PYEOF
say "wrote $out/report.md and report.json in $total s"
