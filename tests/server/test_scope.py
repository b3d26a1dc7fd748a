"""Every field where it does not apply is refused when it arrives, naming it.

Walks the field table as `lucent schema` publishes it (each field's "methods"
and "primitives", protocol/request_scope.c): for every field and every method
it does not apply to, and every kind of data (points, lines, surfaces) it does
not apply to, a one-shot POST /api/v1/render with a value other than the
field's default is answered 400 naming the field, and a WebSocket session's
`params` update that sets it is answered with an `error` naming the field
before any frame of that update (the session's request unchanged: the next
update renders). The same value where the field applies passes that check
(no 400 saying it does not apply). Refusals the renderer used to raise from a
frame (a context layer of points, a guard band with depthRange
"pixel", an attribute a dataset lacks) are answered the same way."""
import asyncio
import json
import subprocess
import sys

from lucent_server import Check, Server, wait_for_message, wait_for_stream_done, websockets

binary = sys.argv[1]
check = Check()

KIND_DATASET = {"points": "demo:points", "lines": "demo:tornado", "surfaces": "demo:surface"}
DATASET_KIND = {v: k for k, v in KIND_DATASET.items()}
ALL_METHODS = ["fourier", "exact", "opaque", "direct", "wboit", "surface-layers", "weighted-average", "binning", "kanzler"]


def path(f):
    return "%s.%s" % (f["section"], f["name"]) if f["section"] else f["name"]


def other_value(f, default):
    """A valid value of f other than default."""
    t = f["type"]
    if t in ("int", "num"):
        lo = f.get("min", 0)
        hi = f.get("max", lo + 10)
        for v in (lo + (hi - lo) / 3, lo + 1, (lo + hi) / 2):
            v = int(round(v)) if t == "int" else v
            if (v > lo or not f.get("loOpen")) and v <= hi and v >= lo and v != default:
                return v
    if t == "bool":
        return not default
    if t == "enum":
        return next(v for v in f["values"] if v != default)
    if t == "str":
        return "x" if default != "x" else "y"
    if t == "range":
        return [0.25, 0.75]
    if t in ("color", "vec3"):
        return [0.25, 0.5, 0.75]
    if t == "terms":
        return [{"attribute": "x", "weight": 1}]
    if t == "filters":
        return [{"attribute": "x", "over": "vertex", "gt": 0}]
    if t == "curve":
        return [[0, 0], [0.5, 0.8], [1, 1]]
    if t == "ranges":
        return [[0, 1]]
    if t == "seed":
        return [[0, 0, 0], [1, 1, 1]]
    raise AssertionError("no value for %s (%s)" % (path(f), t))


def with_field(body, f, value):
    body = json.loads(json.dumps(body))
    if f["section"]:
        body.setdefault(f["section"], {})[f["name"]] = value
    else:
        body[f["name"]] = value
    return body


def refusal(data):
    try:
        e = json.loads(data).get("error", {})
    except ValueError:
        e = {}
    return e.get("field"), e.get("message", "")


schema = json.loads(subprocess.check_output([binary, "schema"], text=True))
scoped = [f for f in schema if "methods" in f or "primitives" in f]
check(len(scoped) >= 40, "the schema says where %d fields apply" % len(scoped))

with Server(binary, data=tuple(KIND_DATASET.values()) + ("demo:abc-flow",), demo_size=200) as srv:
    datasets = srv.json("GET", "/api/v1/datasets")[2]
    field_name = next(fl["name"] for fl in datasets.get("fields", []))
    seed = {"field": field_name, "seed": [[0.5, 0.5, 0.5], [1.5, 1.5, 0.5]], "particles": 50}

    def default_of(f):
        return f.get("default")

    def base(method, dataset):
        b = {"dataset": dataset, "width": 32, "height": 32, "method": method}
        if method == "surface-layers":
            b["surface"] = dict(seed)
        return b

    cases = []  # (field, method, dataset, why)
    for f in scoped:
        for m in ALL_METHODS:
            if m not in f.get("methods", ALL_METHODS):
                cases.append((f, m, "demo:tornado" if "lines" in f.get("primitives", ["lines"]) else
                              KIND_DATASET[f["primitives"][0]], "method " + m))
        for kind, ds in KIND_DATASET.items():
            if kind not in f.get("primitives", list(KIND_DATASET)):
                m = next(x for x in f.get("methods", ALL_METHODS) if x != "surface-layers")
                cases.append((f, m, ds, kind))
    refused, wrong = 0, []
    for f, m, ds, why in cases:
        body = with_field(base(m, ds), f, other_value(f, default_of(f)))
        st, _, data = srv.request("POST", "/api/v1/render", body)
        field, msg = refusal(data)
        if st == 400 and field == path(f) and "applies to" in msg:
            refused += 1
        else:
            wrong.append("%s under %s: %d %s" % (path(f), why, st, data[:160]))
    check(not wrong, "%d of %d requests with a field where it does not apply are refused naming it%s" %
          (refused, len(cases), "; not: " + "; ".join(wrong[:6]) if wrong else ""))

    # The same values where the fields apply do not meet that refusal.
    passed, wrong = 0, []
    for f in scoped:
        m = next(x for x in f.get("methods", ALL_METHODS))
        kind = next(k for k in f.get("primitives", ["lines", "points", "surfaces"]))
        body = with_field(base(m, KIND_DATASET[kind]), f, other_value(f, default_of(f)))
        st, _, data = srv.request("POST", "/api/v1/render", body)
        if "applies to" in refusal(data)[1]:
            wrong.append("%s under %s on %s: %s" % (path(f), m, kind, data[:160]))
        else:
            passed += 1
    check(not wrong, "%d fields pass where they apply%s" % (passed, "; not: " + "; ".join(wrong[:6]) if wrong else ""))

    # The renderer's own refusals, now answered when the request arrives.
    for body, field in (
            ({"layers": [{"dataset": "demo:tornado"}, {"dataset": "demo:points", "role": "context"}]},
             "layers[1].role"),
            ({"dataset": "demo:tornado", "params": {"guardBand": 0.1, "depthRange": "pixel"}}, "params.guardBand"),
            ({"dataset": "demo:tornado", "color": {"attribute": "nope"}}, "color.attribute"),
            ({"dataset": "demo:points", "time": {"window": [0, 1], "attribute": "nope"}}, "time.attribute")):
        st, _, data = srv.request("POST", "/api/v1/render", dict({"width": 32, "height": 32}, **body))
        check(st == 400 and refusal(data)[0] == field,
              "the renderer's refusal of %s is a 400 naming it (%d %s)" % (field, st, data[:160]))

    # Fields that apply under one value of another field ("when", the direct method's opacity parameters under
    # params.alphaSource): refused naming them under another value, rendered under theirs.
    conditional = [f for f in schema if f.get("when")]
    check(len(conditional) >= 3, "the schema names the conditional fields (%d)" % len(conditional))
    for f in conditional:
        when_section, when_name = f["when"][0].split(".")
        m = next(x for x in f.get("methods", ALL_METHODS))
        other = next(v for v in next(g for g in schema if path(g) == f["when"][0])["values"] if v != f["when"][1])
        value = other_value(f, default_of(f))
        # streamlines.*: a field's traced set (a dataset that names the field); the others on the surface
        body = with_field(base(m, field_name if path(f).startswith("streamlines.") else "demo:surface"), f, value)
        body.setdefault(when_section, {})[when_name] = other
        st, _, data = srv.request("POST", "/api/v1/render", body)
        check(st == 400 and refusal(data)[0] == path(f) and f["when"][0] in refusal(data)[1],
              "%s with %s %s: a 400 naming it (%d %s)" % (path(f), f["when"][0], other, st, data[:160]))
        body[when_section][when_name] = f["when"][1]
        st, _, data = srv.request("POST", "/api/v1/render", body)
        check(st == 200, "%s with %s %s: rendered (%d %s)" % (path(f), f["when"][0], f["when"][1], st,
                                                               data[:160] if st != 200 else ""))

    async def conditional_session():
        """A session's update: the constant opacity without its source is refused naming it; a later update that
        gives both renders, and changing the source alone keeps the session rendering."""
        async with websockets.connect(srv.ws_url, max_size=None) as ws:
            await ws.send(json.dumps({"type": "hello", "dataset": "demo:surface", "width": 48, "height": 40,
                                      "devicePixelRatio": 1, "method": "direct"}))
            check((await wait_for_stream_done(ws)).reached, "conditional: the first picture is done")
            await ws.send(json.dumps({"type": "params", "params": {"alphaConstant": 0.5}}))
            got = await wait_for_message(ws, lambda x: x.get("type") in ("error", "frame"))
            last = got[-1] if got.reached else {}
            check(last.get("type") == "error" and last.get("field") == "params.alphaConstant",
                  "conditional: alphaConstant without alphaSource constant is refused naming it (%s)" %
                  {k: v for k, v in last.items() if k != "image"})
            for update in ({"params": {"alphaSource": "constant", "alphaConstant": 0.5}},
                           {"params": {"alphaSource": "angle"}},
                           # the baselines at equal memory in a session, and a moving frame that reuses their opacities
                           {"method": "weighted-average"}, {"method": "binning", "params": {"q": 10}}):
                await ws.send(json.dumps(dict({"type": "params"}, **update)))
                done = await wait_for_stream_done(ws)
                check(done.reached and not [x for x in done if x.get("type") == "error"],
                      "conditional: the update %s renders" % update)
            await ws.send(json.dumps({"type": "camera", "seq": 1, "camera": {"position": [0.5, 3, 4]}}))
            done = await wait_for_stream_done(ws)
            check(done.reached and not [x for x in done if x.get("type") == "error"], "binning: a camera move renders")

    asyncio.run(conditional_session())

    async def session():
        """One session per dataset kind: each refused update answered with an error naming its field before any
        frame, then an update that applies renders."""
        wrong, refused = [], 0
        for kind, ds in KIND_DATASET.items():
            async with websockets.connect(srv.ws_url, max_size=None) as ws:
                await ws.send(json.dumps({"type": "hello", "dataset": ds, "width": 48, "height": 40,
                                          "devicePixelRatio": 1}))
                done = await wait_for_stream_done(ws)
                check(done.reached, "%s: the session's first picture is done" % kind)
                for f, m, cds, why in cases:
                    if cds != ds or m == "surface-layers":
                        continue
                    update = {"type": "params"}
                    if why.startswith("method"):
                        update["method"] = m
                    update = with_field(update, f, other_value(f, default_of(f)))
                    await ws.send(json.dumps(update))
                    got = await wait_for_message(ws, lambda x: x.get("type") in ("error", "frame"))
                    last = got[-1] if got.reached else {}
                    if last.get("type") == "error" and last.get("field") == path(f):
                        refused += 1
                    else:
                        wrong.append("%s under %s on %s: %s" % (path(f), why, kind, {k: v for k, v in last.items()
                                                                                   if k != "image"}))
                await ws.send(json.dumps({"type": "params", "params": {"smoothing": 3}}))
                done = await wait_for_stream_done(ws)
                check(done.reached and not [x for x in done if x.get("type") == "error"],
                      "%s: after the refused updates an update that applies renders" % kind)
        check(not wrong, "%d session updates with a field where it does not apply are refused naming it%s" %
              (refused, "; not: " + "; ".join(wrong[:6]) if wrong else ""))

    asyncio.run(session())
check.done()
