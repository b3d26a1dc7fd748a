"""`mpirun -np N lucent render --mpi` against one process: lines, points and
surfaces, fading off (one frame) and on (several frames with --fade), the
per-pixel depth range and the direct method, equalized colour, line files and a point cloud
that each rank reads only its share of, RMS difference <= 1/255 and the
same visibility report (within 0.01); a rank
that cannot load its shard and a method that cannot be split fail clearly.
Usage: test_mpi_render.py LUCENT RANKS"""
import os
import re
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(__file__))
from mpi_util import MAX_RMSE, mpirun, mpirun_env, rmse  # noqa: E402

lucent, ranks = sys.argv[1], int(sys.argv[2])
launcher = mpirun(ranks)
if not launcher:
    print("SKIP: mpirun not found (apt-get install openmpi-bin)")
    sys.exit(77)
env = mpirun_env()
tmp = tempfile.mkdtemp(prefix="lucent-mpi-")
failures = []

equalize = os.path.join(tmp, "equalize.json")
with open(equalize, "w") as f:
    f.write('{"color": {"equalize": true, "attribute": "velocity"}}')

# (name, flags): every case renders 160x120 in one process and over `ranks`.
CASES = [
    ("tornado", ["--dataset", "demo:tornado?count=120"]),
    ("tornado-fading", ["--dataset", "demo:tornado?count=120", "--frames", "4", "--fade", "0.15"]),
    ("tornado-pixel-range", ["--dataset", "demo:tornado?count=120", "--depth-range", "pixel"]),
    ("abc", ["--dataset", "demo:abc?count=300"]),
    ("abc-direct", ["--dataset", "demo:abc?count=300", "--method", "direct"]),
    ("points", ["--dataset", "demo:points?count=20000"]),
    ("points-fading", ["--dataset", "demo:points?count=20000", "--frames", "3", "--fade", "0.15"]),
    # Surface levels of detail are simplified per shard (docs/MPI.md): every triangle here.
    ("surface", ["--dataset", "demo:surface", "--lod", "0"]),
    ("surface-fading", ["--dataset", "demo:surface", "--frames", "3", "--fade", "0.15", "--lod", "0"]),
    # color.equalize: the ranks add their colour histograms (docs/ALGORITHM.md section 19).
    ("tornado-equalize", ["--dataset", "demo:tornado?count=120", "--request", equalize]),
    ("tornado-equalize-fading", ["--dataset", "demo:tornado?count=120", "--request", equalize, "--frames", "3",
                                 "--fade", "0.15"]),
]
for name, flags in CASES:
    one, many = os.path.join(tmp, name + "-1.png"), os.path.join(tmp, name + "-n.png")
    common = ["render", "--size", "160x120"] + flags
    t0 = time.time()
    a = subprocess.run([lucent] + common + ["--out", one], capture_output=True, text=True)
    t1 = time.time()
    b = subprocess.run(launcher + [lucent] + common + ["--mpi", "--out", many], capture_output=True, text=True,
                       env=env, timeout=300)
    t2 = time.time()
    if a.returncode != 0 or b.returncode != 0:
        failures.append("%s: exit %d / %d: %s %s" % (name, a.returncode, b.returncode, a.stderr[-300:],
                                                      b.stderr[-600:]))
        continue
    if "rank %d of %d" % (ranks - 1, ranks) not in b.stdout:
        failures.append("%s: no per-rank memory report in %r" % (name, b.stdout[:300]))
    vis = [re.search(r"top decile alpha ([0-9.]+), bottom half alpha ([0-9.]+)", o.stdout) for o in (a, b)]
    if all(vis) and max(abs(float(vis[0].group(k)) - float(vis[1].group(k))) for k in (1, 2)) > 0.01:
        failures.append("%s: visibility report differs: %s vs %s" % (name, vis[0].group(0), vis[1].group(0)))
    e = rmse(lucent, one, many)
    print("%-20s %d ranks: rmse %.6f (limit %.6f)  1 process %.1f s, %d ranks %.1f s" %
          (name, ranks, e, MAX_RMSE, t1 - t0, ranks, t2 - t1))
    if e > MAX_RMSE:
        failures.append("%s: rmse %.6f > 1/255" % (name, e))

# Line files in .binlines, .tck, .trk, .trx, .nc and .vtk and a PLY point cloud: each rank reads only its share
# (docs/MPI.md "Loading"). Against one process, and bit for bit against the
# ranks reading the whole file and keeping their shards (LUCENT_MPI_READ=whole),
# since both ways must give every rank the same lines, statistics and elements.
from line_files import write_all  # noqa: E402
files = write_all(tmp, 300)
# A point cloud as PLY (points alone): read in parts too.
files["ply"] = os.path.join(tmp, "points.ply")
subprocess.run([lucent, "gen", "points", "-o", files["ply"], "--count", "20000"], check=True, capture_output=True)
# Polylines as VTK (parsed whole, only the share's lines kept).
files["vtk"] = os.path.join(tmp, "tornado.vtk")
subprocess.run([lucent, "gen", "tornado", "-o", files["vtk"], "--count", "120"], check=True, capture_output=True)
# NetCDF trajectories: the loaders' committed case (three trajectories, one cut short, one dropped).
files["nc"] = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "loaders", "nc", "valid",
                           "trajectories.nc")
PART_CASES = [(ext, ["--dataset", path]) for ext, path in sorted(files.items())]
PART_CASES += [("trk-fading-elements", ["--dataset", files["trk"], "--frames", "3", "--fade", "0.15",
                                        "--elements", "700"]),
               ("binlines-importance", ["--dataset", files["binlines"], "--importance", "speed"])]
for name, flags in PART_CASES:
    one, parts, whole = (os.path.join(tmp, "file-%s-%s.png" % (name, k)) for k in ("1", "parts", "whole"))
    common = ["render", "--size", "160x120"] + flags
    a = subprocess.run([lucent] + common + ["--out", one], capture_output=True, text=True)
    b = subprocess.run(launcher + [lucent] + common + ["--mpi", "--out", parts], capture_output=True, text=True,
                       env=env, timeout=300)
    c = subprocess.run(launcher + [lucent] + common + ["--mpi", "--out", whole], capture_output=True, text=True,
                       env=dict(env, LUCENT_MPI_READ="whole"), timeout=300)
    if a.returncode or b.returncode or c.returncode:
        failures.append("%s: exit %d / %d / %d: %s %s %s" % (name, a.returncode, b.returncode, c.returncode,
                                                            a.stderr[-300:], b.stderr[-600:], c.stderr[-300:]))
        continue
    read = [line for line in b.stdout.splitlines() if "rank %d of %d" % (ranks - 1, ranks) in line]
    if not read or "its share read from the file" not in read[0]:
        failures.append("%s: no report of a share read from the file in %r" % (name, b.stdout[:400]))
    e1, e2 = rmse(lucent, one, parts), rmse(lucent, whole, parts)
    print("%-20s %d ranks reading parts: rmse %.6f against one process, %.6f against reading whole" %
          (name, ranks, e1, e2))
    if e1 > MAX_RMSE or e2 != 0:
        failures.append("%s: rmse %.6f against one process (limit 1/255), %.6f against reading whole (must be 0)" %
                        (name, e1, e2))

# Bad input read in parts: a budget beyond the segments names the field on
# every rank, as one process does.
r = subprocess.run(launcher + [lucent, "render", "--mpi", "--dataset", files["tck"], "--size", "64x64",
                               "--elements", "16000000", "--out", os.path.join(tmp, "z.png")],
                   capture_output=True, text=True, env=env, timeout=120)
if r.returncode == 0 or "elements" not in r.stderr or "every rank exits" not in r.stderr:
    failures.append("elements beyond the segments: exit %d, stderr %r" % (r.returncode, r.stderr[-400:]))
else:
    print("elements beyond the segments refused on every rank: ok")

# Ranks given different files to read in parts refuse before reading (MPMD).
cmd = launcher[:-1] + [str(ranks - 1), lucent, "render", "--mpi", "--dataset", files["trk"], "--size", "64x64",
                       "--out", os.path.join(tmp, "w.png"), ":", "-np", "1", lucent, "render", "--mpi", "--dataset",
                       files["tck"], "--size", "64x64", "--out", os.path.join(tmp, "w.png")]
r = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=120)
if r.returncode == 0 or "ranks see different datasets" not in r.stderr or "helices.tck" not in r.stderr:
    failures.append("different files in parts: exit %d, stderr %r" % (r.returncode, r.stderr[-400:]))
else:
    print("different files to read in parts refused on every rank: ok")

# A method whose compositing is not a sum is refused by name on every rank.
r = subprocess.run(launcher + [lucent, "render", "--mpi", "--dataset", "demo:points?count=2000", "--size", "64x64",
                               "--method", "exact", "--out", os.path.join(tmp, "x.png")],
                   capture_output=True, text=True, env=env, timeout=120)
if r.returncode == 0 or "cannot be split over processes" not in r.stderr:
    failures.append("exact method: exit %d, stderr %r" % (r.returncode, r.stderr[-400:]))
else:
    print("exact method refused: ok")

# A rank that cannot load its shard (MPMD: the last rank gets a missing file):
# a message naming the rank and the file, and every rank exits.
missing = os.path.join(tmp, "missing.ply")
cmd = launcher[:-1] + [str(ranks - 1), lucent, "render", "--mpi", "--dataset", "demo:points?count=2000",
                       "--size", "64x64", "--out", os.path.join(tmp, "y.png"), ":", "-np", "1", lucent, "render",
                       "--mpi", "--dataset", missing, "--size", "64x64", "--out", os.path.join(tmp, "y.png")]
t0 = time.time()
r = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=120)
msg = r.stderr
if r.returncode == 0 or ("rank %d" % (ranks - 1)) not in msg or "missing.ply" not in msg:
    failures.append("missing shard: exit %d, stderr %r" % (r.returncode, msg[-600:]))
else:
    print("missing shard on rank %d: every rank exited after %.1f s: ok" % (ranks - 1, time.time() - t0))

for f in failures:
    print("FAIL:", f, file=sys.stderr)
sys.exit(1 if failures else 0)
