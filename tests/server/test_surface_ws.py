"""Method surface-layers in a WebSocket session (docs/ALGORITHM.md §23): each
frame traces surface.curvesPerFrame more curves and adds them to the layers
kept from the frame before (progressive insertion), so the frame headers count
curves up to surface.particles, each frame draws only its new curves (its
drawn fragments stay those of one batch while the surface grows) and the
frames stop once converged; a camera change redraws the curves traced so far
without tracing again from the start (the count keeps growing); a new seed
starts again from curvesPerFrame; an unknown field is refused naming
surface.field while the session keeps serving; the last frame of a session is
the one-shot render's picture."""
import asyncio
import json
import sys
import time

from lucent_server import (Check, Server, jpeg_size, skip, ssim, wait_for_frame, wait_for_message, wait_for_stream_done,
                           websockets)

if websockets is None:
    skip("python3-websockets is not installed")

binary = sys.argv[1]
check = Check()
SEED = [[3.14, 0.63, 3.14], [3.14, 5.65, 3.14]]
CAMERA = {"position": [14, 3, 8], "focalPoint": [3.14, 3.14, 3.14], "viewUp": [0, 0, 1]}


async def recv(ws, timeout):
    """The next non-stats message within timeout, or None."""
    deadline = time.monotonic() + timeout
    while True:
        left = deadline - time.monotonic()
        if left <= 0:
            return None
        try:
            m = await asyncio.wait_for(ws.recv(), left)
        except asyncio.TimeoutError:
            return None
        if isinstance(m, str) and json.loads(m).get("type") in ("stats", "progress"):
            continue
        return m


QUIET = ("stats", "progress")


newest = {}  # per connection: the highest frame id seen by frames()


async def frames(ws):
    """(header, image) of the frames until the stream ends (converged, however
    long that takes) in frame id order, then text messages as ("text", msg).
    Two encoder threads may send a session's frames out of order (the page
    draws the newest id): frames older than the newest one an earlier call
    returned belong to that earlier stretch and are dropped."""
    got = await wait_for_stream_done(ws, skip=QUIET)
    check(got.reached, "the stream ends with a converged frame")
    last = newest.get(id(ws), 0)
    ids = {m["frame"] for m in got if m["type"] == "frame"}
    top = max(ids, default=last)
    # Frame ids are consecutive: wait for the ones of this stretch still on their way.
    while got.reached and any(i not in ids for i in range(last + 1, top)):
        more = await wait_for_frame(ws, skip=QUIET)
        if not more.reached:
            break
        got += more
        ids |= {m["frame"] for m in more if m["type"] == "frame"}
    fs = sorted((m for m in got if m["type"] == "frame" and last < m["frame"] <= top), key=lambda m: m["frame"])
    if fs:
        newest[id(ws)] = fs[-1]["frame"]
    return [(m, m["image"]) for m in fs] + [("text", m) for m in got if m["type"] != "frame"]


async def error(ws):
    """The error message that answers an update (DEADLINE at most), or None."""
    got = await wait_for_message(ws, lambda m: m["type"] == "error", skip=QUIET)
    return got[-1] if got.reached else None


def surfaces(got):
    return [h["surface"] for h, _ in got if h != "text" and "surface" in h]


async def main(srv):
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        await ws.send(json.dumps({"type": "hello", "dataset": "demo:points", "width": 96, "height": 80,
                                  "devicePixelRatio": 1, "method": "surface-layers", "camera": CAMERA,
                                  "surface": {"field": "demo:abc-flow", "seed": SEED, "particles": 600,
                                              "curvesPerFrame": 150}}))
        ready = json.loads(await recv(ws, 120))
        check(ready.get("type") == "ready", "hello with method surface-layers -> ready: %r" % ready)
        got = await frames(ws)
        s = surfaces(got)
        counts = [x["curves"] for x in s]
        check(counts[:4] == [150, 300, 450, 600], "each frame adds 150 curves up to 600: %r" % counts)
        check(all(c == 600 for c in counts[4:]), "then the surface stays at 600: %r" % counts)
        conv = [h.get("converged") for h, _ in got if h != "text"]
        check(conv and conv[-1] is True and conv[0] is False, "converged only once all curves are in: %r" % conv)
        check(all(x["particles"] == 600 and x["layersPerPixel"] >= 1 and x["k"] == 8 for x in s),
              "headers carry particles, layers per pixel and k: %r" % s[-1:])
        drawn = [(x["drawnCurves"], x["kept"]) for x in s]
        check(drawn[:4] == [(150, False), (150, True), (150, True), (150, True)],
              "each frame draws only its 150 new curves into the kept layers: %r" % drawn)
        check(all(d == (0, True) for d in drawn[4:]), "a converged frame draws nothing new: %r" % drawn[4:])
        frags = [x["drawnFragments"] for x in s[:4]]
        check(min(frags) > 0 and frags[3] < 2 * frags[0],
              "the fourth frame rasterizes about what the first did, not four times as much: %r" % frags)
        imgs = [img for h, img in got if h != "text"]
        check(imgs and jpeg_size(imgs[-1]) == (96, 80), "JPEG frames of the viewport")
        check(len(set(imgs)) >= 3, "the image changes while the surface grows (%d distinct)" % len(set(imgs)))

        # A camera change redraws what was traced: no restart, the count stays.
        cam = dict(CAMERA, position=[3.14, -10, 3.14])
        await ws.send(json.dumps({"type": "camera", "seq": 1, "camera": cam}))
        got = await frames(ws)
        s = surfaces(got)
        counts = [x["curves"] for x in s]
        check(counts and min(counts) == 600, "a camera change keeps the 600 curves: %r" % counts)
        check(s and s[0]["drawnCurves"] == 600 and s[0]["kept"] is False,
              "a camera change draws every curve again: %r" % s[:1])

        # A new seed restarts from curvesPerFrame.
        seed2 = [[2.0, 0.63, 3.14], [2.0, 5.65, 3.14]]
        await ws.send(json.dumps({"type": "params", "surface": {"seed": seed2, "particles": 300}}))
        got = await frames(ws)
        counts = [x["curves"] for x in surfaces(got)]
        check(counts[:2] == [150, 300], "a new seed starts again: %r" % counts)

        # Bad input is refused naming the field; the session goes on.
        await ws.send(json.dumps({"type": "params", "surface": {"field": "no-such-flow"}}))
        err = await error(ws)
        check(err is not None and err.get("field") == "surface.field", "an unknown field names surface.field: %r" % err)
        await ws.send(json.dumps({"type": "params", "surface": {"particles": 450}}))
        got = await frames(ws)
        counts = [x["curves"] for x in surfaces(got)]
        check(counts and counts[-1] == 450, "the session still serves the old field: %r" % counts)


async def refused_layers(srv):
    """A surface session beside layers is refused naming layers; the daemon lives."""
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        await ws.send(json.dumps({"type": "hello", "width": 64, "height": 64, "method": "surface-layers",
                                  "layers": [{"dataset": "demo:points"}],
                                  "surface": {"field": "demo:abc-flow", "seed": SEED, "particles": 50}}))
        m = json.loads(await recv(ws, 120) or "{}")
        check(m.get("type") == "error" and m.get("field") == "layers", "hello: surface-layers with layers -> %r" % m)
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        await ws.send(json.dumps({"type": "hello", "width": 64, "height": 64, "dataset": "demo:points",
                                  "layers": [{"dataset": "demo:points"}]}))
        m = json.loads(await recv(ws, 120) or "{}")
        check(m.get("type") == "ready", "a layered session starts: %r" % m)
        await ws.send(json.dumps({"type": "params", "method": "surface-layers",
                                  "surface": {"field": "demo:abc-flow", "seed": SEED, "particles": 50}}))
        err = await error(ws)
        check(err is not None and err.get("field") == "layers", "params: surface-layers over layers -> %r" % err)


async def default_camera(srv):
    """Without a camera a session frames the surface as the one-shot render does: its last frame is the HTTP
    render of the same request."""
    surface = {"field": "demo:abc-flow", "seed": SEED, "particles": 300, "curvesPerFrame": 150}
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        await ws.send(json.dumps({"type": "hello", "width": 96, "height": 80, "devicePixelRatio": 1,
                                  "method": "surface-layers", "surface": surface, "quality": 95}))
        got = await frames(ws)
    last = [img for h, img in got if h != "text"]
    st, _, ref = srv.request("POST", "/api/v1/render", {"width": 96, "height": 80, "method": "surface-layers",
                                                       "surface": surface, "format": "jpeg", "quality": 95})
    check(st == 200, "the one-shot render of the same surface: %d %r" % (st, ref[:300] if st != 200 else ""))
    s = ssim(binary, last[-1], ref) if last and st == 200 else -1
    check(s >= 0.999, "a session without a camera ends on the one-shot render's picture (SSIM %.4f)" % s)


with Server(binary, data=("demo:points", "demo:abc-flow")) as srv:
    asyncio.run(main(srv))
    asyncio.run(default_camera(srv))
    asyncio.run(refused_layers(srv))
    st, _, data = srv.request("POST", "/api/v1/sessions", json.dumps(
        {"method": "surface-layers", "surface": {"field": "demo:abc-flow", "seed": SEED}}))
    check(st == 400 and json.loads(data).get("error", {}).get("field") == "method",
          "HTTP sessions refuse surface-layers naming method: %d" % st)
check.done()
