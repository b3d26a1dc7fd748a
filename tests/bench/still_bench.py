#!/usr/bin/env python3
"""Where a session's still goes (prints figures; not part of the pass/fail suite).

Starts `lucent serve --data FILE` with every server option at its default, opens one WebSocket session with
defaults at the page's 972x761 and sends no input. Prints each frame until the stream is done: seconds from
hello, size, whether it is interactive (the coarse first frame), its stage and final flag, converged, the
frame's render time (detail.renderMs), level of detail, line stride, reused opacities, the clarity factor
and whether it reached its goal, the top-decile opacity and the per-pass milliseconds,
then the time from hello to the first picture and to the final still (issue 49: <= 2 s and <= 3 s on 2 M
segments).

  tests/bench/still_bench.py build/lucent build/real-data/lammps/lj_melt.dump [--size 972x761]
        [--server-args "..."] [--env NAME=VALUE ...] [--one-shot]
With --one-shot it then renders the same request (dataset and size) over HTTP and prints the X-Lucent headers
(the passes' times), side by side with the session's still.
"""
import argparse
import asyncio
import json
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "server"))
from lucent_server import Server, interactive, served_name, stream_done, unpack_frame, websockets  # noqa: E402


def pick(h, *path):
    for p in path:
        h = h.get(p) if isinstance(h, dict) else None
    return h


async def session(srv, name, w, h, timeout):
    rows = []
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        t0 = time.monotonic()
        await ws.send(json.dumps({"type": "hello", "dataset": name, "width": w, "height": h, "devicePixelRatio": 1}))
        while True:
            try:
                m = await asyncio.wait_for(ws.recv(), timeout)
            except asyncio.TimeoutError:
                print("no message within %.0f s" % timeout)
                break
            t = time.monotonic() - t0
            if isinstance(m, str):
                msg = json.loads(m)
                if msg.get("type") == "error":
                    print("error: %s" % msg)
                    break
                if msg.get("type") == "ready":
                    print("%7.2f s  ready: params %s" % (t, json.dumps(pick(msg, "defaults", "params"))[:400]))
                elif msg.get("type") in ("warning", "notice"):
                    print("%7.2f s  %s: %s" % (t, msg["type"], json.dumps(msg)[:600]))
                continue
            hd, img = unpack_frame(m)
            await ws.send(json.dumps({"type": "ack", "frame": hd["frame"]}))
            hd["type"] = "frame"
            rows.append((t, hd, len(img)))
            tm = hd.get("timings") or {}
            print("%7.2f s  %4dx%-4d %-5s stage %s/%s final %-5s converged %-5s render %7s ms  level %s  lineStride %s  "
                  "reused %-5s  clarity lambda x%s reached %s  top-decile %s  passes %s" %
                  (t, hd.get("width", 0), hd.get("height", 0), "move" if interactive(hd) else "still",
                   hd.get("stage"), hd.get("stages"), hd.get("final"), hd.get("converged"),
                   pick(hd, "detail", "renderMs"), pick(hd, "detail", "level"), pick(hd, "detail", "lineStride"),
                   pick(hd, "detail", "reusedOpacities"), pick(hd, "clarity", "lambdaFactor"),
                   pick(hd, "clarity", "reached"), pick(hd, "visibility", "topDecileAlpha"),
                   " ".join("%s %.0f" % (k, v) for k, v in tm.items() if isinstance(v, (int, float)))))
            if stream_done(hd):
                break
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("binary")
    ap.add_argument("dataset")
    ap.add_argument("--size", default="972x761")
    ap.add_argument("--server-args", default="")
    ap.add_argument("--env", action="append", default=[], help="NAME=VALUE for the daemon")
    ap.add_argument("--timeout", type=float, default=300)
    ap.add_argument("--one-shot", action="store_true", help="then render the same request over HTTP")
    args = ap.parse_args()
    w, h = (int(x) for x in args.size.split("x"))
    env = dict(e.split("=", 1) for e in args.env)
    env.setdefault("LUCENT_LOG_LEVEL", "debug")  # the clarity loop's tries per frame (render/gl/clarity.c)
    with Server(args.binary, *args.server_args.split(), data=(args.dataset,), demo_size=0, env=env,
                timeout=600) as srv:
        rows = asyncio.run(session(srv, served_name(args.dataset), w, h, args.timeout))
        for line in srv.log:  # what the daemon chose for the session (params.subset) and the clarity loop's tries
            if "opens with params.subset" in line or "clarity:" in line:
                print("  log: %s" % line.strip()[:300])
        if args.one_shot:  # the same request over HTTP, for the passes' times side by side
            t0 = time.monotonic()
            st, hdrs, body = srv.request("POST", "/api/v1/render",
                                         {"dataset": served_name(args.dataset), "width": w, "height": h,
                                          "format": "png"}, timeout=args.timeout)
            print("one-shot POST /api/v1/render: %d in %.2f s%s" %
                  (st, time.monotonic() - t0, "" if st == 200 else ": " + body[:300].decode(errors="replace")))
            for k, v in sorted(hdrs.items()):
                if k.startswith("x-lucent"):
                    print("  %s: %s" % (k, v[:400]))
    if rows:
        print("first picture %.2f s after hello, final still %.2f s (%d frames)" % (rows[0][0], rows[-1][0], len(rows)))
    print("load: %s" % open("/proc/loadavg").read().strip())


if __name__ == "__main__":
    main()
