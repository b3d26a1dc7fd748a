"""Work budgets (docs/ALGORITHM.md "Work budgets", issue 47): a surface whose
field has slow regions takes far more RK4 steps per curve than the estimate's
top-speed assumption. On a field that is fast everywhere the same request
renders (the estimate holds); on the one with a slow band it stops with 400
too_expensive naming surface.particles, its message giving the work used and
granted, the work used within the grant plus one batch of steps per tracing
thread; the daemon's peak memory stays far below what the whole tracing
would hold (the issue saw 1.7 GB); a WebSocket surface session over the slow
field gets the same as an error and keeps serving; the daemon still renders."""
import asyncio
import json
import os
import re
import sys
import tempfile

from lucent_server import Check, Server, sanitized, skip, websockets

binary = sys.argv[1]
check = Check()
tmp = tempfile.mkdtemp()
NX = 21
SLOW = 1e-3  # the slow band's speed, a fraction of the top speed
BATCH = 256  # LC_TRACE_CHARGE_STEPS
THREADS = 8  # the most tracing threads of a frame (surface_job.c)


def write_field(path, slow):
    """v = (u(x), 0, 0) on [0, 1]^3: u = 1, or SLOW on 0.3 <= x <= 0.7 when slow."""
    lines = ["# vtk DataFile Version 3.0", "work budget case", "ASCII", "DATASET STRUCTURED_POINTS",
             "DIMENSIONS %d 2 2" % NX, "ORIGIN 0 0 0", "SPACING %g 1 1" % (1.0 / (NX - 1)),
             "POINT_DATA %d" % (NX * 4), "VECTORS velocity float"]
    for _ in range(4):
        for i in range(NX):
            x = i / (NX - 1)
            lines.append("%g 0 0" % (SLOW if slow and 0.3 - 1e-9 <= x <= 0.7 + 1e-9 else 1.0))
    # VTK orders x fastest, then y, then z: the 4 (y, z) rows repeat the x profile
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


write_field(os.path.join(tmp, "steady.vtk"), False)
write_field(os.path.join(tmp, "sluggish.vtk"), True)


def surface(field, particles=200):
    return {"width": 256, "height": 256, "format": "png", "method": "surface-layers",
            "surface": {"field": field, "seed": [[0.05, 0.1, 0.5], [0.05, 0.9, 0.5]], "particles": particles}}


def peak_kb(srv):
    with open("/proc/%d/status" % srv.proc.pid) as f:
        for line in f:
            if line.startswith("VmHWM:"):
                return int(line.split()[1])
    return 0


def cpu_seconds(srv):
    with open("/proc/%d/stat" % srv.proc.pid) as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


async def session(srv):
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        hello = dict(surface("sluggish"), type="hello", dataset="demo:points")
        del hello["format"]
        hello["surface"]["curvesPerFrame"] = 200
        await ws.send(json.dumps(hello))
        got = []
        while True:
            m = await asyncio.wait_for(ws.recv(), 120)
            if isinstance(m, bytes):
                got.append("frame")
                continue
            m = json.loads(m)
            if m.get("type") in ("stats", "progress", "ready"):
                continue
            got.append(m)
            if m.get("type") == "error":
                break
        e = got[-1]
        check(e.get("code") == "too_expensive" and e.get("field") == "surface.particles" and "granted" in
              e.get("message", ""), "a session's surface frame over its budget: an error naming surface.particles: %r"
              % e)
        st, _, h = srv.json("GET", "/api/v1/health")
        check(st == 200 and h.get("memory", {}).get("held", {}).get("surfaces") == 0,
              "the stopped batch's curves are gone and nothing stays reserved for them: %r" % h.get("memory"))
        # the session keeps serving: a fast field's surface renders
        await ws.send(json.dumps({"type": "params", "surface": {"field": "steady"}}))
        while True:
            m = await asyncio.wait_for(ws.recv(), 120)
            if isinstance(m, bytes):
                check(True, "after the error the session renders the fast field's surface")
                return
            m = json.loads(m)
            if m.get("type") not in ("stats", "progress"):
                check(False, "after the error, frames again, not %r" % m)
                return


with Server(binary, data=("demo:points", os.path.join(tmp, "steady.vtk"), os.path.join(tmp, "sluggish.vtk"))) as srv:
    st, headers, data = srv.request("POST", "/api/v1/render", json.dumps(surface("steady")))
    cost = float(headers.get("x-lucent-cost", "0"))
    check(st == 200 and cost > 0, "the fast field's surface renders, estimated %g: %d %s" %
          (cost, st, data[:200] if st != 200 else ""))
    base_kb, cpu0 = peak_kb(srv), cpu_seconds(srv)
    st, headers, data = srv.request("POST", "/api/v1/render", json.dumps(surface("sluggish")))
    cpu = cpu_seconds(srv) - cpu0
    e = json.loads(data).get("error", {}) if st != 200 else {}
    check(st == 400 and e.get("code") == "too_expensive" and e.get("field") == "surface.particles",
          "the slow field's surface stops at its budget naming surface.particles: %d %r" % (st, e))
    m = re.search(r"used ([0-9.e+]+) units of work, over the ([0-9.e+]+) granted", e.get("message", ""))
    check(m is not None, "the message gives the work used and granted: %r" % e.get("message"))
    if m:
        used, granted = float(m.group(1)), float(m.group(2))
        step = 30 + 20 * 1  # LC_TRACE_STEP_UNITS and a segment at 256 pixels high (cost.c)
        check(granted >= 4 * cost * 0.99 and used <= granted + THREADS * BATCH * step,
              "work used %g within the grant %g (estimate %g) and one batch per thread" % (used, granted, cost))
        # Without the budget: 200 curves crossing a band 0.4 wide at SLOW of the top speed, each step
        # diagonal/200 at top speed: the whole tracing's steps, against those the budget let run.
        whole = 200 * 0.4 / (SLOW * 3 ** 0.5 / 200)
        check(used / step < 0.5 * whole, "the budget stopped the tracing at %.3g of its %.3g steps" %
              (used / step, whole))
    peak = peak_kb(srv)
    print("slow-field surface: estimate %.3g units, CPU %.2f s, peak RSS %d MB (before: %d MB)" %
          (cost, cpu, peak // 1024, base_kb // 1024))
    if not sanitized(binary):  # ASan's shadow and quarantine say nothing of lucent's own memory
        check(peak < 1024 * 1024, "peak resident memory %d MB stays under 1 GB" % (peak // 1024))
    if websockets is not None:
        asyncio.run(session(srv))
    st, _, _ = srv.request("POST", "/api/v1/render", json.dumps(surface("steady", 50)))
    check(st == 200, "the daemon still renders: %d" % st)
check.done()
