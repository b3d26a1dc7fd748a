#!/usr/bin/env python3
"""Surface sessions against the memory budget (prints figures; not part of the pass/fail suite).

Opens WebSocket surface sessions (method surface-layers, the field's default surface) one after another on
a daemon started with --max-memory, keeping each open, until one is refused; after each it prints what the
frame ended with, the bytes the surfaces hold (/api/v1/health memory.held.surfaces), the budget's estimate
and the daemon's resident memory; after the refusal, whether the first session still redraws its surface on
a camera move (docs/ALGORITHM.md §33 "Memory held by requests").

  tests/bench/surface_memory_bench.py --binary build/lucent [--max-memory 256M] [--sessions 15]
"""
import argparse
import asyncio
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "server"))
from lucent_server import Server, wait_for_message, websockets  # noqa: E402

SEED = [[0.3, 0.5, 0.1], [0.7, 0.5, 0.1]]
CAMERA = {"position": [0.5, -3, 0.5], "focalPoint": [0.5, 0.5, 0.5], "viewUp": [0, 0, 1]}


def ended(m):
    return m["type"] == "error" or (m["type"] == "frame" and m.get("converged"))


async def run(srv, sessions):
    opened = []
    for i in range(sessions):
        ws = await websockets.connect(srv.ws_url, max_size=None)
        await ws.send(json.dumps({"type": "hello", "width": 256, "height": 256, "method": "surface-layers",
                                  "surface": {"field": "demo:tornado-flow", "seed": SEED}}))
        got = await wait_for_message(ws, ended, skip=("stats", "progress"), deadline=300)
        m = got[-1] if got else {}
        _, _, h = srv.json("GET", "/api/v1/health")
        mem = h["memory"]
        what = m.get("message", "") if m.get("type") == "error" else "%s curves" % m.get("surface", {}).get("curves")
        print("session %2d: %-5s %s | held %.1f MB, estimated %.1f MB of %s, resident %.0f MB" %
              (i + 1, m.get("type"), what, mem["held"]["surfaces"] / 1e6, mem["estimated"] / 1e6,
               "%.1f MB" % (mem["budget"] / 1e6) if mem["budget"] else "no budget", srv.rss_kb() / 1e3), flush=True)
        opened.append(ws)
        if m.get("type") == "error":
            await opened[0].send(json.dumps({"type": "camera", "seq": 1, "camera": CAMERA}))
            g = await wait_for_message(opened[0], lambda x: ended(x) and x.get("cameraSeq") == 1,
                                       skip=("stats", "progress"))
            print("session 1 redraws its surface after the refusal: %s" % g.reached)
            break
    for ws in opened:
        await ws.close()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--binary", default="build/lucent")
    ap.add_argument("--max-memory", default="256M")
    ap.add_argument("--sessions", type=int, default=15, help="at most (the daemon allows 16 per client)")
    a = ap.parse_args()
    if websockets is None:
        sys.exit("python3-websockets is not installed")
    with Server(a.binary, "--max-memory", a.max_memory, data=("demo:points", "demo:tornado-flow")) as srv:
        print("resident before: %.0f MB" % (srv.rss_kb() / 1e3))
        asyncio.run(run(srv, a.sessions))


if __name__ == "__main__":
    main()
