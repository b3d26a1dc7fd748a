"""layers[] against the real daemon: a two-layer HTTP render (points demo and
tornado lines) answers an image that differs from either layer alone, the GET
form takes layers as JSON text, and bad layer specifications get a clear error
naming the field: an unknown dataset (404, layers[i].dataset), an unknown key,
an unknown attribute of one layer's dataset, a layer of the frame's style, a
context layer of points, a method that cannot draw layers. A surface as
opaque context renders.

Layers in sessions: a WebSocket session of two layers (its hello naming no
dataset) streams, as its first still, the very image of the HTTP render of the
same request; after a camera move its last still matches the HTTP render of
that camera (SSIM >= 0.99: the fading may leave a trace); a change of the
layer set (one layer, then the points alone) renders on fresh opacities; an
unknown layer dataset in an update is refused naming layers[i].dataset and the
session goes on; an update only the renderer refuses (a layer's equalize with
exact) gets the error as its reply, naming the field, and the session keeps its
parameters. A layer's own filter (and its own clustering) changes the image, by POST and GET alike,
beside a context surface too, and its errors name layers[i].filter[k].*, layers[i].time.*. A scripted HTTP session of the two layers renders the
one-shot image."""
import json
import os
import subprocess
import sys
import tempfile
import time
import urllib.parse

from lucent_server import ssim as lucent_ssim
from lucent_server import (DEADLINE, Check, Server, jpeg_size, listen, png_size, skip, wait_for_message,
                           wait_for_stream_done, websockets)

binary = sys.argv[1]
check = Check()

LAYERS = [{"dataset": "demo:points", "style": {"pointSize": 3}},
          {"dataset": "demo:tornado", "color": {"colormap": "coolwarm"}}]


def render(srv, body):
    return srv.request("POST", "/api/v1/render", dict({"width": 96, "height": 80}, **body))


def error(srv, body, status, field, what, path="/api/v1/render"):
    st, _, data = srv.request("POST", path, dict({"width": 96, "height": 80}, **body))
    try:
        e = json.loads(data)
    except ValueError:
        e = {}
    got = e.get("field") if "field" in e else e.get("error", {}).get("field")
    check(st == status and got == field,
          "%s -> %d naming %s (got %d, %s)" % (what, status, field, st, data[:200].decode(errors="replace")))


def ssim(a, b):
    return lucent_ssim(binary, a, b)


CAMERA = {"position": [2.2, 1.4, 2.0], "focalPoint": [0.5, 0.5, 0.5], "viewUp": [0, 1, 0]}


def sessions(srv):
    """A scripted session of layers: its frame without dt is the one-shot image."""
    st, _, data = srv.request("POST", "/api/v1/sessions", {"layers": LAYERS, "width": 96, "height": 80})
    check(st == 201, "a scripted session of two layers (no dataset named) -> 201 (%d %s)" % (st, data[:120]))
    if st != 201:
        return
    sid = json.loads(data)["session"]
    st, _, img = srv.request("POST", "/api/v1/sessions/%s/render" % sid, {})
    st2, _, ref = render(srv, {"layers": LAYERS})
    check(st == 200 and st2 == 200 and img == ref, "its frame is the HTTP render's image (%d, %d)" % (st, st2))
    st, _, data = srv.request("POST", "/api/v1/sessions/%s/render" % sid,
                              {"layers": [LAYERS[0], {"dataset": "demo:nope"}]})
    check(st == 404 and json.loads(data).get("error", {}).get("field") == "layers[1].dataset",
          "an unknown layer dataset in its update -> 404 naming layers[1].dataset (%d %s)" % (st, data[:160]))
    st, _, img = srv.request("POST", "/api/v1/sessions/%s/render" % sid, {"layers": [LAYERS[1]]})
    st2, _, ref = render(srv, {"layers": [LAYERS[1]]})
    check(st == 200 and img == ref, "one layer of the two: the session renders it on fresh opacities (%d)" % st)
    srv.request("DELETE", "/api/v1/sessions/%s" % sid)


async def stream(srv):
    import asyncio

    async def recv(ws, timeout):
        try:
            return await asyncio.wait_for(ws.recv(), timeout)
        except asyncio.TimeoutError:
            return None

    def split(got):
        """Frames as (header, image) and error messages, from wait_for_message's list."""
        return ([(m, m["image"]) for m in got if m["type"] == "frame"],
                [m for m in got if m["type"] == "error"])

    async def until_done(ws, predicate=lambda h: True):
        """Frames (acked) and error messages until the stream ends (a converged
        final still that satisfies predicate), however long that takes."""
        got = await wait_for_stream_done(ws, predicate, skip=("stats", "progress"))
        check(got.reached, "the stream ends with a converged still")
        return split(got)

    def still(frames):
        s = [f for f in frames if f[0]["quality"] == 90 and f[0]["width"] == 96]
        return s[-1] if s else (None, b"")

    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        await ws.send(json.dumps({"type": "hello", "width": 96, "height": 80, "devicePixelRatio": 1,
                                  "layers": LAYERS}))
        ready = json.loads(await recv(ws, DEADLINE))
        check(ready.get("type") == "ready" and ready.get("defaults", {}).get("layers", [{}])[0].get("dataset")
              == "demo:points", "a hello of two layers without dataset -> ready, its defaults hold the layers (%s)"
              % json.dumps(ready)[:300])
        frames, errors = await until_done(ws)
        check(frames and not errors, "frames follow (%d), no errors (%r)" % (len(frames), errors[:1]))
        st, _, ref = render(srv, {"layers": LAYERS, "format": "jpeg", "quality": 90})
        h, first = frames[0] if frames else ({}, b"")
        check(st == 200 and first and jpeg_size(first) == (96, 80) and first == ref,
              "the session's first still is the HTTP render of the same layers, byte for byte (SSIM %.4f)"
              % (ssim(first, ref) if first else -1))
        check(frames and h.get("timings") is not None and frames[-1][0]["converged"], "the stream converges")
        lv = (frames[-1][0].get("visibility") or {}).get("layers") if frames else None
        check(isinstance(lv, list) and len(lv) == 2 and all("topDecileAlpha" in x for x in lv),
              "the session's frames carry visibility per layer (%s)" % lv)

        await ws.send(json.dumps({"type": "camera", "seq": 1, "camera": CAMERA}))
        frames, errors = await until_done(ws, lambda h: h["cameraSeq"] == 1)
        inter = [f for f in frames if (f[0].get("detail") or {}).get("interactive")]
        h, img = still(frames)
        st, _, ref = render(srv, {"layers": LAYERS, "format": "jpeg", "quality": 90, "camera": CAMERA})
        s = ssim(img, ref) if img else -1
        check(not errors and inter and img and s >= 0.99,
              "a camera move: %d interactive frames, then a still of SSIM %.4f >= 0.99 to the HTTP render %r"
              % (len(inter), s, [(f[0]["quality"], f[0]["width"]) for f in frames]))

        for i, layers in enumerate(([LAYERS[1]], [dict(LAYERS[0], importance={"exponent": 2})])):
            await ws.send(json.dumps({"type": "params", "layers": layers}))
            frames, errors = await until_done(ws)
            h, img = still(frames)
            st, _, ref = render(srv, {"layers": layers, "format": "jpeg", "quality": 90, "camera": CAMERA})
            s = ssim(img, ref) if img else -1
            check(not errors and img and s >= 0.99,
                  "layer set %d changed: frames on fresh opacities, the still's SSIM %.4f >= 0.99 (%r)"
                  % (i + 1, s, errors[:1]))

        await ws.send(json.dumps({"type": "params", "layers": [LAYERS[0], {"dataset": "demo:nope"}]}))
        frames, errors = split(await wait_for_message(ws, lambda m: m["type"] == "error", skip=("stats", "progress")))
        # Refused: nothing of it applies, so no frame may follow the error (the
        # stream had ended); a short listen cannot fail on a slow machine.
        more, _ = split(await listen(ws, 1.0, skip=("stats", "progress")))
        frames += more
        check(errors and errors[0].get("field") == "layers[1].dataset" and not frames,
              "an unknown layer dataset in params -> error naming layers[1].dataset (%r)" % errors[:1])
        await ws.send(json.dumps({"type": "params", "layers": LAYERS}))
        frames, errors = await until_done(ws)
        check(frames and not errors, "the session goes on with both layers (%d frames)" % len(frames))

        # What only the renderer refuses (a layer's equalize under exact) is the
        # reply to that update: the first message after it (the stream had
        # ended), naming the field; no frame of it follows, and the session
        # keeps its parameters: a camera move then renders the layers as before.
        refused = [LAYERS[0], dict(LAYERS[1], color={"attribute": "velocity", "equalize": True})]
        await ws.send(json.dumps({"type": "params", "method": "exact", "layers": refused}))
        got = await wait_for_message(ws, lambda m: True, skip=("stats", "progress"))
        more, _ = split(await listen(ws, 1.0, skip=("stats", "progress")))
        check(got.reached and got[-1]["type"] == "error" and got[-1].get("field") == "layers[1].color.equalize"
              and not more, "params the renderer refuses (a layer's equalize with exact) -> the reply is an error "
              "naming layers[1].color.equalize, no frame follows (%r)" % list(got)[:1])
        camera = dict(CAMERA, position=[2.0, 1.6, 2.2])
        await ws.send(json.dumps({"type": "camera", "seq": 2, "camera": camera}))
        frames, errors = await until_done(ws, lambda h: h["cameraSeq"] == 2)
        h, img = still(frames)
        st, _, ref = render(srv, {"layers": LAYERS, "format": "jpeg", "quality": 90, "camera": camera})
        s = ssim(img, ref) if img else -1
        check(not errors and img and s >= 0.99, "after the refusal the session renders its previous parameters: "
              "a camera move's still has SSIM %.4f >= 0.99 to the HTTP render of the layers before (%r)"
              % (s, errors[:1]))


# --still-delay 1000: a session's frames begun within a second of its last
# input are moving frames, so that the camera move's interactive frames are
# there even when a loaded machine starts them late (150 ms is a short margin).
with Server(binary, "--still-delay", "1000", data=("demo:points", "demo:tornado", "demo:surface"),
            demo_size=300) as srv:
    st, hdrs, both = render(srv, {"layers": LAYERS})
    check(st == 200 and png_size(both) == (96, 80), "two-layer render -> 200, a 96x80 PNG (%d)" % st)
    # Visibility over the transparent layers together and per layer; the clarity loop acts on it.
    per = [x.split("/") for x in hdrs.get("x-lucent-layer-visibility", "").split(";") if x]
    check("x-lucent-visibility" in hdrs and len(per) == 2 and all(len(x) == 3 for x in per),
          "a layered frame reports visibility in total and per layer (%s | %s)" %
          (hdrs.get("x-lucent-visibility"), hdrs.get("x-lucent-layer-visibility")))
    tops = []
    for clarity in (0, 0.95):
        st, h, _ = render(srv, {"layers": LAYERS, "params": {"clarity": clarity}})
        vis = dict(kv.split("=") for kv in h.get("x-lucent-visibility", "").split(",") if "=" in kv)
        tops.append(float(vis.get("topDecileAlpha", -1)))
    check(tops[0] >= 0 and tops[1] > tops[0] + 0.02,
          "clarity on a layered frame lifts the most important tenth (%.3f at 0, %.3f at 0.95)" % tuple(tops))
    alone = []
    for i in range(2):
        hidden = [dict(l, visible=(k == i)) for k, l in enumerate(LAYERS)]
        st, _, img = render(srv, {"layers": hidden})
        check(st == 200, "layer %d alone (the other hidden) -> 200" % i)
        alone.append(img)
    check(both not in alone and alone[0] != alone[1], "both layers differ from either layer alone")
    st, _, single = render(srv, {"dataset": "demo:tornado"})
    check(st == 200 and single != both, "the single-dataset request still renders (and differs from the layers)")

    q = urllib.parse.urlencode({"width": 96, "height": 80, "layers": json.dumps(LAYERS)})
    st, _, img = srv.request("GET", "/api/v1/render?" + q)
    check(st == 200 and img == both, "GET with layers as JSON text -> the same image as the POST (%d)" % st)

    error(srv, {"layers": [LAYERS[0], {"dataset": "demo:nope"}]}, 404, "layers[1].dataset", "an unknown dataset")
    error(srv, {"layers": [{"dataset": "demo:points", "opacity": 1}]}, 400, "layers[0].opacity", "an unknown key")
    error(srv, {"layers": [{"importance": {"attribute": "x"}}]}, 400, "layers[0].dataset", "a layer without dataset")
    error(srv, {"layers": [LAYERS[0], {"dataset": "demo:tornado", "importance": {"attribute": "nope"}}]}, 400,
          "layers[1].importance.attribute", "an attribute the layer's dataset lacks")
    error(srv, {"layers": [{"dataset": "demo:points", "style": {"background": [0, 0, 0]}}]}, 400,
          "layers[0].style.background", "the frame's style in a layer")
    error(srv, {"layers": [{"dataset": "demo:points", "role": "context"}, LAYERS[1]]}, 400, "layers[0].role",
          "a context layer of points")
    error(srv, {"layers": [{"dataset": "demo:surface", "role": "opaque"}]}, 400, "layers[0].role", "an unknown role")
    ctx = [{"dataset": "demo:surface", "role": "context"}, LAYERS[1]]
    st, _, with_context = render(srv, {"layers": ctx})
    st2, _, transparent = render(srv, {"layers": [dict(ctx[0], role="transparent"), LAYERS[1]]})
    check(st == 200 and st2 == 200 and with_context != transparent,
          "a surface as opaque context renders, unlike the same surface transparent (%d, %d)" % (st, st2))
    error(srv, {"layers": LAYERS, "method": "opaque"}, 400, "method", "the opaque method with layers")
    # A layer's own filter and time window, beside a context surface.
    long_lines = [{"attribute": "line_length", "over": "max", "gt": 1.5}]
    st, _, filtered = render(srv, {"layers": [LAYERS[0], dict(LAYERS[1], filter=long_lines)]})
    check(st == 200 and filtered != both, "a layer's filter renders and changes the image (%d)" % st)
    st, _, _ = render(srv, {"layers": [ctx[0], dict(LAYERS[1], filter=long_lines)]})
    check(st == 200, "a filtered layer beside a context surface renders (%d)" % st)
    st, _, again = srv.request("GET", "/api/v1/render?width=96&height=80&layers=" + urllib.parse.quote(
        json.dumps([LAYERS[0], dict(LAYERS[1], filter=long_lines)])))
    check(st == 200 and again == filtered, "the GET form carries the layer's filter (%d)" % st)
    error(srv, {"layers": [dict(LAYERS[1], filter=[{"attribute": "nope", "over": "max", "gt": 1}])]}, 400,
          "layers[0].filter[0].attribute", "a layer's filter on an attribute its dataset lacks")
    error(srv, {"layers": [dict(LAYERS[1], filter=[{"attribute": "line_length", "over": "vertex", "gt": 1}])]}, 400,
          "layers[0].filter[0].over", "a vertex filter on a layer of lines")
    error(srv, {"layers": [ctx[0], dict(LAYERS[1], time={"window": [0, 1]})]}, 400, "layers[1].time.attribute",
          "a time window on a layer without time")
    error(srv, {"layers": [dict(ctx[0], filter=long_lines), LAYERS[1]]}, 400, "layers[0].filter[0].attribute",
          "a filter on a surface layer")
    error(srv, {"layers": LAYERS, "filter": long_lines}, 400, "filter", "the request's own filter with layers")
    st, _, clustered = render(srv, {"layers": [LAYERS[0], dict(LAYERS[1], lines={"clusters": 10})]})
    check(st == 200 and clustered not in (both, filtered), "a layer's own clustering renders and changes the image "
          "(%d)" % st)
    error(srv, {"layers": [dict(LAYERS[0], lines={"clusters": 10}), LAYERS[1]]}, 400, "layers[0].lines.clusters",
          "clusters on a layer of points")
    error(srv, {"layers": LAYERS, "lines": {"clusters": 10}}, 400, "lines.clusters",
          "the request's own clusters with layers")
    st, _, equalized = render(srv, {"layers": [LAYERS[0], dict(LAYERS[1], color={"attribute": "velocity",
                                                                                  "equalize": True})]})
    st2, _, unequalized = render(srv, {"layers": [LAYERS[0], dict(LAYERS[1], color={"attribute": "velocity"})]})
    check(st == 200 and st2 == 200 and equalized != unequalized, "a layer's own equalized colour renders and changes "
          "the image (%d, %d)" % (st, st2))
    error(srv, {"layers": [LAYERS[0], dict(LAYERS[1], color={"equalize": True})], "method": "exact"}, 400,
          "layers[1].color.equalize", "a layer's equalization with the exact method")
    error(srv, {"layers": LAYERS, "color": {"equalize": True}}, 400, "color.equalize",
          "the request's own equalization with layers")
    error(srv, {"layers": [dict(ctx[0], color={"equalize": True}), LAYERS[1]]}, 400, "layers[0].color.equalize",
          "equalization of a context layer")
    sessions(srv)
    if websockets is not None:
        import asyncio
        asyncio.run(stream(srv))
    else:
        print("skip WebSocket sessions: python3-websockets is not installed")

    st, _, _ = render(srv, {"dataset": "demo:points"})
    check(st == 200, "the daemon keeps serving after the refusals")

check.done()
