"""The Python client (clients/python/lucent) against the real daemon: renders as
arrays of the asked size, bytes and PIL images, client-side validation that
names the field before any round trip, the server's errors on 4xx, the token,
the camera helpers (fit = the server's own fit, turntable about the view-up,
slerp/log-linear interpolation, the page's URL state), and a WebSocket session
(stills matching HTTP renders, one frame per camera, bad updates refused)."""
import math
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, ".."))

from lucent_server import Check, Server  # noqa: E402  (tests/server, on PYTHONPATH)

try:
    import numpy as np
    from PIL import Image
except ImportError:  # pragma: no cover
    print("SKIP: python3-numpy or python3-pil is not installed")
    sys.exit(77)

import lucent  # noqa: E402
from imgcheck import ssim  # noqa: E402

binary = sys.argv[1]
check = Check()
TOKEN = "s3cret-token"


def raises(fn, field=None, code=None, status=None):
    """The LucentError fn raises (None when it does not, or raises another)."""
    try:
        fn()
    except lucent.LucentError as e:
        ok = (field is None or e.field == field) and (code is None or e.code == code) and \
             (status is None or e.status == status)
        return e if ok else None
    return None


def dist(a, b):
    return math.sqrt(sum((x - y) ** 2 for x, y in zip(a, b)))


def session_checks(c, a, cams, what):
    """A session over the WebSocket: its stills match HTTP renders of the same
    view (a: the default camera's). Session.still() must return the frame
    that ends the stream (converged, not interactive, the final stage of a
    staged still), whatever path the server took to it."""
    with c.session("demo:tornado", size=(200, 150), interactiveScale=1, quality=95) as s:
        check(s.session_id and s.defaults["dataset"] == "demo:tornado", "%ssession: ready with defaults" % what)
        still = s.still()
        check(still.shape == (150, 200, 3) and ssim(still, a) > 0.95,
              "%ssession still = the HTTP render of the same view (SSIM %.4f, JPEG)" % (what, ssim(still, a)))
        frames = list(s.frames(cams[:4]))
        check(len(frames) == 4 and all(x.shape == (150, 200, 3) for x in frames) and s.last.header["cameraSeq"] == 4,
              "%sframes(cameras): one full-size frame per camera, the last for camera 4" % what)
        st = s.still(cams[2])
        head = {k: s.last.header.get(k) for k in ("frame", "cameraSeq", "converged", "stage", "stages", "final")}
        check(s.last.header.get("final", True) is not False and s.last.converged and not s.last.interactive,
              "%sstill(camera) returns the frame that ends the stream, not an earlier stage of a staged still "
              "(%s)" % (what, head))
        h = c.render("demo:tornado", size=(200, 150), camera=cams[2])
        check(ssim(st, h) > 0.95, "%sstill(camera) converges to the HTTP render of that camera (SSIM %.4f)"
              % (what, ssim(st, h)))
        e = raises(lambda: s.update(params={"bandz": 1}), "params.bandz", "unknown_field")
        check(e is not None, "%ssession.update with an unknown field raises naming it" % what)
        s.update(params={"q": 5, "r": 5})
        q5 = s.still()
        h5 = c.render("demo:tornado", size=(200, 150), camera=cams[2], params={"q": 5, "r": 5})
        check(ssim(q5, h5) > 0.95 and ssim(q5, st) < ssim(q5, h5),
              "%ssession.update(params) changes the stream (SSIM to HTTP %.4f, to before %.4f)" % (what, ssim(q5, h5),
                                                                                                  ssim(q5, st)))
        check(s.stats is None or s.stats.get("type") == "stats", "%sstats messages are kept" % what)


with Server(binary, "--token", TOKEN, data=("demo:tornado",), demo_size=120) as srv:
    c = lucent.Client(srv.base, TOKEN)
    names = [d["name"] for d in c.datasets()]
    check(names == ["demo:tornado"], "datasets() lists the served dataset: %s" % names)

    a = c.render("demo:tornado", size=(200, 150))
    check(isinstance(a, np.ndarray) and a.shape == (150, 200, 3) and a.dtype == np.uint8,
          "render() gives a uint8 array (150, 200, 3): %s" % (a.shape,))
    check(a.std() > 5, "the array holds an image (std %.1f)" % a.std())
    png = c.render("demo:tornado", size=(200, 150), format="png")
    check(png[:8] == b"\x89PNG\r\n\x1a\n", "format='png' gives the PNG bytes")
    check(np.array_equal(np.asarray(Image.open(__import__("io").BytesIO(png)).convert("RGB")), a),
          "the array is the PNG's pixels")
    jpg = c.render("demo:tornado", size=(200, 150), format="jpeg", quality=80)
    check(jpg[:2] == b"\xff\xd8", "format='jpeg' gives JPEG bytes")
    im = c.render("demo:tornado", size=(64, 48), format="pil")
    check(im.size == (64, 48), "format='pil' gives a PIL image of 64x48")
    b = c.render("demo:tornado", size=(200, 150), params={"q": 5, "r": 5})
    check(not np.array_equal(a, b), "params reach the server (q, r change the image)")

    # Client-side validation: no request leaves the client.
    sent = []
    real_open = c._open
    c._open = lambda *args, **kw: sent.append(args) or real_open(*args, **kw)
    cases = [(dict(params={"bandz": 3}), "params.bandz", "unknown_field"),
             (dict(bandz=3), "bandz", "unknown_field"),
             (dict(params={"bands": 9}), "params.bands", "out_of_range"),
             (dict(params={"bands": "five"}), "params.bands", "bad_field"),
             (dict(size=(9000, 100)), "width", "out_of_range"),
             (dict(color={"colormap": "rainbow"}), "color.colormap", "bad_field"),
             (dict(camera={"position": [0, 0]}), "camera.position", "bad_field"),
             (dict(style={"background": [2, 0, 0]}), "style.background", "out_of_range"),
             (dict(method="raytrace"), "method", "bad_field")]
    for kw, field, code in cases:
        e = raises(lambda: c.render("demo:tornado", **kw), field, code)
        check(e is not None and field in str(e), "%s -> LucentError %s naming %s (%s)" % (kw, code, field, e))
    check(not sent, "none of them reached the server (%d requests)" % len(sent))
    c._open = real_open

    # The server's errors: code, field and its message.
    e = raises(lambda: c.render("demo:tornado", size=(64, 64), importance={"attribute": "nope"}),
               "importance.attribute", "bad_field", 400)
    check(e is not None and "has no attribute" in str(e), "a field only the server checks -> 400 with its text: %s" % e)
    e = raises(lambda: c.render("demo:nope", size=(64, 64)), "dataset", "not_found", 404)
    check(e is not None, "unknown dataset -> 404 not_found naming dataset: %s" % e)
    e = raises(lambda: lucent.Client(srv.base).datasets(), None, "unauthorized", 401)
    check(e is not None, "no token -> 401 unauthorized: %s" % e)

    # fit(): the server's own fit (the dataset's suggested view).
    fitted = c.fit("demo:tornado")
    f = c.render("demo:tornado", size=(200, 150), camera=fitted)
    check(np.array_equal(a, f), "render(camera=fit()) equals the server's default camera, pixel for pixel")

    # turntable(): about the view-up, up fixed, distance fixed, even steps.
    cams = lucent.turntable(fitted, 8)
    up = cams[0]["viewUp"]
    fp = cams[0]["focalPoint"]
    r0 = dist(cams[0]["position"], fp)
    check(all(dist(k["viewUp"], up) < 1e-12 for k in cams), "turntable keeps the view-up vector")
    heights = [sum((p - q) * u for p, q, u in zip(k["position"], fp, up)) for k in cams]
    check(max(heights) - min(heights) < 1e-9 * r0, "turntable keeps the height along the up axis (no pole crossing)")
    check(all(abs(dist(k["position"], fp) - r0) < 1e-9 * r0 for k in cams), "turntable keeps the distance")
    steps = [dist(cams[i]["position"], cams[i + 1]["position"]) for i in range(7)]
    check(max(steps) - min(steps) < 1e-9 * r0, "turntable steps are even")
    check(dist(cams[0]["position"], fitted["position"]) < 1e-12 and
          abs(dist(cams[4]["position"], fitted["position"]) - 2 * math.sqrt(r0 * r0 - heights[0] ** 2)) < 1e-6 * r0,
          "frame 0 is the start and frame n/2 the opposite side")

    # interpolate(): slerp of the orientation, log-linear distance.
    near = dict(fitted)
    near["position"] = [q + 0.25 * (p - q) for p, q in zip(cams[2]["position"], fp)]
    mid = lucent.interpolate(cams[0], near, 0.5)
    d_mid = dist(mid["position"], fp)
    check(abs(d_mid - math.sqrt(r0 * 0.25 * r0)) < 1e-9 * r0, "interpolate: distance is the geometric mean (%.4f)" % d_mid)
    ref = lucent.turntable(fitted, 8)[1]
    dir_mid = [(p - q) / d_mid for p, q in zip(mid["position"], fp)]
    dir_ref = [(p - q) / r0 for p, q in zip(ref["position"], fp)]
    check(dist(dir_mid, dir_ref) < 1e-9 and dist(mid["viewUp"], up) < 1e-9,
          "interpolate: halfway between 0 and 90 degrees looks from 45 degrees with the same up")

    # from_url(): the web page's hash.
    hash_ = "#dataset=demo:tornado&position=%s&focalPoint=%s&viewUp=%s&q=80&colormap=plasma" % tuple(
        ",".join("%.9g" % x for x in cams[1][k]) for k in ("position", "focalPoint", "viewUp"))
    ds, cam, upd = c.from_url("http://host:8080/" + hash_)
    check(ds == "demo:tornado" and upd == {"params": {"q": 80}, "color": {"colormap": "plasma"}} and
          dist(cam["position"], cams[1]["position"]) < 1e-6, "from_url reads dataset, camera and parameters")
    u = c.render(ds, size=(200, 150), camera=cam, **upd)
    v = c.render("demo:tornado", size=(200, 150), camera=cams[1], params={"q": 80}, color={"colormap": "plasma"})
    check(ssim(u, v) > 0.999, "render(from_url(link)) is the link's view (SSIM %.5f)" % ssim(u, v))
    try:
        c.from_url("#bandz=3")
        check(False, "from_url refuses an unknown key")
    except ValueError as ex:
        check("bandz" in str(ex), "from_url names the unknown key: %s" % ex)

    session_checks(c, a, cams, "")
    e = raises(lambda: c.session("demo:nope", size=(64, 64)), "dataset", "not_found")
    check(e is not None, "a session on an unknown dataset raises not_found naming dataset")
    check(srv.stop() == 0, "daemon exits cleanly")

# The same session on a server that sleeps 100 ms before every pass: every
# still takes over 500 ms, so the server stages each still after the first
# (protocol/websocket.md "Staged stills": stage 1 reuses the moving frames'
# opacities and reports converged, stage 2 is the final one). Which of the two
# paths a still takes above depends on the machine's speed (CI's loaded
# sanitizer runs stage them); here the staged path is taken for sure.
with Server(binary, "--pass-delay", "100", data=("demo:tornado",), demo_size=120) as srv:
    c = lucent.Client(srv.base)
    a = c.render("demo:tornado", size=(200, 150))
    cams = lucent.turntable(c.fit("demo:tornado"), 8)
    session_checks(c, a, cams, "staged stills: ")
    check(srv.stop() == 0, "daemon exits cleanly")

check.done()
