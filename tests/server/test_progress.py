"""Progress messages of WebSocket sessions against the real daemon: a slow
first frame (the exact method at 1024x1024 on the tornado demo, on a server
that sleeps --pass-delay before every pass, so that it is slow on any machine)
brings progress messages of the documented shape, at a bounded rate, with
stages in pass order and a fraction that never decreases, and they stop once
the frame is there; a still after a camera move reports its passes again; a
small fast session gets only messages that its frames earned (each one says
it was sent after 300 ms of waiting) and none once its stream has ended; the
default number of render workers follows docs/GUIDE.md's rule.

Nothing here depends on how fast the machine is: the waits are for states
(a converged frame, the end of a stream), and the timing rules of the
messages are checked against the messages' own `elapsed` (the server's
clock), not against when they arrived."""
import asyncio
import json
import os
import sys
import time

from lucent_server import (Check, Server, listen, skip, stream_done, wait_for_message, wait_for_stream_done,
                           websockets)

if websockets is None:
    skip("python3-websockets is not installed")

binary = sys.argv[1]
check = Check()

# protocol/websocket.md "progress": the stages in the order a frame goes through them.
STAGES = ["queued", "prepare", "depthRange", "importance", "opacity", "smooth", "opticalDepth", "accumulate",
          "resolve", "readback", "encode"]
SLOW = {"type": "hello", "dataset": "demo:tornado", "width": 1024, "height": 1024, "devicePixelRatio": 1,
        "method": "exact"}


def check_run(run, what, arrived, t_input, since_hello, least):
    """One frame's progress messages (in arrival order): shape, rate, order,
    fractions. arrived maps id(message) to its arrival (time.monotonic());
    t_input is when the client sent what the frame answers (hello, camera).
    The rate and the 300 ms rule are checked on the messages' own `elapsed`:
    the server's clock, which a busy client cannot bunch up or spread out."""
    if not check(len(run) >= least, "%s: at least %d progress messages before the frame (%d)"
                 % (what, least, len(run))):
        return
    for m in run:
        ok = (set(m) == {"type", "stage", "fraction", "elapsed"} and m["stage"] in STAGES
              and (m["fraction"] is None or (isinstance(m["fraction"], (int, float)) and 0 <= m["fraction"] <= 1))
              and isinstance(m["elapsed"], (int, float)) and m["elapsed"] >= 0.3)
        check(ok, "%s: message of the documented shape, sent after 300 ms of waiting: %s" % (what, m))
    stages = [STAGES.index(m["stage"]) for m in run if m["stage"] in STAGES]
    check(stages == sorted(stages), "%s: stages in the frame's order: %s" % (what, [m["stage"] for m in run]))
    fr = [m["fraction"] for m in run]
    known = [f for f in fr if f is not None]
    check(known == sorted(known) and None not in fr[len(fr) - len(known):],
          "%s: fraction never decreases, null only before it is known: %s" % (what, fr))
    if since_hello:
        check(any(f is not None and 0 < f < 1 for f in fr), "%s: a pass in the middle is reported: %s" % (what, fr))
    el = [m["elapsed"] for m in run]
    check(el == sorted(el), "%s: elapsed grows: %s" % (what, el))
    # The messages of one frame share its start, so the differences of their
    # elapsed are the server's spacing of them (elapsed is rounded to 1 ms).
    gaps = [round(b - a, 3) for a, b in zip(el, el[1:])] or [1]
    check(min(gaps) >= 0.249, "%s: at most one message every 250 ms (elapsed steps %s)" % (what, gaps))
    # elapsed counts from the input the client sent (hello for the first
    # frame), which the server saw after the client sent it, and the message
    # was made before it arrived: never more than the client's own count.
    over = [(m["elapsed"], round(arrived[id(m)] - t_input, 3)) for m in run
            if m["elapsed"] > arrived[id(m)] - t_input + 0.001]
    check(not over, "%s: elapsed counts from %s: never more than the client waited (elapsed, waited): %s"
          % (what, "hello" if since_hello else "the camera move", over))


def arrivals():
    """A `done` wrapper for wait_for_message that notes when each message arrived."""
    arrived = {}

    def note(done):
        def f(m):
            arrived[id(m)] = time.monotonic()
            return done(m)
        return f
    return arrived, note


async def slow(srv):
    """The server sleeps --pass-delay before every pass: the first frame, the
    moving frame after the camera move and its still each take several times
    that, so each is awaited well past 300 ms and brings progress messages."""
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        arrived, note = arrivals()
        t_hello = time.monotonic()
        await ws.send(json.dumps(SLOW))
        ready = json.loads(await asyncio.wait_for(ws.recv(), 60))
        check(ready.get("type") == "ready", "hello -> ready (%s)" % ready.get("type"))
        got = await wait_for_message(ws, note(stream_done), 120)  # the frames until the stream ends
        check(got.reached, "the stream converged (its last frame: converged, a still, final)")
        kinds = [m["type"] for m in got]
        check("frame" in kinds, "the frames came: %s" % kinds)
        check(set(kinds) <= {"frame", "progress"}, "only frames and progress messages: %s" % set(kinds))
        first = kinds.index("frame") if "frame" in kinds else len(kinds)
        run = got[:first]
        print("first frame after %d progress messages: %s" % (len(run), [(m["stage"], m["fraction"], m["elapsed"])
                                                                           for m in run]))
        check_run(run, "first frame", arrived, t_hello, True, 2)
        # The stream has ended: no frame is under way, so a correct server sends
        # nothing more; 1 s is plenty for a stray message (they come every 250 ms).
        after = await listen(ws, 1.0)
        check(not after, "no progress message after the last frame: %s" % after)

        # A camera move: an interactive frame, then the still of the new camera, slow again.
        t_move = time.monotonic()
        await ws.send(json.dumps({"type": "camera", "seq": 1, "camera": {"position": [0.6, 0.5, 3.0],
                                  "focalPoint": [0.5, 0.5, 0.5], "viewUp": [0, 1, 0]}}))
        got = await wait_for_message(ws, note(lambda m: stream_done(m) and m["cameraSeq"] == 1), 120)
        check(got.reached, "the stream of the moved camera ends with a converged still")
        frames = [i for i, m in enumerate(got) if m["type"] == "frame"]
        stills = [i for i in frames if not (got[i].get("detail") or {}).get("interactive", False)]
        check(bool(stills), "a still frame after the camera move")
        if stills:
            before = [i for i in frames if i < stills[0]]
            run = got[(before[-1] + 1 if before else 0):stills[0]]
            check(all(m["type"] == "progress" for m in run), "only progress before the still")
            print("still after %d progress messages: %s" % (len(run), [(m["stage"], m["fraction"]) for m in run]))
            check_run(run, "still", arrived, t_move, False, 1)
            check(all(m["stage"] != "queued" for m in run), "no 'queued' stage after the first frame")
        after = await listen(ws, 1.0)
        check(not after, "nothing after the still that ended the stream: %s" % after)


async def fast(srv):
    """A small opaque session on a server without --pass-delay: its frames
    (after the first, which compiles shaders) usually come well under 300 ms.
    Whether one of them takes longer is up to the machine, so what is checked
    is what the server cannot get wrong however fast it is: every progress
    message that does come was sent after its frame had been awaited 300 ms
    (its own elapsed), has the documented shape and comes before its frame,
    and none comes once the stream has ended."""
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        await ws.send(json.dumps({"type": "hello", "dataset": "demo:points", "width": 32, "height": 32,
                                  "method": "opaque"}))
        await asyncio.wait_for(ws.recv(), 60)
        got = await wait_for_stream_done(ws, deadline=120)
        check(got.reached and any(m["type"] == "frame" for m in got), "the fast session gets frames")
        progress = [m for m in got if m["type"] == "progress"]
        for seq in range(1, 6):
            await ws.send(json.dumps({"type": "camera", "seq": seq, "camera": {
                "position": [0.5, 0.5, 2.0 + 0.1 * seq], "focalPoint": [0.5, 0.5, 0.5], "viewUp": [0, 1, 0]}}))
            got = await wait_for_stream_done(ws, lambda h, seq=seq: h["cameraSeq"] == seq, deadline=120)
            check(got.reached, "camera %d: the stream ends with a converged still of it" % seq)
            progress += [m for m in got if m["type"] == "progress"]
            check(set(m["type"] for m in got) <= {"frame", "progress"}, "camera %d: only frames and progress "
                  "messages: %s" % (seq, [m["type"] for m in got]))
            # The stream has ended: nothing is under way, so no progress message
            # may come; a listen of 0.5 s (two of their 250 ms intervals) cannot
            # fail on a slow machine, only on a server that sends one.
            after = await listen(ws, 0.5)
            check(not after, "camera %d: nothing once the stream ended: %s" % (seq, after))
        bad = [m for m in progress if not (set(m) == {"type", "stage", "fraction", "elapsed"} and m["stage"] in STAGES
                                           and isinstance(m["elapsed"], (int, float)) and m["elapsed"] >= 0.3)]
        check(not bad, "progress messages of the fast session (%d, each sent after 300 ms of waiting by its own "
              "elapsed): %s" % (len(progress), bad or [(m["stage"], m["elapsed"]) for m in progress]))


def main():
    with Server(binary, data=("demo:points",)) as srv:  # 3000 points
        asyncio.run(fast(srv))
        # docs/GUIDE.md "--workers": 2 by default, 1 on llvmpipe with under 8 GiB of memory
        _, _, health = srv.json("GET", "/api/v1/health")
        memory = os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGESIZE")
        software = "llvmpipe" in health.get("renderer", "") or "softpipe" in health.get("renderer", "")
        want = 1 if software and memory < (8 << 30) else 2
        check(any("%d render worker(s)" % want in line for line in srv.log),
              "default worker count %d (%s, %.1f GiB)" % (want, health.get("renderer"), memory / 2 ** 30))
    # --pass-delay 300: every pass of every frame waits 300 ms first, so each of
    # the slow session's frames takes over 2 s (the exact method plans seven
    # passes here) on any machine: its progress messages (the first after
    # 300 ms, then one every 250 ms) are certain, not a guess at speed.
    with Server(binary, "--pass-delay", "300", data=("demo:tornado",), demo_size=0) as srv:
        asyncio.run(slow(srv))
    check.done()


main()
