#!/usr/bin/env python3
"""Play benchmark (prints figures; not part of the pass/fail suite).

One WebSocket client plays a dataset's time window as the page's time bar does (web/js/time-controller.js):
hello at a browser-sized viewport, the first still, then --steps steps of t by a hundredth of the time
attribute's range (from --start, a fraction of the range), each a `params` message with
time.window = [t - length, t] (length 0: from the range's start). Two modes:
  paced     (default) a step every 1/--rate seconds, as the page's Play does (5 a second); every frame
            is acked. Reports frames/s received while playing and, per step, the latency from sending it
            to the first frame that shows it.
  lockstep  (--lockstep) the next step only once the previous one's frame arrived: the step rate the
            server sustains.
A frame shows step k when its cameraSeq >= k: each step's params message is followed by a camera
message of the same (fixed) camera with seq k, which the server applies after the params.
Afterwards: seconds from the last step to the full-size still.

  tests/bench/play_bench.py --binary build/lucent --dataset /tmp/fclar_data/thiophene.dump
  tests/bench/play_bench.py --url http://127.0.0.1:8080 --dataset thiophene --lockstep
"""
import argparse
import asyncio
import json
import math
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "server"))
from lucent_server import Server, served_name, unpack_frame, websockets  # noqa: E402

TIME_NAMES = ("time", "t", "frame", "timestep")  # the server's order (render/gl/filter.c)


def fit_camera(bounds):
    lo, hi = bounds
    c = [(a + b) / 2 for a, b in zip(lo, hi)]
    r = 0.5 * math.sqrt(sum((b - a) ** 2 for a, b in zip(lo, hi))) or 1.0
    d = 2.2 * r
    return {"position": [c[0] + 0.5 * d, c[1] + 0.4 * d, c[2] + 0.75 * d], "focalPoint": c, "viewUp": [0, 1, 0],
            "viewAngle": 30}


async def play(ws_url, token, args):
    async with websockets.connect(ws_url, max_size=None) as ws:
        name = served_name(args.dataset)
        hello = {"type": "hello", "dataset": name, "width": args.width, "height": args.height,
                 "devicePixelRatio": 1, "window": args.window}
        if token:
            hello["token"] = token
        await ws.send(json.dumps(hello))
        while True:
            m = json.loads(await ws.recv())
            if m.get("type") == "ready":
                break
            if m.get("type") == "error":
                raise RuntimeError(m)
        info = m["dataset"]
        attrs = {a["name"]: a for a in info.get("attributes", []) if isinstance(a, dict)}
        tname = args.attribute or next((n for n in TIME_NAMES if n in attrs), None)
        if not tname or "range" not in attrs.get(tname, {}):
            raise RuntimeError("the dataset has no time attribute with a range (%s)" % sorted(attrs))
        lo, hi = attrs[tname]["range"]
        step = (hi - lo) / 100.0 or 1.0
        camera = fit_camera(info["bounds"])
        print("dataset %s: %s primitives, time attribute %s in [%g, %g]" % (name, info.get("primitives"), tname, lo,
                                                                            hi))

        frames = []  # (arrival time, header)
        errors = []

        async def recv(timeout):
            try:
                m = await asyncio.wait_for(ws.recv(), timeout)
            except asyncio.TimeoutError:
                return None
            if isinstance(m, str):
                j = json.loads(m)
                if j.get("type") == "error":
                    errors.append(j)
                return j
            h, _ = unpack_frame(m)
            frames.append((time.time(), h))
            await ws.send(json.dumps({"type": "ack", "frame": h["frame"]}))
            return h

        def window(t):
            return [max(lo, t - args.length) if args.length > 0 else lo, t]

        async def send_step(k, t):
            await ws.send(json.dumps({"type": "params", "time": {"attribute": tname, "window": window(t)}}))
            await ws.send(json.dumps({"type": "camera", "seq": k, "camera": camera}))

        # the first still of the starting window
        t = lo + round(args.start * 100) * step
        t0 = time.time()
        await send_step(0, t)
        while True:
            h = await recv(args.timeout)
            if h is None:
                raise RuntimeError("no first frame within %g s" % args.timeout)
            if "frame" in h and h.get("cameraSeq", -1) >= 0 and h["width"] == args.width and h.get("converged"):
                break
        print("first still %.2f s (timings %s)" % (time.time() - t0, h.get("timings")))
        still_quality = h["quality"]

        sent = {}
        shown = {}
        n0 = len(frames)
        start = time.time()
        for k in range(1, args.steps + 1):
            t = min(hi, t + step)
            sent[k] = time.time()
            await send_step(k, t)
            if args.lockstep:
                while k not in shown:
                    h = await recv(args.timeout)
                    if h is None:
                        raise RuntimeError("step %d: no frame within %g s" % (k, args.timeout))
                    if "frame" in h:
                        for j in range(1, h["cameraSeq"] + 1):
                            shown.setdefault(j, time.time())
            else:
                due = start + k / args.rate
                while time.time() < due:
                    h = await recv(max(0.0, due - time.time()))
                    if h and "frame" in h:
                        for j in range(1, h["cameraSeq"] + 1):
                            shown.setdefault(j, time.time())
        end_steps = time.time()
        # the frames that show the last steps, then the still
        deadline = time.time() + args.timeout
        still = None
        while time.time() < deadline:
            h = await recv(max(0.0, deadline - time.time()))
            if h and "frame" in h:
                for j in range(1, h["cameraSeq"] + 1):
                    shown.setdefault(j, time.time())
                if h["cameraSeq"] >= args.steps and h["width"] == args.width and h["quality"] == still_quality:
                    still = time.time()
                    break
        played = [f for f in frames[n0:] if f[0] <= max(end_steps, shown.get(args.steps, end_steps))]
        span = (shown.get(args.steps, end_steps) - start) or 1e-9
        lat = [shown[k] - sent[k] for k in sent if k in shown]
        print("mode %s, %d steps of %g %s (window length %s), %dx%d" % (
            "lockstep" if args.lockstep else "paced %.1f/s" % args.rate, args.steps, step, tname,
            args.length or "0 = up to t", args.width, args.height))
        print("frames while playing: %d in %.2f s = %.2f frames/s" % (len(played), span, len(played) / span))
        print("steps shown: %d of %d in %.2f s = %.2f steps/s" % (len(lat), args.steps, span, len(lat) / span))
        if lat:
            q = sorted(lat)
            print("per-step latency (send to first frame showing it): median %.0f ms, p95 %.0f ms, max %.0f ms" % (
                1e3 * statistics.median(q), 1e3 * q[min(len(q) - 1, int(0.95 * len(q)))], 1e3 * q[-1]))
        sizes = sorted({(h["width"], h["height"], h["quality"]) for _, h in frames[n0:]})
        print("frame sizes while playing (w, h, quality): %s" % sizes)
        ms = [sum(v for v in h.get("timings", {}).values() if isinstance(v, (int, float))) for _, h in frames[n0:]]
        if ms:
            print("GPU ms per frame while playing (sum of the header's pass timings): median %.0f" % statistics.median(ms))
        if still:
            print("still after the last step: %.2f s" % (still - end_steps))
        if errors:
            print("errors: %s" % errors[:3])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", help="start this lucent binary (default: --url)")
    ap.add_argument("--url", default="http://127.0.0.1:8080")
    ap.add_argument("--token", default=os.environ.get("LUCENT_TOKEN", ""))
    ap.add_argument("--dataset", default="/tmp/fclar_data/thiophene.dump")
    ap.add_argument("--attribute", default="", help="the time attribute (default: the server's choice)")
    ap.add_argument("--steps", type=int, default=30)
    ap.add_argument("--start", type=float, default=0.3, help="the first t, as a fraction of the range")
    ap.add_argument("--length", type=float, default=0, help="window length (0: everything up to t)")
    ap.add_argument("--rate", type=float, default=5, help="steps per second (paced mode)")
    ap.add_argument("--lockstep", action="store_true")
    ap.add_argument("--width", type=int, default=972)
    ap.add_argument("--height", type=int, default=761)
    ap.add_argument("--window", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=180)
    ap.add_argument("--server-args", default="", help="extra flags for the started daemon")
    args = ap.parse_args()
    if websockets is None:
        sys.exit("python3-websockets is required")
    if args.binary:
        extra = args.server_args.split() if args.server_args else []
        t = time.time()
        with Server(args.binary, *extra, data=(args.dataset,), demo_size=0, timeout=900) as srv:
            print("daemon ready in %.1f s" % (time.time() - t))
            asyncio.run(play(srv.ws_url, args.token, args))
            srv.stop()
    else:
        ws_url = args.url.replace("http://", "ws://").rstrip("/") + "/api/v1/ws"
        asyncio.run(play(ws_url, args.token, args))


if __name__ == "__main__":
    main()
