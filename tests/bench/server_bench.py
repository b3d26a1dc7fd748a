#!/usr/bin/env python3
"""Server benchmark (prints figures; not part of the pass/fail suite).

For N simultaneous interactive WebSocket sessions that drag the camera at 60 Hz
(orbiting the data, and ack every frame), reports frames per second (total and
per session), camera-to-frame latency (time from sending camera seq k to
receiving the first frame whose cameraSeq >= k; median and 99th percentile),
the render time and primitives of the interactive frames and the detail they
used (frame header "detail"), and whether the frame after the orbit stops is a
full-size still of the last camera. Then JPEG encode throughput in
megapixels/s, from the daemon's /metrics counters during the streams and from
1024x1024 HTTP renders (X-Lucent-Timings encode=). --json FILE also writes the
figures as JSON (scripts/gpu_check.sh reads it).

  tests/bench/server_bench.py --binary build/lucent --sessions 1,2,4 --seconds 10
  tests/bench/server_bench.py --binary build/lucent --dataset demo:tornado --sessions 1 \
      --width 972 --height 761 --no-encode          (the browser-sized orbit of docs/EVALUATION.md)
  tests/bench/server_bench.py --url http://127.0.0.1:8080 --token T ...   (a running daemon)
"""
import argparse
import asyncio
import json
import os
import re
import signal
import statistics
import sys
import time
import urllib.request
import math

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "server"))
from lucent_server import Server, unpack_frame, websockets  # noqa: E402


def metrics(base, token):
    req = urllib.request.Request(base + "/metrics", headers={"Authorization": "Bearer " + token} if token else {})
    text = urllib.request.urlopen(req).read().decode()
    out = {}
    for name in ("lucent_encoded_pixels_total", "lucent_encode_seconds_sum", "lucent_frames_coalesced_total"):
        m = re.search(r"^%s (\S+)$" % name, text, re.M)
        out[name] = float(m.group(1)) if m else 0.0
    return out


def orbit_camera(bounds, angle):
    """A camera on a circle around the data's centre, 2.2 bounding radii out (ParaView-like fit)."""
    lo, hi = bounds
    c = [(a + b) / 2 for a, b in zip(lo, hi)]
    r = 0.5 * math.sqrt(sum((b - a) ** 2 for a, b in zip(lo, hi))) or 1.0
    d = 2.2 * r
    return {"position": [c[0] + d * math.cos(angle), c[1] + 0.3 * d, c[2] + d * math.sin(angle)],
            "focalPoint": c, "viewUp": [0, 1, 0], "viewAngle": 30}


async def session(ws_url, token, args, idx, t_end, out):
    """Orbits the camera at args.rate Hz until t_end, acking every frame; then
    waits for the still frame and checks it shows the last camera at full size."""
    lat, frames, sent, render_ms, prims, steps = [], 0, {}, [], [], {}
    still = None
    async with websockets.connect(ws_url, max_size=None) as ws:
        hello = {"type": "hello", "dataset": args.dataset, "width": args.width, "height": args.height,
                 "devicePixelRatio": args.dpr, "window": args.window}
        if token:
            hello["token"] = token
        await ws.send(json.dumps(hello))
        ready = json.loads(await ws.recv())
        assert ready["type"] == "ready", ready
        bounds = ready["dataset"]["bounds"]
        seq, answered = 0, 0
        next_send = time.time()
        angle = idx * 0.7
        while time.time() < t_end:
            now = time.time()
            if now >= next_send:
                seq += 1
                angle += 2 * math.pi / (args.rate * args.orbit_seconds)
                sent[seq] = time.time()
                await ws.send(json.dumps({"type": "camera", "seq": seq, "camera": orbit_camera(bounds, angle)}))
                next_send += 1.0 / args.rate
            try:
                m = await asyncio.wait_for(ws.recv(), max(0.001, next_send - time.time()))
            except asyncio.TimeoutError:
                continue
            if isinstance(m, str):
                continue
            h, _ = unpack_frame(m)
            frames += 1
            t = time.time()
            if h["cameraSeq"] > answered:
                lat.append(t - sent[h["cameraSeq"]])
                answered = h["cameraSeq"]
            det = h.get("detail")
            if det and det["interactive"]:
                render_ms.append(det["renderMs"])
                prims.append(det["primitives"])
                key = "%g px/%d" % (det["lodPixels"], det["pointStride"])
                steps[key] = steps.get(key, 0) + 1
            await ws.send(json.dumps({"type": "ack", "frame": h["frame"]}))
        # Input stops: the last frame must be a full-quality still of the last camera.
        deadline = time.time() + 30
        while time.time() < deadline:
            try:
                m = await asyncio.wait_for(ws.recv(), deadline - time.time())
            except asyncio.TimeoutError:
                break
            if isinstance(m, str):
                continue
            h, _ = unpack_frame(m)
            await ws.send(json.dumps({"type": "ack", "frame": h["frame"]}))
            det = h.get("detail") or {}
            if not det.get("interactive", False):
                still = h
                if h["converged"]:
                    break
    out.append({"frames": frames, "lat": lat, "render_ms": render_ms, "prims": prims, "steps": steps,
                "still": still, "last_seq": seq})


def pct(values, p):
    if not values:
        return float("nan")
    v = sorted(values)
    return v[min(len(v) - 1, int(round(p / 100.0 * (len(v) - 1))))]


def run(base, ws_url, token, args):
    report = {"dataset": args.dataset, "width": args.width, "height": args.height, "dpr": args.dpr,
              "rate": args.rate, "seconds": args.seconds, "window": args.window, "runs": [], "jpeg_encode": []}
    try:
        measure(base, ws_url, token, args, report)
    finally:
        if args.json:
            with open(args.json, "w") as f:
                json.dump(report, f, indent=1)


def measure(base, ws_url, token, args, report):
    print("dataset %s, viewport %dx%d x dpr %g, window %d, camera at %g Hz (one orbit per %g s), %g s per run" %
          (args.dataset, args.width, args.height, args.dpr, args.window, args.rate, args.orbit_seconds, args.seconds))
    print("%8s %10s %12s %14s %14s %12s %12s %10s %12s  %s" % (
        "sessions", "frames/s", "per session", "latency p50", "latency p99", "coalesced", "encode MP/s",
        "render p50", "primitives", "still frame"))
    for n in [int(x) for x in args.sessions.split(",")]:
        m0 = metrics(base, token)
        out = []
        t0 = time.time()

        async def all_sessions():
            await asyncio.gather(*[session(ws_url, token, args, i, t0 + args.seconds, out) for i in range(n)])
        asyncio.run(all_sessions())
        el = args.seconds
        m1 = metrics(base, token)
        frames = sum(o["frames"] for o in out)
        lat = [x for o in out for x in o["lat"]]
        rms = [x for o in out for x in o["render_ms"]]
        prims = [x for o in out for x in o["prims"]]
        px = m1["lucent_encoded_pixels_total"] - m0["lucent_encoded_pixels_total"]
        es = m1["lucent_encode_seconds_sum"] - m0["lucent_encode_seconds_sum"]
        stills = []
        for o in out:
            h = o["still"]
            ok = h is not None and h["cameraSeq"] == o["last_seq"] and h["width"] == round(args.width * args.dpr)
            stills.append("ok" if ok else "MISSING" if h is None else "seq %d/%d %dx%d" % (
                h["cameraSeq"], o["last_seq"], h["width"], h["height"]))
        steps = {}
        for o in out:
            for k, v in o["steps"].items():
                steps[k] = steps.get(k, 0) + v
        print("%8d %10.1f %12.1f %11.1f ms %11.1f ms %12d %12.1f %7.1f ms %12d  %s" % (
            n, frames / el, frames / el / n, 1000 * pct(lat, 50), 1000 * pct(lat, 99),
            m1["lucent_frames_coalesced_total"] - m0["lucent_frames_coalesced_total"],
            px / es / 1e6 if es > 0 else float("nan"), pct(rms, 50), int(pct(prims, 50)) if prims else 0,
            ",".join(sorted(set(stills)))))
        report["runs"].append({
            "sessions": n, "frames_per_s": frames / el, "per_session_frames_per_s": frames / el / n,
            "latency_ms": {"p50": 1000 * pct(lat, 50), "p99": 1000 * pct(lat, 99)} if lat else None,
            "render_ms_p50": pct(rms, 50) if rms else None,
            "encode_mp_per_s": px / es / 1e6 if es > 0 else None, "stills": sorted(set(stills))})
        print("%8s interactive detail used (line px / point stride: frames): %s" % (
            "", ", ".join("%s: %d" % kv for kv in sorted(steps.items()))))
        time.sleep(1.0)
    if args.no_encode:
        return
    # JPEG encode throughput on big frames (HTTP, encode time from the header).
    rates = []
    for q in (70, 90):
        for _ in range(3):
            body = json.dumps({"dataset": args.dataset, "width": 1024, "height": 1024, "format": "jpeg",
                               "quality": q}).encode()
            hdr = {"Content-Type": "application/json"}
            if token:
                hdr["Authorization"] = "Bearer " + token
            r = urllib.request.urlopen(urllib.request.Request(base + "/api/v1/render", data=body, headers=hdr))
            r.read()
            enc = float(re.search(r"encode=([0-9.]+)", r.headers["X-Lucent-Timings"]).group(1))
            rates.append((q, 1024 * 1024 / (enc / 1000.0) / 1e6))
    for q in (70, 90):
        mps = statistics.median(r for qq, r in rates if qq == q)
        report["jpeg_encode"].append({"size": "1024x1024", "quality": q, "mp_per_s": mps,
                                      "ms": 1024 * 1024 / 1e6 / mps * 1000})
        print("JPEG encode 1024x1024 quality %d: %.1f MP/s (median of 3)" % (q, mps))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", help="start this lucent binary (default: --url)")
    ap.add_argument("--url", default="http://127.0.0.1:8080")
    ap.add_argument("--token", default=os.environ.get("LUCENT_TOKEN", ""))
    ap.add_argument("--dataset", default="demo:tornado")
    ap.add_argument("--sessions", default="1,2,4")
    ap.add_argument("--seconds", type=float, default=10)
    ap.add_argument("--width", type=int, default=640)
    ap.add_argument("--height", type=int, default=480)
    ap.add_argument("--dpr", type=float, default=1.0)
    ap.add_argument("--window", type=int, default=2)
    ap.add_argument("--rate", type=float, default=60, help="camera messages per second per session")
    ap.add_argument("--orbit-seconds", type=float, default=8, help="seconds per full orbit of the camera")
    ap.add_argument("--no-encode", action="store_true", help="skip the JPEG encode throughput runs")
    ap.add_argument("--server-args", default="", help="extra flags for the started daemon")
    ap.add_argument("--json", metavar="FILE", help="also write the figures to FILE as JSON")
    args = ap.parse_args()
    # SIGTERM (a time limit) ends the runs like an error: --json gets the figures so far, the daemon is stopped.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    if websockets is None:
        sys.exit("python3-websockets is required")
    if args.binary:
        extra = args.server_args.split() if args.server_args else []
        with Server(args.binary, *extra, data=(args.dataset,), demo_size=0) as srv:
            print("daemon: " + next((l for l in srv.log if "GL:" in l), "?").split("] ", 1)[-1])
            run(srv.base, srv.ws_url, args.token, args)
            srv.stop()
    else:
        ws_url = args.url.replace("http://", "ws://").rstrip("/") + "/api/v1/ws"
        run(args.url.rstrip("/"), ws_url, args.token, args)


if __name__ == "__main__":
    main()
