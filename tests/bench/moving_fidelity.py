#!/usr/bin/env python3
"""How much a moving frame looks like the still, per primitive it draws (prints figures; not part of the
pass/fail suite).

Renders the still of one camera (`lucent render`, full detail, --size) and then moving frames of the same
camera as a session draws them: a first frame that optimizes, then a frame that reuses its opacities at a
level of detail, a line or point stride and a smaller size (`lucent render --frames 2 --lod PX --line-stride N`
or `--point-stride N`). Each moving frame is stretched to the still's size as the page stretches it and
compared by SSIM (Rec. 709 luminance, 11x11 Gaussian, sigma 1.5, as `lucent ssim`; also halved and
quartered). Besides it: the primitives the moving frame drew and its P4 and P5 milliseconds (noisy on a
shared host; the host's load is printed). A frame's time on a software rasterizer grows with its primitives
(set-up on the drawing thread: docs/EVALUATION.md "The geometry path") and, at larger sizes, with its
fragments: a coarser level's segments are longer and cover about as many pixels as the lines they simplify,
so equal primitives are not equal time.

The SSIM figures do not depend on the load: they say how much likeness each setting of one camera buys,
where the orbit of tests/bench/browse_bench.py can only say what its controller settled on.

  tests/bench/moving_fidelity.py --binary build/lucent --dataset build/real-data/thiophene.dump \\
      --camera DIR/moving.json 486x381:2:4 340x266:8:16
The camera: a browse_bench.py --save DIR's moving.json (the orbit's last camera), else the data fitted.
A variant is WxH:LOD:STRIDE (LOD in the frame's pixels, 0 = the request's; STRIDE of lines or points).
--json FILE also writes the rows. Needs python3-numpy and python3-pil.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from browse_bench import halve, np, ssim  # noqa: E402

if np is not None:
    from PIL import Image

DEFAULT_VARIANTS = ["486x381:2:1", "486x381:2:2", "486x381:2:4", "486x381:8:1", "486x381:8:16", "340x266:8:16"]


def luminance(path, size=None):
    img = Image.open(path).convert("RGB")
    if size and img.size != size:
        img = img.resize(size, Image.BILINEAR)
    a = np.asarray(img, dtype=np.float64) / 255.0
    return a[..., 0] * 0.2126 + a[..., 1] * 0.7152 + a[..., 2] * 0.0722


def drawn(text):
    """The primitives the last frame drew, from `lucent render`'s report."""
    m = re.search(r"lines: about (\d+) segments .*?, (\d+) of one line in (\d+)", text)
    if m:
        return int(m.group(1)) + int(m.group(2)), "lines 1/%s" % m.group(3)
    m = re.search(r"detail: (\d+) of (\d+) points \(stride (\d+)", text)
    if m:
        return int(m.group(1)), "points 1/%s" % m.group(3)
    m = re.search(r"detail: level (\d+) of \d+ \(lod [^)]*\), (\d+) of \d+ segments", text)
    if m:
        return int(m.group(2)), "level %s" % m.group(1)
    m = re.search(r"method \S+, .*?, (\d+) elements", text)
    return (int(m.group(1)) if m else None), "all"


def render(args, req, out, extra):
    cmd = [args.binary, "render", "--request", req, "--out", out, "--stats", out + ".json"] + extra
    t = time.time()
    p = subprocess.run(cmd, check=True, capture_output=True, text=True)
    with open(out + ".json") as f:
        stats = json.load(f)
    return p.stdout, stats, time.time() - t


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", default="build/lucent")
    ap.add_argument("--dataset", required=True)
    ap.add_argument("--camera", help="a JSON file with a camera (browse_bench --save's moving.json), or the camera")
    ap.add_argument("--size", default="972x761", help="the still's size (the page's viewport)")
    ap.add_argument("--json", metavar="FILE")
    ap.add_argument("variants", nargs="*", default=DEFAULT_VARIANTS, help="WxH:LOD:STRIDE")
    args = ap.parse_args()
    if np is None:
        sys.exit("needs python3-numpy and python3-pil")
    w, h = (int(x) for x in args.size.split("x"))
    req = {"dataset": args.dataset, "width": w, "height": h}
    if args.camera:
        with open(args.camera) as f:
            cam = json.load(f)
        req["camera"] = cam.get("camera", cam)
    tmp = tempfile.mkdtemp(prefix="moving_fidelity.")
    rq = os.path.join(tmp, "request.json")
    with open(rq, "w") as f:
        json.dump(req, f)
    load0 = os.getloadavg()[0]
    still_png = os.path.join(tmp, "still.png")
    text, stats, wall = render(args, rq, still_png, ["--input", args.dataset])
    still = luminance(still_png)
    n_still, _ = drawn(text)
    print("dataset %s, still %dx%d: %s primitives, %.1f s wall" % (args.dataset, w, h, n_still, wall), flush=True)
    print("| moving frame | lod px | stride | drawn | primitives | SSIM vs still | halved | quartered | P4 + P5 ms |")
    print("|---|---|---|---|---|---|---|---|---|")
    rows = []
    for v in args.variants:
        size, lod, stride = v.split(":")
        out = os.path.join(tmp, "moving_%s.png" % v.replace(":", "_"))
        # Drawn at a fraction of the view's size, as the session draws it (splats and markers keep their view size).
        extra = ["--input", args.dataset, "--size", size, "--frames", "2", "--line-stride", stride,
                 "--pixel-scale", "%.6f" % min(1.0, int(size.split("x")[1]) / h)]
        if int(stride) > 1:
            extra += ["--point-stride", stride]
        if float(lod) > 0:
            extra += ["--lod", lod]
        text, stats, wall = render(args, rq, out, extra)
        a, b = luminance(out, (w, h)), still
        s = ssim(a, b)
        a2, b2 = halve(a), halve(b)
        s2, s4 = ssim(a2, b2), ssim(halve(a2), halve(b2))
        n, how = drawn(text)
        t = stats.get("passMs") or {}
        p45 = t.get("opticalDepth", 0) + t.get("accumulate", 0)
        rows.append({"size": size, "lod": float(lod), "stride": int(stride), "drawn": how, "primitives": n,
                     "ssim": s, "ssim_halved": s2, "ssim_quartered": s4, "p4_p5_ms": p45})
        print("| %s | %s | %s | %s | %s | %.3f | %.3f | %.3f | %.0f |" % (size, lod, stride, how, n, s, s2, s4, p45),
              flush=True)
    print("load %.1f before, %.1f after" % (load0, os.getloadavg()[0]))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"dataset": args.dataset, "size": args.size, "still_primitives": n_still, "rows": rows}, f,
                      indent=1)


if __name__ == "__main__":
    main()
