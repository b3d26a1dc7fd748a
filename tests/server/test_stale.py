"""No stale frame after the last input, through an emulated wide-area link
(tests/bench/link_proxy.py: 100 ms round trip, 4 Mbit/s): a WebSocket client
orbits the camera (a message every 30 ms), acking each frame as it arrives,
then stops and waits for the stream to end.

The server takes a frame only while fewer than its window are unacknowledged,
the hello's window is the window's ceiling, and the acks the client sent
before its last camera message reach the server before it (one socket, in
order). So at most `ceiling` frames can have been taken before the last
camera arrived beyond the newest frame acked before it was sent (A): every
frame with an id above A + ceiling was taken after, and must show the last
camera. The checks: the first such frame and every later one carry the last
cameraSeq (with a ceiling of 2 the still is always one), at most `ceiling`
frames in between, no frame shows an older camera than the frame before it
(in id order), and the stream ends with a full still of the last camera.
Twice: a ceiling of 2, and none (8: the window follows the round trip).
Nothing here waits for a time: the orbit sends at its pace, the checks read
frame headers."""
import asyncio
import json
import math
import os
import sys

from lucent_server import DEADLINE, Check, Server, skip, stream_done, unpack_frame, websockets

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bench"))
from link_proxy import Link  # noqa: E402

if websockets is None:
    skip("python3-websockets is not installed")

binary = sys.argv[1]
check = Check()
CAMERAS = 40


def camera(seq):
    a = 0.05 * seq
    pos = [0.5 + 1.8 * math.cos(a), 0.5, 0.5 + 1.8 * math.sin(a)]
    return json.dumps({"type": "camera", "seq": seq,
                       "camera": {"position": pos, "focalPoint": [0.5, 0.5, 0.5], "viewUp": [0, 1, 0]}})


async def orbit(ws_url, ceiling):
    frames = []  # headers in arrival order
    acked = {"id": 0}
    done = asyncio.Event()

    async def receive():
        while True:
            m = await asyncio.wait_for(ws.recv(), DEADLINE)
            if isinstance(m, str):
                if json.loads(m).get("type") not in ("stats", "progress"):
                    check(False, "no error during the orbit (%s)" % m[:200])
                continue
            h, _ = unpack_frame(m)
            frames.append(h)
            await ws.send(json.dumps({"type": "ack", "frame": h["frame"]}))
            acked["id"] = h["frame"]
            if done.is_set() and h["cameraSeq"] == CAMERAS and stream_done(dict(h, type="frame")):
                return

    async with websockets.connect(ws_url, max_size=None) as ws:
        await ws.send(json.dumps({"type": "hello", "dataset": "demo:points", "width": 320, "height": 240,
                                  "window": ceiling}))
        ready = json.loads(await asyncio.wait_for(ws.recv(), DEADLINE))
        check(ready.get("type") == "ready", "ready through the link (%s)" % ready.get("type"))
        task = asyncio.ensure_future(receive())
        for seq in range(1, CAMERAS + 1):
            if seq == CAMERAS:
                last_acked = acked["id"]  # sent before the last camera, so the server has it first
                done.set()
            await ws.send(camera(seq))
            await asyncio.sleep(0.030)
        await asyncio.wait_for(task, DEADLINE)
    return frames, last_acked


def judge(frames, last_acked, ceiling, tight):
    name = "ceiling %d: " % ceiling
    ids = [h["frame"] for h in frames]
    seqs = [h["cameraSeq"] for h in frames]
    check(ids == sorted(ids) and len(set(ids)) == len(ids), name + "frames arrive in id order, each once: %s" %
          ["%d%s" % (h["frame"], "m" if (h.get("detail") or {}).get("interactive") else "s") for h in frames])
    check(seqs == sorted(seqs), name + "no frame shows an older camera than the one before it: %s" % seqs)
    bound = last_acked + ceiling
    after = [h for h in frames if h["frame"] > bound]
    if tight:
        check(len(after) >= 1, name + "frames taken after the last camera came (%d, ids above %d)" %
              (len(after), bound))
    if after:
        check(after[0]["cameraSeq"] == CAMERAS,
              name + "the first frame taken after the last camera shows it (frame %d, cameraSeq %d of %d)" %
              (after[0]["frame"], after[0]["cameraSeq"], CAMERAS))
        check(all(h["cameraSeq"] == CAMERAS for h in after), name + "and every later one: %s" %
              [h["cameraSeq"] for h in after])
    in_flight = [h["cameraSeq"] for h in frames if last_acked < h["frame"] <= bound]
    check(len(in_flight) <= ceiling, name + "at most %d frames taken before it came: %s" % (ceiling, in_flight))
    still = frames[-1]
    check(still["cameraSeq"] == CAMERAS and not (still.get("detail") or {}).get("interactive") and
          still["quality"] == 90 and still["width"] == 320,
          name + "the stream ends with a full still of the last camera (q %d, %d px wide)" %
          (still["quality"], still["width"]))


async def main():
    with Server(binary) as srv:
        link = Link(rtt_ms=100, mbit=4)
        port = link.start(srv.host, srv.port)
        try:
            for ceiling in (2, 8):
                frames, last_acked = await orbit("ws://127.0.0.1:%d/api/v1/ws" % port, ceiling)
                judge(frames, last_acked, ceiling, ceiling == 2)
        finally:
            link.stop()


asyncio.run(main())
check.done()
