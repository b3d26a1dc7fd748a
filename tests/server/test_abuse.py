"""Red-team regressions of the daemon (issue 12), each against the real server:
a FIFO given as a dataset fails at once (info, serve --data);
WebSocket upgrades are authenticated at the handshake (header, ?token= or the
token subprotocol) and unauthenticated ones never hold a connection slot;
over-long tokens are refused at start; blind acks do not open the frame
window; and the minor findings (invalid UTF-8 in a 404, two Content-Length
headers, 1000 query parameters, HEAD on render, an oversized WebSocket message
closes with 1009, pre-hello messages trip the error limit, an authenticated
connection without hello is closed, a camera at 1e308). Raw sockets where the
attack needs bytes a client library would not send."""
import asyncio
import base64
import json
import os
import socket
import struct
import subprocess
import sys
import tempfile
import time

from lucent_server import Check, Server, skip, websockets, ws_connect

if websockets is None:
    skip("python3-websockets is not installed")

binary = sys.argv[1]
check = Check()
TOKEN = "s3cret-token"
AUTH = {"Authorization": "Bearer " + TOKEN}


def token_subprotocol(token):
    return "lucent.token." + base64.urlsafe_b64encode(token.encode()).decode().rstrip("=")


# ---------------------------------------------------------------- raw WebSocket

def ws_frame(payload, opcode=1):
    if isinstance(payload, str):
        payload = payload.encode()
    mask = os.urandom(4)
    n = len(payload)
    h = bytes([0x80 | opcode])
    if n < 126:
        h += bytes([0x80 | n])
    elif n < 65536:
        h += bytes([0x80 | 126]) + struct.pack(">H", n)
    else:
        h += bytes([0x80 | 127]) + struct.pack(">Q", n)
    return h + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(payload))


class FrameReader:
    """Server frames (unmasked) from a raw socket."""

    def __init__(self, sock, rest=b""):
        self.s = sock
        self.buf = rest

    def _need(self, n):
        while len(self.buf) < n:
            d = self.s.recv(65536)
            if not d:
                raise EOFError("connection closed")
            self.buf += d

    def next(self):
        """(opcode, payload)."""
        self._need(2)
        op, ln = self.buf[0] & 0x0F, self.buf[1] & 0x7F
        off = 2
        if ln == 126:
            self._need(4)
            ln = struct.unpack(">H", self.buf[2:4])[0]
            off = 4
        elif ln == 127:
            self._need(10)
            ln = struct.unpack(">Q", self.buf[2:10])[0]
            off = 10
        self._need(off + ln)
        payload = self.buf[off:off + ln]
        self.buf = self.buf[off + ln:]
        return op, payload

    def until_close(self, limit=500):
        """Reads to the close frame: (close code or None, text messages seen);
        the close frame's reason is left in self.reason."""
        texts = []
        self.reason = None
        try:
            for _ in range(limit):
                op, p = self.next()
                if op == 1:
                    texts.append(json.loads(p))
                elif op == 8:
                    self.reason = p[2:].decode(errors="replace")
                    return (struct.unpack(">H", p[:2])[0] if len(p) >= 2 else None), texts
        except (EOFError, ConnectionError, socket.timeout) as e:
            texts.append({"exception": repr(e)})
        return None, texts


def metric(srv, name):
    st, _, body = srv.request("GET", "/metrics", headers=AUTH)
    total = 0.0
    for line in body.decode().splitlines():
        if line.startswith(name):
            total += float(line.split()[-1])
    return total


HELLO = {"type": "hello", "dataset": "demo:points", "width": 64, "height": 64}


def renders_total(srv):
    return metric(srv, "lucent_frames_rendered_total")


def still_held(sock):
    """True while the server has neither sent anything on sock nor closed it:
    an abusive connection that the server has not dealt with yet."""
    import select
    return not select.select([sock], [], [], 0)[0]


def responsive(srv, during, headers=None, abuser=None):
    """The issue's bar: health and an (authenticated) render are answered
    while the abuse goes on. The requests may take as long as a loaded machine
    needs (the timeouts only bound a server that does not answer at all); when
    the server would drop the abusive connection after a while (abuser), it
    must still be held when the answers came: they did not wait for it."""
    t0 = time.monotonic()
    try:
        st1, _, _ = srv.request("GET", "/api/v1/health", timeout=60)
        st2, h, _ = srv.request("GET", "/api/v1/render?width=32&height=32&format=jpeg", headers=headers, timeout=60)
    except OSError as ex:
        st1 = st2 = repr(ex)
    dt = time.monotonic() - t0
    held = abuser is None or still_held(abuser)
    check(st1 == 200 and st2 == 200 and held, "during %s: health and a render answered (%s, %s) in %.2f s%s" %
          (during, st1, st2, dt, "" if abuser is None else ", the abusive connection still held" if held else
           ", but only after the server had dropped the abusive connection"))

# ---------------------------------------------------------------- finding 4: long tokens
for how in ("flag", "env"):
    long_token = "t" * 300
    args = [binary, "serve", "--listen", "127.0.0.1:0", "--data", "demo:points", "--demo-size", "100"]
    env = dict(os.environ)
    env.pop("LUCENT_TOKEN", None)
    if how == "flag":
        args += ["--token", long_token]
    else:
        env["LUCENT_TOKEN"] = long_token
    try:
        p = subprocess.run(args, env=env, capture_output=True, text=True, timeout=120)
        rc, first = p.returncode, p.stderr.splitlines()[:1]
    except subprocess.TimeoutExpired:  # it started serving (with the token cut)
        rc, first = None, ["still running after 120 s"]
    check(rc == 2 and "300 bytes" in first[0], "a 300-byte token (%s) is refused at start (exit %s: %s)" %
          (how, rc, first))

# ---------------------------------------------------------------- finding 6: a FIFO as a dataset
with tempfile.TemporaryDirectory() as tmp:
    fifo = os.path.join(tmp, "data.ply")
    os.mkfifo(fifo)
    for what, args in (("info", [binary, "info", fifo]),
                       ("serve --data", [binary, "serve", "--listen", "127.0.0.1:0", "--data", fifo])):
        try:
            p = subprocess.run(args, capture_output=True, text=True, timeout=120)
            rc, out = p.returncode, p.stdout + p.stderr
        except subprocess.TimeoutExpired:
            rc, out = None, "still blocked after 120 s"
        check(rc not in (0, None) and "not a regular file" in out,
              "%s on a FIFO fails at once (exit %s: %s)" % (what, rc, out.strip().splitlines()[-1:]))

with Server(binary, "--max-connections", "8", env={"LUCENT_TOKEN": TOKEN}) as srv:
    # ------------------------------------------------------------ finding 3: auth at the handshake
    s, status, _, _ = ws_connect(srv.port)
    check(" 401 " in status, "upgrade without a token -> 401 at the handshake (%s)" % status)
    s.close()
    s, status, _, _ = ws_connect(srv.port, "/api/v1/ws?token=wrong")
    check(" 401 " in status, "upgrade with a wrong ?token= -> 401 (%s)" % status)
    s.close()
    s, status, _, _ = ws_connect(srv.port, headers=["Sec-WebSocket-Protocol: lucent, " + token_subprotocol("wrong")])
    check(" 401 " in status, "upgrade with a wrong token subprotocol -> 401 (%s)" % status)
    s.close()
    # Eight unauthenticated upgrades against --max-connections 8 leave room for real work.
    held = [ws_connect(srv.port)[0] for _ in range(8)]
    try:
        st, _, health = srv.json("GET", "/api/v1/health", timeout=60)
    except OSError as ex:
        st = repr(ex)
    check(st == 200, "health answers while 8 unauthenticated upgrades were tried (%s)" % st)
    try:
        st, h, body = srv.request("GET", "/api/v1/render?width=32&height=32&format=jpeg", headers=AUTH, timeout=60)
    except OSError as ex:
        st, h = repr(ex), {}
    check(st == 200 and h.get("content-type") == "image/jpeg", "authenticated render still served (%s)" % st)
    for x in held:
        x.close()

    async def ws_auth():
        for what, kw in (("Authorization header", {"extra_headers": AUTH}),
                         ("?token=", {"uri": srv.ws_url + "?token=" + TOKEN}),
                         ("subprotocol", {"subprotocols": ["lucent", token_subprotocol(TOKEN)]})):
            uri = kw.pop("uri", srv.ws_url)
            async with websockets.connect(uri, **kw) as ws:
                await ws.send(json.dumps(HELLO))
                r = json.loads(await asyncio.wait_for(ws.recv(), 60))
                check(r["type"] == "ready", "token by %s -> ready" % what)
                if what == "subprotocol":
                    check(ws.subprotocol == "lucent", "server selects 'lucent', never the token (%s)" % ws.subprotocol)
    asyncio.run(ws_auth())

    # An authenticated connection that never sends hello is closed (it holds an MHD connection).
    # The close's reason says which timer closed it: the 10 s hello timeout.
    s, status, _, rest = ws_connect(srv.port, headers=["Authorization: Bearer " + TOKEN])
    responsive(srv, "an authenticated connection without hello", AUTH, abuser=s)
    s.settimeout(120)
    t0 = time.monotonic()
    rd = FrameReader(s, rest)
    code, _ = rd.until_close()
    check(code == 1008 and rd.reason == "no hello", "no hello within 10 s -> close 1008 \"no hello\" (%s %r after "
          "%.1f s more)" % (code, rd.reason, time.monotonic() - t0))
    s.close()

    # HTTP: a POST without the token is refused before its body is read.
    c = socket.create_connection(("127.0.0.1", srv.port))
    c.settimeout(60)
    c.sendall(b"POST /api/v1/render HTTP/1.1\r\nHost: x\r\nContent-Length: 60000\r\n\r\n")
    head = c.recv(200).decode(errors="replace")
    check(head.startswith("HTTP/1.1 401"), "POST without a token -> 401 before the body (%s)" % head[:20])
    c.close()
    check(srv.stop() == 0, "clean exit")

with Server(binary) as srv:
    # ------------------------------------------------------------ finding 5: blind acks
    frames_before = metric(srv, "lucent_frames_rendered_total{kind=\"ws\"}")
    s, status, _, rest = ws_connect(srv.port, rcvbuf=4096)
    s.sendall(ws_frame(json.dumps(dict(HELLO, width=256, height=256, window=2))))
    # Blind acks until the stream has begun (a frame rendered, however long
    # that takes), then for 3 s more: the window stays shut, so a correct
    # server renders nothing more however long this goes on (the bound cannot
    # fail on a slow machine; a slow machine can only catch less).
    started, t_end = None, time.monotonic() + 120
    seq = 0
    while time.monotonic() < (t_end if started is None else started + 3.0):  # never reads
        if started is None and metric(srv, "lucent_frames_rendered_total{kind=\"ws\"}") > frames_before:
            started = time.monotonic()
        seq += 1
        s.sendall(ws_frame(json.dumps({"type": "camera", "seq": seq, "camera": {"position": [0.5, 0.5, 2 + seq % 7 / 10],
                                                                                 "focalPoint": [0.5, 0.5, 0.5]}})))
        s.sendall(ws_frame(json.dumps({"type": "ack", "frame": 2 ** 53 - 1})))
        time.sleep(0.02)
    rendered = metric(srv, "lucent_frames_rendered_total{kind=\"ws\"}") - frames_before
    check(started is not None and rendered <= 4, "blind acks of frame 2^53-1 do not open the window: %d frames "
          "rendered (3 s after the first)" % rendered)
    responsive(srv, "a blind-acking client")
    rd = FrameReader(s, rest)
    errs = []
    for _ in range(40):
        op, p = rd.next()
        if op == 1 and json.loads(p).get("type") == "error":
            errs.append(json.loads(p))
            break
    check(errs and errs[0]["code"] == "out_of_range" and errs[0].get("field") == "frame",
          "an ack of an unsent frame is an error naming 'frame' (%s)" % (errs[:1],))
    s.close()

    # Acks that trail the frames (guessed ids, still never reading) are valid:
    # the server stops when the socket stops taking data.
    frames_before = metric(srv, "lucent_frames_rendered_total{kind=\"ws\"}")
    bytes_before = metric(srv, "lucent_bytes_sent_total")
    s, status, _, rest = ws_connect(srv.port, rcvbuf=4096)
    s.sendall(ws_frame(json.dumps(dict(HELLO, width=512, height=512, window=2, quality=100, interactiveQuality=100,
                                       interactiveScale=1, style={"pointSize": 6}))))  # ~250 KB frames
    # As above: from the first frame rendered on, 4 s of input and trailing acks.
    started, t_end = None, time.monotonic() + 120
    seq = 0
    while time.monotonic() < (t_end if started is None else started + 4.0):
        if started is None and metric(srv, "lucent_frames_rendered_total{kind=\"ws\"}") > frames_before:
            started = time.monotonic()
        seq += 1
        s.sendall(ws_frame(json.dumps({"type": "camera", "seq": seq, "camera": {"position": [0.5, 0.5, 2 + seq % 7 / 10],
                                                                                 "focalPoint": [0.5, 0.5, 0.5]}})))
        s.sendall(ws_frame(json.dumps({"type": "ack", "frame": seq // 3})))
        time.sleep(0.02)
    rendered = metric(srv, "lucent_frames_rendered_total{kind=\"ws\"}") - frames_before
    queued = metric(srv, "lucent_bytes_sent_total") - bytes_before
    check(started is not None and rendered <= 8 and queued < 2e6, "trailing acks without reading: %d frames, %.2f MB "
          "queued in 4 s after the first (bounded by the socket buffers; before: 30 frames, 7.6 MB)"
          % (rendered, queued / 1e6))
    responsive(srv, "a client that acks but never reads")
    s.close()

    # ------------------------------------------------------------ finding 8: the minor ones
    c = socket.create_connection(("127.0.0.1", srv.port))
    c.settimeout(60)
    c.sendall(b"GET /\xff\xfe/x HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n")
    data = b""
    while True:
        d = c.recv(4096)
        if not d:
            break
        data += d
    c.close()
    body = data.partition(b"\r\n\r\n")[2]
    try:
        err = json.loads(body)["error"]
    except ValueError:
        err = {}
    check(data.startswith(b"HTTP/1.1 404") and "message" in err and err["message"].startswith("no such page"),
          "404 for an invalid-UTF-8 path carries a message (%s)" % err)

    c = socket.create_connection(("127.0.0.1", srv.port))
    c.settimeout(60)
    body = json.dumps({"width": 32, "height": 32}).encode()
    c.sendall(b"POST /api/v1/render HTTP/1.1\r\nHost: x\r\nContent-Length: %d\r\nContent-Length: 5\r\n\r\n%s"
              % (len(body), body))
    head = c.recv(400).decode(errors="replace")
    check(head.startswith("HTTP/1.1 400") and "Content-Length" in head, "two Content-Length headers -> 400 (%s)" %
          head.split("\r\n")[0])
    c.close()

    q = "&".join("_k%d=1" % i for i in range(1000))
    # "At once": refused before anything is rendered for it (the render counter stays).
    before = renders_total(srv)
    st, _, e = srv.json("GET", "/api/v1/render?" + q)
    check(st == 414 and e["error"]["field"] == "query" and renders_total(srv) == before,
          "1000 query parameters -> 414 at once, nothing rendered (%d; %d renders)" % (st, renders_total(srv) - before))
    st, _, _ = srv.request("GET", "/api/v1/render?width=32&height=32&" + "&".join("_k%d=1" % i for i in range(200)))
    check(st == 200, "200 ignored parameters are still fine (%d)" % st)

    http_rendered = metric(srv, "lucent_frames_rendered_total{kind=\"http\"}")
    st, h, _ = srv.request("HEAD", "/api/v1/render?width=64&height=64")
    check(st == 405 and "GET" in h.get("allow", ""), "HEAD on render -> 405 (%d, Allow %s)" % (st, h.get("allow")))
    check(metric(srv, "lucent_frames_rendered_total{kind=\"http\"}") == http_rendered, "HEAD rendered nothing")

    s, status, _, rest = ws_connect(srv.port)
    s.sendall(ws_frame("x" * 100000))
    code, _ = FrameReader(s, rest).until_close()
    check(code == 1009, "a message over --max-ws-message -> close frame 1009, not a reset (%s)" % code)
    s.close()

    floods = []
    for _ in range(4):  # held connections each parked mid-request with 1000 parameters
        f = socket.create_connection(("127.0.0.1", srv.port))
        f.sendall(("GET /api/v1/render?%s HTTP/1.1\r\nHost: x\r\n\r\n" % q).encode())
        floods.append(f)
    responsive(srv, "four 1000-parameter requests")
    for f in floods:
        f.close()

    s, status, _, rest = ws_connect(srv.port)
    for i in range(40):
        s.sendall(ws_frame(json.dumps({"type": "camera", "seq": i + 1, "camera": {"position": [0, 0, 3]}})))
    code, texts = FrameReader(s, rest).until_close()
    check(code == 1008 and any(t.get("code") == "too_many_errors" for t in texts),
          "40 valid messages before hello trip the error limit (close %s)" % code)
    s.close()

    for cam, field in (({"position": [1e308, 0, 0], "focalPoint": [0, 0, 0]}, "camera.position"),
                       ({"position": [0, 0, 3], "focalPoint": [-1e308, 0, 0]}, "camera.focalPoint"),
                       ({"position": [0, 0, 3], "viewUp": [0, 1e308, 0]}, "camera.viewUp")):
        st, _, e = srv.json("POST", "/api/v1/render", {"width": 32, "height": 32, "camera": cam})
        check(st == 400 and e["error"]["code"] == "out_of_range" and e["error"]["field"] == field,
              "camera %s -> 400 out_of_range naming %s (%s)" % (cam, field, e["error"]))

    st, _, health = srv.json("GET", "/api/v1/health")
    check(st == 200 and health["status"] == "ok", "daemon healthy after the abuse")
    check(srv.stop() == 0, "clean exit")

# ---------------------------------------------------------------- issue 32: slow connections
# 300 connections from this address that send one header line every 2 s and
# never finish it; health (a fresh connection from the same address) must be
# answered throughout (before the fix every probe timed out: the slow ones
# held every connection slot). The hold lasts LUCENT_ABUSE_HOLD seconds (10
# in the suite, 60 for the full measurement) and until 2 probes per
# second of it were answered, so a slow client loop takes longer rather than
# probing less. The latency bound (100 ms) is a performance figure
# that a loaded CI machine cannot promise: the probes' latencies are printed
# (median, 95th percentile, worst) for a person or a benchmark to judge, and
# the test checks what is a state: every probe answered, the slow connections
# closed by the server and counted.
HOLD = float(os.environ.get("LUCENT_ABUSE_HOLD", "10"))
PROBE_TIMEOUT = 60  # bounds a server that does not answer at all


def slow_open(port):
    s = socket.socket()
    s.setblocking(False)
    s.connect_ex(("127.0.0.1", port))
    return [s, False]  # socket, request line sent


with Server(binary, env={"LUCENT_TOKEN": TOKEN}) as srv:
    slow = [slow_open(srv.port) for _ in range(300)]
    latencies, failures, reopened = [], [], 0
    t_end = time.monotonic() + HOLD
    limit = t_end + 300
    next_line = 0.0
    while (time.monotonic() < t_end or len(latencies) < HOLD * 2 or not reopened) and time.monotonic() < limit:
        if time.monotonic() >= next_line:  # one more header line on every slow connection
            next_line = time.monotonic() + 2.0
            for entry in slow:
                try:
                    entry[0].send(b"X-Slow: 1\r\n" if entry[1] else b"GET /api/v1/health HTTP/1.1\r\nHost: x\r\n")
                    entry[1] = True
                except BlockingIOError:
                    pass
                except OSError:  # closed by the server: the attacker comes back at once
                    entry[0].close()
                    entry[:] = slow_open(srv.port)
                    reopened += 1
        t0 = time.monotonic()
        try:
            st, _, _ = srv.request("GET", "/api/v1/health", timeout=PROBE_TIMEOUT)
        except OSError as ex:
            st = repr(ex)
        dt = time.monotonic() - t0
        latencies.append(dt)
        if st != 200:
            failures.append(st)
        time.sleep(0.2)  # paces the probes; nothing waits on it
    for entry in slow:
        entry[0].close()
    latencies.sort()
    worst = latencies[-1] if latencies else float("inf")
    p95 = latencies[int(0.95 * (len(latencies) - 1))] if latencies else float("inf")
    print("health probe latencies while 300 slow connections were held (the issue's bound: 100 ms; not checked, "
          "see above): median %.1f ms, 95th percentile %.1f ms, worst %.1f ms" %
          (1e3 * latencies[len(latencies) // 2] if latencies else float("inf"), 1e3 * p95, 1e3 * worst))
    check(not failures and len(latencies) >= HOLD * 2,
          "300 slow connections held %.0f s (%d reopened after the server closed them): %d health probes, "
          "every one answered (failures %s)" % (HOLD, reopened, len(latencies), failures[:3]))
    st, _, _ = srv.request("GET", "/api/v1/render?width=32&height=32&format=jpeg", headers=AUTH, timeout=60)
    check(st == 200, "an authenticated render still answers afterwards (%s)" % st)
    closed = metric(srv, "lucent_http_unfinished_closed_total")
    check(closed >= reopened > 0, "/metrics counts the connections closed unfinished: %d (%d seen here)" %
          (closed, reopened))

check.done()
