#!/usr/bin/env python3
"""Cost model calibration (prints figures; not part of the pass/fail suite).

For each feature the cost model prices (server/daemon/cost.h) — plain lines,
points and surfaces, halos, tiled stills, line clusters, shadows, colour
equalization, surface-layers, antialias, clarity — renders one request
through a real daemon (one at a time, after a warm-up; --rounds rounds over
all cases, so that the load moves between cases as little as it can), reads
the estimate (X-Lucent-Cost) and the render time (X-Lucent-Timings wall=, the
median over the rounds), and prints:
  units       the estimate
  ms          the measured render time
  Munits/s    the rate
  x plain     how many times slower the case ran than the plain rate predicts
              (the median rate of the plain cases): 1 = priced right, > 1 =
              under-priced
  extra x     for a feature case: its extra time over its plain case against
              its extra units (Δms / plain ms) / (Δunits / plain units): how
              many times the feature's own price is too low
A feature whose "x plain" or "extra x" is above 2 is under-priced by more
than 2x: raise its constants in cost.c.

  tests/bench/cost_bench.py --binary build/lucent [--rounds 3] [--size 512] [--lines 2000] [--only halos,tiles]
"""
import argparse
import json
import os
import statistics
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "server"))
from lucent_server import Server  # noqa: E402

POINTS, SURFACE = "demo:points", "demo:surface"
LINES_DATA = "demo:tornado"


def cases(size):
    lines = {"dataset": LINES_DATA}
    pts = {"dataset": POINTS}
    surf = {"dataset": SURFACE}
    flow = {"method": "surface-layers",
            "surface": {"field": "demo:abc-flow", "seed": [[3.14, 0.63, 3.14], [3.14, 5.65, 3.14]],
                        "particles": 400}}
    # (name, plain case it extends or None, request)
    return [
        ("plain lines", None, lines),
        ("plain points", None, pts),
        ("plain surfaces", None, surf),
        ("halos", "plain lines", dict(lines, style={"haloWidth": 1.0})),
        ("tiles", "plain lines", dict(lines, width=2560, height=1800)),  # above 2048^2: 3x2 tiles
        ("clusters", "plain lines", dict(lines, lines={"clusters": 50})),
        # a new liftImportance every round: the cluster tree is built again each time
        ("cluster rebuild", "plain lines", dict(lines, lines={"clusters": 50, "liftImportance": "ROUND"})),
        ("shadows", "plain lines", dict(lines, style={"shadow": 0.5})),
        ("equalize", "plain lines", dict(lines, color={"equalize": True})),
        ("antialias", "plain lines", dict(lines, style={"antialias": 4})),
        ("clarity", "plain lines", dict(lines, params={"clarity": 0.5})),
        ("surface-layers", None, dict(flow, dataset=POINTS)),
    ]


def vary(body, i):
    """body with every "ROUND" value replaced by a number of round i (a new one each round)."""
    if isinstance(body, dict):
        return {k: vary(v, i) for k, v in body.items()}
    return 0.05 * (i + 1) if body == "ROUND" else body


def render(srv, body):
    st, headers, data = srv.request("POST", "/api/v1/render", json.dumps(body), timeout=600)
    if st != 200:
        raise RuntimeError("%d %s" % (st, data[:300]))
    timings = dict(kv.split("=") for kv in headers.get("x-lucent-timings", "").split(",") if "=" in kv)
    return float(headers.get("x-lucent-cost", "nan")), float(timings.get("wall", "nan"))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--binary", default="build/lucent")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--only", default="", help="comma-separated case names (their plain cases run too)")
    ap.add_argument("--lines", type=int, default=0, help="the tornado's line count (0 = the demo's 500)")
    ap.add_argument("--json", help="also write the figures here")
    a = ap.parse_args()
    global LINES_DATA
    if a.lines:
        LINES_DATA = "demo:tornado?count=%d" % a.lines
    todo = cases(a.size)
    if a.only:
        want = set(a.only.split(","))
        plains = {base for name, base, _ in todo if name in want and base}
        todo = [c for c in todo if c[0] in want or c[0] in plains]
    rows = {}
    with Server(a.binary, "--max-cost", "0", "--workers", "2", data=(LINES_DATA, POINTS, SURFACE, "demo:abc-flow"),
                demo_size=0) as srv:
        bodies = {name: dict({"width": a.size, "height": a.size, "format": "jpeg"}, **body) for name, _, body in todo}
        for name in bodies:
            render(srv, vary(bodies[name], 0))  # warm-up: uploads, programs, clusters' first build
        # Round by round over every case, so that the host's load (never quiet on a shared machine) changes
        # between cases as little as it can: each case's figure is its median over the rounds.
        got = {name: [] for name in bodies}
        for i in range(a.rounds):
            for name in bodies:
                got[name].append(render(srv, vary(bodies[name], i + 1)))
            print("  round %d of %d" % (i + 1, a.rounds), file=sys.stderr, flush=True)
        for name, base, _ in todo:
            cost = got[name][0][0]
            ms = statistics.median(g[1] for g in got[name])
            rows[name] = {"base": base, "units": cost, "ms": ms, "rate": cost / (ms / 1000.0)}
    plain = statistics.median(r["rate"] for n, r in rows.items() if n.startswith("plain")) if any(
        n.startswith("plain") for n in rows) else None
    print("%-15s %12s %10s %10s %8s %8s" % ("case", "units", "ms", "Munits/s", "x plain", "extra x"))
    for name, r in rows.items():
        slow = r["ms"] / (r["units"] / plain * 1000.0) if plain else float("nan")
        extra = ""
        b = rows.get(r["base"]) if r["base"] else None
        if b and r["units"] > b["units"]:
            extra = "%8.2f" % (((r["ms"] - b["ms"]) / b["ms"]) / ((r["units"] - b["units"]) / b["units"]))
        elif b:
            extra = "%8s" % "-"
        r["x_plain"] = slow
        print("%-15s %12.4g %10.1f %10.2f %8.2f %s" % (name, r["units"], r["ms"], r["rate"] / 1e6, slow, extra))
    print("plain rate: %.3g units/s; load: %s" % (plain or float("nan"), open("/proc/loadavg").read().split()[:3]))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
