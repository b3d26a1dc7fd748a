"""Importance terms, filters and curves against the real daemon on the NetCDF
trajectory sample: /api/v1/datasets lists the derived trajectory attributes;
a WebSocket session filters and re-weights the loaded dataset with params
messages (the frames change, nothing is loaded again) and gets errors that name
the element; HTTP renders take the same fields."""
import asyncio
import json
import os
import sys
import time

from lucent_server import Check, Server, png_size, skip, unpack_frame, websockets

if websockets is None:
    skip("python3-websockets is not installed")

binary = sys.argv[1]
here = os.path.dirname(os.path.abspath(__file__))
sample = os.path.join(here, "..", "data", "loaders", "nc", "valid", "trajectories.nc")
check = Check()


async def recv(ws, timeout):
    deadline = time.time() + timeout
    while True:
        left = deadline - time.time()
        if left <= 0:
            return None
        try:
            m = await asyncio.wait_for(ws.recv(), left)
        except asyncio.TimeoutError:
            return None
        if not (isinstance(m, str) and json.loads(m).get("type") in ("stats", "progress")):
            return m


async def settle(ws, quiet=1.5, first=60):
    """Frames (acked) until none comes for `quiet` s: the last image, and text messages."""
    last, texts, n = None, [], 0
    while True:
        m = await recv(ws, first if n == 0 else quiet)
        if m is None:
            return last, texts, n
        n += 1
        if isinstance(m, str):
            texts.append(json.loads(m))
            continue
        h, img = unpack_frame(m)
        last = img
        await ws.send(json.dumps({"type": "ack", "frame": h["frame"]}))


async def session(srv, name):
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        await ws.send(json.dumps({"type": "hello", "dataset": name, "width": 64, "height": 48,
                                  "importance": {"attribute": "temperature"}}))
        ready = json.loads(await recv(ws, 60))
        check(ready.get("type") == "ready", "hello on the NetCDF sample -> ready")
        base, _, n = await settle(ws)
        check(base is not None and n > 0, "frames of the unfiltered trajectories")

        # the warm-conveyor-belt style filter: only lines whose pressure fell by more than 200 hPa
        await ws.send(json.dumps({"type": "params", "filter": [{"attribute": "pressure_change", "over": "first", "lt": -200}]}))
        filtered, texts, n = await settle(ws)
        check(n > 0 and filtered is not None and filtered != base, "a filter changes the frames")
        check(not any(t.get("type") == "error" for t in texts), "no error for a valid filter")

        await ws.send(json.dumps({"type": "params", "importance": {"terms": [
            {"attribute": "speed", "weight": 1}, {"attribute": "turning_angle", "weight": -0.5}]}}))
        weighted, texts, n = await settle(ws)
        check(n > 0 and weighted is not None and weighted != filtered, "re-weighting with terms changes the frames")

        await ws.send(json.dumps({"type": "params", "filter": [{"attribute": "nope", "over": "min", "gt": 0}]}))
        _, texts, _ = await settle(ws, quiet=1.0, first=10)
        errs = [t for t in texts if t.get("type") == "error"]
        check(errs and errs[0].get("field") == "filter[0].attribute",
              "an unknown filter attribute is an error naming filter[0].attribute: %r" % (errs[:1],))

        await ws.send(json.dumps({"type": "params", "filter": [{"attribute": "pressure", "over": "median", "gt": 0}]}))
        _, texts, _ = await settle(ws, quiet=1.0, first=10)
        errs = [t for t in texts if t.get("type") == "error"]
        check(errs and errs[0].get("field") == "filter[0].over", "a bad statistic is refused naming filter[0].over")

        await ws.send(json.dumps({"type": "params", "filter": [], "importance": {"terms": [], "curve": [[0, 0], [1, 1]]}}))
        back, texts, n = await settle(ws)
        check(n > 0 and back is not None, "the session still renders after the errors")


def main():
    with Server(binary, data=(sample,), demo_size=0) as srv:
        status, _, body = srv.json("GET", "/api/v1/datasets")
        entries = body if isinstance(body, list) else body.get("datasets", [])
        entry = next((d for d in entries if "trajectories" in d.get("name", "")), None)
        check(entry is not None, "the NetCDF sample is listed")
        if entry is None:
            check.done()
        names = [a if isinstance(a, str) else a.get("name") for a in entry.get("attributes", [])]
        for want in ("pressure", "pressure_change", "pressure_change_48h", "speed", "turning_angle", "ascent_angle"):
            check(want in names, "/api/v1/datasets lists the derived attribute %s" % want)
        asyncio.run(session(srv, entry["name"]))

        req = {"dataset": entry["name"], "width": 64, "height": 48, "method": "exact",
               "filter": [{"attribute": "pressure_change", "over": "last", "lt": -200}],
               "importance": {"terms": [{"attribute": "speed"}, {"attribute": "temperature", "weight": -0.5}]}}
        status, _, data = srv.request("POST", "/api/v1/render", req)
        check(status == 200 and png_size(data) == (64, 48), "HTTP render with terms and a filter: %d" % status)
        req["filter"] = [{"attribute": "pressure_change", "over": "last", "lt": "x"}]
        status, _, err = srv.json("POST", "/api/v1/render", req)
        check(status == 400 and err["error"]["field"] == "filter[0].lt", "a bad bound is 400 naming filter[0].lt")
        loads = [l for l in srv.log if "[datasets] loading" in l and "trajectories.nc" in l]
        check(len(loads) == 1, "the dataset was loaded once: filters and terms reload nothing (%d loads)" % len(loads))
        check(srv.stop() == 0, "the daemon exits cleanly")
    check.done()


main()
