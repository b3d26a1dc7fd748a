"""Bounded soak test (issue 12): 8 WebSocket sessions dragging the camera (and
acking their frames) plus concurrent HTTP renders and health probes, for about
a minute on loopback, in two rounds with a full disconnect between them.
Asserts: the daemon stays up; no error message on any stream and every HTTP
answer an image or 429/503 with Retry-After; health answers throughout (its
latency is printed: a figure for a person or a benchmark, not a bound a busy
CI machine can promise); every session is served, none far below the others
(round robin fairness); all sessions close after the clients leave; resident
memory (VmRSS from /proc) after each round's disconnect returns near the
plateau seen under load, and the second round does not end higher than the
first (no growth per round). LUCENT_SOAK_SECONDS sets the load time (default
60); a round goes on past its half of it until every session has had
MIN_FRAMES frames and the HTTP clients MIN_IMAGES images, so a slow machine
takes longer rather than failing."""
import asyncio
import json
import os
import sys
import threading
import time

from lucent_server import Check, Server, jpeg_size, skip, unpack_frame, websockets

if websockets is None:
    skip("python3-websockets is not installed")

binary = sys.argv[1]
SECONDS = float(os.environ.get("LUCENT_SOAK_SECONDS", "60"))
ROUND = SECONDS / 2
SESSIONS = 8
HTTP_THREADS = 2
MIN_FRAMES = 10   # frames every session has had before a round ends (fairness is judged on enough of them)
MIN_IMAGES = 11   # HTTP images before a round ends
DEADLINE = 120    # seconds a round may go on past its time for those, and the bound of the other waits
check = Check()


def served(stats):
    """Every session has had MIN_FRAMES frames this round."""
    live = stats["live"]
    return len(live) == SESSIONS and min(live.values()) >= MIN_FRAMES


async def ws_client(srv, idx, stop_at, stats):
    frames = 0
    stats["live"][idx] = 0
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        await ws.send(json.dumps({"type": "hello", "dataset": "demo:points", "width": 80 + 8 * idx, "height": 64,
                                  "window": 2}))
        ready = json.loads(await asyncio.wait_for(ws.recv(), DEADLINE))
        if ready.get("type") != "ready":
            stats["errors"].append(ready)
            return
        seq = 0
        next_camera = 0.0
        end = stop_at + DEADLINE
        # every session drives on until all have had their frames: the load stays the same for all
        while (time.time() < stop_at or not served(stats)) and time.time() < end:
            now = time.time()
            if now >= next_camera:  # ~30 Hz of camera input, as a drag
                seq += 1
                z = 2.0 + 0.6 * ((seq + idx) % 12) / 12
                await ws.send(json.dumps({"type": "camera", "seq": seq,
                                          "camera": {"position": [0.5, 0.5 + 0.1 * (idx % 3), z],
                                                     "focalPoint": [0.5, 0.5, 0.5]}}))
                next_camera = now + 1 / 30
            try:
                m = await asyncio.wait_for(ws.recv(), max(0.005, next_camera - time.time()))
            except asyncio.TimeoutError:
                continue
            if isinstance(m, str):
                if json.loads(m).get("type") not in ("stats", "progress"):
                    stats["errors"].append(m)
                continue
            h, img = unpack_frame(m)
            jpeg_size(img)
            frames += 1
            stats["live"][idx] = frames
            await ws.send(json.dumps({"type": "ack", "frame": h["frame"]}))
    stats["frames"][idx] = stats["frames"].get(idx, 0) + frames


def http_client(srv, stop_at, stats, ws_done):
    """Renders until stop_at, until the sessions are done and until MIN_IMAGES images came (DEADLINE at most)."""
    i = 0
    end = stop_at + 2 * DEADLINE
    while (time.time() < stop_at or not ws_done.is_set() or stats["http"].count("ok") < MIN_IMAGES) \
            and time.time() < end:
        i += 1
        size = 48 + 16 * (i % 4)
        try:  # the timeout outlasts the daemon's --render-deadline (60 s), which answers 503
            st, h, body = srv.request("POST", "/api/v1/render", {"width": size, "height": size, "format": "jpeg",
                                                                 "params": {"q": 10 + i % 50}}, timeout=DEADLINE)
        except OSError as ex:
            stats["http"].append("exception %r" % ex)
            continue
        if st == 200 and h.get("content-type") == "image/jpeg" and jpeg_size(body) == (size, size):
            stats["http"].append("ok")
        elif st in (429, 503) and h.get("retry-after"):
            stats["http"].append("overloaded")
            time.sleep(0.1)
        else:
            stats["http"].append("status %d" % st)


def prober(srv, stop_at, stats, ws_done):
    while time.time() < stop_at or not ws_done.is_set():
        t0 = time.time()
        try:
            st, _, _ = srv.request("GET", "/api/v1/health", timeout=DEADLINE)
        except OSError:
            st = 0
        stats["health"].append((st, time.time() - t0))
        stats["rss"].append(srv.rss_kb())
        time.sleep(1.0)  # paces the probes; nothing waits on it


def one_round(srv, seconds, stats):
    stop_at = time.time() + seconds
    ws_done = threading.Event()
    threads = [threading.Thread(target=http_client, args=(srv, stop_at, stats, ws_done))
               for _ in range(HTTP_THREADS)]
    threads.append(threading.Thread(target=prober, args=(srv, stop_at, stats, ws_done)))
    for t in threads:
        t.start()

    async def all_ws():
        await asyncio.gather(*[ws_client(srv, i, stop_at, stats) for i in range(SESSIONS)])
    try:
        asyncio.run(all_ws())
    finally:
        ws_done.set()
    for t in threads:
        t.join()


def settled_rss(srv, bound_kb, timeout=30.0):
    """Resident KB once at or under bound_kb (what the closed sessions held is
    freed as they go), or the last reading after timeout seconds."""
    end = time.time() + timeout
    while True:
        kb = srv.rss_kb()
        if kb <= bound_kb or time.time() > end:
            return kb
        time.sleep(0.25)


def settle(srv, timeout=DEADLINE):
    """Waits for every session to close; returns the health sessions object."""
    end = time.time() + timeout
    while True:
        _, _, health = srv.json("GET", "/api/v1/health")
        if health["sessions"] == {"http": 0, "ws": 0} or time.time() > end:
            return health["sessions"]
        time.sleep(0.25)


with Server(binary, "--max-queue", "16") as srv:
    for size in (48, 64, 80, 96):  # first-use allocations (shaders, targets) belong to the baseline
        srv.request("POST", "/api/v1/render", {"width": size, "height": size, "format": "jpeg"})
    base = srv.rss_kb()
    after = []
    stats = None
    for r in range(2):
        stats = {"frames": {}, "live": {}, "errors": [], "http": [], "health": [], "rss": []}
        one_round(srv, ROUND, stats)
        check(srv.proc.poll() is None, "round %d: daemon alive after %.0f s of load" % (r + 1, ROUND))
        http = stats["http"]
        bad = [x for x in http if x not in ("ok", "overloaded")]
        check(not bad and http.count("ok") >= MIN_IMAGES, "round %d: HTTP %d requests, %d images, %d overloaded, "
              "others %s" % (r + 1, len(http), http.count("ok"), http.count("overloaded"), bad[:3]))
        check(not stats["errors"], "round %d: no error messages on the streams (%s)" % (r + 1, stats["errors"][:3]))
        unanswered = [x for x in stats["health"] if x[0] != 200]
        check(stats["health"] and not unanswered, "round %d: health answered %d times, every time (worst %.2f s; "
              "a figure, not a bound)" % (r + 1, len(stats["health"]),
                                          max((x[1] for x in stats["health"]), default=0)))
        frames = [stats["frames"].get(i, 0) for i in range(SESSIONS)]
        mean = sum(frames) / SESSIONS
        check(min(frames) >= MIN_FRAMES and min(frames) >= 0.3 * mean,
              "round %d: every session served, none far below the mean %.0f: %s" % (r + 1, mean, frames))
        sessions = settle(srv)
        check(sessions == {"http": 0, "ws": 0}, "round %d: sessions all closed: %s" % (r + 1, sessions))
        plateau = max(stats["rss"][len(stats["rss"]) // 2:] or [srv.rss_kb()])
        bound = plateau * 1.1 + 8 * 1024
        if after:  # and the second round ends no higher than the first
            bound = min(bound, after[0] * 1.05 + 8 * 1024)
        after.append(settled_rss(srv, bound))
        print("round %d: RSS baseline %.1f MB, plateau under load %.1f MB, after disconnect %.1f MB" %
              (r + 1, base / 1024, plateau / 1024, after[-1] / 1024))
        check(after[-1] <= plateau * 1.1 + 8 * 1024, "round %d: RSS after disconnect near the plateau (%.1f vs %.1f MB)"
              % (r + 1, after[-1] / 1024, plateau / 1024))
    check(after[1] <= after[0] * 1.05 + 8 * 1024, "no growth from round to round (%.1f -> %.1f MB)" %
          (after[0] / 1024, after[1] / 1024))
    check(srv.stop() == 0, "clean exit after the soak")

check.done()
