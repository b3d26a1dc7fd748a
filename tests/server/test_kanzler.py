"""Method "kanzler" (docs/ALGORITHM.md section 28) in every path of the real
daemon: a one-shot POST and GET (flat aliases) render, differ from "direct"
with the penalty's weights, carry the visibility report, and a field that does
not apply (kanzlerVariance on points) is refused naming it; a WebSocket
session switched to kanzler streams frames whose header has the visibility,
an update of its weights re-renders, and a refused update names its field; a
movie of a kanzler request renders every frame."""
import asyncio
import json
import sys
import time
import urllib.parse

from lucent_server import Check, Server, skip, ssim, wait_for_message, wait_for_stream_done, websockets

binary = sys.argv[1]
check = Check()
SIZE = {"width": 96, "height": 80}

with Server(binary, data=("demo:tornado", "demo:points"), demo_size=120) as srv:
    base = dict(SIZE, dataset="demo:tornado", format="png")
    st, hdrs, kanzler = srv.request("POST", "/api/v1/render", dict(base, method="kanzler"))
    vis = dict(kv.split("=") for kv in hdrs.get("x-lucent-visibility", "").split(",") if "=" in kv)
    check(st == 200 and kanzler[:4] == b"\x89PNG", "a one-shot kanzler render is an image (%d)" % st)
    check(float(vis.get("topDecileAlpha", -1)) > 0, "its X-Lucent-Visibility header reports the method (%s)" % vis)
    st, _, direct = srv.request("POST", "/api/v1/render", dict(base, method="direct"))
    s = ssim(binary, kanzler, direct)
    check(st == 200 and 0 < s < 0.999, "kanzler differs from direct (SSIM %.4f)" % s)
    query = dict(SIZE, dataset="demo:tornado", method="kanzler", format="png", kanzlerDepth=0, kanzlerImportance=0,
                 kanzlerCoverage=0, kanzlerVariance=0)
    st, _, flat = srv.request("GET", "/api/v1/render?" + urllib.parse.urlencode(query))
    s = ssim(binary, flat, direct)
    check(st == 200 and s > 0.999, "GET with every weight 0 through the flat aliases is the direct image (SSIM %.4f)" % s)
    st, _, data = srv.request("POST", "/api/v1/render", dict(base, dataset="demo:points", method="kanzler",
                                                             params={"kanzlerVariance": 2}))
    e = json.loads(data).get("error", {}) if st != 200 else {}
    check(st == 400 and e.get("field") == "params.kanzlerVariance",
          "kanzlerVariance on points is refused naming it (%d %s)" % (st, e))
    st, _, data = srv.request("POST", "/api/v1/render", dict(base, dataset="demo:points", method="kanzler"))
    check(st == 200, "points render with kanzler (%d)" % st)

    async def session():
        async with websockets.connect(srv.ws_url, max_size=None) as ws:
            await ws.send(json.dumps({"type": "hello", "dataset": "demo:tornado", "width": 80, "height": 64,
                                      "devicePixelRatio": 1}))
            done = await wait_for_stream_done(ws)
            check(done.reached, "the session's first picture is done")
            await ws.send(json.dumps({"type": "params", "method": "kanzler"}))
            done = await wait_for_stream_done(ws)
            frame = done[-1] if done.reached else {}
            check(done.reached and (frame.get("visibility") or {}).get("topDecileAlpha", -1) > 0,
                  "switched to kanzler, the session streams frames with the report (%s)" %
                  {k: v for k, v in frame.items() if k != "image"})
            first = frame.get("image", b"")
            await ws.send(json.dumps({"type": "params", "params": {"kanzlerDepth": 8}}))
            done = await wait_for_stream_done(ws)
            second = done[-1].get("image", b"") if done.reached else b""
            check(done.reached and second != first, "an update of its weights renders a new picture")
            await ws.send(json.dumps({"type": "params", "params": {"subset": 4}}))
            got = await wait_for_message(ws, lambda m: m.get("type") in ("error", "frame"))
            last = got[-1] if got.reached else {}
            check(last.get("type") == "error" and last.get("field") == "params.subset",
                  "params.subset under kanzler is refused naming it (%s)" % last)

    asyncio.run(session())

    st, _, data = srv.request("POST", "/api/v1/movies", dict(SIZE, request=dict(dataset="demo:tornado",
                                                                                method="kanzler"), frames=3, fps=3))
    job = json.loads(data) if st in (202, 400) else {}
    if st == 400 and job.get("error", {}).get("field") == "codec":
        skip("this server cannot encode movies: " + job["error"]["message"])
    end = time.time() + 120
    state = {}
    while time.time() < end:
        st, _, data = srv.request("GET", "/api/v1/movies/" + job.get("id", "none"))
        state = json.loads(data) if st == 200 else {}
        if state.get("state") in ("done", "failed", "cancelled"):
            break
        time.sleep(0.2)
    check(state.get("state") == "done" and state.get("framesDone") == 3,
          "a movie of a kanzler request renders its frames (%s)" % json.dumps(state)[:300])
check.done()
