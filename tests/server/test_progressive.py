"""params.progressive (docs/ALGORITHM.md section 34) in every path of the real
daemon: a one-shot POST and a GET (flat alias) run every batch and return the
one-shot image with X-Lucent-Progressive saying batch n of n and when the first
batch's picture was ready; `lucent render --progressive` prints the same; a
method it does not apply to (exact) and a combination the renderer refuses
(subset) name params.progressive; an HTTP session, a WebSocket session's update
and a movie refuse it naming params.progressive (their frames do not draw in
batches yet)."""
import asyncio
import json
import os
import subprocess
import sys
import tempfile
import urllib.parse

from lucent_server import Check, Server, foreign_leaks_only, ssim, wait_for_message, wait_for_stream_done, websockets

binary = sys.argv[1]
check = Check()
SIZE = {"width": 96, "height": 80}


def refused(st, data, field, what):
    e = json.loads(data).get("error", {}) if st != 200 else {}
    check(st == 400 and e.get("field") == field, "%s is refused naming %s (%d %s)" % (what, field, st, e))


with Server(binary, data=("demo:tornado", "demo:points"), demo_size=120) as srv:
    for dataset in ("demo:tornado", "demo:points"):
        base = dict(SIZE, dataset=dataset, format="png")
        st, _, whole = srv.request("POST", "/api/v1/render", base)
        st2, hdrs, batched = srv.request("POST", "/api/v1/render", dict(base, params={"progressive": 4}))
        prog = dict(kv.split("=") for kv in hdrs.get("x-lucent-progressive", "").split(",") if "=" in kv)
        s = ssim(binary, batched, whole)
        check(st == 200 and st2 == 200 and s > 0.999,
              "%s in 4 batches is the one-shot image (SSIM %.5f)" % (dataset, s))
        check(prog.get("batch") == "4" and prog.get("of") == "4" and
              0 < float(prog.get("firstMs", -1)) < float(prog.get("wallMs", -1)),
              "X-Lucent-Progressive says batch 4 of 4 and the first picture before the whole (%s)" % prog)
        st, hdrs, _ = srv.request("GET", "/api/v1/render?" + urllib.parse.urlencode(dict(base, progressive=3)))
        check(st == 200 and hdrs.get("x-lucent-progressive", "").startswith("batch=3,of=3"),
              "GET with the flat alias progressive=3 (%d %s)" % (st, hdrs.get("x-lucent-progressive")))
    base = dict(SIZE, dataset="demo:tornado", format="png")
    st, _, data = srv.request("POST", "/api/v1/render", dict(base, method="exact", params={"progressive": 4}))
    refused(st, data, "params.progressive", "method exact with batches")
    st, _, data = srv.request("POST", "/api/v1/render", dict(base, params={"progressive": 4, "subset": 2}))
    refused(st, data, "params.progressive", "batches with params.subset")
    st, _, data = srv.request("POST", "/api/v1/sessions", dict(base, params={"progressive": 4}))
    refused(st, data, "params.progressive", "an HTTP session with batches")

    async def session():
        async with websockets.connect(srv.ws_url, max_size=None) as ws:
            await ws.send(json.dumps({"type": "hello", "dataset": "demo:tornado", "width": 80, "height": 64,
                                      "devicePixelRatio": 1}))
            done = await wait_for_stream_done(ws)
            check(done.reached, "the session's first picture is done")
            await ws.send(json.dumps({"type": "params", "params": {"progressive": 4}}))
            got = await wait_for_message(ws, lambda m: m.get("type") in ("error", "frame"))
            last = got[-1] if got.reached else {}
            check(last.get("type") == "error" and last.get("field") == "params.progressive",
                  "a WebSocket update with batches is refused naming params.progressive (%s)" % last)

    asyncio.run(session())
    st, _, data = srv.request("POST", "/api/v1/movies", dict(SIZE, request=dict(dataset="demo:tornado",
                                                                                params={"progressive": 4}),
                                                             frames=3, fps=3))
    refused(st, data, "params.progressive", "a movie with batches")

with tempfile.TemporaryDirectory() as d:
    out = os.path.join(d, "p.png")
    run = subprocess.run([binary, "render", "--input", "demo:tornado", "--out", out, "--width", "96", "--height", "80",
                          "--progressive", "4"], capture_output=True, text=True)
    # Under LeakSanitizer the CLI exits non-zero for the GL driver's own leaks alone (as the daemon would).
    ok = run.returncode == 0 or foreign_leaks_only(run.stderr, binary)
    check(ok and "progressive: 4 batches" in run.stdout,
          "lucent render --progressive 4 reports its batches (%d: %s %s)" % (run.returncode, run.stdout[-300:],
                                                                             run.stderr[-300:]))
check.done()
