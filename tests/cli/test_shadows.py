#!/usr/bin/env python3
"""Ground shadows and smart transparency (docs/ALGORITHM.md §29) through the command line, against
the real daemon: `lucent render --request` with style.shadow, style.shadowColored and
style.smartTransparency draws the image POST /api/v1/render answers for the same request (the daemon
serving the same demo), which differs from the plain one; `lucent movie` of that request starts with
that still; errors name the field: a shadow with the exact method, a shadow nothing receives.
Usage: test_shadows.py LUCENT"""
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
STYLE = {"shadow": 0.8, "shadowColored": True, "smartTransparency": 0.7}


def run(args):
    return subprocess.run([lucent] + args, capture_output=True, text=True)


def write(name, body):
    path = os.path.join(tmp, name + ".json")
    with open(path, "w") as f:
        json.dump(body, f)
    return path


def cli_render(name, style, **extra):
    body = dict(SIZE, dataset="demo:tornado?count=%d" % N, style=style, **extra)
    out = os.path.join(tmp, name + ".png")
    return run(["render", "--request", write(name, body), "--out", out]), out


def ssim(a, b):
    words = run(["ssim", a, b]).stdout.split()
    v = dict(zip(words[0::2], words[1::2]))
    return float(v.get("ssim", -1)), float(v.get("rmse", -1))


with Server(lucent, data=("demo:tornado",), demo_size=N) as srv:
    p, cli_img = cli_render("aids", STYLE)
    st, _, img = srv.request("POST", "/api/v1/render", dict(SIZE, dataset="demo:tornado", style=STYLE))
    http_img = os.path.join(tmp, "http.png")
    with open(http_img, "wb") as f:
        f.write(img)
    s, e = ssim(cli_img, http_img) if p.returncode == 0 and st == 200 else (-1, -1)
    check(s >= 0.999, "lucent render with a shadow and outlines draws the HTTP render (SSIM %.6f, RMSE %.6f; rc %d, "
          "HTTP %d) %s" % (s, e, p.returncode, st, p.stderr[-200:]))
    p, plain = cli_render("plain", {})
    s, _ = ssim(cli_img, plain) if p.returncode == 0 else (1, 0)
    check(p.returncode == 0 and s < 0.98, "and differs from the plain render (SSIM %.4f)" % s)

for name, style, extra, field in (("exact", {"shadow": 0.5}, {"method": "exact"}, "style.shadow"),
                                  ("nothing", {"shadow": 0.5, "ground": "off"}, {}, "style.shadow")):
    p, _ = cli_render(name, style, **extra)
    check(p.returncode != 0 and field in p.stderr, "%s: refused naming %s (rc %d) %s"
          % (name, field, p.returncode, p.stderr.strip()[-200:]))

movie = write("movie", {"request": dict(dataset="demo:tornado?count=%d" % N, style=STYLE), "frames": 2, "fps": 2,
                        **SIZE})
p = run(["movie", movie, "-o", os.path.join(tmp, "m.mp4")])
if "libavcodec" in p.stderr:
    print("skip lucent movie: built without libavcodec")
else:
    check(p.returncode == 0 and "2 frames" in p.stdout,
          "lucent movie with them (rc %d): %s" % (p.returncode, p.stdout.strip() or p.stderr[-300:]))
    if p.returncode == 0 and shutil.which("ffmpeg"):
        frame0 = os.path.join(tmp, "frame0.png")
        subprocess.run(["ffmpeg", "-v", "error", "-y", "-i", os.path.join(tmp, "m.mp4"), "-frames:v", "1", frame0],
                       check=False)
        s, _ = ssim(frame0, cli_img) if os.path.exists(frame0) else (-1, -1)
        s0, _ = ssim(frame0, plain) if os.path.exists(frame0) else (-1, -1)
        check(s >= 0.97 and s > s0, "its first frame is the still with them (SSIM %.4f after H.264; plain %.4f)"
              % (s, s0))

shutil.rmtree(tmp, ignore_errors=True)
check.done()
