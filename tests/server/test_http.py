"""HTTP API against the real daemon: health, datasets, POST/GET render (decodable
images of the requested size), scripted sessions with dt fading, static files,
metrics, errors, a dataset's suggested view, and a clean SIGTERM exit."""
import json
import os
import sys

from lucent_server import Check, Server, jpeg_size, png_size, ws_connect

binary = sys.argv[1]
check = Check()

with Server(binary) as srv:
    st, _, health = srv.json("GET", "/api/v1/health")
    check(st == 200 and health["status"] == "ok", "health answers ok")
    check(health.get("renderer") and health.get("glVersion"), "health names renderer and GL version: %s" % health.get("renderer"))
    check(health.get("datasets") == 1 and health.get("uptime", -1) >= 0, "health counts datasets and uptime")
    # Which path P4 and P5 take per primitive type: on a software rasterizer the
    # compute rasterizer for points, drawn lines and surfaces (compute_raster.c).
    paths = health.get("rasterPaths", {})
    software = any(w in health.get("renderer", "") for w in ("llvmpipe", "softpipe", "swrast"))
    want = {"points": "compute" if software else "drawn", "lines": "drawn", "triangles": "drawn"}
    forced = os.environ.get("LUCENT_COMPUTE_RASTER", "")
    if forced in ("0", "1"):  # the override, where the rasterizer applies
        want["points"] = want["lines"] = "compute" if forced == "1" else "drawn"
    # Drawn segments are ribbons unless LUCENT_LINE_PRIMITIVE=1 (line_primitive.c).
    form = "lines" if os.environ.get("LUCENT_LINE_PRIMITIVE", "") == "1" else "ribbons"
    check(all(paths.get(k) == dict({"opticalDepth": v, "accumulate": v}, **({"primitive": form} if k == "lines" else {}))
              for k, v in want.items()),
          "health says the path of P4 and P5 per primitive type and the lines' primitive: %s" % paths)

    st, _, ds = srv.json("GET", "/api/v1/datasets")
    d = ds["datasets"][0] if st == 200 and ds["datasets"] else {}
    check(d.get("name") == "demo:points", "datasets lists demo:points")
    check(d.get("elements", 0) > 0 and d.get("vertices", 0) > 0 and len(d.get("bounds", [])) == 2,
          "dataset has counts and bounds")
    check(any("range" in a for a in d.get("attributes", [])), "dataset attributes carry ranges")
    st, _, one = srv.json("GET", "/api/v1/datasets/demo:points")
    check(st == 200 and one["name"] == "demo:points", "GET /api/v1/datasets/NAME")
    check("view" not in one, "no suggested view for demo:points (the renderer uses ParaView's default)")
    st, _, e = srv.json("GET", "/api/v1/datasets/demo:nope")
    check(st == 404 and e["error"]["code"] == "not_found", "GET /api/v1/datasets/UNKNOWN -> 404")
    check(isinstance(health.get("workers"), int) and health["workers"] >= 1 and health.get("platform") and
          health.get("sessions") == {"http": 0, "ws": 0}, "health has workers, platform and sessions")

    req = {"dataset": "demo:points", "width": 96, "height": 64, "format": "jpeg", "quality": 80}
    st, h, img = srv.request("POST", "/api/v1/render", req)
    check(st == 200 and h.get("content-type") == "image/jpeg", "POST render answers image/jpeg (%d)" % st)
    check(st == 200 and jpeg_size(img) == (96, 64), "JPEG decodes to the requested 96x64")
    check("importance=" in h.get("x-lucent-timings", "") and "resolve=" in h.get("x-lucent-timings", ""),
          "per-pass timings header: %s" % h.get("x-lucent-timings"))
    check("importance;dur=" in h.get("server-timing", "") and "encode;dur=" in h.get("server-timing", ""),
          "Server-Timing header: %s" % h.get("server-timing"))
    check(h.get("x-lucent-converged") == "true" and float(h.get("x-lucent-max-alpha-change", "nan")) >= 0,
          "one-shot render: X-Lucent-Converged true, X-Lucent-Max-Alpha-Change")

    st, h, img = srv.request("POST", "/api/v1/render", {"dataset": "points", "width": 64, "height": 48, "format": "png"})
    check(st == 200 and h.get("content-type") == "image/png" and png_size(img) == (64, 48),
          "PNG of 64x48 (dataset by short name)")

    st, h, img = srv.request("GET", "/api/v1/render?dataset=demo:points&width=80&height=60&format=jpeg&q=80"
                             "&camera.position=0,0,5&_=123")
    check(st == 200 and jpeg_size(img) == (80, 60), "GET render with query parameters gives 80x60")

    # Errors with the field named.
    st, _, e = srv.json("POST", "/api/v1/render", {"width": 9000})
    check(st == 400 and e["error"]["field"] == "width", "width 9000 -> 400 naming the field")
    st, _, e = srv.json("POST", "/api/v1/render", {"params": {"bandz": 3}})
    check(st == 400 and e["error"]["code"] == "unknown_field" and e["error"]["field"] == "params.bandz",
          "unknown field -> 400 unknown_field params.bandz")
    st, _, e = srv.json("POST", "/api/v1/render", {"params": {"bands": "five"}})
    check(st == 400 and e["error"]["field"] == "params.bands", "wrong type -> 400 params.bands")
    st, _, e = srv.json("POST", "/api/v1/render", "{not json")
    check(st == 400 and e["error"]["code"] == "bad_json", "malformed JSON -> 400 bad_json")
    st, _, e = srv.json("POST", "/api/v1/render", {"dataset": "/etc/passwd"})
    check(st == 404 and e["error"]["code"] == "not_found", "a file path is not a dataset -> 404")
    st, _, e = srv.json("GET", "/api/v1/render?bandz=3")
    check(st == 400 and e["error"]["field"] == "bandz", "unknown query parameter -> 400")
    st, h, e = srv.json("DELETE", "/api/v1/render")
    check(st == 405 and "POST" in h.get("allow", ""), "DELETE /api/v1/render -> 405 with Allow")
    st, _, e = srv.json("GET", "/api/v1/nope")
    check(st == 404 and e["error"]["code"] == "not_found", "unknown route -> 404 JSON")
    # A value only the renderer can check (an attribute the dataset lacks) is a 400 naming the field.
    for field in ("importance", "color"):
        st, _, e = srv.json("POST", "/api/v1/render", {"width": 32, "height": 32, field: {"attribute": "nope"}})
        check(st == 400 and e["error"]["code"] == "bad_field" and e["error"].get("field") == field + ".attribute"
              and e["error"]["message"].startswith(field + ".attribute: "),
              "unknown %s.attribute -> 400 bad_field naming it (%s)" % (field, e))
    st, _, e = srv.json("GET", "/api/v1/render?width=32&height=32&importance=nope")
    check(st == 400 and e["error"].get("field") == "importance.attribute", "GET form too (%s)" % e)
    # WebSocket handshake with a version other than 13 -> 426 naming the supported one.
    st, h, e = srv.json("GET", "/api/v1/ws", headers={"Connection": "Upgrade", "Upgrade": "websocket",
                                                      "Sec-WebSocket-Key": "dGhlIHNhbXBsZSBub25jZQ==",
                                                      "Sec-WebSocket-Version": "8"})
    check(st == 426 and h.get("sec-websocket-version") == "13" and e["error"]["field"] == "Sec-WebSocket-Version",
          "WebSocket version 8 -> 426 with Sec-WebSocket-Version: 13 (%s)" % st)

    # Scripted session: a params change fades with the given dt.
    st, h, s = srv.json("POST", "/api/v1/sessions", {"dataset": "demo:points", "width": 64, "height": 64,
                                                      "format": "jpeg", "params": {"fadeHalfLife": 0.5}})
    check(st == 201 and len(s.get("session", "")) == 32, "POST /api/v1/sessions -> 201 with an id")
    sid = s["session"]
    check(h.get("location") == "/api/v1/sessions/" + sid, "Location: /api/v1/sessions/ID (%s)" % h.get("location"))
    check(s.get("dataset", {}).get("name") == "demo:points" and s.get("defaults", {}).get("width") == 64,
          "201 body carries dataset info and the session's defaults")
    path = "/api/v1/sessions/%s/render" % sid

    def frame(body):
        st, h, img = srv.request("POST", path, body)
        assert st == 200, (st, img[:200])
        return float(h["x-lucent-max-alpha-change"]), h["x-lucent-converged"] == "true", img

    ch0, conv0, img = frame({"dt": 0})
    check(conv0 and jpeg_size(img) == (64, 64), "first session frame starts at its targets (converged)")
    ch1, conv1, _ = frame({"dt": 0.01, "params": {"q": 0, "r": 0}})
    bound = 1 - 2 ** (-0.01 / 0.5)
    check(0 < ch1 <= bound + 1e-4 and not conv1, "dt=0.01: opacity change %.5f within 1-2^(-dt/t) = %.5f" % (ch1, bound))
    ch2, conv2, _ = frame({"dt": 0.5})
    check(ch2 > ch1 and not conv2, "dt=0.5 moves further (%.5f > %.5f)" % (ch2, ch1))
    ch3, conv3, _ = frame({"dt": 100})
    check(conv3 and ch3 > 1e-3, "a long dt reaches the targets in one frame: converged at once, though the step "
          "was large (%.2g)" % ch3)
    ch4, conv4, _ = frame({"dt": 100})
    check(conv4 and ch4 < 1e-3, "after a long dt the session has converged (%.2g, then %.2g)" % (ch3, ch4))
    st, _, info = srv.json("GET", "/api/v1/sessions/" + sid)
    check(st == 200 and info["frames"] == 5 and info["request"]["params"]["q"] == 0,
          "GET session shows 5 frames and the merged params")
    check(info.get("session") == sid and info.get("dataset") == "demo:points", "GET session names its id and dataset")
    st, _, e = srv.json("POST", path, {"dataset": "demo:other"})
    check(st == 400 and e["error"]["field"] == "dataset", "dataset cannot change within a session")
    st, _, e = srv.json("POST", path, {"params": {"bands": 99}})
    check(st == 400 and e["error"]["code"] == "out_of_range", "session update validated (bands 99 -> 400)")
    st, _, _ = srv.request("DELETE", "/api/v1/sessions/" + sid)
    check(st == 204, "DELETE session -> 204")
    st, _, e = srv.json("POST", path, {"dt": 0.1})
    check(st == 404, "render on a deleted session -> 404")
    st, _, e = srv.json("POST", "/api/v1/sessions", {"dataset": "demo:nope"})
    check(st == 404, "session on an unknown dataset -> 404")

    # Static web client (if the web/ folder had files at build time) and metrics.
    st, h, page = srv.request("GET", "/")
    if st == 200:
        check(h.get("content-type", "").startswith("text/html") and "etag" in h, "GET / serves index.html with an ETag")
        st2, _, _ = srv.request("GET", "/", headers={"If-None-Match": h["etag"]})
        check(st2 == 304, "If-None-Match -> 304")
    else:
        check(st == 404, "GET / without an embedded web client -> 404")
    st, h, text = srv.request("GET", "/metrics")
    text = text.decode()
    check(st == 200 and h.get("content-type", "").startswith("text/plain"), "GET /metrics is text")
    for name in ("lucent_frames_rendered_total", "lucent_render_seconds_bucket", "lucent_pass_seconds_bucket",
                 "lucent_encode_seconds_count", "lucent_bytes_sent_total", "lucent_sessions_active",
                 "lucent_queue_depth", "lucent_frames_coalesced_total", "lucent_errors_total{code=\"bad_json\"}"):
        check(name in text, "metrics has " + name)

    code = srv.stop()
    check(code == 0, "SIGTERM -> exit 0 (got %s)" % code)
    check(any("shutting down" in line for line in srv.log), "shutdown is logged")

# The streamline demos suggest a view (side on, +Z up): info carries it as view {direction, up}.
with Server(binary, data=("demo:abc", "demo:points"), demo_size=40) as srv:
    st, _, ds = srv.json("GET", "/api/v1/datasets")
    by_name = {d["name"]: d for d in ds.get("datasets", [])}
    view = by_name.get("demo:abc", {}).get("view")
    check(isinstance(view, dict) and len(view.get("direction", [])) == 3 and len(view.get("up", [])) == 3,
          "demo:abc has view {direction, up}: %s" % view)
    if view:
        check(all(abs(a - b) < 1e-12 for a, b in zip(view["direction"], [-1, 0.6, -0.45])) and view["up"] == [0, 0, 1],
              "view is the scene's (direction from the camera toward the data, +Z up)")
    check("view" not in by_name.get("demo:points", {}), "demo:points has none")
    st, _, one = srv.json("GET", "/api/v1/datasets/demo:abc")
    check(st == 200 and one.get("view") == view, "GET /api/v1/datasets/demo:abc carries the same view")
    # color.equalize (docs/ALGORITHM.md section 19): a one-shot render, exact, a session, and the refusal of wboit.
    eq = {"dataset": "demo:abc", "width": 64, "height": 48, "format": "png"}
    st, ph, plain = srv.request("POST", "/api/v1/render", eq)
    st2, eh, equalized = srv.request("POST", "/api/v1/render", dict(eq, color={"equalize": True}))
    check(st == 200 and st2 == 200 and png_size(equalized) == (64, 48) and equalized != plain,
          "color.equalize renders another image (%d, %d)" % (st, st2))
    ticks = [float(x) for x in eh.get("x-lucent-color-ticks", "").split(",") if x]
    check(len(ticks) == 5 and ticks == sorted(ticks) and ticks[0] < ticks[4] and "x-lucent-color-ticks" not in ph,
          "the equalized render's legend ticks in X-Lucent-Color-Ticks, the plain one has none (%s)" % ticks)
    st, _, ex = srv.request("POST", "/api/v1/render", dict(eq, method="exact", color={"equalize": True}))
    check(st == 200 and png_size(ex) == (64, 48), "color.equalize with method exact renders (%d)" % st)
    st, _, e = srv.json("POST", "/api/v1/render", dict(eq, method="wboit", color={"equalize": True}))
    check(st == 400 and e["error"]["code"] == "bad_field" and e["error"].get("field") == "color.equalize",
          "color.equalize with method wboit -> 400 naming color.equalize (%s)" % e)
    st, _, s = srv.json("POST", "/api/v1/sessions", dict(eq, color={"equalize": True, "fadeHalfLife": 0.4}))
    frames = [srv.request("POST", "/api/v1/sessions/%s/render" % s.get("session"), {"dt": 0.1})[0] for _ in range(2)]
    check(st == 201 and frames == [200, 200], "an equalized session renders (%s, %s)" % (st, frames))
    # params.clarity's outcome: the strength used and whether the goal was met (X-Lucent-Clarity).
    outcome = {}
    for target in (0.5, 1.0):
        st, h, _ = srv.request("POST", "/api/v1/render", {"dataset": "demo:abc", "width": 64, "height": 48,
                                                         "params": {"clarity": target}})
        outcome[target] = dict(kv.split("=") for kv in h.get("x-lucent-clarity", "").split(",") if "=" in kv)
    check(outcome[0.5].get("reached") == "true" and float(outcome[0.5].get("lambdaFactor", 0)) >= 1,
          "clarity 0.5 on demo:abc is reached (%s)" % outcome[0.5])
    check(outcome[1.0].get("reached") == "false" and float(outcome[1.0].get("lambdaFactor", 0)) > 1,
          "clarity 1 is out of reach and says where it stopped (%s)" % outcome[1.0])
    # A render whose colormap's highest values are lost in its background says so (X-Lucent-Warning).
    base = {"dataset": "demo:abc", "width": 32, "height": 32}
    for extra, warned in (({}, True), ({"style": {"background": [0.1, 0.1, 0.1]}}, False),
                          ({"color": {"colormap": "coolwarm"}}, False),
                          ({"color": {"colormap": "grayscale", "range": [1, 0]}}, False),
                          ({"color": {"colormap": "plasma"}}, True)):
        st, h, _ = srv.request("POST", "/api/v1/render", dict(base, **extra))
        w = h.get("x-lucent-warning", "")
        check(st == 200 and (w.startswith("color.colormap:") and "style.background" in w) == warned and
              (bool(w) == warned), "%r: %s (%s)" % (extra, "warned" if warned else "no warning", w))
    # The WebSocket handshake, read raw: one Connection header (strict clients refuse "Upgrade, Upgrade").
    sock, status, text, _ = ws_connect(srv.port)
    sock.close()
    lines = text.split("\r\n")
    conn = [ln.split(":", 1)[1].strip() for ln in lines[1:] if ln.lower().startswith("connection:")]
    check(status.startswith("HTTP/1.1 101") and conn == ["Upgrade"],
          "the WebSocket handshake answers 101 with one Connection: Upgrade (%s, %s)" % (status, conn))
    check(srv.stop() == 0, "second server exits 0")

check.done()
