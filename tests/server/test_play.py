"""Playing a time window against the real daemon (issue 27): steps of t at 5 a second, each a `params`
message with time.window and a camera message in one burst, as the page's Play sends them. Input that
keeps coming at a steady pace must not start a still between two steps (the session waits 1.5 times the
recent spacing of input before a still: docs/GUIDE.md's --still-delay): no still frame of a step arrives and
no still is begun and abandoned (/metrics lucent_frames_yielded_total) while the steps keep their pace,
frames keep coming, and after the last step the still of the last window follows. The first step is
excused (no pace is known before the second: its still may begin after --still-delay), and so is a step
whose successor reached the daemon late: by the server's own rule (1.5 times the running mean of the
spacing) applied to the times the daemon read the steps from its socket, which it logs at debug level
("flow SESSION input camera seq K at T", CLOCK_MONOTONIC as time.monotonic here). A busy host delays the
client, the link and the daemon's reading alike; the daemon can only keep the pace it sees. Abandoned
stills are counted from the first frame of the second step on, when the pace is known (however often the
first step's still was begun and given up before it).

The rule under test is one of time (the pace of input), so this test cannot be free of the clock; what
it does not do is assume a fast machine: the steps go on at 5 a second until enough frames came while
playing (a state), and every step the client itself sent late is excused."""
import asyncio
import json
import os
import re
import sys
import tempfile
import time

from lucent_server import Check, Server, served_name, skip, unpack_frame, websockets

if websockets is None:
    skip("python3-websockets is not installed")

binary = sys.argv[1]
check = Check()
W, H = 320, 240
STEPS, RATE = 20, 5.0  # at least STEPS steps, RATE a second, and on until MIN_FRAMES frames came while playing
MIN_FRAMES = STEPS // 4
SLACK = 0.005  # seconds: the log's rounding and the daemon's own comparison
INPUT_LINE = re.compile(r"flow (\S+) input camera seq (\d+) at ([0-9.]+)")

# 30 atoms crossing the box along x over 20 frames, TIMESTEP = 10 x frame (tests/browser/scenes.mjs).
tmp = tempfile.mkdtemp(prefix="lucent-play-")
dump = os.path.join(tmp, "crossing.dump")
with open(dump, "w") as f:
    for fr in range(20):
        f.write("ITEM: TIMESTEP\n%d\nITEM: NUMBER OF ATOMS\n30\nITEM: BOX BOUNDS ff ff ff\n-20 20\n-20 20\n"
                "-20 20\nITEM: ATOMS id type xu yu zu\n" % (fr * 10))
        for a in range(30):
            f.write("%d 1 %.4f %.4f %.4f\n" % (a + 1, -18 + 1.8 * fr + 0.3 * (a % 7), -14.5 + a, 0.1 * a))
CAMERA = {"position": [0, 0, 80], "focalPoint": [0, 0, 0], "viewUp": [0, 1, 0], "viewAngle": 30}


def yielded(srv):
    status, _, body = srv.request("GET", "/metrics")
    for line in body.decode().splitlines() if status == 200 else []:
        parts = line.split()
        if len(parts) == 2 and parts[0] == "lucent_frames_yielded_total":
            return float(parts[1])
    return None


async def play(srv):
    frames = []  # (arrival time, header)
    session = {"id": None}

    async def recv(ws, timeout):
        try:
            m = await asyncio.wait_for(ws.recv(), timeout)
        except asyncio.TimeoutError:
            return None
        if isinstance(m, str):
            o = json.loads(m)
            if o.get("type") == "error":
                check(False, "no error message: %s" % o)
            if o.get("type") == "ready":
                session["id"] = o.get("session")
            return o
        h, _ = unpack_frame(m)
        frames.append((time.monotonic(), h))
        await ws.send(json.dumps({"type": "ack", "frame": h["frame"]}))
        return h

    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        await ws.send(json.dumps({"type": "hello", "dataset": served_name(dump), "width": W, "height": H,
                                  "devicePixelRatio": 1}))

        async def step(k, t):
            await ws.send(json.dumps({"type": "params", "time": {"window": [0, t]}}))
            await ws.send(json.dumps({"type": "camera", "seq": k, "camera": CAMERA}))

        # the first still of the window [0, 20], converged, and nothing after it
        await step(0, 20)
        end = time.monotonic() + 120
        while time.monotonic() < end:
            h = await recv(ws, end - time.monotonic())
            if h and "frame" in h and h["cameraSeq"] == 0 and h.get("converged") and \
                    not (h.get("detail") or {}).get("interactive") and h.get("final", True):
                break
        # the stream has ended: anything still coming (stats) is read before the play starts
        while await recv(ws, 1.0) is not None:
            pass
        y0, y2 = yielded(srv), None
        n0 = len(frames)
        sent = []
        start = time.monotonic()
        k, end = 0, start + 120
        while k < STEPS or len(frames) - n0 < MIN_FRAMES and time.monotonic() < end:
            k += 1
            sent.append(time.monotonic())
            await step(k, 20 + 8 * ((k - 1) % STEPS + 1))  # past STEPS the window starts over
            due = start + k / RATE
            while time.monotonic() < due:
                await recv(ws, max(0.0, due - time.monotonic()))
            # The pace is known from the second step on: count abandoned stills from the first frame of step
            # 2 (a state: the first step's still, excused, was abandoned or done before that frame was begun).
            if y2 is None and any(h.get("cameraSeq", 0) >= 2 for _, h in frames[n0:]):
                y2 = yielded(srv)
        y1 = yielded(srv)
        last_step = time.monotonic()
        # the last steps' frames, then the still of the last window
        still = None
        end = time.monotonic() + 120
        while time.monotonic() < end and still is None:
            h = await recv(ws, end - time.monotonic())
            if h and "frame" in h and h["cameraSeq"] == k and not (h.get("detail") or {}).get("interactive"):
                still = h
        return (frames[n0:], sent, y1 - y0 if y0 is not None and y1 is not None else None,
                y1 - y2 if y2 is not None and y1 is not None else None, last_step, still, session["id"])


def arrivals(log, session, steps):
    """The times the daemon read steps 1..steps' camera messages (its debug "flow" lines), or None where one
    is missing."""
    at = {}
    for line in log:
        m = INPUT_LINE.search(line)
        if m and m.group(1) == session:
            at[int(m.group(2))] = float(m.group(3))
    times = [at.get(k) for k in range(1, steps + 1)]
    return None if any(t is None for t in times) else times


def excused(sent):
    """The steps whose still may begin: the first (no pace known yet), and
    step k when step k+1 came late by the server's rule applied to the times
    in sent (a gap of 1.5 times the running mean of the earlier gaps, at most
    1 s; a gap of 1 s or more starts the mean afresh), less SLACK."""
    late, mean = {1}, 0.0
    for k in range(1, len(sent)):  # sent[k - 1]: step k, sent[k]: step k + 1
        gap = sent[k] - sent[k - 1]
        if not mean or gap >= min(1.5 * mean, 1.0) - SLACK:
            late.add(k)
        mean = 0.0 if gap >= 1.0 else 0.7 * mean + 0.3 * gap if mean else gap
    return late


async def main():
    with Server(binary, "--log-level", "debug", data=(dump,), demo_size=0) as srv:
        played, sent, aborted_all, aborted, last_step, still, session = await play(srv)
        arrived = arrivals(srv.log, session, len(sent))
        check(arrived is not None, "the daemon logged when it read each step (session %s)" % session)
        gaps = [b - a for a, b in zip(sent, sent[1:])]
        late = excused(arrived or sent)
        print("client's largest gap %.3f s; the daemon's %.3f s; late by the client's clock %s" % (
            max(gaps), max(b - a for a, b in zip(arrived, arrived[1:])) if arrived else float("nan"),
            sorted(excused(sent))))
        during = [h for t, h in played if t <= last_step]
        stills = [h for h in during if not (h.get("detail") or {}).get("interactive") and h["cameraSeq"] >= 1]
        unexcused = [h["cameraSeq"] for h in stills if h["cameraSeq"] not in late]
        print("steps sent over %.2f s (largest gap %.3f s, excused steps %s); %d frames while playing, "
              "stills %s, stills abandoned %s (%s from step 2's first frame on)"
              % (sent[-1] - sent[0], max(gaps), sorted(late), len(during), [h["cameraSeq"] for h in stills],
                 aborted_all, aborted))
        check(len(during) >= MIN_FRAMES, "frames keep coming while playing (%d for %d steps)" % (len(during),
                                                                                                 len(sent)))
        check(not unexcused, "no still of a step while the steps keep their pace (stills of steps %s)" % unexcused)
        check(aborted is not None and aborted <= len(late - {1}),  # at most one a late step from the second on
              "no still begun and abandoned while playing at a known pace (%s, %d late steps after the first)"
              % (aborted, len(late - {1})))
        check(still is not None, "the still of the last window follows the last step")
        check(srv.stop() == 0, "the daemon exits cleanly")


asyncio.run(main())
check.done()
