#!/usr/bin/env python3
"""Streamline sets asked for by a request, through the command line (docs/ALGORITHM.md §22): `lucent
render --request` whose dataset names a vector field draws the set its streamlines section describes,
the same PNG byte for byte as the load-time set of the same spec (--input streamlines:FIELD?...) and
the image POST /api/v1/render answers for the same request; errors name the field (a section on a
loaded dataset, a rake of one point); `lucent movie` of that request renders its frames.
Usage: test_streamlines.py LUCENT"""
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
SIZE = {"width": 96, "height": 80}
CAM = {"position": [-0.5, 0, 3], "focalPoint": [-0.5, 0, 0], "viewUp": [0, 1, 0]}
SECTION = {"seeding": "rake", "seeds": [[-0.5, -0.5, 0], [-0.5, 0.5, 0]], "count": 5, "length": 0.4,
           "direction": "both"}
SPEC = "streamlines:demo:shear-flow?seeding=rake&seeds=-0.5,-0.5,0;-0.5,0.5,0&count=5&length=0.4&direction=both"


def run(args):
    return subprocess.run([lucent] + args, capture_output=True, text=True)


def write(name, body):
    path = os.path.join(tmp, name + ".json")
    with open(path, "w") as f:
        json.dump(body, f)
    return path


def cli_render(name, body, *flags):
    out = os.path.join(tmp, name + ".png")
    return run(["render", "--request", write(name, dict(SIZE, camera=CAM, **body)), "--out", out] + list(flags)), out


def read(path):
    with open(path, "rb") as f:
        return f.read()


p, req_img = cli_render("request", {"dataset": "demo:shear-flow", "streamlines": SECTION})
q, spec_img = cli_render("spec", {}, "--input", SPEC)
same = p.returncode == 0 and q.returncode == 0 and read(req_img) == read(spec_img)
check(same, "the request's set renders the load-time spec's PNG byte for byte (rc %d, %d) %s"
      % (p.returncode, q.returncode, (p.stderr + q.stderr)[-300:]))

with Server(lucent, data=("demo:shear-flow",)) as srv:
    st, _, img = srv.request("POST", "/api/v1/render", dict(SIZE, camera=CAM, dataset="demo:shear-flow",
                                                            streamlines=SECTION))
    http_img = os.path.join(tmp, "http.png")
    with open(http_img, "wb") as f:
        f.write(img)
    words = run(["ssim", req_img, http_img]).stdout.split() if st == 200 else []
    s = float(dict(zip(words[0::2], words[1::2])).get("ssim", -1))
    check(s >= 0.999, "and the HTTP render of the same request (SSIM %.6f, HTTP %d)" % (s, st))

for name, body, field in (("loaded", {"dataset": "demo:tornado?count=50", "streamlines": {"count": 5}},
                           "streamlines.count"),
                          ("rake", {"dataset": "demo:shear-flow", "streamlines": {"seeding": "rake",
                                                                                  "seeds": [[0, 0, 0]]}},
                           "streamlines.seeds")):
    p, _ = cli_render(name, body)
    check(p.returncode != 0 and field in p.stderr, "%s: refused naming %s (rc %d) %s"
          % (name, field, p.returncode, p.stderr.strip()[-200:]))

movie = write("movie", {"request": dict(dataset="demo:shear-flow", streamlines=SECTION), "frames": 2, "fps": 2,
                        **SIZE})
p = run(["movie", movie, "-o", os.path.join(tmp, "m.mp4")])
if "libavcodec" in p.stderr:
    print("skip lucent movie: built without libavcodec")
else:
    check(p.returncode == 0 and "2 frames" in p.stdout,
          "lucent movie of the field's set (rc %d): %s" % (p.returncode, p.stdout.strip() or p.stderr[-300:]))

shutil.rmtree(tmp, ignore_errors=True)
check.done()
