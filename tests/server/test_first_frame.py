"""Coarse to fine on a large dataset (issue 35): a WebSocket session's first
frame on 500,000 points or more is an interactive frame at the coarse end of
the detail ladder (every 64th point, 0.35 of the viewport's width), and
the full-resolution still of the same camera follows without any input; on a
small dataset the first frame is the still itself."""
import asyncio
import json
import sys

from lucent_server import Check, Server, unpack_frame, websockets

binary = sys.argv[1]
check = Check()
W, H = 320, 240


async def frames_until_still(srv, dataset):
    """Every frame header from hello to the first still (not interactive)."""
    got = []
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        # opaque: the ladder is the method's business only through what it draws, and the
        # opaque frames keep the test short (no fading frames after the still)
        await ws.send(json.dumps({"type": "hello", "dataset": dataset, "width": W, "height": H,
                                  "devicePixelRatio": 1, "method": "opaque"}))
        while True:
            m = await asyncio.wait_for(ws.recv(), 120)
            if isinstance(m, str):
                continue
            h, img = unpack_frame(m)
            await ws.send(json.dumps({"type": "ack", "frame": h["frame"]}))
            got.append(h)
            if not (h.get("detail") or {}).get("interactive", False):
                return got


async def main():
    with Server(binary, data=("demo:points",), demo_size=500000) as srv:
        got = await frames_until_still(srv, "demo:points")
        first, still = got[0], got[-1]
        d = first.get("detail") or {}
        check(len(got) >= 2 and d.get("interactive") is True, "the first frame is interactive: %s" % d)
        # points: stride 64 (7,812 of the 500,000 stay above the floor of 4,096), and the thinned
        # scale 0.7 of the default interactiveScale 0.5
        check(d.get("pointStride") == 64 and first["width"] <= int(W * 0.35) + 1,
              "the coarse end of the ladder: stride %s, %dx%d" % (d.get("pointStride"), first["width"],
                                                                 first["height"]))
        check(still["width"] == W and still["height"] == H and still["cameraSeq"] == first["cameraSeq"],
              "the full-resolution still follows without input: %dx%d" % (still["width"], still["height"]))
        check(all(h["cameraSeq"] == 0 for h in got), "no camera was sent")
        check(srv.stop() == 0, "the daemon exits cleanly")
    # the count given with the demo's name (serve --data demo:NAME?count=N), over --demo-size
    with Server(binary, data=("demo:points?count=3000",), demo_size=600000) as srv:
        status, _, listing = srv.json("GET", "/api/v1/datasets")
        items = [d for d in (listing or {}).get("datasets", []) if d.get("name") == "demo:points?count=3000"]
        check(status == 200 and len(items) == 1 and items[0].get("vertices") == 3000,
              "demo:points?count=3000 is served under that name with 3000 points: %s"
              % [(d.get("name"), d.get("vertices")) for d in items])
        got = await frames_until_still(srv, "demo:points?count=3000")
        check(len(got) == 1 and got[0]["width"] == W, "a small dataset's first frame is the still")
        check(srv.stop() == 0, "the daemon exits cleanly")


asyncio.run(main())
check.done()
