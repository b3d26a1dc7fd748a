#!/usr/bin/env python3
"""Browsing benchmark (prints figures; not part of the pass/fail suite).

One WebSocket client browses a dataset the way the web page does: hello at a
browser-sized viewport (default 972x761), camera updates at 30 per second
along an orbit, an ack for every frame, then release. It reports:
  first frame     seconds from hello to the first frame (and to the first still); with --binary
                  also from the daemon's launch (the scene cache's figure: run twice with
                  --server-args "--cache DIR" for a cold and a warm start)
  frames/s        frames received while orbiting
  input-to-frame  p50/p95 from sending camera seq k to the first frame with cameraSeq >= k
  still           seconds from the last camera update to the first full-size still of that camera
                  (a staged still's first stage), to its final stage, and to the converged still
  moving vs still SSIM between the last moving frame (stretched to the still's size, as the page
                  stretches it) and the still of the same camera; with a staged still, also
                  between its first stage and its final one; each also with both images halved
                  and quartered (2x2 box averages), the scales of structure rather than of pixels;
                  and what that moving frame drew (primitives, level of detail, strides;
                  tests/bench/moving_fidelity.py scores other settings at the same camera)
  targets         issue 42's: >= 10 frames/s orbiting, the full (final-stage) still <= 1.5 s after
                  the last input, moving vs still SSIM >= 0.7; each met or not
  pause           with --pause S: the orbit stops for S seconds mid-drag and resumes; the delay from
                  the first update after the pause to its frame (a still started in the pause must
                  not hold it up)
  per frame       render, read-back and JPEG encode milliseconds of the moving frames and of the
                  still (from the frame headers: detail.renderMs, timings.readback, encodeMs)
--json FILE also writes the figures as JSON (scripts/gpu_check.sh reads it).
With --link RTT,MBIT (repeatable; "loopback" for none) the orbit runs once through each emulated
wide-area link (tests/bench/link_proxy.py: RTT/2 each way, MBIT Mbit/s each way with a 100 ms
queue, 0 = no rate limit) and a table compares them: frames/s, input-to-frame p50/p95, still after
release, mean bytes of a moving frame (its most common size, its mean JPEG quality), the link's use while orbiting (Mbit/s received and the share
of the rate), and the session's flow-control window, round trip and link estimate (linkMbps: the link's rate where
frames waited on it, else what it carried) from its last stats message.
With --rounds N the links run in turn N times after an uncounted orbit (the daemon's first session pays its
one-time costs): the table gives each link's medians, and a line per link its frames/s as a share of the same
round's first link (orbits seconds apart, so a busy host moves both alike). Each round's line says how many
moving frames were at the most common size: a drag starts at the rung its still's time predicts, and orbits that
start a rung finer (frames within the budget, fewer a second) differ in frames/s for that alone.
The issue 46 table:
  tests/bench/browse_bench.py --binary build/lucent --seconds 6 --link loopback --link 50,20 --link 100,5 --rounds 3
With --trace FILE (and --binary, --link) the daemon runs with --log-level debug, and a second table says where
each link's input-to-frame time went, per frame that showed a newer camera, from the client's times and the
daemon's per-frame "flow" lines (render start, end, hand-over to the connection, ack): the wait for a render to
start, the render, the encode, and the link (transfer, queue and the proxy's and client's own time); all frames and
the tail (>= 97 % of the p95), and what the tail's frames were (the drag's first moving frame, one that ran P1-P3
again, another). FILE keeps both sides' times, and each frame's pass timings, as JSON.
With --contend N, N other clients render --contend-size stills over HTTP in a loop
during the orbit (the fairness case: another user's 4K render must not stall the drag); the
orbit's p95 input-to-frame is the figure, and the daemon's yield counters (/metrics) say how
often stills were pre-empted and large renders waited for the orbit.

  tests/bench/browse_bench.py --binary build/lucent --dataset build/real-data/traj.dump
  tests/bench/browse_bench.py --binary build/lucent --dataset demo:points?count=1000000 --pause 0.4
  tests/bench/browse_bench.py --binary build/lucent --dataset demo:tornado --contend 1
  tests/bench/browse_bench.py --url http://127.0.0.1:8080 --token T --dataset NAME   (a running daemon)

SSIM needs python3-numpy and python3-pil (Rec. 709 luminance, 11x11 Gaussian, sigma 1.5, as
`lucent ssim`); without them that column says n/a.
"""
import argparse
import asyncio
import io
import json
import math
import os
import re
import statistics
import sys
import threading
import time
import urllib.request

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "server"))
from lucent_server import Server, served_name, unpack_frame, websockets  # noqa: E402
from link_proxy import Link  # noqa: E402

try:
    import numpy as np
    from PIL import Image
except ImportError:  # pragma: no cover
    np = None


def orbit_camera(bounds, angle):
    """A camera on a circle about the data's centre in the plane normal to +Y, 2.2 bounding radii out."""
    lo, hi = bounds
    c = [(a + b) / 2 for a, b in zip(lo, hi)]
    r = 0.5 * math.sqrt(sum((b - a) ** 2 for a, b in zip(lo, hi))) or 1.0
    d = 2.2 * r
    return {"position": [c[0] + d * math.cos(angle), c[1] + 0.3 * d, c[2] + d * math.sin(angle)],
            "focalPoint": c, "viewUp": [0, 1, 0], "viewAngle": 30}


def luminance(jpeg, size=None):
    img = Image.open(io.BytesIO(jpeg)).convert("RGB")
    if size and img.size != size:
        img = img.resize(size, Image.BILINEAR)
    a = np.asarray(img, dtype=np.float64) / 255.0
    return a[..., 0] * 0.2126 + a[..., 1] * 0.7152 + a[..., 2] * 0.0722


def ssim(a, b):
    """Mean SSIM of two luminance images (Wang et al. 2004; 11x11 Gaussian, sigma 1.5, valid windows)."""
    x = np.arange(11) - 5
    g = np.exp(-x * x / (2 * 1.5 * 1.5))
    g /= g.sum()

    def blur(m):
        m = np.apply_along_axis(lambda r: np.convolve(r, g, mode="valid"), 1, m)
        return np.apply_along_axis(lambda c: np.convolve(c, g, mode="valid"), 0, m)
    c1, c2 = 0.01 ** 2, 0.03 ** 2
    ma, mb = blur(a), blur(b)
    va, vb, cov = blur(a * a) - ma * ma, blur(b * b) - mb * mb, blur(a * b) - ma * mb
    s = ((2 * ma * mb + c1) * (2 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2))
    return float(s.mean())


def halve(m):
    """2x2 box average (the next scale of a multi-scale comparison)."""
    h, w = m.shape[0] // 2 * 2, m.shape[1] // 2 * 2
    return 0.25 * (m[0:h:2, 0:w:2] + m[1:h:2, 0:w:2] + m[0:h:2, 1:w:2] + m[1:h:2, 1:w:2])


def ssim_coarse(a, b):
    """SSIM of both images halved and quartered: how alike they are at the scales of structure, where SSIM at
    full size also weighs the pixel-level detail (noise-like on dense lines and points)."""
    a2, b2 = halve(a), halve(b)
    return ssim(a2, b2), ssim(halve(a2), halve(b2))


def timings_text(h):
    """A frame header's pass timings, "pass ms, ..."."""
    return ", ".join("%s %.0f" % kv for kv in (h.get("timings") or {}).items())


def frame_costs(h):
    """A frame header's costs: size, render ms (wall), GPU ms of its passes, read-back ms, encode ms."""
    t = h.get("timings") or {}
    return {"size": "%dx%d" % (h["width"], h["height"]), "render_ms": (h.get("detail") or {}).get("renderMs"),
            "gpu_ms": sum(v for v in t.values() if isinstance(v, (int, float))), "readback_ms": t.get("readback"),
            "encode_ms": h.get("encodeMs"), "quality": h.get("quality")}


def cost_summary(frames):
    """Mean and median of each cost over frames, and the most common size."""
    out = {"count": len(frames)}
    if frames:
        sizes = [f["size"] for f in frames]
        out["size"] = max(set(sizes), key=sizes.count)
    for k in ("render_ms", "gpu_ms", "readback_ms", "encode_ms"):
        v = [f[k] for f in frames if isinstance(f.get(k), (int, float))]
        out[k] = {"mean": sum(v) / len(v), "p50": pct(v, 50)} if v else None
    return out


def pct(values, p):
    if not values:
        return float("nan")
    v = sorted(values)
    return v[min(len(v) - 1, int(round(p / 100.0 * (len(v) - 1))))]


YIELD_METRICS = ("lucent_frames_yielded_total", "lucent_yield_waits_total", "lucent_yield_wait_seconds_total")


def yield_metrics(base, token):
    """The daemon's yield counters (docs/ARCHITECTURE.md "Yielding"); {} when /metrics cannot be read."""
    hdr = {"Authorization": "Bearer " + token} if token else {}
    try:
        text = urllib.request.urlopen(urllib.request.Request(base + "/metrics", headers=hdr), timeout=10).read()
    except Exception:  # an older daemon, or metrics behind another token
        return {}
    out = {}
    for line in text.decode().splitlines():
        parts = line.split()
        if len(parts) == 2 and parts[0] in YIELD_METRICS:
            out[parts[0]] = float(parts[1])
    return out


def contender(base, token, args, stop, out):
    """Renders args.contend_size stills over HTTP until stop is set; records their wall times."""
    w, h = (int(x) for x in args.contend_size.split("x"))
    hdr = {"Content-Type": "application/json"}
    if token:
        hdr["Authorization"] = "Bearer " + token
    body = json.dumps({"dataset": served_name(args.dataset), "width": w, "height": h, "format": "jpeg"}).encode()
    while not stop.is_set():
        t = time.time()
        try:
            urllib.request.urlopen(urllib.request.Request(base + "/api/v1/render", data=body, headers=hdr),
                                   timeout=600).read()
            out.append(("ok", time.time() - t))
        except Exception as e:  # a refusal (cost, queue) is a figure too
            out.append((str(e)[:60], time.time() - t))
            stop.wait(0.5)


async def browse(ws_url, token, args):
    r = {"lat": [], "moving": 0, "pause_delay": None, "moving_frames": [], "moving_bytes": [], "moving_q": [], "rx": 0,
         "stats": None, "trace": []}
    async with websockets.connect(ws_url, max_size=None) as ws:
        name = served_name(args.dataset)
        hello = {"type": "hello", "dataset": name, "width": args.width, "height": args.height,
                 "devicePixelRatio": 1}
        if args.window:
            hello["window"] = args.window
        if token:
            hello["token"] = token
        t_hello = time.time()
        await ws.send(json.dumps(hello))
        while True:
            m = json.loads(await ws.recv())
            if m.get("type") == "ready":
                r["session"] = m.get("session")
                break
            if m.get("type") == "error":
                raise RuntimeError(m)
        bounds = m["dataset"]["bounds"]

        async def recv(timeout):
            try:
                m = await asyncio.wait_for(ws.recv(), timeout)
            except asyncio.TimeoutError:
                return None, None
            r["rx"] += len(m)
            if isinstance(m, str):
                m = json.loads(m)
                if m.get("type") == "stats":
                    r["stats"] = m
                return m, None
            h, img = unpack_frame(m)
            if args.trace:  # the client's side of a frame's way (the daemon's: its "flow" debug lines)
                d = h.get("detail") or {}
                r["trace"].append({"ev": "frame", "t": time.monotonic(), "frame": h["frame"], "seq": h["cameraSeq"],
                                   "bytes": len(m), "moving": d.get("interactive", False), "q": h.get("quality"),
                                   "size": "%dx%d" % (h["width"], h["height"]), "renderMs": d.get("renderMs"),
                                   "encodeMs": h.get("encodeMs"), "reused": d.get("reusedOpacities"),
                                   "step": d.get("detailStep"), "timings": h.get("timings")})
            await ws.send(json.dumps({"type": "ack", "frame": h["frame"]}))
            return h, img

        # First frame, then the first still of the initial view (no input yet).
        deadline = t_hello + args.timeout
        while time.time() < deadline:
            h, img = await recv(deadline - time.time())
            if img is not None:
                r["first"] = time.time() - t_hello
                r["first_at"] = time.time()
                if args.verbose:
                    d = h.get("detail") or {}
                    print(f"  first frame +{r['first']:.2f} s: {h['width']}x{h['height']} render "
                          f"{d.get('renderMs', 0):.0f} ms ({timings_text(h)}), encode {h.get('encodeMs', 0):.0f} ms",
                          flush=True)
                if not (h.get("detail") or {}).get("interactive", False) and h["width"] == args.width:
                    r["first_still"] = r["first"]
                break
        # A staged first still: its first stage, then wait for the last (final) one.
        if "first_still" in r and h.get("stage", 0) == h.get("stages", 0):
            r["first_final"] = r["first_still"]  # the first frame was the whole still
        while "first_final" not in r and time.time() < deadline:
            h, img = await recv(deadline - time.time())
            if img is not None and not (h.get("detail") or {}).get("interactive", False):
                r.setdefault("first_still", time.time() - t_hello)
                if h.get("stage", 0) == h.get("stages", 0):
                    r["first_final"] = time.time() - t_hello
                if args.verbose:
                    print(f"  first still +{time.time() - t_hello:.2f} s: stage {h.get('stage', '-')}/"
                          f"{h.get('stages', '-')} {h['width']}x{h['height']} render "
                          f"{(h.get('detail') or {}).get('renderMs', 0):.0f} ms", flush=True)
        # Orbit: updates at args.rate per second for args.seconds (with an optional pause half-way).
        sent, seq, answered, angle = {}, 0, 0, 0.0
        t0 = time.time()
        rx0 = r["rx"]
        next_send = t0
        paused = not args.pause
        resume_seq = None
        last_moving = None
        while time.time() < t0 + args.seconds + (args.pause or 0):
            now = time.time()
            if not paused and now >= t0 + args.seconds / 2:
                paused = True
                next_send = now + args.pause
            if now >= next_send:
                seq += 1
                if resume_seq is None and args.pause and now > t0 + args.seconds / 2:
                    resume_seq = seq
                angle += 2 * math.pi / (args.rate * args.orbit_seconds)
                sent[seq] = time.time()
                if args.trace:
                    r["trace"].append({"ev": "camera", "t": time.monotonic(), "seq": seq})
                await ws.send(json.dumps({"type": "camera", "seq": seq, "camera": orbit_camera(bounds, angle)}))
                next_send += 1.0 / args.rate
            h, img = await recv(max(0.001, next_send - time.time()))
            if img is None:
                continue
            r["moving"] += 1
            r["moving_frames"].append(dict(frame_costs(h), at=time.monotonic()))
            if (h.get("detail") or {}).get("interactive", False):
                r["moving_bytes"].append(len(img))
                r["moving_q"].append(h.get("quality", 0))
            if args.verbose:
                d = h.get("detail") or {}
                print(f"  frame {h['frame']} {h['width']}x{h['height']} seq {h['cameraSeq']}/{seq} "
                      f"{'moving' if d.get('interactive') else 'still'} level {d.get('level')} "
                      f"points 1/{d.get('pointStride')} lines 1/{d.get('lineStride', 1)} "
                      f"reused {d.get('reusedOpacities')} primitives {d.get('primitives')} "
                      f"render {d.get('renderMs', 0):.0f} ms", flush=True)
            if h["cameraSeq"] > answered:
                r["lat"].append(time.time() - sent[h["cameraSeq"]])
                answered = h["cameraSeq"]
                if resume_seq is not None and r["pause_delay"] is None and h["cameraSeq"] >= resume_seq:
                    r["pause_delay"] = time.time() - sent[resume_seq]
            if h["cameraSeq"] == seq and (h.get("detail") or {}).get("interactive", False):
                last_moving = (h, img)
        r["orbit_s"] = args.seconds
        if args.trace:
            r["trace"].append({"ev": "release", "t": time.monotonic(), "seq": seq})
        r["orbit_rx"] = r["rx"] - rx0
        r["orbit_stats"] = r["stats"]
        t_last = sent[seq]
        # Release: the still of the last camera, then convergence.
        deadline = time.time() + args.timeout
        still = None
        stages = []  # every still frame of the last camera, in order: stages[0] is the first stage
        while time.time() < deadline:
            h, img = await recv(deadline - time.time())
            if img is None:
                continue
            if resume_seq is not None and r["pause_delay"] is None and h["cameraSeq"] >= resume_seq:
                r["pause_delay"] = time.time() - sent[resume_seq]
            if args.verbose:
                d = h.get("detail") or {}
                print(f"  after release +{time.time() - t_last:.2f} s: frame {h['frame']} {h['width']}x{h['height']} "
                      f"{'moving' if d.get('interactive') else 'still'} stage {h.get('stage', '-')}/"
                      f"{h.get('stages', '-')} converged {h.get('converged')} render {d.get('renderMs', 0):.0f} ms "
                      f"({timings_text(h)})", flush=True)
            if h["cameraSeq"] == seq and not (h.get("detail") or {}).get("interactive", False):
                if still is None:
                    r["still"] = time.time() - t_last
                still = (h, img)
                r["still_frame"] = frame_costs(h)
                stages.append(still)
                if h.get("final", True) and "full" not in r:  # a staged still's last stage, or an unstaged one
                    r["full"] = time.time() - t_last
                if h.get("converged") and h.get("final", True):  # a staged still's last stage
                    r["converged"] = time.time() - t_last
                    break
            elif h["cameraSeq"] == seq:
                last_moving = (h, img)
        if args.save and still is not None and last_moving is not None:
            os.makedirs(args.save, exist_ok=True)
            for name, (head, data) in (("moving", last_moving), ("still", still)):
                with open(os.path.join(args.save, name + ".jpg"), "wb") as out:
                    out.write(data)
                with open(os.path.join(args.save, name + ".json"), "w") as out:
                    json.dump({"header": head, "camera": orbit_camera(bounds, angle)}, out, indent=1)
        if np is not None and still is not None and last_moving is not None:
            size = (still[0]["width"], still[0]["height"])
            moving_l, still_l = luminance(last_moving[1], size), luminance(still[1])
            r["ssim"] = ssim(moving_l, still_l)
            r["ssim_coarse"] = ssim_coarse(moving_l, still_l)
            if args.verbose:
                for head, data in stages:
                    print("  %dx%d stage %s/%s vs the final still: SSIM %.3f" % (
                        head["width"], head["height"], head.get("stage", "-"), head.get("stages", "-"),
                        ssim(luminance(data, size), still_l)))
                print("  last moving frame vs the first still frame: SSIM %.3f" % ssim(
                    moving_l, luminance(stages[0][1], size)))
            if len(stages) > 1:
                first_head, first_img = stages[0]
                first_l = luminance(first_img, size)
                r["ssim_first"] = ssim(first_l, still_l)
                r["ssim_first_coarse"] = ssim_coarse(first_l, still_l)
                r["first_stage"] = "stage %s of %s" % (first_head.get("stage"), first_head.get("stages"))
            r["moving_size"] = "%dx%d" % (last_moving[0]["width"], last_moving[0]["height"])
            d = last_moving[0].get("detail") or {}
            r["moving_detail"] = {k: d.get(k) for k in ("level", "lodPixels", "lineStride", "pointStride", "primitives",
                                                        "reusedOpacities", "renderMs")}
    return r


TARGET_FPS, TARGET_FULL_S, TARGET_SSIM = 10.0, 1.5, 0.7  # issue 42, at 972x761 on the 2-core host


def targets(r):
    """The browsing targets of issue 42, each "met" or "not met" with its figure: frames/s orbiting, the full
    (final-stage) still after the last input, SSIM of the last moving frame against that still."""
    fps = r["moving"] / r["orbit_s"]
    out = ["%.1f frames/s %s" % (fps, "met" if fps >= TARGET_FPS else "not met")]
    full = r.get("full")
    out.append("full still %s %s" % ("%.2f s" % full if full is not None else "none",
                                      "met" if full is not None and full <= TARGET_FULL_S else "not met"))
    s = r.get("ssim")
    out.append("SSIM %s %s" % ("%.3f" % s if s is not None else "n/a",
                               "met" if s is not None and s >= TARGET_SSIM else "not met"))
    return out


def run(base, ws_url, token, args, launched=None, listening=None):
    stop, cout, threads = threading.Event(), [], []
    y0 = yield_metrics(base, token)
    for _ in range(args.contend):
        t = threading.Thread(target=contender, args=(base, token, args, stop, cout), daemon=True)
        t.start()
        threads.append(t)
    if args.contend:
        time.sleep(1.0)  # let the first large still get under way
    try:
        r = asyncio.run(browse(ws_url, token, args))
    finally:
        stop.set()
    f = lambda k, fmt="%.2f s": (fmt % r[k]) if k in r and r[k] is not None else "-"  # noqa: E731
    print("dataset %s, %dx%d, camera updates at %g/s for %g s, window %d%s" % (
        args.dataset, args.width, args.height, args.rate, args.seconds, args.window or 0,
        ", %d client(s) rendering %s stills" % (args.contend, args.contend_size) if args.contend else ""))
    print("first frame after hello     %s (first still %s, its final stage %s)" % (
        f("first"), f("first_still"), f("first_final")))
    if launched is not None and "first_at" in r:
        print("first frame after launch    %.2f s (listening after %.2f s)" % (r["first_at"] - launched,
                                                                            listening - launched))
    print("frames/s while orbiting     %.1f" % (r["moving"] / r["orbit_s"]))
    print("input-to-frame p50 / p95    %.0f / %.0f ms" % (1000 * pct(r["lat"], 50), 1000 * pct(r["lat"], 95)))
    print("still after last input      %s, final stage %s (converged %s)" % (f("still"), f("full"), f("converged")))
    print("moving vs still SSIM        %s%s" % (f("ssim", "%.3f"),
          " (moving frame %s; halved %.3f, quartered %.3f)" % ((r["moving_size"],) + r["ssim_coarse"])
          if "moving_size" in r else "" if np is not None else " (n/a: needs python3-numpy, python3-pil)"))
    if "moving_detail" in r:
        d = r["moving_detail"]
        print("last moving frame drew      %s primitives (level %s, lod %s px, lines 1/%s, points 1/%s), render %s ms" % (
            d["primitives"], d["level"], d["lodPixels"], d["lineStride"] or 1, d["pointStride"] or 1,
            "%.0f" % d["renderMs"] if isinstance(d["renderMs"], (int, float)) else "-"))
    if "ssim_first" in r:
        print("first stage vs still SSIM   %.3f (%s; halved %.3f, quartered %.3f)" % (
            (r["ssim_first"], r["first_stage"]) + r["ssim_first_coarse"]))
    if args.pause:
        print("first frame after a %.1f s pause  %s" % (args.pause, f("pause_delay")))
    if args.contend:
        ok = [t for s, t in cout if s == "ok"]
        print("contending stills           %d done (median %.1f s), %d refused" % (
            len(ok), pct(ok, 50) if ok else float("nan"), len(cout) - len(ok)))
    print("issue 42 targets            %s" % "; ".join(targets(r)))
    moving = cost_summary(r["moving_frames"])
    ms = lambda c, k: "%.1f" % c[k]["mean"] if c.get(k) else "-"  # noqa: E731
    print("moving frames, mean ms      render %s, GPU passes %s, read-back %s, JPEG encode %s (%s, %d frames)" % (
        ms(moving, "render_ms"), ms(moving, "gpu_ms"), ms(moving, "readback_ms"), ms(moving, "encode_ms"),
        moving.get("size", "-"), moving["count"]))
    y1 = yield_metrics(base, token)
    if y1:
        d = {k: y1.get(k, 0) - y0.get(k, 0) for k in YIELD_METRICS}
        print("yielding                    %d stills pre-empted by input, %d waits of large renders (%.1f s)" % (
            d["lucent_frames_yielded_total"], d["lucent_yield_waits_total"], d["lucent_yield_wait_seconds_total"]))
    if args.json:
        out = {"dataset": args.dataset, "width": args.width, "height": args.height, "rate": args.rate,
               "seconds": args.seconds, "window": args.window,
               "frames_per_s": r["moving"] / r["orbit_s"], "input_to_frame_ms": {
                   "p50": 1000 * pct(r["lat"], 50) if r["lat"] else None,
                   "p95": 1000 * pct(r["lat"], 95) if r["lat"] else None, "samples": len(r["lat"])},
               "moving": moving, "still_frame": r.get("still_frame"), "moving_detail": r.get("moving_detail"),
               "ssim_coarse": r.get("ssim_coarse"), "ssim_first": r.get("ssim_first"), "targets": targets(r)}
        for k in ("first", "first_still", "first_final", "still", "full", "converged", "ssim", "pause_delay"):
            out[k + ("" if k == "ssim" else "_s")] = r.get(k)
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)


FLOW_LINE = re.compile(r"flow (\S+) (begin|done|sent|ack) (\d+)(.*)")


def trace_breakdown(traces, daemon):
    """Where each orbit frame's input-to-frame time went, from the client's times and the daemon's "flow" lines
    (one clock: both on this host, CLOCK_MONOTONIC). For each frame that showed a newer camera: wait (the camera's
    arrival, RTT/2 after it was sent, to its frame's render start), render, encode (render end to the hand-over to
    the connection), link (hand-over to arrival at the client less RTT/2: the transfer, any queue, the proxy's and
    client's own time). Prints the mean over all such frames and over those at or above 97 % of the p95 (the tail),
    with the moving frames' render times of reused against re-optimized opacities (P1-P3 run again every 1-3 s), and
    what the tail's frames were: the drag's first moving frame, one that re-optimized, or another."""
    srv = {}
    for line in daemon:
        m = FLOW_LINE.search(line)
        if m:
            kv = m.group(4).split()
            srv.setdefault(m.group(1), {}).setdefault(int(m.group(3)), {})[m.group(2)] = {
                k: float(v) for k, v in zip(kv[0::2], kv[1::2])}
    print("| link | frames | part | input-to-frame | wait | render | encode | link (less RTT/2) | bytes |")
    print("|---|---|---|---|---|---|---|---|---|")
    for tr in traces:
        frames, ev = srv.get(tr["session"], {}), tr["events"]
        half = tr["rtt_ms"] / 2000.0
        cam = {e["seq"]: e["t"] for e in ev if e["ev"] == "camera"}
        end = min([e["t"] for e in ev if e["ev"] == "release"] or [float("inf")])
        rows, answered = [], 0
        first = next((e["frame"] for e in ev if e["ev"] == "frame" and e["moving"]), None)
        for e in ev:
            if e["ev"] != "frame" or e["t"] > end or e["seq"] <= answered or e["seq"] not in cam:
                continue
            answered = e["seq"]
            f = frames.get(e["frame"], {})
            if not all(k in f for k in ("begin", "done", "sent")):
                continue
            tb, td, ts = f["begin"]["at"], f["done"]["at"], f["sent"]["at"]
            rows.append({"lat": e["t"] - cam[e["seq"]], "wait": tb - cam[e["seq"]] - half, "render": td - tb,
                         "encode": ts - td, "link": e["t"] - ts - half, "bytes": e["bytes"],
                         "kind": "first" if e["frame"] == first else "re-optimized" if e.get("reused") is False
                         else "other"})
        if not rows:
            continue
        p95 = pct([r["lat"] for r in rows], 95)
        for part, sel in (("all", rows), ("tail", [r for r in rows if r["lat"] >= 0.97 * p95])):
            mean = lambda k: sum(r[k] for r in sel) / len(sel)  # noqa: E731
            print("| %s | %d | %s | %.0f ms | %.0f | %.0f | %.0f | %.0f | %.1f KB |" % (
                tr["link"], len(sel), part, 1000 * mean("lat"), 1000 * mean("wait"), 1000 * mean("render"),
                1000 * mean("encode"), 1000 * mean("link"), mean("bytes") / 1000))
        tail = [r["kind"] for r in rows if r["lat"] >= 0.97 * p95]
        print("  %s: the tail's frames: %d the drag's first, %d re-optimized, %d other" % (
            tr["link"], tail.count("first"), tail.count("re-optimized"), tail.count("other")))
        moving = [e for e in ev if e["ev"] == "frame" and e["moving"] and e["t"] <= end]
        for name, sel in (("reused", [e for e in moving if e.get("reused")]),
                          ("re-optimized", [e for e in moving if e.get("reused") is False])):
            if sel:
                print("  %s: %d moving frames with %s opacities, render %.0f ms mean" % (
                    tr["link"], len(sel), name, sum(e["renderMs"] for e in sel) / len(sel)))


def parse_link(text):
    """"RTT,MBIT" (ms, Mbit/s; MBIT 0 = no rate limit) or "loopback" -> (rtt_ms, mbit)."""
    if text == "loopback":
        return 0.0, 0.0
    rtt, _, mbit = text.partition(",")
    return float(rtt), float(mbit or 0)


def link_row(link, rtt, mbit, r):
    """One orbit's figures through one link."""
    mb = r["moving_bytes"]
    use = r["orbit_rx"] * 8 / r["orbit_s"] / 1e6
    st = r.get("orbit_stats") or {}
    return {"link": link.label(), "rtt_ms": rtt, "mbit": mbit, "frames_per_s": r["moving"] / r["orbit_s"],
            "p50_ms": 1000 * pct(r["lat"], 50), "p95_ms": 1000 * pct(r["lat"], 95),
            "still_s": r.get("still"), "full_s": r.get("full"),
            "moving_kb": sum(mb) / len(mb) / 1000 if mb else None,
            "moving_size": cost_summary(r["moving_frames"]).get("size"),
            "moving_quality": sum(r["moving_q"]) / len(r["moving_q"]) if r["moving_q"] else None,
            "still_quality": (r.get("still_frame") or {}).get("quality"),
            "link_mbit": use, "link_share": use / mbit if mbit else None,
            "window": st.get("window"), "rtt_est_ms": st.get("rttMs"),
            "link_est_mbit": st.get("linkMbps"), "link_measured": st.get("linkMeasured")}


def rate_at(frames, size):
    """Frames a second while the orbit drew frames of this size: the frames of that size over the time from
    the frame before each to it (while frames follow one another, the time to render it). Orbits that spend a
    different share of their time at a finer rung compare alike by it (the link's own cost shows as longer
    spacing at the same size)."""
    gaps = [b["at"] - a["at"] for a, b in zip(frames, frames[1:]) if b["size"] == size]
    return len(gaps) / sum(gaps) if gaps and sum(gaps) > 0 else None


def median_row(runs):
    """A link's rounds as one row: the median of each figure (the last round's for what is not a number)."""
    row = dict(runs[-1])
    for k, v in row.items():
        vals = [x[k] for x in runs if isinstance(x.get(k), (int, float)) and not isinstance(x.get(k), bool)]
        if vals and isinstance(v, (int, float)) and not isinstance(v, bool):
            row[k] = statistics.median(vals)
    return row


def run_links(ws_url, token, args):
    """The orbit once per --link, each through its own emulated link, --rounds times in turn (the links of
    a round side by side, so a ratio to loopback compares orbits a few seconds apart); prints a table of each
    link's medians over the rounds, and each round's frames/s as a share of that round's first link."""
    host, port = ws_url.split("//", 1)[1].split("/", 1)[0].rsplit(":", 1)
    runs, traces = {}, []
    if args.rounds > 1:
        # The daemon's first session pays its one-time costs (programs compiled, buffers grown) in the still
        # before its drag, and a drag starts at the rung that still's time predicts: coarser, so more frames
        # a second than the orbits after it. An uncounted orbit first keeps round 1 like the others.
        asyncio.run(browse(ws_url, token, args))
    for rnd in range(args.rounds):
        for spec in args.link:
            rtt, mbit = parse_link(spec)
            link = Link(rtt, mbit)
            proxied = "ws://127.0.0.1:%d/api/v1/ws" % link.start(host, int(port))
            try:
                r = asyncio.run(browse(proxied, token, args))
            finally:
                link.stop()
            row = link_row(link, rtt, mbit, r)
            sizes = [f["size"] for f in r["moving_frames"]]
            row["size_counts"] = {sz: sizes.count(sz) for sz in set(sizes)}
            row["rate_at"] = {sz: rate_at(r["moving_frames"], sz) for sz in set(sizes)}
            runs.setdefault(row["link"], []).append(row)
            print("  round %d, %s: %.1f frames/s (%d of %d moving frames at %s)" % (
                rnd + 1, row["link"], row["frames_per_s"], sizes.count(row["moving_size"]), len(sizes),
                row["moving_size"]), flush=True)
            traces.append({"link": link.label(), "rtt_ms": rtt, "round": rnd + 1, "session": r.get("session"),
                           "events": r["trace"]})
    rows = [median_row(v) for v in runs.values()]
    print("dataset %s, %dx%d, camera updates at %g/s for %g s%s%s; load %s" % (
        args.dataset, args.width, args.height, args.rate, args.seconds,
        ", window %d" % args.window if args.window else "",
        ", medians of %d rounds" % args.rounds if args.rounds > 1 else "", os.getloadavg()[0]))
    print("| link | frames/s | input-to-frame p50 / p95 | still after release | moving frame | link used | "
          "window, RTT (stats) | link estimate (stats) |")
    print("|---|---|---|---|---|---|---|---|")
    for w in rows:
        est = w["link_est_mbit"]
        print("| %s | %.1f | %.0f / %.0f ms | %s | %s | %s | %s | %s |" % (
            w["link"], w["frames_per_s"], w["p50_ms"], w["p95_ms"],
            "%.2f s (q %s)" % (w["still_s"], w["still_quality"]) if w["still_s"] is not None else "-",
            "%.1f KB (%s, q %.0f)" % (w["moving_kb"], w["moving_size"], w["moving_quality"]) if w["moving_kb"] else "-",
            "%.2f Mbit/s%s" % (w["link_mbit"], " (%.0f %%)" % (100 * w["link_share"]) if w["link_share"] else ""),
            "%s, %s ms" % (w["window"], w["rtt_est_ms"]) if w["window"] else "-",
            "-" if est is None else "%.2f Mbit/s %s" % (est, "measured" if w["link_measured"] else "carried (at least)")))
    base = list(runs)[0]
    if len(runs) > 1:
        print("frames/s as a share of the same round's %s:" % base)
        for label, rs in list(runs.items())[1:]:
            shares = [100 * x["frames_per_s"] / b["frames_per_s"] for x, b in zip(rs, runs[base]) if b["frames_per_s"]]
            print("  %s: %s (median %.0f %%)" % (label, ", ".join("%.0f %%" % v for v in shares),
                                                  statistics.median(shares) if shares else float("nan")))
        print("frames/s at the same size (rate_at) as a share of the same round's %s at that size:" % base)
        for label, rs in list(runs.items())[1:]:
            shares = []
            for x, b in zip(rs, runs[base]):
                common = [sz for sz, v in x["rate_at"].items() if v and b["rate_at"].get(sz)]
                if common:  # the size this orbit drew most of those both drew
                    sz = max(common, key=lambda z: x["size_counts"][z])
                    shares.append((sz, 100 * x["rate_at"][sz] / b["rate_at"][sz]))
            print("  %s: %s (median %.0f %%)" % (label, ", ".join("%.0f %% at %s" % (v, sz) for sz, v in shares),
                                                  statistics.median([v for _, v in shares]) if shares else float("nan")))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"dataset": args.dataset, "width": args.width, "height": args.height, "rate": args.rate,
                       "seconds": args.seconds, "window": args.window, "rounds": args.rounds, "links": rows,
                       "runs": runs}, f, indent=1)
    return traces


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", help="start this lucent binary (default: --url)")
    ap.add_argument("--url", default="http://127.0.0.1:8080")
    ap.add_argument("--token", default=os.environ.get("LUCENT_TOKEN", ""))
    ap.add_argument("--dataset", default="demo:tornado")
    ap.add_argument("--seconds", type=float, default=8, help="seconds of orbiting input")
    ap.add_argument("--width", type=int, default=972)
    ap.add_argument("--height", type=int, default=761)
    ap.add_argument("--window", type=int, default=0, help="the hello's window (default: none sent, the server's)")
    ap.add_argument("--verbose", action="store_true", help="print each frame received while orbiting (size, detail, render time)")
    ap.add_argument("--rate", type=float, default=30, help="camera updates per second")
    ap.add_argument("--orbit-seconds", type=float, default=12, help="seconds per full orbit")
    ap.add_argument("--pause", type=float, default=0, help="pause mid-drag for this many seconds")
    ap.add_argument("--contend", type=int, default=0, help="clients rendering large stills meanwhile")
    ap.add_argument("--contend-size", default="3840x2160")
    ap.add_argument("--timeout", type=float, default=120, help="seconds to wait for a first frame or a still")
    ap.add_argument("--server-args", default="", help="extra flags for the started daemon")
    ap.add_argument("--save", metavar="DIR", help="write the last moving frame and the still to DIR (moving.jpg, still.jpg)")
    ap.add_argument("--json", metavar="FILE", help="also write the figures to FILE as JSON")
    ap.add_argument("--trace", metavar="FILE", help="with --link and --binary: write each frame's client times "
                    "and the daemon's per-frame flow lines (started with --log-level debug) to FILE as JSON")
    ap.add_argument("--link", action="append", metavar="RTT,MBIT",
                    help="run through an emulated link of RTT ms and MBIT Mbit/s ('loopback': none); repeatable")
    ap.add_argument("--rounds", type=int, default=1, help="with --link: run the links in turn this many times; "
                    "the table gives medians, and each round's share of the first link's frames/s")
    args = ap.parse_args()
    if websockets is None:
        sys.exit("python3-websockets is required")
    if args.binary:
        extra = args.server_args.split() if args.server_args else []
        if args.trace:
            extra += ["--log-level", "debug"]
        launched = time.time()
        with Server(args.binary, *extra, data=(args.dataset,), demo_size=0, timeout=600) as srv:
            if args.link:
                traces = run_links(srv.ws_url, args.token, args)
                if args.trace:  # the daemon's per-frame lines (--log-level debug) beside the client's
                    daemon = [line.rstrip() for line in srv.log if " flow " in line]
                    with open(args.trace, "w") as f:
                        json.dump({"links": traces, "daemon": daemon}, f)
                    trace_breakdown(traces, daemon)
            else:
                run(srv.base, srv.ws_url, args.token, args, launched, time.time())
            srv.stop()
    else:
        ws_url = args.url.replace("http://", "ws://").rstrip("/") + "/api/v1/ws"
        if args.link:
            run_links(ws_url, args.token, args)
        else:
            run(args.url.rstrip("/"), ws_url, args.token, args)


if __name__ == "__main__":
    main()
