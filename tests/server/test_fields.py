"""Vector fields through the daemon: a demo field and a gridded .vtk file in
/api/v1/datasets ("fields", beside the scene datasets) and by name, a field
.vtk and a NetCDF u/v/w grid inside a --data folder, and a bad field file
refused at start-up naming the file and the line."""
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

bad = os.path.join(fields, "invalid", "bad_spacing.vtk")
p = subprocess.run([binary, "serve", "--listen", "127.0.0.1:0", "--data", bad], capture_output=True, text=True,
                   timeout=120)
out = p.stdout + p.stderr
check(p.returncode != 0 and "bad_spacing.vtk: line 6: SPACING y is 0" in out,
      "a bad field file stops the start naming the file and line (rc %d): %s" % (p.returncode, out.strip()[-200:]))
shutil.rmtree(tmp)
check.done()
