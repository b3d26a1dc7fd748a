#!/usr/bin/env python3
"""Benchmark of `lucent render --mpi` on one host (docs/MPI.md): for N ranks and
image sizes, the frame time (wall, last of --frames frames, so start-up and
loading are not in it), the time spent in the reductions (wall, including the
wait for the slowest rank) per frame and per reduction, the bytes each rank
sends per frame, and each rank's scene memory and peak resident size (of a
line file, point cloud or point table --dataset each rank reads only its share;
LUCENT_MPI_READ=whole in the environment compares reading everything). Prints a Markdown table.

  tests/bench/mpi_bench.py --binary build/lucent [--ranks 1,2,3,4] [--sizes 512,1024]
                           [--dataset demo:tornado] [--frames 3]

Ranks share this host's cores (and, on llvmpipe, the renderer's threads), so
with more ranks than cores the frame times measure contention, not scaling."""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "mpi"))
from mpi_util import mpirun, mpirun_env  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", default="build/lucent")
    ap.add_argument("--ranks", default="1,2,3,4")
    ap.add_argument("--sizes", default="512,1024")
    ap.add_argument("--dataset", default="demo:tornado")
    ap.add_argument("--frames", type=int, default=3)
    args = ap.parse_args()
    if not mpirun(1):
        sys.exit("mpirun not found (apt-get install openmpi-bin)")
    tmp = tempfile.mkdtemp(prefix="lucent-mpi-bench-")
    print("dataset %s, %d frames per run (the last is reported), %d CPU cores, load average %.1f\n" %
          (args.dataset, args.frames, os.cpu_count(), os.getloadavg()[0]))
    print("| ranks | size | frame ms | reductions ms / frame | of which waiting ms | transfer ms per reduction |"
          " MB reduced per frame (each rank) | scene MB per rank (whole) | peak resident MB per rank |")
    print("|---|---|---|---|---|---|---|---|---|")
    for size in [int(s) for s in args.sizes.split(",")]:
        for n in [int(r) for r in args.ranks.split(",")]:
            stats = os.path.join(tmp, "s.json")
            cmd = mpirun(n) + [args.binary, "render", "--mpi", "--dataset", args.dataset, "--size",
                               "%dx%d" % (size, size), "--frames", str(args.frames), "--stats", stats,
                               "--out", os.path.join(tmp, "o.png")]
            env = mpirun_env()
            if "OMPI_MCA_btl_vader_single_copy_mechanism" not in os.environ:
                env.pop("OMPI_MCA_btl_vader_single_copy_mechanism")  # the tests' fallback; measure the default
            env["LUCENT_MPI_PROFILE"] = "1"  # a barrier before each reduction: waiting apart from transfer
            r = subprocess.run(cmd, capture_output=True, text=True, env=env)
            if r.returncode != 0:
                print("| %d | %d | failed: %s |" % (n, size, r.stderr.strip().splitlines()[-1:]))
                continue
            with open(stats) as f:
                s = json.load(f)
            mpi = s.get("mpi", {"reductions": 0, "reduceMs": 0.0, "reduceBytes": 0})
            mem = [float(m) for m in re.findall(r"rank \d+ of \d+: .*?, ([0-9.]+) MB of scene arrays", r.stdout)]
            whole = re.search(r"of the whole ([0-9.]+) MB", r.stdout)
            peak = re.findall(r"rank \d+ of \d+: .*peak resident ([0-9.]+) MB", r.stdout)
            prof = re.search(r"waited ([0-9.]+) ms for the other ranks, ([0-9.]+) ms transferring", r.stdout)
            wait, transfer = (float(prof.group(1)), float(prof.group(2))) if prof else (0.0, 0.0)
            per = transfer / mpi["reductions"] if mpi["reductions"] else 0.0
            print("| %d | %d² | %.0f | %.1f | %.1f | %.1f | %.1f | %s (%s) | %s |" %
                  (n, size, s["wallMs"], mpi["reduceMs"], wait, per, mpi["reduceBytes"] / 1e6,
                   " / ".join("%.1f" % m for m in mem), whole.group(1) if whole else "?", " / ".join(peak)),
                  flush=True)


if __name__ == "__main__":
    main()
