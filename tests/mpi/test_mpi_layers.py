"""`mpirun -np N lucent render --mpi --request` of layers[] (docs/MPI.md "Layers") against one process
rendering the same request file: two transparent layers (the points demo and the tornado lines; one frame
and fading frames whose state spans both), a line file read in parts beside the tornado, a plane as opaque
context through the tornado (the plane alone on one rank: the other ranks take its depth from the
combination) and a curved surface as context shared between the ranks. Each within RMSE 1/255 and SSIM
0.99; in the context scene every pixel where the plane is in front of every line is the one-process pixel
exactly, and some lines lie in front of it. Bad layers fail on every rank naming the field, as in one
process: an unknown dataset file (layers[1].dataset), a context layer of points (layers[0].role).
Usage: test_mpi_layers.py LUCENT RANKS"""
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(__file__))
from line_files import write_all  # noqa: E402
from mpi_util import MAX_RMSE, mpirun, mpirun_env, read_png, rmse  # noqa: E402

lucent, ranks = sys.argv[1], int(sys.argv[2])
launcher = mpirun(ranks)
if not launcher:
    print("SKIP: mpirun not found (apt-get install openmpi-bin)")
    sys.exit(77)
env = mpirun_env()
tmp = tempfile.mkdtemp(prefix="lucent-mpi-layers-")
failures = []

# The plane z = 0.5 over the left half of the tornado (the unit cube), looked at down -z as in
# tests/cli/test_layers.py: two triangles, one element, so one rank holds all of it.
PLANE = os.path.join(tmp, "plane.obj")
with open(PLANE, "w") as f:
    f.write("v -0.2 -0.2 0.5\nv 0.5 -0.2 0.5\nv 0.5 1.2 0.5\nv -0.2 1.2 0.5\nf 1 2 3\nf 1 3 4\n")
CAMERA = {"position": [0.5, 0.5, 3.2], "focalPoint": [0.5, 0.5, 0.5], "viewUp": [0, 1, 0], "viewAngle": 30}
SIZE = {"width": 160, "height": 128}
POINTS = {"dataset": "demo:points?count=5000", "style": {"pointSize": 4}}
TORNADO = {"dataset": "demo:tornado?count=150", "color": {"colormap": "coolwarm"}}
LINES = write_all(tmp, 300)["tck"]  # read in parts under --mpi
CONTEXT = dict(SIZE, camera=CAMERA, layers=[{"dataset": PLANE, "role": "context"}, TORNADO])

# (name, request, flags)
CASES = [
    ("two", dict(SIZE, layers=[POINTS, TORNADO]), []),
    ("two-fading", dict(SIZE, layers=[POINTS, TORNADO]), ["--frames", "3", "--fade", "0.15"]),
    ("file-in-parts", dict(SIZE, layers=[{"dataset": LINES}, TORNADO]), []),
    ("context", CONTEXT, []),
    # A curved surface as context, shared between the ranks: where its parts on two ranks overlap, the
    # nearest one's colour (surface levels of detail are simplified per shard: every triangle here).
    ("surface-context", dict(SIZE, layers=[{"dataset": "demo:surface", "role": "context"}, TORNADO],
                             params={"lod": 0}), []),
]


def request_file(name, body):
    path = os.path.join(tmp, name + ".json")
    with open(path, "w") as f:
        json.dump(body, f)
    return path


def render(name, body, flags=(), n=1):
    """(process, image path) of `lucent render --request` in one process (n = 1) or over the ranks. Float vertex
    buffers on both sides: compact positions quantize a line shard's boundary chunk over fewer vertices than one
    process does (docs/MPI.md "Limits"), which with 3 ranks moved one line pixel of the context scene."""
    out = os.path.join(tmp, "%s-%s.png" % (name, n))
    cmd = [lucent, "render", "--request", request_file(name, body), "--out", out, "--exact-positions"] + list(flags)
    if n > 1:
        return subprocess.run(launcher + cmd + ["--mpi"], capture_output=True, text=True, env=env, timeout=300), out
    return subprocess.run(cmd, capture_output=True, text=True, timeout=300), out


def ssim(a, b):
    words = subprocess.run([lucent, "ssim", a, b], capture_output=True, text=True).stdout.split()
    return float(dict(zip(words[0::2], words[1::2])).get("ssim", -1))


images = {}
for name, body, flags in CASES:
    (a, one), (b, many) = render(name, body, flags), render(name, body, flags, ranks)
    if a.returncode != 0 or b.returncode != 0:
        failures.append("%s: exit %d / %d: %s %s" % (name, a.returncode, b.returncode, a.stderr[-300:],
                                                      b.stderr[-600:]))
        continue
    if "layer 1: demo:tornado" not in b.stdout or "rank %d of %d" % (ranks - 1, ranks) not in b.stdout:
        failures.append("%s: no layer or per-rank report in %r" % (name, b.stdout[:400]))
    e, s = rmse(lucent, one, many), ssim(one, many)
    print("%-14s %d ranks: rmse %.6f (limit %.6f), ssim %.6f" % (name, ranks, e, MAX_RMSE, s))
    if e > MAX_RMSE or s < 0.99:
        failures.append("%s: rmse %.6f (limit 1/255), ssim %.6f (limit 0.99)" % (name, e, s))
    if name == "file-in-parts" and "its share read from the file" not in b.stdout:
        failures.append("file-in-parts: the line file was not read in parts: %r" % b.stdout[:400])
    images[name] = (one, many)

# The context scene by pixels: where the plane alone differs from the background it covers the pixel; where
# the one-process scene shows the plane alone's pixel, the plane is in front of every line there, and the
# ranks must give that pixel exactly (its shaded colour entered once, its depth hid the lines behind it on
# every rank).
if "context" in images:
    alone = dict(CONTEXT, layers=[CONTEXT["layers"][0], dict(TORNADO, visible=False)])
    p, plane_path = render("plane-alone", alone)
    if p.returncode != 0:
        failures.append("plane alone: exit %d: %s" % (p.returncode, p.stderr[-300:]))
    else:
        w, h, plane = read_png(plane_path)
        _, _, one = read_png(images["context"][0])
        _, _, many = read_png(images["context"][1])
        background = plane[w - 1]  # the top right corner: right of the plane
        covered = [i for i in range(w * h) if plane[i] != background]
        front = [i for i in covered if one[i] == plane[i]]
        behind = [i for i in covered if one[i] != plane[i]]
        wrong = [i for i in front if many[i] != one[i]]
        print("context: %d pixels covered by the plane, %d with the plane in front, %d with lines in front; "
              "%d of the first differ over %d ranks" % (len(covered), len(front), len(behind), len(wrong), ranks))
        if len(covered) < w * h // 5 or len(front) < len(covered) // 4 or len(behind) < 50:
            failures.append("context: the plane covers %d pixels, in front at %d, lines in front at %d: not the "
                            "scene this test expects" % (len(covered), len(front), len(behind)))
        if wrong:
            i = wrong[0]
            failures.append("context: %d pixels where the plane is in front differ over the ranks, e.g. (%d, %d): "
                            "%s, one process %s" % (len(wrong), i % w, i // w, many[i], one[i]))

# Bad layers: the same errors naming the field as in one process, and every rank exits.
BAD = [
    ("unknown-dataset", dict(SIZE, layers=[POINTS, {"dataset": os.path.join(tmp, "missing.ply")}]),
     "layers[1].dataset"),
    ("context-points", dict(SIZE, layers=[dict(POINTS, role="context"), TORNADO]), "layers[0].role"),
]
for name, body, field in BAD:
    (a, _), (b, _) = render(name, body), render(name, body, (), ranks)
    if a.returncode == 0 or b.returncode == 0 or field not in a.stderr or field not in b.stderr:
        failures.append("%s: exit %d / %d, one process %r, %d ranks %r" % (name, a.returncode, b.returncode,
                                                                        a.stderr[-300:], ranks, b.stderr[-400:]))
    else:
        print("%s: refused naming %s in one process and over %d ranks: ok" % (name, field, ranks))

for f in failures:
    print("FAIL:", f, file=sys.stderr)
sys.exit(1 if failures else 0)
