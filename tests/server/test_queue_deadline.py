"""A queued HTTP render that no worker takes within its deadline is answered
while it is still queued (issue 47; pool/queue_deadline.h): 503 "overloaded"
with Retry-After and a JSON error saying how long it waited, never a silent
close. One worker renders a WebSocket session's frame made slow by
--pass-delay (8 passes, 600 ms before each); the frame is in hand once its
progress messages come. A one-shot render and an HTTP session's render queued
behind it, with a deadline of 1 s (--render-deadline 1), get their 503 while
that frame is still rendering (no frame has been rendered yet when they are
answered; without the deadline thread the worker would answer them only after
the frame). The refusals are counted by reason=deadline; then the frame
arrives, and the HTTP session renders again."""
import asyncio
import json
import sys
import threading

from lucent_server import Check, Server, skip, wait_for_frame, wait_for_message, websockets

if websockets is None:
    skip("python3-websockets is not installed")

binary = sys.argv[1]
check = Check()
CHEAP = "/api/v1/render?width=32&height=32&format=jpeg"


def metric(srv, name):
    """The sum of a metric's samples (every label)."""
    st, _, text = srv.request("GET", "/metrics")
    return sum(float(line.split()[-1]) for line in text.decode().splitlines()
               if line.startswith(name + " ") or line.startswith(name + "{"))


def in_background(srv, method, path, out, key):
    def run():
        try:
            out[key] = srv.request(method, path, "{}" if method == "POST" else None, timeout=120)
        except OSError as e:  # a close without an answer: what this test must never see
            out[key] = (0, {}, str(e).encode())

    t = threading.Thread(target=run)
    t.start()
    return t


async def main(srv, sid):
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        await ws.send(json.dumps({"type": "hello", "dataset": "demo:points", "width": 64, "height": 64}))
        got = await wait_for_message(ws, lambda m: m["type"] == "progress", skip=("stats",))
        check(got.reached and not any(m["type"] == "frame" for m in got),
              "the session's first frame is in hand on the one worker (its progress came)")
        before = metric(srv, "lucent_frames_rendered_total")
        out = {}
        threads = [in_background(srv, "GET", CHEAP, out, "oneshot"),
                   in_background(srv, "POST", "/api/v1/sessions/%s/render" % sid, out, "session")]
        for t in threads:
            t.join()
        rendered = metric(srv, "lucent_frames_rendered_total")
        check(rendered == before, "both were answered while the frame in hand still renders (%d frames rendered "
              "meanwhile)" % (rendered - before))
        for key in ("oneshot", "session"):
            st, h, body = out[key]
            try:
                e = json.loads(body).get("error", {})
            except ValueError:
                e = {}
            check(st == 503 and h.get("retry-after") and e.get("code") == "overloaded" and
                  "waited" in e.get("message", "") and "deadline" in e.get("message", ""),
                  "the queued %s render: 503 with Retry-After %s and a JSON error: %r" %
                  (key, h.get("retry-after"), body[:300]))
        check(metric(srv, 'lucent_renders_refused_total{reason="deadline"}') == 2, "counted by reason=deadline")
        got = await wait_for_frame(ws, skip=("stats", "progress"))
        check(got.reached, "then the session's frame arrives")


# The frame in hand takes seven passes of at least 1.5 s: the two renders queued
# behind it reach their 1 s deadline with seconds to spare however busy the host.
with Server(binary, "--workers", "1", "--render-deadline", "1", "--pass-delay", "1500") as srv:
    st, _, s = srv.json("POST", "/api/v1/sessions", {"dataset": "demo:points", "width": 32, "height": 32})
    check(st == 201, "an HTTP session")
    asyncio.run(main(srv, s.get("session", "")))
    st, _, _ = srv.request("POST", "/api/v1/sessions/%s/render" % s.get("session", ""), "{}", timeout=120)
    check(st in (200, 503), "the HTTP session renders again, or is refused up front by the deadline (%d)" % st)
    check(srv.stop() == 0, "clean exit")
check.done()
