#!/usr/bin/env python3
"""Time windows on a LAMMPS dump (docs/ALGORITHM.md §26) through `lucent render`: a
window [50, 120] over the dump's TIMESTEPs (the reader's per-vertex `timestep`) draws
what the same dump cut to the frames 50..120 draws (opaque lines, one camera; SSIM >=
0.99 unshaded), and clearly not the whole dump; the
errors name time.window (t0 > t1) and time.attribute (an attribute the dump lacks).
Usage: test_time.py LUCENT"""
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

lucent = sys.argv[1]
tmp = tempfile.mkdtemp()
failures = []


def dump(path, frames):
    """30 atoms moving on straight lines (so that a cut end's ribbon tangent is the
    window's: only the segments differ); TIMESTEP = 10 x frame."""
    with open(path, "w") as f:
        for fr in frames:
            f.write("ITEM: TIMESTEP\n%d\nITEM: NUMBER OF ATOMS\n30\nITEM: BOX BOUNDS ff ff ff\n" % (fr * 10))
            f.write("-20 20\n-20 20\n-20 20\nITEM: ATOMS id type xu yu zu\n")
            for a in range(30):
                ang, r = a * 0.7, 1 + 0.6 * fr
                f.write("%d 1 %.4f %.4f %.4f\n" % (a + 1, r * math.cos(ang), r * math.sin(ang), 0.2 * fr + 0.1 * a))


def render(name, dataset, extra):
    req = {"dataset": dataset, "width": 200, "height": 200, "method": "opaque",
           "camera": {"position": [0, 0, 60], "focalPoint": [0, 0, 3], "viewUp": [0, 1, 0], "viewAngle": 30},
           "color": {"attribute": "type", "range": [0, 2]}, "style": {"lineWidth": 0.3, "shading": "none"}}
    req.update(extra)
    path = os.path.join(tmp, name + ".json")
    with open(path, "w") as f:
        json.dump(req, f)
    out = os.path.join(tmp, name + ".png")
    p = subprocess.run([lucent, "render", "--request", path, "--out", out], capture_output=True, text=True)
    return p, out


def ssim(a, b):
    p = subprocess.run([lucent, "ssim", a, b], capture_output=True, text=True)
    if p.returncode != 0:
        failures.append("lucent ssim: " + p.stderr.strip())
        return 0.0
    # "SSIM 0.999 RMSE ..." or JSON; take the first number after "SSIM".
    words = p.stdout.replace(",", " ").replace(":", " ").split()
    for i, w in enumerate(words):
        if w.strip('"').lower() == "ssim" and i + 1 < len(words):
            return float(words[i + 1])
    failures.append("no SSIM in: " + p.stdout)
    return 0.0


whole, cut = os.path.join(tmp, "whole.dump"), os.path.join(tmp, "cut.dump")
dump(whole, range(20))
dump(cut, range(5, 13))  # TIMESTEPs 50..120

p, windowed = render("windowed", whole, {"time": {"window": [50, 120]}})
if p.returncode == 77 or "OpenGL" in p.stderr and p.returncode != 0:
    print(p.stderr)
    sys.exit(77 if os.environ.get("CI") != "true" else 1)
if p.returncode != 0:
    failures.append("windowed render: " + p.stderr.strip())
p2, reference = render("cut", cut, {})
p3, full = render("full", whole, {})
if p2.returncode != 0 or p3.returncode != 0:
    failures.append("reference renders: " + p2.stderr.strip() + p3.stderr.strip())
if not failures:
    s_cut, s_full = ssim(windowed, reference), ssim(windowed, full)
    print("windowed vs cut dump SSIM %.5f, vs whole dump %.5f" % (s_cut, s_full))
    if s_cut < 0.99:
        failures.append("the window draws other than the cut dump (SSIM %.5f)" % s_cut)
    if s_full > 0.95:
        failures.append("the window draws like the whole dump (SSIM %.5f)" % s_full)

for extra, field in (({"time": {"window": [120, 50]}}, "time.window"),
                     ({"time": {"window": [0, 100], "attribute": "clock"}}, "time.attribute")):
    p, _ = render("bad", whole, extra)
    print("error:", p.stderr.strip())
    if p.returncode == 0 or field not in p.stderr:
        failures.append("%s: expected an error naming %s, got rc %d: %s" % (extra, field, p.returncode, p.stderr))

for f in failures:
    print("FAIL:", f)
shutil.rmtree(tmp, ignore_errors=True)
sys.exit(1 if failures else 0)
