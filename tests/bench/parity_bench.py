"""Session parity on real files: what the page settles on against the one-shot render.

For each file it starts `lucent serve --data FILE` with every server option at its default. Then it opens a
WebSocket session with defaults, the way the page does, and waits for the final still. It compares that still
with POST /api/v1/render of the same request. The comparisons are:
  - topDecileAlpha within 0.05
  - SSIM >= 0.95 (JPEG at quality 95)

It does this at the default clarity (0.5), at clarity 0 and 0.9, and at 0.5 again after a detour through other
settings and views. With the defaults it also prints the time from hello to the first picture and to the
final still.

Usage: parity_bench.py LUCENT FILE... [--size WxH]
Prints one Markdown row per file and comparison. Exits 1 when a comparison misses.
Opt-in: scripts/real_data.sh --lammps fetches the corpus; docs/EVALUATION.md has the table.
"""
import io
import json
import os
import sys
import time

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.dirname(os.path.dirname(here))
sys.path[:0] = [os.path.join(root, "tests", "server"), os.path.join(root, "clients", "python"),
                os.path.join(root, "clients", "python", "tests")]

import numpy as np  # noqa: E402
from PIL import Image  # noqa: E402

import lucent  # noqa: E402
from imgcheck import ssim  # noqa: E402
from lucent_server import Server  # noqa: E402

args = [a for a in sys.argv[1:] if not a.startswith("--size")]
size = next((tuple(int(x) for x in a.split("=", 1)[1].split("x")) for a in sys.argv[1:] if a.startswith("--size=")),
            (640, 480))
binary, files = args[0], args[1:]
misses = 0


opened = {}  # params the server opened the session with (a params.subset where a full frame is over --max-cost)


def http_render(srv, name, params):
    body = {"dataset": name, "width": size[0], "height": size[1], "format": "png", "params": dict(opened, **params)}
    t0 = time.monotonic()
    st, headers, data = srv.request("POST", "/api/v1/render", json.dumps(body), timeout=900)
    ms = (time.monotonic() - t0) * 1e3
    if st != 200:
        raise RuntimeError("HTTP render of %s: %d %s" % (name, st, data[:300]))
    vis = dict(kv.split("=") for kv in headers.get("x-lucent-visibility", "").split(",") if "=" in kv)
    return np.asarray(Image.open(io.BytesIO(data)).convert("RGB")), float(vis.get("topDecileAlpha", -1)), ms


def row(name, what, s_top, h_top, sim, extra=""):
    global misses
    ok = abs(s_top - h_top) <= 0.05 and sim >= 0.95
    misses += not ok
    print("| %s | %s | %.3f | %.3f | %.4f | %s | %s |" % (name, what, s_top, h_top, sim, "yes" if ok else "**no**",
                                                       extra), flush=True)


def compare(srv, s, name, label, params, what):
    still = s.still(timeout=900)
    top = (s.last.header.get("visibility") or {}).get("topDecileAlpha", -1)
    img, h_top, _ = http_render(srv, name, params)
    row(label, what, top, h_top, ssim(still, img))
    return top


print("| file | settings | session still: top decile | one-shot: top decile | SSIM | parity | times |")
print("|---|---|---|---|---|---|---|")
for path in files:
    with Server(binary, data=(path,), demo_size=0, timeout=900) as srv:
        info = srv.json("GET", "/api/v1/datasets")[2]["datasets"][0]
        name = info["name"]
        lo, hi = info["bounds"]
        centre = [(a + b) / 2 for a, b in zip(lo, hi)]
        diag = sum((b - a) ** 2 for a, b in zip(lo, hi)) ** 0.5
        detour = {"position": [c + diag * k for c, k in zip(centre, (0.9, 1.1, 0.7))], "focalPoint": centre,
                  "viewUp": [0, 0, 1]}
        label = os.path.basename(path)
        c = lucent.Client(srv.base)
        t0 = time.monotonic()
        with c.session(name, size=size, quality=95, timeout=900) as s:
            opened.clear()
            subset = (s.defaults or {}).get("params", {}).get("subset", 1)
            if subset > 1:
                opened["subset"] = subset
            first = s.next_frame()
            t_first = time.monotonic() - t0
            done = first.converged and not first.interactive and first.header.get("final", True) is not False
            still = first.array() if done else s.still(timeout=900)
            t_still = time.monotonic() - t0
            top = (s.last.header.get("visibility") or {}).get("topDecileAlpha", -1)
            img, h_top, h_ms = http_render(srv, name, {})
            row(label, "defaults", top, h_top, ssim(still, img),
                "first picture %.2f s (%dx%d), final still %.2f s after hello; one-shot %.2f s%s" %
                (t_first, first.header["width"], first.header["height"], t_still, h_ms / 1e3,
                 "; opened with params.subset %d (over --max-cost at 1)" % subset if subset > 1 else ""))
            tops = {}
            for clarity in (0, 0.9):
                s.update(params={"clarity": clarity})
                tops[clarity] = compare(srv, s, name, label, {"clarity": clarity}, "clarity %g" % clarity)
            # A detour through other settings and a view, then back to the defaults' camera fit.
            s.update(params={"clarity": 0.2, "smoothing": 3})
            s.camera(detour)
            s.still(timeout=900)
            s.update(params={"clarity": 0.5, "smoothing": 15})
            s.camera(None)
            compare(srv, s, name, label, {"clarity": 0.5}, "clarity 0.5 after a detour")
sys.exit(1 if misses else 0)
