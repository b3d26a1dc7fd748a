#!/usr/bin/env python3
"""Memory benchmark (prints figures; not part of the pass/fail suite).

Resident bytes per vertex while rendering, for points, lines and surfaces at
1, 10 and 50 million vertices, with the load time (generate, finalize,
upload). Each size runs in a fresh `lucent bench` process that first renders
a tiny dataset of the same kind (so programs and render targets exist), then
the large one; the figure is the process's resident memory after the large
one's frames minus before it was loaded, divided by its vertices. On llvmpipe
GPU buffers live in system memory, so they count (docs/MEMORY.md).

  tests/bench/memory_bench.py --binary build/lucent
  tests/bench/memory_bench.py --kinds points --sizes 20 --exact-positions
  tests/bench/memory_bench.py --spec 'demo:tornado?count=5000'

Lines are the tornado demo (about 524 vertices a line), surfaces the surface
demo (3 res^2 vertices at resolution count=res).
"""
import argparse
import math
import re
import subprocess
import sys
import time

TINY = {"points": "demo:points?count=1000", "lines": "demo:tornado?count=10", "surfaces": "demo:surface?count=16"}
VERTICES_PER_TORNADO_LINE = 524.5


def spec_for(kind, millions):
    n = millions * 1e6
    if kind == "points":
        return "demo:points?count=%d" % n
    if kind == "lines":
        return "demo:tornado?count=%d" % max(1, round(n / VERTICES_PER_TORNADO_LINE))
    # count is the demo's resolution res: 3 res^2 vertices (knot 4res x res/4, ellipsoid res x 2res)
    return "demo:surface?count=%d" % max(16, round(math.sqrt(n / 3)))


def kind_of(spec):
    return "points" if "points" in spec else "surfaces" if "surface" in spec else "lines"


def run(binary, spec, args):
    cmd = [binary, "bench", "--size", args.size, "--frames", str(args.frames), "--warmup", "0", "--memory",
           "--datasets", TINY[kind_of(spec)] + "," + spec]
    if args.exact_positions:
        cmd.append("--exact-positions")
    t0 = time.time()
    out = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.time() - t0
    rows = [line for line in out.stdout.splitlines() if line.startswith("demo:")]
    if out.returncode != 0 or len(rows) < 2:
        return None, out.stderr.strip().splitlines()[-1:] or ["failed"]
    cols = rows[-1].split()
    gpu = re.search(r"GPU buffers\s+([\d.]+)", out.stdout.split(rows[-1])[1])
    state = re.findall(r"per-(?:element|session) state\s+([\d.]+)", out.stdout.split(rows[-1])[1])
    return {
        "vertices": None,
        "load_s": float(cols[-3]),
        "rss_mb": float(cols[-2]),
        "rss_per_vertex": float(cols[-1]),
        "gpu_per_vertex": float(gpu.group(1)) if gpu else float("nan"),
        "state_per_vertex": sum(float(s) for s in state),
        "wall_s": wall,
    }, None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", default="build/lucent")
    ap.add_argument("--kinds", default="points,lines,surfaces")
    ap.add_argument("--sizes", default="1,10,50", help="millions of vertices")
    ap.add_argument("--spec", action="append", default=[], help="a dataset spec instead of kinds x sizes")
    ap.add_argument("--size", default="64x64", help="image size (small: the figure is about the data)")
    ap.add_argument("--frames", type=int, default=1)
    ap.add_argument("--exact-positions", action="store_true", help="the float layout instead of the compact one")
    args = ap.parse_args()
    specs = args.spec or [spec_for(k, float(m)) for k in args.kinds.split(",") for m in args.sizes.split(",")]
    layout = "exact" if args.exact_positions else "compact"
    print("%-34s %-8s %8s %11s %11s %12s %8s" % ("dataset", "layout", "load s", "RSS MB", "RSS B/vtx",
                                                 "GPU B/vtx", "state B/vtx"))
    for spec in specs:
        r, err = run(args.binary, spec, args)
        if not r:
            print("%-34s %-8s failed: %s" % (spec, layout, " ".join(err)))
            continue
        print("%-34s %-8s %8.2f %11.1f %11.1f %12.2f %8.2f" % (spec, layout, r["load_s"], r["rss_mb"],
                                                              r["rss_per_vertex"], r["gpu_per_vertex"],
                                                              r["state_per_vertex"]))
        sys.stdout.flush()
    print("\nRSS B/vtx: resident growth while rendering per vertex (scene arrays, GPU buffers, per-element and\n"
          "session state, driver overhead); GPU B/vtx: the dataset's buffers; state B/vtx: one worker's\n"
          "per-element buffers and one session's opacities. load s: generate, finalize and upload.")
    return 0


if __name__ == "__main__":
    sys.exit(main())
