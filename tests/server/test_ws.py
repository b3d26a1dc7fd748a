"""WebSocket sessions against the real daemon: hello -> ready -> frames, the
unacknowledged-frame window, a coalesced camera burst, interactive then still
frames, frames stopping once converged, stats messages while frames flow and
once after, malformed and oversized messages while another session keeps
working, close frames on SIGTERM, and the detail of interactive frames (reused
opacities, coarser lines and resolution under a frame budget no frame meets,
then a full still frame of the last camera)."""
import asyncio
import json
import sys
import time

from lucent_server import (DEADLINE, Check, Server, jpeg_size, listen, skip, stream_done, unpack_frame,
                           wait_for_message, wait_for_stream_done, websockets)

if websockets is None:
    skip("python3-websockets is not installed")

binary = sys.argv[1]
check = Check()


def camera(seq, z):
    return json.dumps({"type": "camera", "seq": seq,
                       "camera": {"position": [0.5, 0.5, z], "focalPoint": [0.5, 0.5, 0.5], "viewUp": [0, 1, 0]}})


QUIET = ("stats", "progress")  # text messages that may come with any frame (a slow one brings progress)


def is_stats(m):
    return isinstance(m, str) and json.loads(m).get("type") in ("stats", "progress")


async def recv(ws, timeout, keep_stats=False):
    """The next message within timeout, or None. stats messages (which come
    about once a second while frames flow) are skipped unless keep_stats."""
    deadline = time.monotonic() + timeout
    while True:
        left = deadline - time.monotonic()
        if left <= 0:
            return None
        try:
            m = await asyncio.wait_for(ws.recv(), left)
        except asyncio.TimeoutError:
            return None
        if keep_stats or not is_stats(m):
            return m


async def hello(ws, **extra):
    msg = {"type": "hello", "dataset": "demo:points", "width": 48, "height": 40, "devicePixelRatio": 2}
    msg.update(extra)
    await ws.send(json.dumps(msg))
    ready = json.loads(await recv(ws, DEADLINE))
    return ready


def frames_of(got):
    """The frame headers (with their "image") among messages from wait_for_message."""
    return [m for m in got if m["type"] == "frame"]


async def basic(srv):
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        ready = await hello(ws)
        check(ready.get("type") == "ready" and len(ready.get("session", "")) == 32, "hello -> ready with a session id")
        check(ready.get("dataset", {}).get("name") == "demo:points" and "defaults" in ready and "stream" in ready,
              "ready carries dataset info, defaults and stream settings")
        got = await wait_for_stream_done(ws, skip=QUIET)
        imgs = frames_of(got)
        check(len(imgs) >= 1, "frames follow the hello (%d)" % len(imgs))
        if imgs:
            h = imgs[0]
            check(h["frame"] == 1 and h["format"] == "jpeg" and (h["width"], h["height"]) == (96, 80),
                  "first frame is 96x80 = viewport x devicePixelRatio")
            check(jpeg_size(h["image"]) == (96, 80), "frame image is a JPEG of the header's size")
            check("importance" in h["timings"] and h["encodeMs"] >= 0 and "cameraSeq" in h,
                  "frame header has timings, encodeMs, cameraSeq")
        check(got.reached, "the last frame reports converged")
        # Once converged, nothing more arrives on its own: the stream has ended,
        # so a correct server sends no frame however long one listens.
        more = frames_of(await listen(ws, 1.0, skip=QUIET))
        check(not more, "no frames after convergence without input")

        # A burst of 100 camera messages is coalesced; the last frame shows seq 100.
        # The client reads (and acks) nothing until all 100 are sent, and the
        # server handles the messages of a socket in order, so only the frames
        # begun before it saw the first ack can show an earlier camera: at most
        # the window (2) of them, whatever the speed of either side.
        for s in range(1, 101):
            await ws.send(camera(s, 2.0 + 0.01 * s))
        got = await wait_for_stream_done(ws, lambda h: h["cameraSeq"] == 100, skip=QUIET)
        imgs = frames_of(got)
        early = [h["cameraSeq"] for h in imgs if h["cameraSeq"] < 100]
        check(got.reached, "the stream ends with a converged still of camera 100 (%d frames)" % len(imgs))
        check(len(early) <= 2, "burst of 100 cameras coalesced: %d frames, those before the last camera: %s "
              "(at most the window of 2)" % (len(imgs), early))
        if imgs:
            check(imgs[-1]["cameraSeq"] == 100, "last frame reflects the last camera seq (%d)" % imgs[-1]["cameraSeq"])
            seqs = [h["cameraSeq"] for h in imgs]
            check(seqs == sorted(seqs), "cameraSeq never goes backwards")
            check(imgs[-1]["converged"], "stream stops once converged")
            inter = [h for h in imgs if h.get("detail", {}).get("interactive")]
            check(len(inter) >= 1 and inter[0]["width"] == 48 and inter[0]["quality"] == 85,
                  "interactive frames at quality 85 (loopback carries them) and half size")
            check(imgs[-1]["quality"] == 90 and imgs[-1]["width"] == 96, "a full-quality still frame ends the stream")
        check(not [m for m in got if m["type"] != "frame"], "no error messages during the burst")

        # Resize changes the frame size.
        await ws.send(json.dumps({"type": "resize", "width": 40, "height": 32, "devicePixelRatio": 1}))
        got = await wait_for_stream_done(ws, lambda h: (h["width"], h["height"]) == (40, 32), skip=QUIET)
        imgs = frames_of(got)
        check(got.reached and jpeg_size(imgs[-1]["image"]) == (40, 32), "resize -> 40x32 frames")


async def window(srv):
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        await hello(ws, window=2)
        # Never ack while input keeps arriving: at most 2 frames may be outstanding.
        # Input goes on until the two frames came (however long that takes),
        # then for one more second: a third frame in that time breaks the
        # window; a correct server sends none, however slow the machine.
        got = []
        seq, end, full = 0, time.monotonic() + DEADLINE, None
        while time.monotonic() < end and (full is None or time.monotonic() < full + 1.0):
            seq += 1
            await ws.send(camera(seq, 2.0 + 0.02 * (seq % 20)))
            m = await recv(ws, 0.05)  # paces the input; frames are counted whenever they come
            if m is not None and not isinstance(m, str):
                got.append(unpack_frame(m)[0])
                if len(got) == 2:
                    full = time.monotonic()
        check(len(got) == 2, "window 2 without acks -> exactly 2 frames (%d)" % len(got))
        await ws.send(json.dumps({"type": "ack", "frame": got[0]["frame"] if got else 1}))
        m = await recv(ws, DEADLINE)
        check(m is not None and not isinstance(m, str) and unpack_frame(m)[0]["frame"] == 3,
              "one ack -> exactly the next frame")
        m2 = await recv(ws, 1.0)  # the window is full again: nothing may come, however long one waits
        check(m2 is None, "and no more until the next ack")


async def bad_input(srv):
    async with websockets.connect(srv.ws_url, max_size=None) as good:
        await hello(good)
        await wait_for_stream_done(good, skip=QUIET)
        async with websockets.connect(srv.ws_url, max_size=None) as ws:
            await ws.send(json.dumps({"type": "camera", "seq": 1, "camera": {}}))
            e = json.loads(await recv(ws, DEADLINE))
            check(e["type"] == "error" and e["code"] == "bad_state" and e.get("field") == "type" and not e["fatal"],
                  "camera before hello -> recoverable bad_state naming type (%s)" % e["code"])
            await ws.send("{not json")
            e = json.loads(await recv(ws, DEADLINE))
            check(e["type"] == "error" and e["code"] == "bad_json" and not e["fatal"], "garbage -> bad_json, session stays")
            await ws.send(json.dumps({"type": "hello", "dataset": "demo:nope", "width": 10, "height": 10}))
            e = json.loads(await recv(ws, DEADLINE))
            check(e["type"] == "error" and e["code"] == "not_found" and e.get("field") == "dataset" and not e["fatal"],
                  "hello with an unknown dataset -> recoverable not_found naming dataset")
            await ws.send(b"\x00\x01binary")
            e = json.loads(await recv(ws, DEADLINE))
            check(e["type"] == "error", "binary client message -> error")
            ready = await hello(ws)
            check(ready.get("type") == "ready", "a valid hello still works after errors (the socket stayed open)")
            await wait_for_stream_done(ws, skip=QUIET)
            await ws.send(json.dumps({"type": "hello", "dataset": "demo:points", "width": 10, "height": 10}))
            e = json.loads(await recv(ws, DEADLINE))
            check(e["type"] == "error" and e["code"] == "bad_state" and e.get("field") == "type" and not e["fatal"],
                  "a second hello -> recoverable bad_state (%s)" % e["code"])
            await ws.send(json.dumps({"type": "params", "params": {"bands": 42}}))
            e = json.loads(await recv(ws, DEADLINE))
            check(e["code"] == "out_of_range" and e.get("field") == "params.bands", "params out of range names the field")
            await ws.send(json.dumps({"type": "params", "importance": {"attribute": "no_such_attribute"}}))
            got = await wait_for_message(ws, lambda m: m["type"] == "error", skip=QUIET)
            texts = [m for m in got if m["type"] != "frame"]
            check(texts and texts[0]["type"] == "error" and texts[0]["code"] == "bad_field" and
                  texts[0].get("field") == "importance.attribute" and not texts[0]["fatal"],
                  "unknown attribute -> bad_field naming importance.attribute (%s)" % (texts[0] if texts else None))
            # Oversized message -> close 1009.
            await ws.send(json.dumps({"type": "params", "params": {"q": 1}, "pad": "x" * 9000}))
            try:
                while True:
                    await asyncio.wait_for(ws.recv(), DEADLINE)
            except websockets.ConnectionClosed:
                pass
            except asyncio.TimeoutError:
                pass
            check(ws.close_code == 1009, "oversized message -> close code 1009 (%s)" % ws.close_code)
        # The other session is unaffected.
        await good.send(camera(1, 3.0))
        got = await wait_for_stream_done(good, lambda h: h["cameraSeq"] == 1, skip=QUIET)
        check(got.reached, "another session keeps working meanwhile")

    # A client that disconnects mid-frame does not disturb the server.
    for _ in range(3):
        ws = await websockets.connect(srv.ws_url, max_size=None)
        await ws.send(json.dumps({"type": "hello", "dataset": "demo:points", "width": 200, "height": 200}))
        await ws.close()
    st, _, h = srv.json("GET", "/api/v1/health")
    check(st == 200, "server healthy after abrupt disconnects")


async def stats(srv):
    """stats messages: about once a second while frames flow, one more after
    the stream stops, none while idle; their figures agree with what arrived."""
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        await hello(ws, window=2)
        frames = frame_bytes = seq = 0
        seen = []  # (frames received before it, their bytes, the message)
        last_frame = []  # the header of the last frame received, with "type": "frame"

        async def take(m):
            nonlocal frames, frame_bytes
            if isinstance(m, str):
                o = json.loads(m)
                check(o["type"] in ("stats", "progress"), "only stats/progress text messages while streaming (%s)" % o)
                if o["type"] == "stats":  # a slow frame on a loaded host may bring progress messages too
                    seen.append((frames, frame_bytes, o))
                return
            h, _ = unpack_frame(m)
            last_frame[:] = [dict(h, type="frame")]
            frames += 1
            frame_bytes += len(m)
            await ws.send(json.dumps({"type": "ack", "frame": h["frame"]}))

        # A burst (coalesced for sure), then 30 cameras a second until two
        # stats messages that count frames of their last second have come
        # (stats flow about once a second while frames do; however long the
        # frames take here, that state comes).
        for _ in range(30):
            seq += 1
            await ws.send(camera(seq, 2.0 + 0.02 * (seq % 20)))
        end = time.monotonic() + DEADLINE
        next_cam = time.monotonic()
        while time.monotonic() < end and sum(1 for _, _, o in seen if o["fps"] > 0) < 2:
            if time.monotonic() >= next_cam:
                seq += 1
                await ws.send(camera(seq, 2.0 + 0.02 * (seq % 20)))
                next_cam += 1 / 30
            m = await recv(ws, 0.01, keep_stats=True)  # paces the input; messages are taken whenever they come
            if m is not None:
                await take(m)
        during = len(seen)
        check(sum(1 for _, _, o in seen if o["fps"] > 0) >= 2,
              "stats while frames flow (%d of them, %d frames)" % (during, frames))
        # Input stops: the still frame and any fading frames until the stream
        # ends, then a stats that counts every frame (right after the last
        # frame or within about two seconds of it).
        end = time.monotonic() + DEADLINE
        while time.monotonic() < end and not (last_frame and stream_done(last_frame[0]) and
                                              last_frame[0]["cameraSeq"] == seq and seen and seen[-1][0] == frames
                                              and len(seen) > during):
            m = await recv(ws, end - time.monotonic(), keep_stats=True)
            if m is None:
                break
            await take(m)
        check(len(seen) > during, "one more stats after the frames stop")
        if not seen:
            return
        for before, nbytes, o in seen:
            # fps counts the last second: 0 is right for a stats that follows the
            # end of the stream, and for one sent by the once-a-second check when
            # a loaded machine spaced the frames more than a second apart. The
            # interval (server's clock) bounds the rate: at most one a second.
            ok = (o["framesSent"] == before and nbytes <= o["bytesSent"] <= nbytes + 65536 and
                  0 <= o["fps"] <= o["framesSent"] and 0 < o["renderMs"] < 60000 and 0 < o["renderP50Ms"] < 60000 and
                  0 <= o["encodeMs"] < 60000 and o["queue"] >= 0 and 0 <= o["unacked"] <= o["window"] == 2 and
                  0 <= o["framesDropped"] <= seq and o["interval"] >= 1.0)
            check(ok, "stats agree with the frames received before them (%d): %s" % (before, o))
        last = seen[-1][2]
        check(seen[-1][0] == frames and last["framesSent"] == frames, "the last stats counts every frame (%d)" % frames)
        check(last["framesDropped"] >= seq - frames and last["framesDropped"] > 0,
              "framesDropped counts coalesced cameras (%d dropped, %d cameras, %d frames)" %
              (last["framesDropped"], seq, frames))
        sent = [o["framesSent"] for _, _, o in seen]
        check(sent == sorted(sent), "framesSent never goes backwards")


async def shutdown(srv):
    ws = await websockets.connect(srv.ws_url, max_size=None)
    await hello(ws)
    await wait_for_stream_done(ws, skip=QUIET)
    code = None
    srv.proc.send_signal(15)
    try:
        while True:
            await asyncio.wait_for(ws.recv(), 60)
    except websockets.ConnectionClosed:
        code = ws.close_code
    except asyncio.TimeoutError:
        pass
    check(code == 1001, "SIGTERM closes WebSockets with a close frame 1001 (%s)" % code)
    rc = srv.stop()
    check(rc == 0, "daemon exits 0 (%s)" % rc)


async def detail(srv):
    """Drags (30 ms between camera messages) until four interactive frames
    came, however long that takes, with a 5 ms frame budget (no frame meets
    it): interactive frames reuse opacities and coarsen step by step; the
    still frame after release optimizes again at full size and shows the last
    camera."""
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        await hello(ws, dataset="demo:tornado")
        first = frames_of(await wait_for_stream_done(ws, skip=QUIET))
        check(first and "detail" in first[0], "frame headers carry detail")
        if first and "detail" in first[0]:
            d = first[0]["detail"]
            check(not d["interactive"] and not d["reusedOpacities"] and d["lodPixels"] == 0.2 and d["level"] >= 0
                  and d["primitives"] > 0 and d["renderMs"] > 0, "the first frame is a still frame: %s" % d)
        got = []
        dragging = True

        async def reader():
            while dragging:  # reads (and acks) while the drag goes on; the 0.1 s only lets it see the end
                m = await recv(ws, 0.1)
                if m is None or isinstance(m, str):
                    continue
                h, _ = unpack_frame(m)
                got.append(dict(h, type="frame"))
                await ws.send(json.dumps({"type": "ack", "frame": h["frame"]}))
        task = asyncio.create_task(reader())
        last, end = 0, time.monotonic() + DEADLINE
        for s in range(1, 100000):
            interactive = sum(1 for h in got if h.get("detail", {}).get("interactive"))
            if s > 40 and interactive >= 4 or time.monotonic() > end:
                break
            await ws.send(camera(s, 2.0 + 0.02 * (s % 100)))
            last = s
            await asyncio.sleep(0.03)
        dragging = False
        await task
        # Released: the frames until the stream ends with the still of the last camera.
        if not (got and stream_done(got[-1]) and got[-1]["cameraSeq"] == last):
            rest = await wait_for_stream_done(ws, lambda h: h["cameraSeq"] == last, skip=QUIET)
            check(rest.reached, "the stream ends after the release")
            got += frames_of(rest)
        inter = [h for h in got if h.get("detail", {}).get("interactive")]
        check(len(inter) >= 4, "interactive frames while dragging (%d)" % len(inter))
        check(any(h["detail"]["reusedOpacities"] for h in inter), "interactive frames reuse the opacities")
        check(max(h["detail"]["lodPixels"] for h in inter) > 0.5 if inter else False,
              "over budget, line detail coarsens (%s)" % [h["detail"]["lodPixels"] for h in inter])
        check(min(h["width"] for h in inter) < 48 if inter else False,
              "over budget, resolution drops below interactiveScale x 96 (%s)" % [h["width"] for h in inter])
        if got:
            h = got[-1]
            check(not h["detail"]["interactive"] and not h["detail"]["reusedOpacities"] and h["width"] == 96
                  and h["cameraSeq"] == last and h["converged"] and h["detail"]["lodPixels"] == 0.2,
                  "the last frame is a full still of the last camera: %s" % {k: v for k, v in h.items()
                                                                              if k != "image"})


async def colors_settle(srv):
    """color.equalize in a session: after a jump of the camera the colour map keeps approaching the new view's
    (frames keep coming though the opacities settled) until it is that view's: the last frame's legend ticks
    are the one-shot render's of the same request."""
    cam = {"position": [9, 3, 2], "focalPoint": [3.1, 3.1, 3.1], "viewUp": [0, 0, 1], "viewAngle": 30}
    color = {"equalize": True, "fadeHalfLife": 0.25}
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        await ws.send(json.dumps({"type": "hello", "dataset": "demo:abc", "width": 64, "height": 48,
                                  "devicePixelRatio": 1, "color": color}))
        first = await wait_for_stream_done(ws)
        await ws.send(json.dumps({"type": "camera", "seq": 1, "camera": cam}))
        got = await wait_for_stream_done(ws, lambda h: h.get("cameraSeq") == 1)
    frames = [m for m in got if m.get("type") == "frame"]
    st, h, _ = srv.request("POST", "/api/v1/render", {"dataset": "demo:abc", "width": 64, "height": 48,
                                                     "camera": cam, "color": color, "format": "jpeg"})
    want = [float(x) for x in h.get("x-lucent-color-ticks", "").split(",") if x]
    last = frames[-1].get("colorTicks") if frames else None
    span = (want[4] - want[0]) if len(want) == 5 else 1
    check(first.reached and got.reached and st == 200 and last and len(want) == 5 and
          max(abs(a - b) for a, b in zip(last, want)) <= 0.02 * span,
          "after a camera jump the session's colours settle on the view's own (%d frames; ticks %s, one-shot %s)" %
          (len(frames), last, want))


async def main():
    # --still-delay 1000: frames begun within a second of the last input are
    # interactive ones, so that the burst's moving frames are moving frames
    # even when a loaded machine starts them late (150 ms is a short margin).
    with Server(binary, "--max-ws-message", "4096", "--still-delay", "1000", "--frame-budget", "10000") as srv:
        await basic(srv)
        await window(srv)
        await bad_input(srv)
        await stats(srv)
        await shutdown(srv)
    with Server(binary, data=("demo:abc",), demo_size=100) as srv:
        await colors_settle(srv)
    with Server(binary, "--still-delay", "150", "--frame-budget", "5", data=("demo:tornado",), demo_size=60) as srv:
        await detail(srv)


asyncio.run(main())
check.done()
