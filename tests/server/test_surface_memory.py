"""The curves of surface-layers count in the one memory budget (issue 47,
docs/ALGORITHM.md §33 "Memory held by requests"): a WebSocket surface session reserves its
surface's curves in --max-memory before it traces them and holds what they
take until it ends; /api/v1/health, /api/v1/datasets and the metrics count
them. Sessions are opened one after another under a budget of the datasets
and 2.5 sessions' curves (the size one session's surface holds, measured on a
daemon without a budget): two converge, the third is refused before it
traces, as an error naming surface.particles that says how many particles
fit; the budget is never exceeded; the sessions already open keep serving
(a camera move redraws their surface); the refused session serves the number
the refusal named; a one-shot render of the whole surface is refused too (400
naming surface.particles); closing a session gives its curves back, and then
the whole surface is served again."""
import asyncio
import json
import re
import sys

from lucent_server import Check, Server, skip, wait_for_message, wait_for_stream_done, wait_until, websockets

if websockets is None:
    skip("python3-websockets is not installed")

binary = sys.argv[1]
check = Check()
DATA = ("demo:points", "demo:abc-flow")
SEED = [[3.14, 0.63, 3.14], [3.14, 5.65, 3.14]]
PARTICLES = 1000
# A short length keeps every curve inside the field, so that each surface holds the same curves.
SURFACE = {"field": "demo:abc-flow", "seed": SEED, "particles": PARTICLES, "curvesPerFrame": 250, "length": 1.0}
CAMERA = {"position": [14, 3, 8], "focalPoint": [3.14, 3.14, 3.14], "viewUp": [0, 0, 1]}
QUIET = ("stats", "progress")


def memory(srv):
    st, _, h = srv.json("GET", "/api/v1/health")
    return h.get("memory", {}) if st == 200 else {}


def held(srv):
    return memory(srv).get("held", {}).get("surfaces", -1)


async def open_surface(srv, surface=SURFACE):
    ws = await websockets.connect(srv.ws_url, max_size=None)
    await ws.send(json.dumps({"type": "hello", "width": 64, "height": 64, "method": "surface-layers",
                              "camera": CAMERA, "surface": surface}))
    return ws


async def outcome(ws):
    """The converged frame or the error that ends the session's first stretch."""
    got = await wait_for_message(ws, lambda m: m["type"] == "error" or (m["type"] == "frame" and m.get("converged")),
                                 skip=QUIET)
    return got[-1] if got.reached else None


async def measure(srv):
    """What one session's surface holds once converged, and that it is given back at its end."""
    ws = await open_surface(srv)
    m = await outcome(ws)
    check(m is not None and m["type"] == "frame", "without a budget the surface converges: %r" % (m or {}).get("type"))
    one = held(srv)
    await ws.close()
    check(wait_until(lambda: held(srv) == 0) is True, "a closed session gives its curves back")
    return one


async def main(srv, datasets, one, budget):
    opened = []
    refused = None
    for i in range(6):  # 2.5 surfaces fit: the third is refused
        ws = await open_surface(srv)
        m = await outcome(ws)
        h = held(srv)
        check(datasets + h <= budget, "session %d: the datasets and the curves held (%d + %d) stay within "
              "--max-memory %d" % (i + 1, datasets, h, budget))
        if m is not None and m["type"] == "error":
            refused = (ws, m)
            break
        check(m is not None and m.get("surface", {}).get("curves") == PARTICLES,
              "session %d converges with its %d curves" % (i + 1, PARTICLES))
        opened.append(ws)
    check(len(opened) == 2, "two surfaces fit beside the datasets (%d did)" % len(opened))
    check(refused is not None, "a session beyond the budget is refused")
    if refused is None:
        return
    ws3, err = refused
    msg = err.get("message", "")
    check(err.get("field") == "surface.particles" and err.get("code") == "too_expensive" and "--max-memory" in msg,
          "the refusal names surface.particles and the budget: %r" % err)
    fit = re.search(r"at most (\d+) particles fit", msg)
    check(fit is not None and 0 < int(fit.group(1)) < PARTICLES, "it says how many particles fit: %r" % msg)
    check(held(srv) == 2 * one, "the refused session holds no curves (%d held, %d per surface)" % (held(srv), one))
    mem = memory(srv)
    check(mem.get("estimated") == datasets + 2 * one and mem.get("budget") == budget,
          "health's estimate counts the curves: %r" % mem)
    st, _, text = srv.request("GET", "/metrics")
    text = text.decode()
    check("lucent_memory_estimated_bytes %d" % (datasets + 2 * one) in text,
          "the metrics' estimate counts the curves")
    st, _, ds = srv.json("GET", "/api/v1/datasets")
    check(st == 200 and ds["memory"].get("held", {}).get("surfaces") == 2 * one,
          "/api/v1/datasets shows the curves held: %r" % ds.get("memory"))

    # The open sessions keep serving: a camera move redraws their surface.
    for k, ws in enumerate(opened):
        await ws.send(json.dumps({"type": "camera", "seq": 1, "camera": dict(CAMERA, position=[3.14, -10, 3.14])}))
        got = await wait_for_stream_done(ws, lambda h: h.get("cameraSeq", 0) >= 1, skip=QUIET)
        frames = [m for m in got if m["type"] == "frame"]
        check(got.reached and frames[-1].get("surface", {}).get("curves") == PARTICLES,
              "open session %d still serves its surface" % (k + 1))

    # A one-shot render of the whole surface does not fit either.
    st, _, body = srv.request("POST", "/api/v1/render", {"width": 64, "height": 64, "method": "surface-layers",
                                                        "surface": SURFACE})
    e = json.loads(body).get("error", {}) if st != 200 else {}
    check(st == 400 and e.get("field") == "surface.particles" and e.get("code") == "too_expensive",
          "a one-shot surface beyond the budget: 400 naming surface.particles (%d %r)" % (st, e))
    check(held(srv) == 2 * one, "the refused one-shot holds nothing afterwards")

    # The refused session serves the number its refusal named.
    if fit is not None:
        n = int(fit.group(1))
        await ws3.send(json.dumps({"type": "params", "surface": {"particles": n}}))
        m = await outcome(ws3)
        check(m is not None and m["type"] == "frame" and m.get("surface", {}).get("curves") == n,
              "the refused session serves the %d particles that fit: %r" % (n, (m or {}).get("surface")))
        check(datasets + held(srv) <= budget, "still within the budget")
        await ws3.close()
        wait_until(lambda: held(srv) == 2 * one)

    # Closing a session gives its curves back: a new one gets the whole surface.
    await opened[0].close()
    check(wait_until(lambda: held(srv) == one) is True, "closing a session gives its curves back (%d)" % held(srv))
    ws = await open_surface(srv)
    m = await outcome(ws)
    check(m is not None and m["type"] == "frame" and m.get("surface", {}).get("curves") == PARTICLES,
          "then a new session gets the whole surface")
    for w in (ws, opened[1]):
        await w.close()


with Server(binary, data=DATA) as srv:
    datasets = memory(srv).get("datasets", 0)
    one = asyncio.run(measure(srv))
check(datasets > 0 and one > 0, "the datasets' estimate %d and one surface's curves %d bytes" % (datasets, one))
budget = datasets + one * 5 // 2
with Server(binary, "--max-memory", str(budget), data=DATA) as srv:
    check(memory(srv).get("datasets") == datasets, "the same datasets' estimate under the budget")
    asyncio.run(main(srv, datasets, one, budget))
check.done()
