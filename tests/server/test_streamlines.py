"""Streamline sets asked for by requests (docs/ALGORITHM.md §22): a request whose dataset names a vector
field draws the set its streamlines section describes, traced by the load-time code path. The set a
one-shot request asks for is the load-time set of the same spec: the same PNG byte for byte and the
same description (lines, vertices, bounds). The default section traces 64 density-seeded lines; the
traced attributes (vorticity) drive importance under methods fourier, exact and kanzler. Every
refusal names its field: a section on a loaded dataset, a rake of three points, a separation off
density seeding, a count with point seeding, a set over the trace budget, a set over --max-cost's
tracing price, seeds outside the field, layers beside the set. An HTTP session traces once and
re-traces only when the section changes (camera moves and other fields do not: its "traces" and
the daemon's "traced" log lines count them); a WebSocket session likewise; a movie draws the set."""
import asyncio
import json
import sys
import time

from lucent_server import Check, Server, wait_for_frame, wait_for_message, wait_until, websockets

binary = sys.argv[1]
check = Check()
QUERY = "seeding=rake&seeds=-0.5,-0.5,0;-0.5,0.5,0&count=5&length=0.4&direction=both"
SPEC = "streamlines:demo:shear-flow?" + QUERY
SECTION = {"seeding": "rake", "seeds": [[-0.5, -0.5, 0], [-0.5, 0.5, 0]], "count": 5, "length": 0.4,
           "direction": "both"}
CAM = {"position": [-0.5, 0, 3], "focalPoint": [-0.5, 0, 0], "viewUp": [0, 1, 0]}
SIZE = {"width": 96, "height": 80}


def render(srv, body):
    st, _, data = srv.request("POST", "/api/v1/render", json.dumps(dict(SIZE, **body)))
    return st, data


def error_of(data):
    try:
        return json.loads(data).get("error", {})
    except ValueError:
        return {}


def traced(srv):
    """The daemon's "traced" log lines: one per trace call."""
    return sum(1 for line in list(srv.log) if "[traced] traced " in line)


with Server(binary, data=(SPEC, "demo:shear-flow", "demo:points"), demo_size=500) as srv:
    st, _, body = srv.json("GET", "/api/v1/datasets")
    loaded = {d["name"]: d for d in body.get("datasets", [])}.get("streamlines:demo:shear-flow", {})
    check(loaded.get("lines") == 5, "the load-time set is served: %r" % sorted(loaded)[:5])

    # The request's set is the load-time set: the same image byte for byte.
    st_a, a = render(srv, {"dataset": "streamlines:demo:shear-flow", "camera": CAM})
    st_b, b = render(srv, {"dataset": "demo:shear-flow", "streamlines": SECTION, "camera": CAM})
    check(st_a == 200 and st_b == 200 and a == b and a[:4] == b"\x89PNG",
          "a request's set renders the load-time set's PNG byte for byte (%d, %d, %d/%d bytes)"
          % (st_a, st_b, len(a), len(b)))
    st_c, c = render(srv, {"dataset": "demo:shear-flow", "streamlines": dict(SECTION, count=3), "camera": CAM})
    check(st_c == 200 and c != a, "3 curves of the rake draw another image than 5 (%d)" % st_c)
    st, _, sess = srv.json("POST", "/api/v1/sessions", json.dumps(
        dict(SIZE, dataset="demo:shear-flow", streamlines=SECTION)))
    info = sess.get("dataset", {})
    same = all(info.get(k) == loaded.get(k) for k in ("lines", "vertices", "bounds", "type"))
    check(st == 201 and same and info.get("name") == "demo:shear-flow",
          "its description is the load-time set's (lines, vertices, bounds), named after the field: %r"
          % {k: info.get(k) for k in ("name", "lines", "vertices")})
    check(sess.get("defaults", {}).get("streamlines", {}).get("count") == 5,
          "the session's defaults echo the section: %r" % sess.get("defaults", {}).get("streamlines"))
    srv.request("DELETE", "/api/v1/sessions/" + sess.get("session", "none"))

    # Defaults: 64 density-seeded lines; the traced attributes drive importance in every line method.
    st, _, sess = srv.json("POST", "/api/v1/sessions", json.dumps(dict(SIZE, dataset="shear-flow")))
    info = sess.get("dataset", {})
    attrs = [x["name"] for x in info.get("attributes", [])]
    check(st == 201 and info.get("type") == "lines" and 0 < info.get("lines", 0) <= 64 and "vorticity" in attrs
          and info.get("defaultImportance") == "speed",
          "a field alone traces density seeds (%s lines), importance speed, vorticity beside it: %r"
          % (info.get("lines"), attrs[:8]))
    srv.request("DELETE", "/api/v1/sessions/" + sess.get("session", "none"))
    for method in ("fourier", "exact", "kanzler", "weighted-average"):
        st, data = render(srv, {"dataset": "demo:shear-flow", "method": method, "streamlines": SECTION,
                                "importance": {"attribute": "vorticity"}, "camera": CAM})
        check(st == 200 and data[:4] == b"\x89PNG", "method %s with importance vorticity: %d %s"
              % (method, st, data[:120] if st != 200 else ""))
    st, _, data = srv.request("GET", "/api/v1/render?dataset=demo:shear-flow&width=64&height=64&streamlinesCount=4"
                              "&streamlinesSeeding=box&streamlinesDirection=backward")
    check(st == 200, "query parameters ask for a set too: %d %s" % (st, data[:200] if st != 200 else ""))

    # Every refusal names its field.
    for what, body, field in (
            ("a section on a loaded dataset", {"dataset": "streamlines:demo:shear-flow",
                                               "streamlines": {"direction": "both"}}, "streamlines.direction"),
            ("a rake of three points", {"streamlines": {"seeding": "rake", "seeds": [[0, 0, 0], [1, 1, 0],
                                                                                     [0, 1, 0]]}},
             "streamlines.seeds"),
            ("a rake without seeds", {"streamlines": {"seeding": "rake"}}, "streamlines.seeds"),
            ("separation off density", {"streamlines": dict(SECTION, separation=0.1)}, "streamlines.separation"),
            ("a count with point seeding", {"streamlines": {"seeding": "points", "seeds": [[0, 0, 0]], "count": 3}},
             "streamlines.count"),
            ("a set over the trace budget", {"streamlines": {"count": 100000, "length": 1000}}, "streamlines.count"),
            ("seeds outside the field", {"streamlines": {"seeding": "points", "seeds": [[50, 50, 50]]}},
             "streamlines.seeds"),
            ("a flat box", {"streamlines": {"seeding": "box", "seeds": [[0, 0, 0], [0, 1, 1]]}}, "streamlines.seeds"),
            ("an unknown direction", {"streamlines": {"direction": "sideways"}}, "streamlines.direction"),
            ("a count of 0", {"streamlines": {"count": 0}}, "streamlines.count")):
        st, data = render(srv, dict({"dataset": "demo:shear-flow"}, **body))
        e = error_of(data)
        check(st == 400 and e.get("field") == field, "%s is refused naming %s: %d %r" % (what, field, st, e))
    for name, body in (("an HTTP session", {"dataset": "demo:points", "streamlines": {"count": 5}}),):
        st, _, e = srv.json("POST", "/api/v1/sessions", json.dumps(dict(SIZE, **body)))
        check(st == 400 and e.get("error", {}).get("field") == "streamlines.count",
              "%s on a loaded dataset refuses the section naming streamlines.count: %d %r" % (name, st, e))

    # An HTTP session traces once; camera moves and other fields reuse the set, seeding changes re-trace.
    before = traced(srv)
    st, _, sess = srv.json("POST", "/api/v1/sessions", json.dumps(
        dict(SIZE, dataset="demo:shear-flow", streamlines=SECTION, camera=CAM)))
    sid = sess.get("session", "none")
    path = "/api/v1/sessions/%s/render" % sid
    images = []
    three = dict(SECTION, count=3)  # an update's streamlines object is the whole set
    for update in ({}, {"camera": dict(CAM, position=[-0.4, 0.1, 3])}, {"params": {"q": 5}},
                   {"streamlines": three}, {"camera": CAM}, {"streamlines": three}, {"streamlines": SECTION}):
        st, _, data = srv.request("POST", path, json.dumps(update))
        images.append(data if st == 200 else None)
        check(st == 200, "session frame after %s: %d %s" % (json.dumps(update), st, data[:150] if st != 200 else ""))
    st, _, got = srv.json("GET", "/api/v1/sessions/" + sid)
    wait_until(lambda: traced(srv) - before >= 3)
    check(got.get("traces") == 3 and got.get("frames") == 7 and traced(srv) - before == 3,
          "7 frames, 3 traces: the first, count 3, count 5 again (camera, q and a repeated count re-trace "
          "nothing): %r, %d log lines" % ({k: got.get(k) for k in ("traces", "frames")}, traced(srv) - before))
    check(images[4] == c and images[6] != images[4], "after count 3 the session draws the one-shot 3-curve image, "
          "after count 5 again another")
    st, _, e = srv.json("POST", path, json.dumps({"streamlines": {"seeding": "rake", "seeds": [[0, 0, 0]]}}))
    check(st == 400 and e.get("error", {}).get("field") == "streamlines.seeds",
          "a session update with a one-point rake is refused naming streamlines.seeds: %d %r" % (st, e))
    st, _, e = srv.json("POST", path, json.dumps({"layers": [{"dataset": "demo:points"}]}))
    check(st == 400 and e.get("error", {}).get("field") == "layers",
          "layers beside a field's set are refused naming layers: %d %r" % (st, e))
    st, _, e = srv.json("POST", path, json.dumps({"layers": [{"dataset": "demo:shear-flow"}]}))
    check(st == 400 and e.get("error", {}).get("field") == "layers[0].dataset" and "vector field" in
          e.get("error", {}).get("message", ""), "a field as a layer is refused naming layers[0].dataset: %d %r" % (st, e))
    st, _, data = srv.request("POST", path, json.dumps({}))
    check(st == 200 and data == images[6], "the session still serves its set after refusals (%d)" % st)
    st, _, data = srv.request("POST", path, json.dumps({"streamlines": {"seeding": "points", "seeds": [[-0.5, 0, 0]],
                                                                        "length": 0.4}}))
    check(st == 200 and data != images[6], "an update's object replaces the whole set: point seeding leaves the "
          "earlier count out (%d %s)" % (st, data[:150] if st != 200 else ""))
    srv.request("DELETE", "/api/v1/sessions/" + sid)

    # A WebSocket session: re-traces on a seeding change only. Its set has a length of its own, so
    # that its "traced" log lines (written in order by the thread that applies the updates) tell.
    if websockets is not None:
        def ws_lines():
            return [line for line in list(srv.log) if "[traced] traced " in line and "length=0.5" in line]

        async def ws_session():
            async with websockets.connect(srv.ws_url, max_size=None) as ws:
                await ws.send(json.dumps({"type": "hello", "dataset": "demo:shear-flow", "width": 96, "height": 80,
                                          "devicePixelRatio": 1, "streamlines": dict(SECTION, length=0.5),
                                          "camera": CAM}))
                ready = json.loads(await ws.recv())
                check(ready.get("type") == "ready" and ready.get("dataset", {}).get("lines") == 5,
                      "a WebSocket hello on the field opens a session over its 5-curve set: %r"
                      % {k: ready.get(k) for k in ("type", "message", "field")})
                got = await wait_for_frame(ws)
                check(got.reached, "its first frame arrives")
                await ws.send(json.dumps({"type": "camera", "seq": 1, "camera": dict(CAM, position=[-0.3, 0, 3])}))
                got = await wait_for_frame(ws, lambda h: h.get("cameraSeq", 0) >= 1)
                check(got.reached, "a camera move renders")
                await ws.send(json.dumps({"type": "params", "streamlines": dict(SECTION, length=0.5, count=3)}))
                got = await wait_for_frame(ws)
                check(got.reached, "a count change renders")
                lines = wait_until(lambda: [x for x in ws_lines() if "count=3&" in x] and ws_lines())
                check(lines and len(lines) == 2 and "count=5&" in lines[0],
                      "the hello traced and the count change traced, the camera move did not: %r"
                      % [x[-90:] for x in (lines or [])])
                await ws.send(json.dumps({"type": "params", "streamlines": {"seeding": "sideways"}}))
                got = await wait_for_message(ws, lambda m: m.get("type") == "error")
                check(got.reached and got[-1].get("field") == "streamlines.seeding",
                      "an unknown seeding is refused naming streamlines.seeding: %r" % got[-1:])
        asyncio.run(ws_session())

    # A movie of the field's set.
    st, _, data = srv.request("POST", "/api/v1/movies", json.dumps(
        {"width": 64, "height": 64, "frames": 2, "fps": 2,
         "request": {"dataset": "demo:shear-flow", "streamlines": SECTION}}))
    job = json.loads(data) if st in (202, 400) else {}
    if st == 400 and job.get("error", {}).get("field") == "codec":
        print("movies: no encoder here, not checked")
    else:
        end = time.time() + 120
        while True:
            st2, _, d2 = srv.request("GET", "/api/v1/movies/" + job.get("id", "none"))
            j = json.loads(d2) if st2 == 200 else {}
            if j.get("state") in ("done", "failed", "cancelled") or time.time() > end:
                break
            time.sleep(0.2)
        check(j.get("state") == "done" and j.get("framesDone") == 2 and j.get("dataset") == "demo:shear-flow",
              "a movie draws the field's set: %s" % json.dumps(j)[:300])
    st, _, data = srv.request("POST", "/api/v1/movies", json.dumps(
        {"width": 64, "height": 64, "frames": 2, "request": {"dataset": "demo:shear-flow",
                                                             "streamlines": {"seeding": "rake"}}}))
    check(st == 400 and error_of(data).get("field") == "request.streamlines.seeds",
          "a movie's bad section is refused naming request.streamlines.seeds: %d %s" % (st, data[:200]))

# --max-cost prices the tracing: a set whose RK4 steps cost more is refused naming streamlines.count.
with Server(binary, "--max-cost", "2e6", data=("demo:shear-flow",)) as srv:
    st, data = render(srv, {"dataset": "demo:shear-flow", "streamlines": {"count": 2000}})
    e = error_of(data)
    check(st == 400 and e.get("code") == "too_expensive" and e.get("field") == "streamlines.count",
          "tracing over --max-cost is refused naming streamlines.count: %d %r" % (st, e))
    st, data = render(srv, {"dataset": "demo:shear-flow", "streamlines": SECTION})
    check(st == 200, "a small set fits: %d %s" % (st, data[:200] if st != 200 else ""))
# --max-memory counts the sets alive beside the datasets: a set over what is left is refused naming streamlines.count.
with Server(binary, "--max-memory", "3M", data=("demo:shear-flow",)) as srv:
    st, data = render(srv, {"dataset": "demo:shear-flow", "streamlines": {"count": 300}})
    e = error_of(data)
    check(st == 400 and e.get("code") == "too_expensive" and e.get("field") == "streamlines.count"
          and "--max-memory" in e.get("message", ""), "a set over --max-memory is refused naming streamlines.count: %d %r"
          % (st, e))
    st, data = render(srv, {"dataset": "demo:shear-flow", "streamlines": SECTION})
    check(st == 200, "a small set fits: %d %s" % (st, data[:200] if st != 200 else ""))
check.done()
