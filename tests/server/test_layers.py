"""layers[] against the real daemon: a two-layer HTTP render (points demo and
tornado lines) answers an image that differs from either layer alone, the GET
form takes layers as JSON text, and bad layer specifications get a clear error
naming the field: an unknown dataset (404, layers[i].dataset), an unknown key,
an unknown attribute of one layer's dataset, a layer of the frame's style, a
context layer of points, layers in a session or a WebSocket hello, a method
that cannot draw layers. A surface as opaque context renders."""
import json
import sys
import urllib.parse

from lucent_server import Check, Server, png_size, skip, websockets

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


with Server(binary, data=("demo:points", "demo:tornado", "demo:surface"), demo_size=300) as srv:
    st, hdrs, both = render(srv, {"layers": LAYERS})
    check(st == 200 and png_size(both) == (96, 80), "two-layer render -> 200, a 96x80 PNG (%d)" % st)
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
    error(srv, {"layers": LAYERS, "dataset": "demo:points"}, 400, "layers", "layers in a scripted session",
          path="/api/v1/sessions")

    if websockets is not None:
        import asyncio

        async def hello():
            async with websockets.connect(srv.ws_url, max_size=None) as ws:
                await ws.send(json.dumps({"type": "hello", "dataset": "demo:points", "width": 64, "height": 48,
                                          "layers": LAYERS}))
                while True:
                    m = json.loads(await asyncio.wait_for(ws.recv(), 30))
                    if m.get("type") not in ("stats", "progress"):
                        return m

        m = asyncio.run(hello())
        check(m.get("type") == "error" and m.get("field") == "layers", "a WebSocket hello with layers -> error naming layers (%r)" % m)
    else:
        print("skip WebSocket hello: python3-websockets is not installed")

    st, _, _ = render(srv, {"dataset": "demo:points"})
    check(st == 200, "the daemon keeps serving after the refusals")

check.done()
