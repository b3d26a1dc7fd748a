"""`mpirun -np N lucent render --mpi --request` with ground shadows and smart transparency
(docs/ALGORITHM.md §29) against one process rendering the same request file: the ranks sum the light's
map as they sum P4 (every rank's context needs every caster), so the image is the one-process image
within RMSE 1/255, and it differs from the plain render (the shadow is drawn, not dropped).
Usage: test_mpi_shadows.py LUCENT RANKS"""
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(__file__))
from mpi_util import MAX_RMSE, mpirun, mpirun_env, rmse  # noqa: E402

lucent, ranks = sys.argv[1], int(sys.argv[2])
launcher = mpirun(ranks)
if not launcher:
    print("SKIP: mpirun not found (apt-get install openmpi-bin)")
    sys.exit(77)
env = mpirun_env()
tmp = tempfile.mkdtemp(prefix="lucent-mpi-shadows-")
failures = []
BASE = {"dataset": "demo:tornado?count=150", "width": 160, "height": 128}


def render(name, style, mpi):
    req = os.path.join(tmp, name + ".json")
    with open(req, "w") as f:
        json.dump(dict(BASE, style=style), f)
    out = os.path.join(tmp, name + ("_mpi" if mpi else "") + ".png")
    cmd = (launcher + [lucent, "render", "--mpi"]) if mpi else [lucent, "render"]
    p = subprocess.run(cmd + ["--request", req, "--out", out], capture_output=True, text=True, env=env, timeout=600)
    if p.returncode != 0:
        failures.append("%s%s: rc %d %s" % (name, " --mpi" if mpi else "", p.returncode, p.stderr[-300:]))
    return out


style = {"shadow": 0.8, "shadowColored": True, "smartTransparency": 0.7}
one, many = render("aids", style, False), render("aids", style, True)
plain = render("plain", {}, False)
if not failures:
    e, e_plain = rmse(lucent, one, many), rmse(lucent, one, plain)
    print("%d ranks against one process: RMSE %.6f (bound %.6f); one process against the plain render %.4f"
          % (ranks, e, MAX_RMSE, e_plain))
    if e > MAX_RMSE:
        failures.append("%d ranks differ from one process: RMSE %.6f" % (ranks, e))
    if e_plain < 10 * MAX_RMSE:
        failures.append("the shadow and outlines change nothing (RMSE %.6f to the plain render)" % e_plain)
for f in failures:
    print("FAIL: " + f)
print("%d failed" % len(failures))
sys.exit(1 if failures else 0)
