"""Helpers for the server integration tests: start the real daemon on a free
loopback port, talk HTTP with urllib/http.client, read frame messages and image
sizes. Standard library plus Debian's python3-websockets only."""
import base64
import ctypes
import http.client
import json
import os
import re
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time
import zlib

SKIP = 77  # ctest SKIP_RETURN_CODE


def skip(reason):
    print("SKIP: " + reason)
    sys.exit(SKIP)


try:
    import websockets  # noqa: F401  (python3-websockets)
except ImportError:  # pragma: no cover
    websockets = None


def foreign_leaks_only(text, binary):
    """True when text (a process's output) holds a LeakSanitizer report (and
    no other sanitizer error) in which no leaked block has a frame in lucent's
    own code (its binary or its source tree): the GL driver (Mesa, LLVM) keeps
    allocations for the life of the process, sometimes from modules that are
    already unloaded (<unknown module>)."""
    if "ERROR: LeakSanitizer" not in text or "ERROR: AddressSanitizer" in text or "runtime error:" in text:
        return False
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    binary = os.path.abspath(binary)
    blocks = text.split("leak of")[1:]
    for b in blocks:
        frames = re.findall(r"#(\d+) 0x[0-9a-f]+ +(.*)", b.split("\n\n")[0])
        for num, where in frames:
            if num != "0" and (root + os.sep in where or binary in where):
                return False
    return bool(blocks)


class Server:
    """`lucent serve --listen 127.0.0.1:0 ...`; the port comes from the log line
    "listening on http://127.0.0.1:PORT/"."""

    def __init__(self, binary, *args, env=None, data=("demo:points",), demo_size=3000, timeout=90):
        self.binary = binary
        cmd = [binary, "serve", "--listen", "127.0.0.1:0"]
        for d in data:
            cmd += ["--data", d]
        if demo_size:
            cmd += ["--demo-size", str(demo_size)]
        cmd += ["--cache", "off"]  # no scene cache in $HOME from tests; a test's own --cache comes later and wins
        cmd += list(args)
        e = dict(os.environ)
        e.pop("LUCENT_TOKEN", None)
        # A private TMPDIR (unless the test gives one), removed once the daemon
        # has exited: a daemon the test kills leaves its movie files there,
        # not in /tmp.
        self._tmp = None
        if not (env and "TMPDIR" in env):
            self._tmp = e["TMPDIR"] = tempfile.mkdtemp(prefix="lucent-server-")
        if env:
            e.update(env)
        self.log = []
        self.proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                     stderr=subprocess.STDOUT, env=e, text=True)
        self._port = None
        self._ready = threading.Event()
        self._drainer = threading.Thread(target=self._drain, daemon=True)
        self._drainer.start()
        if not self._ready.wait(timeout) or self._port is None:
            self.proc.kill()
            self.proc.wait()
            self._remove_tmp()
            text = "\n".join(self.log)
            if re.search(r"EGL|OpenGL 4\.5|GL 4\.5", text):
                skip("no usable EGL/OpenGL 4.5 here:\n" + text)
            raise RuntimeError("server did not start:\n" + text)
        self.port = self._port
        self.host = "127.0.0.1"
        self.base = "http://127.0.0.1:%d" % self.port
        self.ws_url = "ws://127.0.0.1:%d/api/v1/ws" % self.port

    def _drain(self):
        for line in self.proc.stdout:
            line = line.rstrip("\n")
            self.log.append(line)
            if os.environ.get("LUCENT_TEST_VERBOSE"):
                print("  | " + line, flush=True)
            m = re.search(r"listening on http://127\.0\.0\.1:(\d+)/", line)
            if m and self._port is None:
                self._port = int(m.group(1))
                self._ready.set()
        self._ready.set()

    def request(self, method, path, body=None, headers=None, timeout=60):
        """Returns (status, headers dict with lower-case names, body bytes)."""
        conn = http.client.HTTPConnection(self.host, self.port, timeout=timeout)
        if isinstance(body, (dict, list)):
            body = json.dumps(body)
        if isinstance(body, str):
            body = body.encode()
        conn.request(method, path, body=body, headers=headers or {})
        r = conn.getresponse()
        data = r.read()
        hdrs = {k.lower(): v for k, v in r.getheaders()}
        conn.close()
        return r.status, hdrs, data

    def json(self, method, path, body=None, headers=None, timeout=60):
        status, hdrs, data = self.request(method, path, body, headers, timeout)
        return status, hdrs, json.loads(data) if data else None

    def rss_kb(self):
        with open("/proc/%d/status" % self.proc.pid) as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
        return 0

    def memory_map(self, n=6):
        """Where the daemon's resident memory lies, for a failure's message:
        the n largest mappings by resident size (path, or [anon]/[heap]) in MB,
        so that a held texture (one large anonymous mapping) reads apart from a
        heap that was not given back (many arenas)."""
        maps = []
        with open("/proc/%d/smaps" % self.proc.pid) as f:
            for line in f:
                head = line.split()
                if head and "-" in head[0] and not head[0].endswith(":"):
                    maps.append([head[5] if len(head) > 5 else "[anon]", 0])
                elif head and head[0] == "Rss:" and maps:
                    maps[-1][1] = int(head[1])
        maps.sort(key=lambda m: -m[1])
        return ", ".join("%s %.0f MB" % (name.rsplit("/", 1)[-1], kb / 1024.0) for name, kb in maps[:n])

    def open_files(self):
        """The paths of the daemon's open descriptors. The daemon opens and
        closes files meanwhile: a descriptor gone between the listing and
        its readlink is skipped, not an error."""
        fd_dir = "/proc/%d/fd" % self.proc.pid
        paths = []
        for fd in os.listdir(fd_dir):
            try:
                paths.append(os.readlink(os.path.join(fd_dir, fd)))
            except FileNotFoundError:
                pass
        return paths

    def stop(self, sig=signal.SIGTERM, timeout=60, main_thread=False):
        """Signals the daemon and returns its exit status. main_thread: to
        its main thread (tgkill), as a fault is delivered to the thread that
        faulted; a kill() goes to any thread that does not block the signal."""
        if self.proc.poll() is None and main_thread:
            if ctypes.CDLL(None, use_errno=True).tgkill(self.proc.pid, self.proc.pid, int(sig)) != 0:
                raise OSError(ctypes.get_errno(), "tgkill")
        elif self.proc.poll() is None:
            self.proc.send_signal(sig)
        try:
            rc = self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
            raise AssertionError("server did not exit within %d s after signal %d" % (timeout, sig))
        self._drainer.join(timeout)  # the log's last lines: the pipe closes when the daemon has exited
        self._remove_tmp()
        if rc != 0 and self.only_foreign_leaks():
            print("note: LeakSanitizer found only leaks inside the GL driver (Mesa/LLVM); "
                  "`lucent render` shows the same ones, so they are not the server's")
            return 0
        if rc != 0:
            print("daemon exited %d; the end of its log:" % rc)
            for line in self.log[-60:]:
                print("  | " + line)
        return rc

    def only_foreign_leaks(self):
        """True when the daemon's log holds only leaks inside the GL driver
        (foreign_leaks_only)."""
        return foreign_leaks_only("\n".join(self.log), self.binary)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()
        self._remove_tmp()

    def _remove_tmp(self):
        if self._tmp:
            shutil.rmtree(self._tmp, ignore_errors=True)
            self._tmp = None


def served_name(dataset):
    """The name `serve --data` serves a dataset under: a file path under its stem, anything else as given."""
    if os.path.exists(dataset):
        return os.path.splitext(os.path.basename(dataset.rstrip("/")))[0]
    return dataset


def sanitized(binary):
    """True for a binary built with AddressSanitizer (scripts/test.sh's second
    build): its shadow memory and quarantine make resident sizes and CPU times
    say nothing about lucent's own, so tests skip bounds on those there."""
    with open(binary, "rb") as f:
        return b"__asan_init" in f.read()


def decode_png(data):
    """8-bit RGB/RGBA PNG -> (w, h, channels, rows of bytes), filters undone."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    i, idat, w = 8, b"", 0
    while i < len(data):
        n, kind = struct.unpack(">I4s", data[i:i + 8])
        body = data[i + 8:i + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and ctype in (2, 6), "PNG type %d depth %d" % (ctype, depth)
            ch = 3 if ctype == 2 else 4
        elif kind == b"IDAT":
            idat += body
        i += 12 + n
    raw, rows, stride, prev = zlib.decompress(idat), [], w * ch, bytearray(w * ch)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - ch] if x >= ch else 0
            b, c = prev[x], prev[x - ch] if x >= ch else 0
            p = {0: 0, 1: a, 2: b, 3: (a + b) // 2}.get(f)
            if p is None:  # Paeth
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                p = a if pa <= pb and pa <= pc else b if pb <= pc else c
            line[x] = (line[x] + p) & 255
        rows.append(bytes(line))
        prev = line
    return w, h, ch, rows


def jpeg_size(data):
    """(width, height) from a JPEG's SOF marker; raises if not a JPEG."""
    assert data[:2] == b"\xff\xd8", "not a JPEG (no SOI marker)"
    i = 2
    while i + 4 <= len(data):
        assert data[i] == 0xFF, "bad JPEG marker at %d" % i
        marker = data[i + 1]
        if marker == 0xFF:
            i += 1
            continue
        length = struct.unpack(">H", data[i + 2:i + 4])[0]
        if marker in (0xC0, 0xC1, 0xC2, 0xC3, 0xC5, 0xC6, 0xC7, 0xC9, 0xCA, 0xCB, 0xCD, 0xCE, 0xCF):
            h, w = struct.unpack(">HH", data[i + 5:i + 9])
            assert data[-2:] == b"\xff\xd9", "JPEG without EOI marker"
            return w, h
        i += 2 + length
    raise AssertionError("JPEG without SOF marker")


def png_size(data):
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    w, h = struct.unpack(">II", data[16:24])
    return w, h


def ssim(binary, a, b):
    """`lucent ssim` of two encoded images (bytes); -1 when it cannot tell."""
    import tempfile
    with tempfile.TemporaryDirectory() as d:
        pa, pb = os.path.join(d, "a.img"), os.path.join(d, "b.img")
        with open(pa, "wb") as f:
            f.write(a)
        with open(pb, "wb") as f:
            f.write(b)
        out = subprocess.run([binary, "ssim", pa, pb], capture_output=True, text=True).stdout.split()
    return float(out[1]) if len(out) > 1 and out[0].lower() == "ssim" else -1.0


def unpack_frame(msg):
    """Binary frame message: uint32 LE header length N, N bytes JSON header, image."""
    assert isinstance(msg, (bytes, bytearray)), "expected a binary frame, got %r" % (msg,)
    n = struct.unpack("<I", msg[:4])[0]
    header = json.loads(msg[4:4 + n].decode())
    return header, bytes(msg[4 + n:])


def ws_connect(port, path="/api/v1/ws", headers=(), rcvbuf=None):
    """Handshake by hand; returns (socket, status line, headers text, bytes after the header)."""
    s = socket.socket()
    if rcvbuf:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, rcvbuf)
    s.connect(("127.0.0.1", port))
    s.settimeout(60)
    key = base64.b64encode(os.urandom(16)).decode()
    req = ("GET %s HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
           "Sec-WebSocket-Key: %s\r\nSec-WebSocket-Version: 13\r\n" % (path, key))
    for h in headers:
        req += h + "\r\n"
    s.sendall((req + "\r\n").encode())
    buf = b""
    while b"\r\n\r\n" not in buf:
        d = s.recv(4096)
        if not d:
            break
        buf += d
    head, _, rest = buf.partition(b"\r\n\r\n")
    text = head.decode(errors="replace")
    return s, text.split("\r\n")[0], text, rest


# ---------------------------------------------------------------- waiting for states
#
# Tests wait for a STATE (a frame with a given property, a message, a status
# field), each with a generous deadline, never for a fixed time: CI runs on
# small machines that are sometimes busy, and a sanitizer build is several
# times slower. The deadlines only bound a test that would otherwise hang.

DEADLINE = 120  # seconds: the default bound of a wait for a state


def interactive(header):
    """A frame rendered while input was active (its header's detail.interactive)."""
    return bool((header.get("detail") or {}).get("interactive"))


def stream_done(m):
    """True for the frame after which a session sends nothing more without
    input (protocol/websocket.md): converged, not an interactive frame (a still
    follows those, converged or not: moving frames that reuse opacities report
    converged) and not a stage before the last of a staged still (stage 1 reuses
    opacities, so it reports converged too). Takes a message as returned by
    next_message (a frame is its header with "type": "frame")."""
    return (m.get("type") == "frame" and m.get("converged") is True and not interactive(m)
            and m.get("final", True) is not False)


async def next_message(ws, timeout, ack=True):
    """The next message within timeout seconds, or None: a text message as
    its parsed object, a binary frame as its header plus "type": "frame" and
    "image" (the image bytes). Frames are acknowledged unless ack is false."""
    import asyncio
    try:
        m = await asyncio.wait_for(ws.recv(), timeout)
    except asyncio.TimeoutError:
        return None
    if isinstance(m, str):
        return json.loads(m)
    h, img = unpack_frame(m)
    if ack:
        await ws.send(json.dumps({"type": "ack", "frame": h["frame"]}))
    return dict(h, type="frame", image=img)


class Received(list):
    """The messages a wait received; reached says whether the state came
    (then it is the last of them) before the deadline."""
    reached = False


async def wait_for_message(ws, done, deadline=DEADLINE, ack=True, skip=("stats",)):
    """Receives messages (next_message) until done(message) holds for one,
    or deadline seconds pass. Returns them as a Received list, the one that
    satisfied done last (reached true); messages whose type is in skip are
    neither kept nor tested (stats come about once a second while frames
    flow)."""
    got = Received()
    end = time.monotonic() + deadline
    while True:
        left = end - time.monotonic()
        if left <= 0:
            return got
        m = await next_message(ws, left, ack)
        if m is None:
            return got
        if m.get("type") in skip:
            continue
        got.append(m)
        if done(m):
            got.reached = True
            return got


async def wait_for_frame(ws, predicate=lambda h: True, deadline=DEADLINE, ack=True, skip=("stats",)):
    """wait_for_message for a frame whose header satisfies predicate."""
    return await wait_for_message(ws, lambda m: m.get("type") == "frame" and predicate(m), deadline, ack, skip)


async def wait_for_stream_done(ws, predicate=lambda h: True, deadline=DEADLINE, ack=True, skip=("stats",)):
    """wait_for_message until the stream ends (stream_done) with a frame that
    also satisfies predicate (e.g. the camera seq it must reflect)."""
    return await wait_for_message(ws, lambda m: stream_done(m) and predicate(m), deadline, ack, skip)


async def listen(ws, seconds, ack=True, skip=("stats",)):
    """Every message (next_message) that arrives within `seconds`. Only for
    checking that NOTHING more comes once a state has been reached (e.g. no
    frame after the stream ended): a correct server sends nothing then, so
    such a check cannot fail because the machine is slow."""
    return list(await wait_for_message(ws, lambda m: False, seconds, ack, skip))


def wait_until(probe, deadline=60, interval=0.1):
    """Calls probe() until it returns a true value (returned) or deadline
    seconds pass (its last value is returned): for states read over HTTP or
    from /proc."""
    end = time.monotonic() + deadline
    while True:
        v = probe()
        if v or time.monotonic() > end:
            return v
        time.sleep(interval)


class Check:
    """Counts failed expectations so that one run reports all of them."""

    def __init__(self):
        self.failures = 0
        self.count = 0

    def __call__(self, cond, what):
        self.count += 1
        print(("ok   " if cond else "FAIL ") + what, flush=True)
        if not cond:
            self.failures += 1
        return cond

    def done(self):
        print("%d checks, %d failed" % (self.count, self.failures))
        sys.exit(1 if self.failures else 0)
