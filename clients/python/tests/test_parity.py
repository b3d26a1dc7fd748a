"""A session's still is the one-shot render of the same request, on data large
enough that the session starts with a coarse, thinned first frame and stages
its stills (≥ 500k primitives): the converged still's visibility report and
picture match POST /api/v1/render of the same camera, size and parameters, at
clarity 0, 0.5 and 0.9 and after a detour through other settings (the session's
history does not change its still). On such data the still once kept the
strength the coarse frame had found and stopped at fog."""
import io
import json
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
SIZE = (192, 144)
# 1000 tornado streamlines: about 524k segments, over the daemon's threshold
# for a coarse first frame (500k primitives).
LINES = 1000
CAMERA = {"position": [0.5, -1.6, 1.4], "focalPoint": [0.5, 0.5, 0.5], "viewUp": [0, 0, 1]}


def http_render(srv, params):
    body = {"dataset": "demo:tornado", "width": SIZE[0], "height": SIZE[1], "camera": CAMERA, "format": "png",
            "params": params}
    st, headers, data = srv.request("POST", "/api/v1/render", json.dumps(body), timeout=300)
    assert st == 200, "HTTP render: %d %s" % (st, data[:300])
    vis = dict(kv.split("=") for kv in headers.get("x-lucent-visibility", "").split(",") if "=" in kv)
    img = np.asarray(Image.open(io.BytesIO(data)).convert("RGB"))
    return img, {k: float(v) for k, v in vis.items()}


def compare(srv, s, params, what):
    still = s.still()
    h = s.last.header
    sv = h.get("visibility") or {}
    img, hv = http_render(srv, params)
    top_s, top_h = sv.get("topDecileAlpha", -1), hv.get("topDecileAlpha", -2)
    check(abs(top_s - top_h) <= 0.05,
          "%s: the still's top-decile opacity %.3f = the HTTP render's %.3f (within 0.05)"
          % (what, top_s, top_h))
    sim = ssim(still, img)
    check(sim >= 0.95, "%s: the still is the HTTP render's picture (SSIM %.4f, JPEG)" % (what, sim))
    return top_s


with Server(binary, data=("demo:tornado",), demo_size=LINES) as srv:
    c = lucent.Client(srv.base)
    with c.session("demo:tornado", size=SIZE, camera=CAMERA, quality=95, interactiveScale=1) as s:
        first = s.next_frame()
        check(first.interactive, "the first frame on %d lines is a coarse one: %s" % (LINES, first.header.get("detail")))
        compare(srv, s, {}, "defaults")
        tops = {}
        for clarity in (0, 0.5, 0.9):
            s.update(params={"clarity": clarity})
            tops[clarity] = compare(srv, s, {"clarity": clarity}, "clarity %g" % clarity)
        check(tops[0.9] > tops[0.5] + 0.03, "the clarity knob acts in the session: top decile %s" % tops)
        # A detour through other settings and views, then back: the same still as before.
        s.update(params={"clarity": 0.2})
        s.still({"position": [2.0, 0.5, 0.5], "focalPoint": [0.5, 0.5, 0.5], "viewUp": [0, 0, 1]})
        s.update(params={"clarity": 0.5})
        s.camera(CAMERA)
        after = compare(srv, s, {"clarity": 0.5}, "clarity 0.5 after a detour")
        check(abs(after - tops[0.5]) <= 0.02, "no history: clarity 0.5 gives %.3f as before %.3f" % (after, tops[0.5]))
check.done()
