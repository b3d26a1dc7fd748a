"""Ground shadows and smart transparency (docs/ALGORITHM.md §29) in every path
of the real daemon: an HTTP render of the tornado with style.shadow and
style.smartTransparency answers an image that differs from the plain one and
from each alone, and the GET form's flat names draw the POST render; a scripted HTTP session's frame is that image byte for byte; a
WebSocket session whose hello asks for them streams as its first still the
HTTP render's JPEG byte for byte, and an update that turns them off streams the
plain render; a movie of the request renders and its first frame is the HTTP
render (SSIM after H.264, where ffmpeg is installed). Refusals name their
field: a shadow with the exact method (the scope table), a shadow that nothing
receives, smart transparency on a tiled still, and the same in a WebSocket
update and a movie request."""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.parse

from lucent_server import DEADLINE, Check, Server, wait_for_stream_done, wait_for_message, websockets

binary = sys.argv[1]
check = Check()
SIZE = {"width": 96, "height": 80}
AIDS = {"shadow": 0.8, "shadowColored": True, "smartTransparency": 0.7}
BASE = {"dataset": "demo:tornado"}


def render(srv, style=None, **extra):
    body = dict(SIZE, **BASE, **extra)
    if style is not None:
        body["style"] = style
    return srv.request("POST", "/api/v1/render", body)


def field_of(data):
    try:
        e = json.loads(data)
    except ValueError:
        return None
    return e.get("field") if "field" in e else e.get("error", {}).get("field")


def refused(st, data, field, what):
    check(st == 400 and field_of(data) == field, "%s -> 400 naming %s (%d %s)" % (what, field, st, data[:200]))


def ssim(a, b):
    words = subprocess.run([binary, "ssim", a, b], capture_output=True, text=True).stdout.split()
    return float(dict(zip(words[0::2], words[1::2])).get("ssim", -1))


async def stream(srv):
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        await ws.send(json.dumps(dict({"type": "hello", "devicePixelRatio": 1, "style": AIDS}, **SIZE, **BASE)))
        frames = [m for m in await wait_for_stream_done(ws, lambda h: True, skip=("stats", "progress"))
                  if m["type"] == "frame"]
        st, _, ref = render(srv, AIDS, format="jpeg", quality=90)
        first = frames[0]["image"] if frames else b""
        check(st == 200 and first == ref, "the session's first still with shadows and outlines is the HTTP "
              "render's JPEG byte for byte (%d frames)" % len(frames))
        await ws.send(json.dumps({"type": "params", "style": {"shadow": 0, "smartTransparency": 0}}))
        got = await wait_for_stream_done(ws, lambda h: True, skip=("stats", "progress"))
        stills = [m for m in got if m["type"] == "frame" and m["quality"] == 90]
        st, _, plain = render(srv, {"shadowColored": True}, format="jpeg", quality=90)
        check(stills and stills[-1]["image"] == plain, "an update turning both off streams the plain render")
        await ws.send(json.dumps({"type": "params", "method": "exact", "style": {"shadow": 0.5}}))
        got = await wait_for_message(ws, lambda m: m["type"] == "error", skip=("stats", "progress", "frame"))
        errors = [m for m in got if m["type"] == "error"]
        check(errors and errors[0].get("field") == "style.shadow",
              "an update asking for a shadow with the exact method -> error naming style.shadow (%r)" % errors[:1])


def movie(srv, tmp):
    st, _, data = srv.request("POST", "/api/v1/movies", dict(SIZE, request=dict(BASE, style=AIDS), frames=2, fps=2))
    job = json.loads(data) if st in (202, 400) else {}
    if st == 400 and field_of(data) == "codec":
        print("skip movies: this server cannot encode them")
        return
    check(st == 202, "a movie with shadows and outlines is queued (%d %s)" % (st, data[:200]))
    end = time.time() + 120
    while st == 202:
        s, _, d = srv.request("GET", "/api/v1/movies/%s" % job.get("id"))
        done = json.loads(d) if s == 200 else {}
        if done.get("state") in ("done", "failed", "cancelled") or time.time() > end:
            break
        time.sleep(0.2)
    check(done.get("state") == "done" and done.get("framesDone") == 2, "it renders (%s)" % json.dumps(done)[:200])
    st, _, video = srv.request("GET", "/api/v1/movies/%s/file" % job.get("id"))
    if st != 200 or not (shutil.which("ffmpeg")):
        print("skip decoding the movie: ffmpeg not installed")
        return
    path, frame0, ref = (os.path.join(tmp, n) for n in ("m.mp4", "f0.png", "ref.png"))
    with open(path, "wb") as f:
        f.write(video)
    subprocess.run(["ffmpeg", "-v", "error", "-y", "-i", path, "-frames:v", "1", frame0], check=False)
    _, _, img = render(srv, AIDS)
    with open(ref, "wb") as f:
        f.write(img)
    _, _, img = render(srv, {})
    plain = os.path.join(tmp, "plain.png")
    with open(plain, "wb") as f:
        f.write(img)
    with_aids, without = (ssim(frame0, ref), ssim(frame0, plain)) if os.path.exists(frame0) else (-1, -1)
    check(with_aids >= 0.95 and with_aids > without, "its first frame is the HTTP render with them (SSIM %.4f after "
          "H.264), not the plain one (%.4f)" % (with_aids, without))
    st, _, data = srv.request("POST", "/api/v1/movies",
                              dict(SIZE, request=dict(BASE, method="wboit", style={"shadow": 1}), frames=2))
    refused(st, data, "style.shadow", "a movie of wboit with a shadow")


tmp = tempfile.mkdtemp()
with Server(binary, data=("demo:tornado",), demo_size=150) as srv:
    st, _, plain = render(srv, {})
    st1, _, both = render(srv, AIDS)
    st2, _, shadow = render(srv, {"shadow": 0.8})
    st3, _, smart = render(srv, {"smartTransparency": 0.7})
    check(st == st1 == st2 == st3 == 200 and len({plain, both, shadow, smart}) == 4,
          "HTTP renders: the shadow, the outlines and both each change the image (%d %d %d %d)" % (st, st1, st2, st3))
    query = urllib.parse.urlencode({"dataset": "demo:tornado", "width": 96, "height": 80, "shadow": 0.8,
                                    "shadowColored": "true", "smartTransparency": 0.7, "shadowLight": "1,0,1"})
    st, _, got = srv.request("GET", "/api/v1/render?" + query)
    st2, _, ref = render(srv, dict(AIDS, shadowLight=[1, 0, 1]))
    check(st == 200 and got == ref and got != both,
          "the GET form with flat names (shadowLight=1,0,1) is the POST render, not the default light's (%d, %d)"
          % (st, st2))
    st, _, data = srv.request("POST", "/api/v1/sessions", dict(SIZE, **BASE, style=AIDS))
    if st == 201:
        sid = json.loads(data)["session"]
        st, _, img = srv.request("POST", "/api/v1/sessions/%s/render" % sid, {})
        check(st == 200 and img == both, "a scripted session's frame is the HTTP render (%d)" % st)
        srv.request("DELETE", "/api/v1/sessions/%s" % sid)
    else:
        check(False, "a scripted session with them -> 201 (%d %s)" % (st, data[:200]))
    st, _, data = render(srv, {"shadow": 0.5}, method="exact")
    refused(st, data, "style.shadow", "a shadow with the exact method")
    st, _, data = render(srv, {"shadow": 0.5, "ground": "off"})
    refused(st, data, "style.shadow", "a shadow nothing receives")
    st, _, data = render(srv, {"smartTransparency": 0.5}, width=4200, height=4200)
    refused(st, data, "style.smartTransparency", "smart transparency on a tiled still")
    if websockets:
        import asyncio
        asyncio.run(stream(srv))
    movie(srv, tmp)

shutil.rmtree(tmp, ignore_errors=True)
check.done()
