"""Presets and the visibility report through the daemon: demo presets and a
file's sidecar NAME.lucent.json in /api/v1/datasets (with the attributes'
percentiles), the sidecar's attribute as the dataset default, --elements, the
X-Lucent-Visibility header, the frame header's "visibility" on a WebSocket
session, and bad sidecars refused at start-up naming the file and the field; class labels
reported categorical, never the default importance but the default colour, a sidecar winning."""
import asyncio
import json
import os
import subprocess
import sys
import tempfile

from lucent_server import Check, Server, unpack_frame, websockets

binary = sys.argv[1]
check = Check()
tmp = tempfile.mkdtemp()
ply = os.path.join(tmp, "flow.ply")
gen = subprocess.run([binary, "gen", "abc", "-o", ply, "--count", "30"], capture_output=True, text=True)
check(gen.returncode == 0, "lucent gen wrote %s (%s)" % (ply, gen.stderr.strip()))
sidecar = os.path.join(tmp, "flow.lucent.json")


def write_sidecar(obj_or_text):
    with open(sidecar, "w") as f:
        f.write(obj_or_text if isinstance(obj_or_text, str) else json.dumps(obj_or_text))


def start_fails(*args):
    p = subprocess.run([binary, "serve", "--listen", "127.0.0.1:0", "--data", ply, *args], capture_output=True,
                       text=True, timeout=120)
    return p.returncode, p.stdout + p.stderr


write_sidecar({"importance": {"attribute": "arc_length", "exponent": 2}, "params": {"q": 30, "r": 250},
               "color": {"colormap": "plasma"}, "elements": 200})
with Server(binary, data=(ply, "demo:tornado"), demo_size=20) as srv:
    st, _, body = srv.json("GET", "/api/v1/datasets")
    ds = {d["name"]: d for d in body["datasets"]}
    flow = ds.get("flow", {})
    check(flow.get("preset") == {"importance": {"attribute": "arc_length", "exponent": 2},
                                 "params": {"q": 30, "r": 250}, "color": {"colormap": "plasma"}},
          "the sidecar is the file's preset, without its elements field: %r" % flow.get("preset"))
    check(flow.get("elements") == 200, "the sidecar's elements: %r" % flow.get("elements"))
    check(flow.get("defaultImportance") == "arc_length", "the sidecar's importance attribute is the default")
    check(ds.get("demo:tornado", {}).get("preset", {}).get("params") == {"q": 60, "r": 500, "lambda": 1},
          "the tornado demo carries Lucent's default q, r and lambda")
    attrs = flow.get("attributes", [])
    check(attrs and all(a["range"][0] <= a["percentiles"][0] <= a["percentiles"][1] <= a["range"][1] for a in attrs),
          "every attribute has percentiles inside its range")
    check(all(a["range"][0] <= a["autoRange"][0] <= a["percentiles"][0] and
              a["percentiles"][1] <= a["autoRange"][1] <= a["range"][1] for a in attrs),
          "every attribute's auto range lies between its percentiles and its range")

    st, headers, _ = srv.request("GET", "/api/v1/render?dataset=flow&width=96&height=64")
    vis = dict(kv.split("=") for kv in headers.get("x-lucent-visibility", "").split(",") if "=" in kv)
    # The shares lie in [0, 1]; topDecileReach (fourier) is a ratio, 1 where the top decile shows as drawn.
    check(st == 200 and set(vis) == {"topDecileAlpha", "bottomHalfAlpha", "coveredFraction", "occluderAlpha",
                                     "importantOccluded", "topDecileReach"}
          and all(0 <= float(v) <= 1 for k, v in vis.items() if k != "topDecileReach")
          and float(vis["topDecileReach"]) > 0, "X-Lucent-Visibility: %r" % vis)
    st, headers, _ = srv.request("GET", "/api/v1/render?dataset=flow&width=96&height=64&method=opaque")
    check(st == 200 and "x-lucent-visibility" not in headers, "no visibility for the opaque method")

    async def session():
        async with websockets.connect(srv.ws_url, max_size=None) as ws:
            await ws.send(json.dumps({"type": "hello", "dataset": "flow", "width": 80, "height": 64}))
            while True:
                msg = await asyncio.wait_for(ws.recv(), 60)
                if isinstance(msg, bytes):
                    return unpack_frame(msg)[0]
                if json.loads(msg).get("type") == "error":
                    return json.loads(msg)
    if websockets:
        header = asyncio.run(session())
        v = header.get("visibility", {})
        check(set(v) == {"topDecileAlpha", "bottomHalfAlpha", "coveredFraction", "occluderAlpha", "importantOccluded",
                         "topDecileReach"},
              "the first frame's header carries visibility: %r" % header)

with Server(binary, "--elements", "120", data=(ply,), demo_size=0) as srv:
    st, _, body = srv.json("GET", "/api/v1/datasets")
    check(body["datasets"][0]["elements"] == 120, "--elements wins over the sidecar: %r" % body["datasets"][0]["elements"])

for content, field in (({"params": {"q": 1}, "colour": {}}, "colour"), ({"params": {"bands": 20}}, "bands"),
                       ({"elements": -4}, "elements"), ("{not json", "not JSON"),
                       ({"importance": {"attribute": "nope"}}, "nope"), ({"color": {"attribute": "rgb"}}, "rgb")):
    write_sidecar(content)
    rc, out = start_fails()
    check(rc != 0 and "flow.lucent.json" in out and field in out,
          "bad sidecar %r refused naming the file and %s (rc %d): %s" % (content, field, rc, out.strip()[-200:]))
os.unlink(sidecar)

# Class labels (docs/GUIDE.md "Default attributes"): never the default importance, the default colour; a sidecar wins.
for name, header in (("tagged", "x,y,z,label,height"), ("labels", "x,y,z,label")):
    with open(os.path.join(tmp, name + ".csv"), "w") as f:
        f.write(header + "\n")
        for i in range(400):
            row = [i % 20 * 0.1, i // 20 * 0.1, (i * 7 % 11) * 0.05, i % 4 - 1, i * 0.01 + 0.005]
            f.write(",".join("%g" % v for v in row[:len(header.split(","))]) + "\n")
with open(os.path.join(tmp, "labels.lucent.json"), "w") as f:
    json.dump({"color": {"attribute": "importance"}}, f)
with Server(binary, data=(os.path.join(tmp, "tagged.csv"), os.path.join(tmp, "labels.csv")), demo_size=0) as srv:
    st, _, body = srv.json("GET", "/api/v1/datasets")
    ds = {d["name"]: d for d in body.get("datasets", [])}
    tagged, labels = ds.get("tagged", {}), ds.get("labels", {})
    cats = {a["name"]: a.get("categorical", False) for a in tagged.get("attributes", [])}
    check(cats == {"label": True, "height": False}, "the label is reported categorical, height not: %r" % cats)
    check(tagged.get("defaultImportance") == "height" and tagged.get("defaultColor") == "label",
          "a label is not the default importance but the default colour: %r / %r"
          % (tagged.get("defaultImportance"), tagged.get("defaultColor")))
    check(labels.get("defaultImportance") == "density" and labels.get("defaultColor") == "importance",
          "only a label: density the importance, the sidecar's colour wins: %r / %r"
          % (labels.get("defaultImportance"), labels.get("defaultColor")))
    st, _, _ = srv.request("GET", "/api/v1/render?dataset=tagged&width=64&height=48")
    check(st == 200, "a render with the defaults (colour by the label): %d" % st)
check.done()
