"""Vector fields through the daemon: a demo field and a gridded .vtk file in
/api/v1/datasets ("fields", beside the scene datasets) and by name, a field
.vtk and a NetCDF u/v/w grid inside a --data folder, and a bad field file
refused at start-up naming the file and the line; a streamline set traced from
a field at start served as a line dataset, and bad set specs refused naming
their key."""
import json
import os
import shutil
import subprocess
import sys
import tempfile

from lucent_server import Check, Server

binary = sys.argv[1]
check = Check()
here = os.path.dirname(os.path.abspath(__file__))
fields = os.path.join(here, "..", "data", "fields")
grid = os.path.join(fields, "valid", "rectilinear_be.vtk")
tmp = tempfile.mkdtemp()
folder = os.path.join(tmp, "data")
os.mkdir(folder)
shutil.copy(os.path.join(fields, "valid", "uniform_ascii.vtk"), os.path.join(folder, "gusts.vtk"))
shutil.copy(os.path.join(here, "..", "fuzz", "corpus", "nc_field", "wind_time.nc"), os.path.join(folder, "wind.nc"))

with Server(binary, data=("demo:points", grid, "demo:abc-flow", folder), demo_size=500) as srv:
    st, _, body = srv.json("GET", "/api/v1/datasets")
    names = [d["name"] for d in body.get("datasets", [])]
    check(st == 200 and names == ["demo:points"], "the scene datasets are unchanged: %r" % names)
    fl = {f["name"]: f for f in body.get("fields", [])}
    check(sorted(fl) == ["demo:abc-flow", "gusts", "rectilinear_be", "wind"], "four fields listed: %r" % sorted(fl))
    r = fl.get("rectilinear_be", {})
    check(r.get("grid") == {"type": "rectilinear", "dims": [3, 3, 2]}, "the file's grid: %r" % r.get("grid"))
    check(r.get("bounds") == [[0, -1, 0], [3, 2, 1]], "the file's bounds: %r" % r.get("bounds"))
    lo, hi = r.get("magnitudeRange", [0, 0])
    check(abs(lo - 10 ** 0.5) < 1e-6 and abs(hi - 62 ** 0.5) < 1e-6, "|v| over the nodes: [%g, %g]" % (lo, hi))
    check(r.get("vectors") == "wind" and r.get("timeDependent") is False and r.get("kind") == "field",
          "array name, steady, kind: %r" % r)
    g = fl.get("gusts", {})
    check(g.get("grid") == {"type": "uniform", "dims": [3, 2, 2]} and g.get("bounds") == [[0, 0, 0], [1, 1, 2]],
          "the folder's field: %r" % g)
    w = fl.get("wind", {})
    check(w.get("grid") == {"type": "uniform", "dims": [5, 4, 3]} and w.get("bounds") == [[0, 30, 0], [40, 60, 2]]
          and w.get("vectors") == "U,V,W; time 0 of 2", "the folder's NetCDF field (lat reversed, time 0): %r" % w)
    a = fl.get("demo:abc-flow", {})
    check(a.get("grid", {}).get("type") == "analytic" and "ABC" in a.get("description", ""),
          "the demo field is analytic and described: %r" % a)
    st, _, one = srv.json("GET", "/api/v1/datasets/abc-flow")
    check(st == 200 and one.get("name") == "demo:abc-flow", "a field by its short name: %d %r" % (st, one.get("name")))
    st, _, err = srv.json("GET", "/api/v1/datasets/no-such-flow")
    check(st == 404 and err.get("error", {}).get("field") == "dataset", "an unknown name is 404: %r" % err)

# A streamline set traced at start (docs/ALGORITHM.md §22) is a line dataset like any other: listed, rendered
# one-shot and in a session; two ways from a rake of 5 in the shear flow it spans x in [-0.9, -0.1].
rake = "streamlines:demo:shear-flow?seeding=rake&seeds=-0.5,-0.5,0;-0.5,0.5,0&count=5&length=0.4&direction=both"
with Server(binary, data=(rake,)) as srv:
    st, _, body = srv.json("GET", "/api/v1/datasets")
    ds = {d["name"]: d for d in body.get("datasets", [])}
    sl = ds.get("streamlines:demo:shear-flow", {})
    check(sl.get("type") == "lines" and sl.get("lines") == 5, "the set is a dataset of 5 lines: %r" % sorted(ds))
    b = sl.get("bounds", [[0] * 3, [0] * 3])
    check(abs(b[0][0] + 0.9) < 0.01 and abs(b[1][0] + 0.1) < 0.01, "two-way lines span x -0.9 .. -0.1: %r" % b)
    attrs = [a["name"] for a in sl.get("attributes", [])]
    check("time" in attrs and "turning_angle" in attrs, "traced attributes and the derived motion: %r" % attrs)
    req = {"dataset": "streamlines:demo:shear-flow", "width": 64, "height": 64}
    st, _, data = srv.request("POST", "/api/v1/render", json.dumps(req))
    check(st == 200, "a one-shot render of the set: %d" % st)
    st, _, sess = srv.json("POST", "/api/v1/sessions", json.dumps(req))
    check(st in (200, 201) and sess.get("session") and sess.get("dataset", {}).get("lines") == 5,
          "a session over the set: %d %r" % (st, sess.get("session")))
    check("seed_u_rate" not in attrs and "normal_x_delta" not in attrs, "no rates of the tracer's own attributes")
for spec, what in (("streamlines:demo:shear-flow?seeding=sideways", "streamlines.seeding"),
                   ("streamlines:demo:shear-flow?count=100000&length=1000", "streamlines.count: 100000 curves"),
                   ("streamlines:demo:no-flow", "streamlines.field")):
    p = subprocess.run([binary, "serve", "--listen", "127.0.0.1:0", "--data", spec], capture_output=True, text=True,
                       timeout=120)
    out = p.stdout + p.stderr
    check(p.returncode != 0 and what in out, "%s stops the start naming %s (rc %d): %s"
          % (spec, what, p.returncode, out.strip()[-200:]))

bad = os.path.join(fields, "invalid", "bad_spacing.vtk")
p = subprocess.run([binary, "serve", "--listen", "127.0.0.1:0", "--data", bad], capture_output=True, text=True,
                   timeout=120)
out = p.stdout + p.stderr
check(p.returncode != 0 and "bad_spacing.vtk: line 6: SPACING y is 0" in out,
      "a bad field file stops the start naming the file and line (rc %d): %s" % (p.returncode, out.strip()[-200:]))
shutil.rmtree(tmp)
check.done()
