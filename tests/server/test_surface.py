"""Method surface-layers over HTTP (docs/ALGORITHM.md §23): a real client asks
for a field's stream surface. On the linear shear field a straight seed line
across the flow gives a planar surface, seen face-on: every covered pixel holds
one layer and shows exactly opacity * colour + (1 - opacity) * background; the
weighted-average baseline of the same curves saturates towards the surface
colour (PRT Fig. 5); surface.direction extends the surface downstream, upstream
or both ways from the seed. Bad surface objects are refused naming the field."""
import json
import sys
import urllib.parse

from lucent_server import Check, Server, decode_png

binary = sys.argv[1]
check = Check()
SIZE = 96
BG = [1.0, 1.0, 1.0]
COLOR = [0.2, 0.4, 0.8]
OPACITY = 0.3


def pixel(img, x, y):
    w, h, ch, rows = img
    return tuple(rows[y][x * ch:x * ch + 3])


def surface_request(**surface):
    s = dict(field="demo:shear-flow", seed=[[-0.9, -0.6, 0], [-0.9, 0.6, 0]], particles=200, opacity=OPACITY,
             color=COLOR, length=1.6)
    s.update(surface)
    return {"method": "surface-layers", "width": SIZE, "height": SIZE, "format": "png",
            "camera": {"position": [0, 0, 3], "focalPoint": [0, 0, 0], "viewUp": [0, 1, 0], "viewAngle": 40},
            "style": {"background": BG}, "surface": s}


def header_fields(headers):
    text = headers.get("x-lucent-surface", "")
    return dict(kv.split("=", 1) for kv in text.split(",") if "=" in kv)


def render(srv, body):
    st, headers, data = srv.request("POST", "/api/v1/render", json.dumps(body))
    return st, headers, data


def error(srv, body, status, field, what):
    st, _, data = render(srv, body)
    try:
        e = json.loads(data).get("error", {})
    except ValueError:
        e = {}
    check(st == status and e.get("field") == field,
          "%s -> %d naming %s (got %d, %s)" % (what, status, field, st, data[:200].decode(errors="replace")))


with Server(binary, data=("demo:points", "demo:shear-flow", "demo:abc-flow")) as srv:
    st, headers, data = render(srv, surface_request())
    check(st == 200 and headers.get("content-type") == "image/png",
          "a shear surface renders: %d %s" % (st, data[:200] if st != 200 else ""))
    hf = header_fields(headers)
    check(hf.get("curves") == "200", "X-Lucent-Surface counts the 200 curves traced: %r" % hf)
    check(int(hf.get("drawnFragments", "0")) > 200, "a one-shot render draws all its curves' fragments: %r" % hf)
    lpp = float(hf.get("layersPerPixel", "0"))
    check(1.0 <= lpp <= 1.02 and hf.get("maxLayers") in ("1", "2") and hf.get("overflow") == "0",
          "a planar surface is one layer per covered pixel: %r" % hf)
    img = decode_png(data)
    want = tuple(round(255 * (OPACITY * c + (1 - OPACITY) * b)) for c, b in zip(COLOR, BG))
    centre = pixel(img, SIZE // 2, SIZE // 2)
    check(all(abs(a - b) <= 1 for a, b in zip(centre, want)),
          "the centre shows one layer over the background: %r, want %r" % (centre, want))
    corner = pixel(img, 1, 1)
    check(corner == (255, 255, 255), "outside the surface the background: %r" % (corner,))

    # The count-based baseline: many curves per pixel saturate towards the surface colour.
    st, headers, wa = render(srv, surface_request(composite="weighted-average", particles=2000))
    wimg = decode_png(wa) if st == 200 else None
    wc = pixel(wimg, SIZE // 2, SIZE // 2) if wimg else (0, 0, 0)
    opaque = tuple(round(255 * c) for c in COLOR)
    check(st == 200 and all(abs(a - b) <= 12 for a, b in zip(wc, opaque)),
          "weighted-average saturates to the surface colour %r: %r" % (opaque, wc))
    st, headers, la = render(srv, surface_request(particles=2000))
    lc = pixel(decode_png(la), SIZE // 2, SIZE // 2) if st == 200 else (0, 0, 0)
    check(all(abs(a - b) <= 1 for a, b in zip(lc, want)), "the layers stay at one layer's colour: %r" % (lc,))

    # surface.direction: from a seed across the middle (x = 0) the forward surface covers x > 0, the backward one
    # x < 0, and both ways cover both sides (half-width 3 tan 20 deg = 1.09 at z = 0: x = +-0.4 is 48 +- 18 px).
    seen = {}
    for direction in ("forward", "backward", "both"):
        st, headers, data = render(srv, surface_request(seed=[[0, -0.6, 0], [0, 0.6, 0]], length=0.8,
                                                        direction=direction))
        img = decode_png(data) if st == 200 else None
        seen[direction] = tuple(pixel(img, SIZE // 2 + dx, SIZE // 2) != (255, 255, 255) for dx in (-18, 18)) \
            if img else None
    check(seen == {"forward": (False, True), "backward": (True, False), "both": (True, True)},
          "direction covers downstream, upstream or both sides of the seed (left, right covered): %r" % seen)
    error(srv, surface_request(direction="sideways"), 400, "surface.direction", "an unknown direction")

    # The flat query form reaches the same fields.
    q = urllib.parse.urlencode({"method": "surface-layers", "surfaceField": "demo:abc-flow",
                                "surfaceSeed": "[[3.14,0.63,3.14],[3.14,5.65,3.14]]", "surfaceParticles": 100,
                                "width": 64, "height": 64})
    st, headers, data = srv.request("GET", "/api/v1/render?" + q)
    check(st == 200 and header_fields(headers).get("curves") == "100", "GET with surfaceField/surfaceSeed: %d" % st)

    error(srv, surface_request(field="no-such-flow"), 404, "surface.field", "an unknown field")
    error(srv, surface_request(field="demo:points"), 404, "surface.field", "a scene dataset is no field")
    error(srv, surface_request(seed=[[0, 0, 0]]), 400, "surface.seed", "a seed of one point")
    error(srv, surface_request(seed=[[0, 0, 0], [0, 0, 0]]), 400, "surface.seed[1]", "a zero-length segment")
    error(srv, surface_request(seed=[[0, 0, "x"], [0, 1, 0]]), 400, "surface.seed[0]", "a seed point not a number")
    error(srv, surface_request(seed=[[5, 5, 5], [6, 6, 6]]), 400, "surface.seed", "a seed outside the field")
    error(srv, surface_request(particles=0), 400, "surface.particles", "no particles")
    error(srv, surface_request(particles=10 ** 6), 400, "surface.particles", "too many particles")
    error(srv, surface_request(opacity=0), 400, "surface.opacity", "opacity 0")
    error(srv, surface_request(composite="paint"), 400, "surface.composite", "an unknown composite")
    body = surface_request()
    del body["surface"]["seed"]
    error(srv, body, 400, "surface.seed", "no seed")
    body = surface_request()
    del body["surface"]["field"]
    error(srv, body, 400, "surface.field", "no field")
    st, _, data = srv.request("POST", "/api/v1/sessions", json.dumps(surface_request()))
    check(st == 400 and json.loads(data).get("error", {}).get("field") == "method",
          "HTTP sessions refuse surface-layers naming method: %d" % st)
    # ... and so does an update of one: refused by the session's one update function, the session unchanged.
    st, _, data = srv.request("POST", "/api/v1/sessions", json.dumps({"dataset": "demo:points", "width": 64,
                                                                       "height": 48}))
    sid = json.loads(data).get("session") if st == 201 else None
    path = "/api/v1/sessions/%s/render" % sid
    st, _, before = srv.request("POST", path, json.dumps({"format": "png"}))
    st2, _, data = srv.request("POST", path, json.dumps({"method": "surface-layers", "surface": surface_request()["surface"]}))
    st3, _, after = srv.request("POST", path, json.dumps({"format": "png"}))
    check(sid and st == 200 and st2 == 400 and json.loads(data).get("error", {}).get("field") == "method"
          and st3 == 200 and after == before,
          "an HTTP session's update to surface-layers is refused naming method and changes nothing: %s %d %d %d"
          % (sid, st, st2, st3))
    st, _, data = srv.request("POST", "/api/v1/render", json.dumps(dict(surface_request(), **{"dataset": "demo:points"})))
    check(st == 200, "the request's dataset does not matter to the method: %d" % st)

    # Every method with every kind of data, POST and GET: an image, or a 4xx
    # naming a field; never a dead daemon (surface-layers with layers was one).
    surface = {"field": "demo:shear-flow", "seed": [[-0.9, -0.6, 0], [-0.9, 0.6, 0]], "particles": 20}
    kinds = {"dataset": {"dataset": "demo:points"}, "layers": {"layers": [{"dataset": "demo:points"}]},
             "field": {"surface": surface},
             "layers+field": {"layers": [{"dataset": "demo:points"}], "surface": surface}}
    for method in ("fourier", "exact", "opaque", "direct", "wboit", "surface-layers", "weighted-average", "binning", "kanzler"):
        for kind, extra in kinds.items():
            body = dict({"method": method, "width": 32, "height": 32}, **extra)
            flat = {k: json.dumps(v) if isinstance(v, (list, dict)) else v for k, v in body.items()}
            if "surface" in flat:
                del flat["surface"]
                flat.update(surfaceField=surface["field"], surfaceSeed=json.dumps(surface["seed"]),
                            surfaceParticles=surface["particles"])
            for verb, (st, _, data) in (("POST", render(srv, body)),
                                        ("GET", srv.request("GET", "/api/v1/render?" + urllib.parse.urlencode(flat)))):
                e = json.loads(data).get("error", {}) if st != 200 else {}
                check(st == 200 or (400 <= st < 500 and e.get("field")),
                      "%s %s with %s: an image or an error naming a field (%d %r)" % (verb, method, kind, st, e))
                if method == "surface-layers" and kind == "layers+field":
                    check(st == 400 and e.get("field") == "layers",
                          "%s surface-layers with layers is refused naming layers: %d %r" % (verb, st, e))
    st, _, h = srv.json("GET", "/api/v1/health")
    check(st == 200, "the daemon still serves: %d" % st)

    # The page's sizes: where a frame's layers would not fit one storage block, fewer layers, not a failure.
    for w, h in ((972, 761), (1920, 1080)):
        req = dict(surface_request(particles=100), width=w, height=h, format="jpeg")
        st, headers, data = render(srv, req)
        k = int(header_fields(headers).get("k", "0")) if st == 200 else 0
        check(st == 200 and 1 <= k <= 8, "a %dx%d surface renders with %d layers a pixel (%d %s)" %
              (w, h, k, st, data[:200] if st != 200 else ""))

with Server(binary, "--max-cost", "1e6", data=("demo:points", "demo:shear-flow")) as srv:
    st, _, data = render(srv, surface_request(particles=5000))
    e = json.loads(data).get("error", {}) if st != 200 else {}
    check(st == 400 and e.get("code") == "too_expensive" and e.get("field") == "surface.particles",
          "--max-cost refuses a large surface naming surface.particles: %d %r" % (st, e))
check.done()
