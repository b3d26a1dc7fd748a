"""A WebSocket session (protocol/websocket.md) with a blocking API: camera
moves and parameter updates in, frames out as arrays, converged stills. The
server keeps the session's opacities, which fade from frame to frame, so a
sequence of cameras gives frame-coherent images.

Debian 12's python3-websockets (10.x) is asyncio-only: the session runs its
own event loop on a thread, so it works the same in scripts and in Jupyter
(whose kernel already runs a loop on the main thread)."""
import asyncio
import base64
import json
import struct
import threading

from .images import decode_image
from .schema import LucentError

STREAM_KEYS = ("quality", "interactiveQuality", "interactiveScale")


class Frame:
    """One frame message: header (dict: frame, width, height, cameraSeq,
    converged, timings, detail, ...) and the encoded image."""

    def __init__(self, header, data):
        self.header = header
        self.data = data

    @property
    def converged(self):
        return bool(self.header.get("converged"))

    @property
    def interactive(self):
        return bool(self.header.get("detail", {}).get("interactive"))

    def array(self):
        return decode_image(self.data)

    def pil(self):
        return decode_image(self.data, "pil")


class Session:
    """Opened by Client.session(dataset, size=(w, h), camera=..., params=...,
    window=..., quality=...). Use as a context manager or call close()."""

    def __init__(self, client, dataset=None, size=(640, 480), window=None, timeout=120, **request):
        self.client = client
        self.timeout = timeout
        self.seq = 0
        self.stats = None  # the last `stats` message
        self.last = None   # the last Frame received
        self._dirty = True  # input sent since the last settled frame
        hello = {"type": "hello", "width": int(size[0]), "height": int(size[1])}
        if window is not None:  # a ceiling; without one the server covers the round trip (up to 8 frames)
            hello["window"] = window
        if dataset is not None:
            hello["dataset"] = dataset
        self._check_update(request, allow_camera=True)
        hello.update(request)
        self._loop = asyncio.new_event_loop()
        self._thread = threading.Thread(target=self._loop.run_forever, name="lucent-session", daemon=True)
        self._thread.start()
        try:
            self.ready = self._call(self._open(hello))
        except BaseException:
            self._stop_loop()
            raise
        self.session_id = self.ready.get("session")
        self.defaults = self.ready.get("defaults")

    # ---- plumbing

    def _call(self, coro, timeout=None):
        return asyncio.run_coroutine_threadsafe(coro, self._loop).result(timeout)

    def _check_update(self, fields, allow_camera=False):
        schema = self.client.schema()
        req = {k: v for k, v in fields.items() if k not in STREAM_KEYS}
        if not allow_camera and "camera" in req:
            raise LucentError("unknown_field", "camera: use Session.camera() to move the camera", "camera")
        schema.validate(req)
        for k in STREAM_KEYS:
            if k in fields:
                v = fields[k]
                ok = isinstance(v, (int, float)) and not isinstance(v, bool)
                ok = ok and (0.25 <= v <= 1 if k == "interactiveScale" else 1 <= v <= 100)
                if not ok:
                    raise LucentError("out_of_range", "%s: %r is out of range" % (k, v), k)

    async def _open(self, hello):
        import websockets
        url = self.client.url.replace("http://", "ws://", 1).replace("https://", "wss://", 1) + "/api/v1/ws"
        protocols = ["lucent"]
        if self.client.token:
            b = base64.urlsafe_b64encode(self.client.token.encode()).decode().rstrip("=")
            protocols.append("lucent.token." + b)
        try:
            self._ws = await websockets.connect(url, subprotocols=protocols, max_size=None, open_timeout=self.timeout)
        except Exception as e:  # refused handshake (401), unreachable server
            raise LucentError("unreachable", "%s: %s" % (url, e)) from None
        await self._ws.send(json.dumps(hello))
        while True:
            msg = await asyncio.wait_for(self._ws.recv(), self.timeout)
            if isinstance(msg, str):
                m = json.loads(msg)
                if m.get("type") == "ready":
                    return m
                if m.get("type") == "error":
                    await self._ws.close()
                    raise LucentError(m.get("code"), m.get("message"), m.get("field"))

    async def _send(self, obj):
        await self._ws.send(json.dumps(obj))

    async def _next(self, timeout):
        while True:
            msg = await asyncio.wait_for(self._ws.recv(), timeout)
            if isinstance(msg, str):
                m = json.loads(msg)
                if m.get("type") == "stats":
                    self.stats = m
                elif m.get("type") == "error":
                    raise LucentError(m.get("code"), m.get("message"), m.get("field"))
                continue
            n = struct.unpack("<I", msg[:4])[0]
            if n > len(msg) - 4:
                raise LucentError("bad_frame", "frame header longer than the message")
            header = json.loads(msg[4:4 + n].decode())
            await self._send({"type": "ack", "frame": header["frame"]})
            return Frame(header, bytes(msg[4 + n:]))

    # ---- API

    def camera(self, camera):
        """Moves the camera (a dict with the request's camera keys; None = fit
        the data again). Returns the move's sequence number."""
        if camera is not None:
            self.client.schema().validate({"camera": camera})
        self.seq += 1
        self._dirty = True
        self._call(self._send({"type": "camera", "seq": self.seq, "camera": camera}))
        return self.seq

    def update(self, **fields):
        """Changes parameters: params=..., style=..., color=..., importance=...,
        method=..., quality=..., interactiveQuality=..., interactiveScale=..."""
        self._check_update(fields)
        self._dirty = True
        self._call(self._send(dict(fields, type="params")))

    def resize(self, width, height):
        self._dirty = True
        self._call(self._send({"type": "resize", "width": int(width), "height": int(height)}))

    def next_frame(self, timeout=None):
        """The next frame the server sends (acknowledged); raises TimeoutError
        when none comes within timeout (a converged session sends nothing
        until the next input)."""
        try:
            self.last = self._call(self._next(timeout or self.timeout))
        except asyncio.TimeoutError:
            raise TimeoutError("no frame within %s s" % (timeout or self.timeout)) from None
        return self.last

    def frame(self, timeout=None):
        """The next frame as a numpy array (H, W, 3)."""
        return self.next_frame(timeout).array()

    def still(self, camera=..., timeout=None):
        """Moves the camera when one is given, then waits for the converged
        full-resolution frame of the latest move (opacities done fading) and
        returns it as an array. The previous converged frame is returned at once
        when nothing changed since it."""
        if camera is not ...:
            self.camera(camera)
        if not self._dirty and self.last is not None and self._settled(self.last):
            return self.last.array()
        while True:
            f = self.next_frame(timeout)
            if self._settled(f):
                self._dirty = False
                return f.array()

    def _settled(self, f):
        # A staged still's earlier stages are not the still (header "final": false).
        return (f.converged and not f.interactive and f.header.get("final", True) is not False
                and f.header.get("cameraSeq", 0) >= self.seq)

    def frames(self, cameras, timeout=None, full=True):
        """One frame per camera, in order: each camera is sent and the first
        frame that reflects it is returned (fading carries over from frame to
        frame, as in the browser). With full (the default) that is the first
        full-resolution frame of the camera: frames rendered while input is
        active may be smaller (the server's frame budget), the one that
        follows ~150 ms of quiet is not. A generator of numpy arrays."""
        for cam in cameras:
            seq = self.camera(cam)
            while True:
                f = self.next_frame(timeout)
                if f.header.get("cameraSeq", 0) >= seq and not (full and f.interactive):
                    yield f.array()
                    break

    def close(self):
        if getattr(self, "_ws", None) is not None:
            try:
                self._call(self._ws.close(), 10)
            except Exception:  # noqa: BLE001 (closing a broken socket)
                pass
            self._ws = None
        self._stop_loop()

    def _stop_loop(self):
        if self._loop.is_running():
            self._loop.call_soon_threadsafe(self._loop.stop)
            self._thread.join(10)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
