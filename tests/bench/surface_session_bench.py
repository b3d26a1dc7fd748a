#!/usr/bin/env python3
"""Surface session benchmark (prints figures; not part of the pass/fail suite).

One WebSocket client streams a field's stream surface (method surface-layers) with the camera still, as the
page's surface panel does, and prints every frame's work and time from its header: the curves traced so far,
the curves and fragments the frame drew (`drawnCurves`, `drawnFragments`; absent from daemons before the
layers were kept between frames, printed as -) and its render time (detail.renderMs: tracing the frame's
new curves, drawing and compositing). A daemon whose frames
draw every traced curve anew shows the frame cost growing with the surface; one that adds each frame's
curves to kept layers shows it flat (docs/EVALUATION.md "Surfaces").

  tests/bench/surface_session_bench.py --binary build/lucent [--particles 4000] [--per-frame 200] [--size 512]
"""
import argparse
import asyncio
import json
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "server"))
from lucent_server import Server, unpack_frame, websockets  # noqa: E402

SEED = [[3.14159, 0.63, 3.14159], [3.14159, 5.65, 3.14159]]


async def run(url, args):
    async with websockets.connect(url, max_size=None) as ws:
        t0 = time.monotonic()
        await ws.send(json.dumps({"type": "hello", "dataset": "demo:points", "width": args.size,
                                  "height": args.size, "devicePixelRatio": 1, "method": "surface-layers",
                                  "surface": {"field": "demo:" + args.field, "seed": SEED,
                                              "particles": args.particles, "curvesPerFrame": args.per_frame}}))
        rows = []
        while True:
            m = await asyncio.wait_for(ws.recv(), 600)
            if isinstance(m, str):
                continue
            h, _ = unpack_frame(m)
            await ws.send(json.dumps({"type": "ack", "frame": h["frame"]}))
            s = h.get("surface", {})
            total = h.get("detail", {}).get("renderMs", 0.0)  # tracing the frame's new curves and drawing
            rows.append((s.get("curves"), s.get("drawnCurves"), s.get("drawnFragments"), s.get("kept"), total,
                         time.monotonic() - t0))
            if h.get("converged") and s.get("curves") == args.particles:
                break
    print("%8s %8s %12s %5s %10s %9s" % ("curves", "drawn", "fragments", "kept", "frame ms", "at s"))
    for c, d, f, k, ms, at in rows:
        print("%8s %8s %12s %5s %10.1f %9.2f" % (c, "-" if d is None else d, "-" if f is None else f,
                                                  "-" if k is None else ("y" if k else "n"), ms, at))
    first = [r for r in rows if r[0] == args.per_frame]
    print("frames %d; first frame %.1f ms, last %.1f ms; all curves in after %.2f s" %
          (len(rows), first[0][4] if first else rows[0][4], rows[-1][4], rows[-1][5]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--binary", default="build/lucent")
    ap.add_argument("--field", default="abc-flow")
    ap.add_argument("--particles", type=int, default=4000)
    ap.add_argument("--per-frame", type=int, default=200)
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args()
    if websockets is None:
        sys.exit("python3-websockets is not installed")
    with Server(args.binary, "--workers", str(args.workers), data=("demo:points", "demo:" + args.field)) as srv:
        asyncio.run(run(srv.ws_url, args))


if __name__ == "__main__":
    main()
