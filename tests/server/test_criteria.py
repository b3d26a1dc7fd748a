"""Importance terms, filters and curves against the real daemon on the NetCDF
trajectory sample: /api/v1/datasets lists the derived trajectory attributes;
a WebSocket session filters and re-weights the loaded dataset with params
messages (the frames change, nothing is loaded again) and gets errors that name
the element; HTTP renders take the same fields."""
import asyncio
import json
import os
import sys

from lucent_server import Check, Server, png_size, skip, wait_for_message, wait_for_stream_done, websockets

if websockets is None:
    skip("python3-websockets is not installed")

binary = sys.argv[1]
here = os.path.dirname(os.path.abspath(__file__))
sample = os.path.join(here, "..", "data", "loaders", "nc", "valid", "trajectories.nc")
check = Check()


QUIET = ("stats", "progress")


async def settle(ws):
    """The frames (acked) until the stream ends (a converged final still, however
    long that takes): the last image, the text messages, the number of frames."""
    got = await wait_for_stream_done(ws, skip=QUIET)
    check(got.reached, "the stream ends with a converged still")
    frames = [m for m in got if m["type"] == "frame"]
    return (frames[-1]["image"] if frames else None), [m for m in got if m["type"] != "frame"], len(frames)


async def refused(ws):
    """The error message that answers a params message (nothing of it is applied: no frames follow)."""
    got = await wait_for_message(ws, lambda m: m["type"] == "error", skip=QUIET)
    return [m for m in got if m["type"] == "error"]


async def session(srv, name):
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        await ws.send(json.dumps({"type": "hello", "dataset": name, "width": 64, "height": 48,
                                  "importance": {"attribute": "temperature"}}))
        ready = (await wait_for_message(ws, lambda m: True, skip=QUIET) or [{}])[-1]
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
        errs = await refused(ws)
        check(errs and errs[0].get("field") == "filter[0].attribute",
              "an unknown filter attribute is an error naming filter[0].attribute: %r" % (errs[:1],))

        await ws.send(json.dumps({"type": "params", "filter": [{"attribute": "pressure", "over": "median", "gt": 0}]}))
        errs = await refused(ws)
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
