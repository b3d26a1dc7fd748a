"""`lucent serve --data DIR`: every recognized file of the folder is served
(named after its stem; a TRX directory is one dataset), unrelated files are ignored, a broken dataset file is
logged and skipped, and a folder with nothing to serve stops the start-up."""
import os
import shutil
import subprocess
import sys
import tempfile

from lucent_server import Check, Server

binary = sys.argv[1]
check = Check()
here = os.path.dirname(os.path.abspath(__file__))
loaders = os.path.join(here, "..", "data", "loaders")

with tempfile.TemporaryDirectory() as folder:
    shutil.copy(os.path.join(loaders, "tck", "valid", "lines_f32le.tck"), os.path.join(folder, "tracts.tck"))
    shutil.copy(os.path.join(loaders, "binlines", "valid", "v2.binlines"), os.path.join(folder, "flow.binlines"))
    shutil.copy(os.path.join(loaders, "csv", "valid", "points.csv"), os.path.join(folder, "cloud.csv"))
    shutil.copy(os.path.join(loaders, "trk", "valid", "tracts_le.trk"), os.path.join(folder, "fibres.trk"))
    shutil.copy(os.path.join(loaders, "invalid", "truncated.ply"), os.path.join(folder, "broken.ply"))
    shutil.copytree(os.path.join(loaders, "trx", "valid", "dir.trx"), os.path.join(folder, "bundle.trx"))
    with open(os.path.join(folder, "README.txt"), "w") as f:
        f.write("not a dataset\n")
    os.mkdir(os.path.join(folder, "sub"))
    with Server(binary, data=(folder,), demo_size=0) as srv:
        st, _, ds = srv.json("GET", "/api/v1/datasets")
        names = sorted(d["name"] for d in ds["datasets"]) if st == 200 else []
        check(names == ["bundle", "cloud", "fibres", "flow", "tracts"], "the folder's datasets are served: %s" % names)
        log = "\n".join(srv.log)
        check("skipping broken.ply" in log, "the broken file is logged and skipped")
        check("README" not in log, "files of other types are ignored")
        st, _, one = srv.json("GET", "/api/v1/datasets/cloud")
        check(st == 200 and one.get("type") == "points" and one.get("vertices") == 3, "cloud.csv: 3 points")

    empty = os.path.join(folder, "sub")
    r = subprocess.run([binary, "serve", "--listen", "127.0.0.1:0", "--data", empty], capture_output=True, text=True,
                       timeout=60)
    check(r.returncode != 0 and "no dataset files" in r.stderr + r.stdout,
          "an empty folder stops the start-up: %s" % (r.stderr + r.stdout)[-300:])

check.done()
