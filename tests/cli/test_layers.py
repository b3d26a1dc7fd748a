#!/usr/bin/env python3
"""layers[] in request files (docs/ALGORITHM.md §24) through the command line, against the real daemon:
`lucent render --request` of two layers (the points demo and the tornado lines) draws the image POST
/api/v1/render answers for the same request (the daemon serving the same demos), and so does a plane file
as opaque context through the tornado; the two-layer image is neither layer's alone; `lucent compare`
draws the layers with Fourier and exact (SSIM >= 0.99, the issue's bound); `lucent movie` of the layers
starts with the layered frame. Bad layer specifications get errors naming the field: an unknown dataset
file (layers[1].dataset), a context layer of points (layers[0].role), a time window (time.window); the
flags of one dataset's mapping, --input and `lucent bench` are refused naming layers.
Usage: test_layers.py LUCENT"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "server"))
from lucent_server import Check, Server  # noqa: E402

lucent = sys.argv[1]
tmp = tempfile.mkdtemp()
check = Check()
N = 150  # the daemon's --demo-size, the command line's ?count=
SIZE = {"width": 160, "height": 128}
# Looking down -z at the tornado (the unit cube); the plane z = 0.5 covers its left half, through the middle.
CAMERA = {"position": [0.5, 0.5, 3.2], "focalPoint": [0.5, 0.5, 0.5], "viewUp": [0, 1, 0], "viewAngle": 30}
PLANE = os.path.join(tmp, "plane.obj")
with open(PLANE, "w") as f:
    f.write("v -0.2 -0.2 0.5\nv 0.5 -0.2 0.5\nv 0.5 1.2 0.5\nv -0.2 1.2 0.5\nf 1 2 3\nf 1 3 4\n")

POINTS = {"dataset": "demo:points", "style": {"pointSize": 5}}
TORNADO = {"dataset": "demo:tornado", "color": {"colormap": "coolwarm"}}
TWO = [POINTS, TORNADO]
CONTEXT = [{"dataset": "plane", "role": "context"}, TORNADO]
# What the daemon calls a dataset, the command line opens: the demos at the daemon's size, the file by path.
SPEC = {"demo:points": "demo:points?count=%d" % N, "demo:tornado": "demo:tornado?count=%d" % N, "plane": PLANE}


def cli_request(body):
    """The request with each layer's dataset as the command line names it."""
    b = dict(body)
    b["layers"] = [dict(l, dataset=SPEC[l["dataset"]]) for l in body["layers"]]
    return b


def run(args):
    return subprocess.run([lucent] + args, capture_output=True, text=True)


def cli_render(name, body, extra=()):
    path = os.path.join(tmp, name + ".json")
    with open(path, "w") as f:
        json.dump(cli_request(body), f)
    out = os.path.join(tmp, name + ".png")
    p = run(["render", "--request", path, "--out", out] + list(extra))
    return p, out


def ssim(a, b):
    """(SSIM, RMSE) of two image files by `lucent ssim`."""
    words = run(["ssim", a, b]).stdout.split()
    v = dict(zip(words[0::2], words[1::2]))
    return float(v.get("ssim", -1)), float(v.get("rmse", -1))


def http_png(srv, name, body):
    st, _, img = srv.request("POST", "/api/v1/render", body)
    path = os.path.join(tmp, name + ".png")
    with open(path, "wb") as f:
        f.write(img)
    return st, path


with Server(lucent, data=("demo:points", "demo:tornado", PLANE), demo_size=N) as srv:
    two = dict(SIZE, layers=TWO)
    p, cli_two = cli_render("two", two)
    check(p.returncode == 0 and "layer 1: demo:tornado" in p.stdout,
          "lucent render of two layers (rc %d): %s" % (p.returncode, (p.stdout.splitlines() or [""])[0] + p.stderr))
    st, http_two = http_png(srv, "http_two", two)
    s, e = ssim(cli_two, http_two) if p.returncode == 0 and st == 200 else (-1, -1)
    check(s >= 0.999, "the command line's two layers are the HTTP render's (SSIM %.6f, RMSE %.6f; HTTP %d)"
          % (s, e, st))
    for i in range(2):
        alone = dict(SIZE, layers=[dict(l, visible=(k == i)) for k, l in enumerate(TWO)])
        p, img = cli_render("alone%d" % i, alone)
        s, _ = ssim(cli_two, img) if p.returncode == 0 else (1, 0)
        check(p.returncode == 0 and s < 0.97, "layer %d alone differs from the two layers (SSIM %.4f)" % (i, s))

    ctx = dict(SIZE, layers=CONTEXT, camera=CAMERA)
    p, cli_ctx = cli_render("context", ctx)
    st, http_ctx = http_png(srv, "http_context", ctx)
    s, e = ssim(cli_ctx, http_ctx) if p.returncode == 0 and st == 200 else (-1, -1)
    check(s >= 0.999, "a plane file as opaque context: the command line draws the HTTP render (SSIM %.6f, RMSE "
          "%.6f; rc %d, HTTP %d) %s" % (s, e, p.returncode, st, p.stderr[-200:]))
    p, cli_see = cli_render("see_through", dict(ctx, layers=[dict(CONTEXT[0], role="transparent"), TORNADO]))
    s, _ = ssim(cli_ctx, cli_see) if p.returncode == 0 else (1, 0)
    check(p.returncode == 0 and s < 0.97, "the context plane differs from the same plane transparent (SSIM %.4f)" % s)

path = os.path.join(tmp, "two.json")  # as the command line names them
p = run(["compare", "--request", path, "--repeat", "0"])
got = dict(line.split(" ", 1) for line in p.stdout.splitlines() if " " in line)
s = float(got.get("SSIM", -1))
check(p.returncode == 0 and got.get("layers") == "2" and s >= 0.99,
      "lucent compare of the two layers: Fourier against exact SSIM %.4f >= 0.99 (rc %d) %s"
      % (s, p.returncode, p.stderr[-200:]))

movie = os.path.join(tmp, "movie.json")
with open(movie, "w") as f:
    json.dump({"request": cli_request({"layers": TWO}), "frames": 3, "fps": 3, "width": 160, "height": 128}, f)
p = run(["movie", movie, "-o", os.path.join(tmp, "layers.mp4")])
if "libavcodec" in p.stderr:
    print("skip lucent movie: built without libavcodec")
else:
    check(p.returncode == 0 and "3 frames" in p.stdout and "demo:points + demo:tornado" in p.stdout,
          "lucent movie of two layers (rc %d): %s" % (p.returncode, p.stdout.strip() or p.stderr[-300:]))
    if p.returncode == 0 and shutil.which("ffmpeg"):
        frame0 = os.path.join(tmp, "frame0.png")
        subprocess.run(["ffmpeg", "-v", "error", "-y", "-i", os.path.join(tmp, "layers.mp4"), "-frames:v", "1",
                        frame0], check=False)
        # Turntable frame 0 is the request's camera (none: fitted to both layers); H.264 loses a little.
        s, _ = ssim(frame0, cli_two) if os.path.exists(frame0) else (-1, -1)
        check(s >= 0.97, "the movie's first frame is the two-layer still (SSIM %.4f after H.264)" % s)

bad_layers = ((dict(SIZE, layers=[POINTS, TORNADO]), "layers[1].dataset", {1: os.path.join(tmp, "nope.ply")}),
              (dict(SIZE, layers=[dict(POINTS, role="context"), TORNADO]), "layers[0].role", {}),
              (dict(SIZE, layers=TWO, time={"window": [0, 1]}), "time.window", {}))
for body, field, replace in bad_layers:
    b = cli_request(body)
    for i, spec in replace.items():
        b["layers"][i]["dataset"] = spec
    with open(path, "w") as f:
        json.dump(b, f)
    p = run(["render", "--request", path, "--out", os.path.join(tmp, "bad.png")])
    check(p.returncode != 0 and field in p.stderr, "an error naming %s (rc %d): %s" % (field, p.returncode, p.stderr))
with open(path, "w") as f:
    json.dump(cli_request(two), f)
for args in (["render", "--request", path, "-o", os.path.join(tmp, "x.png"), "--colormap", "inferno"],
             ["render", "--request", path, "-o", os.path.join(tmp, "x.png"), "--input", "demo:points"],
             ["bench", "--request", path, "--frames", "1"]):
    p = run(args)
    check(p.returncode != 0 and "layers" in p.stderr,
          "%s %s refused naming layers (rc %d): %s" % (args[0], args[-2], p.returncode, p.stderr.strip()))

shutil.rmtree(tmp, ignore_errors=True)
check.done()
