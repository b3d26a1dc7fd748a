"""The victim's drag (issue 47): one WebSocket client drags the camera (about
30 updates a second, every frame acked) while ONE other client runs a mix of
accepted requests without pause: halo renders, tiled stills (above 2048^2),
surface-layers renders, 40 scripted HTTP sessions rendering, and movie jobs.
The drag must keep at least half its moving-frame rate alone.

The rates are measured robustly on a busy machine: each is FRAMES moving
frames counted over a window that states open and close, never a timer: the
window opens at a moving frame (alone: once the hello's stream is done; under
load: once every kind of the attacker's work has been accepted and is running)
and closes at the FRAMES-th moving frame after it; the rate is FRAMES over the
window's length. The drag alone is measured before and after the attack in
the same run and the attack is judged against their mean, so that the host's
other load drifting during the test moves both sides alike. The figures are
printed."""
import asyncio
import http.client
import json
import multiprocessing
import os
import sys
import threading
import time

from lucent_server import Check, Server, skip, stream_done, unpack_frame, websockets

if websockets is None:
    skip("python3-websockets is not installed")

binary = sys.argv[1]
check = Check()
FRAMES = int(os.environ.get("LUCENT_VICTIM_FRAMES", "120"))  # moving frames in each window
SESSIONS = 40
DEADLINE = 240  # bounds a stuck wait; never a measured quantity
POINTS = "demo:points?count=20000"
VICTIM = {"type": "hello", "dataset": POINTS, "width": 256, "height": 192, "devicePixelRatio": 1, "window": 2}


def interactive(h):
    return (h.get("detail") or {}).get("interactive", False)


async def drag_window(ws, seq0, frames):
    """Drags until `frames` moving frames have come after the first one;
    returns (moving frames per second, last camera seq). Frames are acked."""
    seq, first, count, end = seq0, None, 0, time.time() + DEADLINE
    renders = []  # the server's render times of the victim's frames (stats), printed
    next_camera = 0.0
    while count < frames and time.time() < end:
        now = time.time()
        if now >= next_camera:  # ~30 Hz of camera input, as a drag
            seq += 1
            await ws.send(json.dumps({"type": "camera", "seq": seq, "camera": {
                "position": [0.5 + 0.05 * (seq % 20), 0.5, 2.6], "focalPoint": [0.5, 0.5, 0.5],
                "viewUp": [0, 1, 0]}}))
            next_camera = now + 1 / 30
        try:
            m = await asyncio.wait_for(ws.recv(), max(0.002, next_camera - time.time()))
        except asyncio.TimeoutError:
            continue
        if isinstance(m, str):
            msg = json.loads(m)
            if msg.get("type") not in ("stats", "progress"):
                check(False, "the victim gets no error: %r" % msg)
            if msg.get("type") == "stats":
                renders.append(msg.get("renderMs", 0))
            continue
        h, _ = unpack_frame(m)
        await ws.send(json.dumps({"type": "ack", "frame": h["frame"]}))
        if not interactive(h):
            continue
        t = time.time()
        if first is None:
            first = t  # the window opens at a moving frame
        else:
            count += 1
    check(count >= frames, "the window closed on its %d moving frames (%d)" % (frames, count))
    print("  window: %d moving frames, the server's render times %s ms" % (count, [round(r) for r in renders]))
    return (count / (time.time() - first) if first and count else 0.0), seq


async def settle(ws):
    """Receives (acking) until the stream ends: no input pending."""
    end = time.time() + DEADLINE
    while time.time() < end:
        m = await asyncio.wait_for(ws.recv(), DEADLINE)
        if isinstance(m, str):
            continue
        h, _ = unpack_frame(m)
        await ws.send(json.dumps({"type": "ack", "frame": h["frame"]}))
        if stream_done(dict(h, type="frame")):
            return


CLIENT_TIMEOUT = 30  # the attacker's client gives up on an answer and asks again (its threads never hang)
ATTACKER = "127.0.0.2"  # another client address than the victim's 127.0.0.1 (clients are keyed by address)


def request(srv, method, path, body=None):
    """(status, headers, body) of a request from the attacker's address."""
    conn = http.client.HTTPConnection(srv.host, srv.port, timeout=CLIENT_TIMEOUT, source_address=(ATTACKER, 0))
    try:
        conn.request(method, path, body, {"Content-Type": "application/json"} if body else {})
        r = conn.getresponse()
        data = r.read()
        return r.status, {k.lower(): v for k, v in r.getheaders()}, data
    except OSError as e:  # a closed connection is a failure the test reports, not a crash of the thread
        return 0, {}, repr(e).encode()
    finally:
        conn.close()


class Attacker:
    """One client (127.0.0.2) running a mix of accepted requests in threads until stop."""

    def __init__(self, srv):
        self.srv, self.stop, self.threads = srv, threading.Event(), []
        self.ok = {}  # kind -> accepted answers
        self.errors = []
        self.lock = threading.Lock()

    def count(self, kind, st, body):
        with self.lock:
            if st in (200, 201, 202):
                self.ok[kind] = self.ok.get(kind, 0) + 1
            elif st == 0:  # closed unanswered (a render queued past the HTTP timeout): counted and printed
                self.ok["closed"] = self.ok.get("closed", 0) + 1
            elif st not in (429, 503):  # busy is an answer; anything else is a failure
                self.errors.append((kind, st, body[:200]))

    def backoff(self, st):
        """A refused or dropped request is retried as a client honouring Retry-After would, not at once
        (load shaping of the attacker's client, not a wait of the test)."""
        if st in (0, 429, 503):
            self.stop.wait(0.5)

    def loop(self, kind, body):
        while not self.stop.is_set():
            st, _, data = request(self.srv, "POST", "/api/v1/render", json.dumps(body))
            self.count(kind, st, data)
            self.backoff(st)

    def session(self, i):
        st = 0
        while st != 201 and not self.stop.is_set():
            st, _, data = request(self.srv, "POST", "/api/v1/sessions", json.dumps(
                {"dataset": POINTS, "width": 96, "height": 96}))
            self.count("sessions", st, data)
            self.backoff(st)
        if st != 201:
            return
        sid = json.loads(data)["session"]
        k = 0
        while not self.stop.is_set():
            k += 1
            st, _, data = request(self.srv, "POST", "/api/v1/sessions/%s/render" % sid, json.dumps(
                {"camera": {"position": [0.5, 0.5 + 0.01 * (k % 10), 2.5], "focalPoint": [0.5, 0.5, 0.5]}}))
            self.count("session renders", st, data)
            self.backoff(st)
        for _ in range(3):  # closed unanswered: try again
            if request(self.srv, "DELETE", "/api/v1/sessions/" + sid)[0] != 0:
                break

    def movies(self):
        while not self.stop.is_set():
            st, _, data = request(self.srv, "POST", "/api/v1/movies", json.dumps(
                {"width": 320, "height": 240, "frames": 600, "fps": 30, "request": {"dataset": "demo:tornado"}}))
            self.count("movies", st, data)
            if st != 202:
                if st == 400 and b"codec" in data:
                    with self.lock:
                        self.ok["movies"] = -1  # no encoder on this host: not part of the mix
                    return
                time.sleep(0.2)  # refused as busy: ask again (a client's retry, not a measured wait)
                continue
            job = json.loads(data)["id"]
            while not self.stop.is_set():
                st, _, data = request(self.srv, "GET", "/api/v1/movies/" + job)
                state = json.loads(data).get("state") if st == 200 else "gone"
                if state == "running":
                    with self.lock:
                        self.ok["movie running"] = 1
                if state in ("done", "failed", "cancelled", "gone"):
                    break
                time.sleep(0.2)
            request(self.srv, "DELETE", "/api/v1/movies/" + job)

    def start(self):
        kinds = [("halos", {"dataset": "demo:tornado", "width": 512, "height": 512, "format": "jpeg",
                            "style": {"haloWidth": 1.0}}),
                 ("tiles", {"dataset": POINTS, "width": 2100, "height": 2100, "format": "jpeg"}),
                 ("surfaces", {"dataset": POINTS, "width": 256, "height": 256, "format": "jpeg",
                               "method": "surface-layers",
                               "surface": {"field": "demo:abc-flow", "particles": 300,
                                           "seed": [[3.14, 0.63, 3.14], [3.14, 5.65, 3.14]]}})]
        self.threads = [threading.Thread(target=self.loop, args=k, daemon=True) for k in kinds]
        self.threads += [threading.Thread(target=self.session, args=(i,), daemon=True) for i in range(SESSIONS)]
        self.threads.append(threading.Thread(target=self.movies, daemon=True))
        for t in self.threads:
            t.start()

    def running(self):
        """Every kind has been accepted at least once (the movie is rendering), and every session is open."""
        with self.lock:
            ok = dict(self.ok)
        movie = ok.get("movies") == -1 or ok.get("movie running")
        return all(ok.get(k) for k in ("halos", "tiles", "surfaces", "session renders")) and \
            ok.get("sessions", 0) >= SESSIONS and movie

    def finish(self):
        self.stop.set()
        for t in self.threads:
            t.join(DEADLINE)


def attack(srv, stop, pipe):
    """The attacker's process (its own, so that its 44 client threads share no
    interpreter with the victim's client): starts the mix, says "running" once
    every kind is under way, runs until stop, then sends what it got."""
    a = Attacker(srv)
    a.start()
    said = False
    while not stop.is_set():
        if not said and a.running():
            pipe.send(("running", dict(a.ok)))
            said = True
        stop.wait(0.1)  # polls a state (every kind under way) or the stop
    a.finish()
    pipe.send(("done", dict(a.ok), a.errors))


def metric(srv, name):
    _, _, body = srv.request("GET", "/metrics")
    return sum(float(line.split()[-1]) for line in body.decode().splitlines()
               if line.startswith(name + " ") or line.startswith(name + "{"))


async def main(srv):
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        await ws.send(json.dumps(VICTIM))
        await settle(ws)
        alone1, seq = await drag_window(ws, 0, FRAMES)
        await settle(ws)
        ctx = multiprocessing.get_context("fork")
        stop = ctx.Event()
        mine, theirs = ctx.Pipe()
        proc = ctx.Process(target=attack, args=(srv, stop, theirs), daemon=True)
        proc.start()
        running = mine.poll(DEADLINE) and mine.recv()  # a state: every kind of the attack accepted and running
        check(running and running[0] == "running", "the attack is under way: %r" % (running,))
        t_attack = time.time()
        loaded, seq = await drag_window(ws, seq, FRAMES)
        print("  loaded window over after %.1f s" % (time.time() - t_attack))
        stop.set()
        done = mine.recv() if mine.poll(DEADLINE) else ("done", {}, [("attacker", 0, b"no report")])
        proc.join(DEADLINE)
        print("  attacker stopped after %.1f s" % (time.time() - t_attack))
        ok_during, errors = done[1], done[2]
        # The attacker's work is over once nothing of it is queued (a state; its clients have all had answers).
        end = time.time() + DEADLINE
        while metric(srv, "lucent_queue_depth") > 0 and time.time() < end:
            await asyncio.sleep(0.1)
        print("  after the attack: queue %g, sessions %g" % (metric(srv, "lucent_queue_depth"),
                                                           metric(srv, "lucent_sessions_active")))
        await settle(ws)
        alone2, seq = await drag_window(ws, seq, FRAMES)
    alone = (alone1 + alone2) / 2
    print("victim drag: alone %.2f and %.2f moving frames/s, beside the attack %.2f (%.0f %%); the attacker's "
          "accepted answers: %s; load %s" % (alone1, alone2, loaded, 100 * loaded / alone if alone else 0,
                                              ok_during, open("/proc/loadavg").read().split()[:3]))
    kinds = {}
    for kind, st, body in errors:
        kinds.setdefault(kind, (st, body))
    check(not errors, "the attacker's requests are answered or refused as busy: %r" % kinds)
    check(alone > 0 and loaded >= 0.5 * alone, "the drag keeps at least half its rate alone: %.2f of %.2f frames/s"
          % (loaded, alone))


with Server(binary, "--workers", "2", "--max-sessions-per-client", "48", data=(
        POINTS, "demo:tornado", "demo:abc-flow"), demo_size=0, timeout=120) as srv:
    asyncio.run(main(srv))
    check(srv.stop() == 0, "the daemon exits cleanly")
check.done()
