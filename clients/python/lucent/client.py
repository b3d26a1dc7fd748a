"""HTTP client of a Lucent daemon (standard library urllib; numpy and Pillow
for images): datasets, one-shot renders as arrays, sessions over the
WebSocket, and movie jobs."""
import json
import time
import urllib.error
import urllib.parse
import urllib.request
import warnings

from . import camera as cameras
from .images import decode_image
from .schema import SECTIONS, LucentError, Schema


class LucentWarning(UserWarning):
    """The server rendered the request but says the picture may not show what
    was asked (header X-Lucent-Warning), e.g. the important end of the
    colormap in the background's colour."""

FORMATS = ("array", "pil", "png", "jpeg")


def build_request(dataset=None, camera=None, params=None, size=None, importance=None, color=None, style=None,
                  **fields):
    """A render request dict from keyword arguments that mirror its fields:
    size=(width, height), the sections as dicts, any top-level field by name
    (method="exact", quality=80, width=..., height=...)."""
    req = {}
    if dataset is not None:
        req["dataset"] = dataset
    if size is not None:
        if not isinstance(size, (list, tuple)) or len(size) != 2:
            raise LucentError("bad_field", "size: expected (width, height)", "size")
        req["width"], req["height"] = size
    for name, value in (("camera", camera), ("params", params), ("importance", importance), ("color", color),
                        ("style", style)):
        if value is not None:
            req[name] = dict(value) if isinstance(value, dict) else value
    req.update(fields)
    return req


class Client:
    """A Lucent daemon at url (http://host:port), with the bearer token when it
    runs with --token. Every request is checked against the server's schema
    (GET /api/v1/schema, fetched once) before it is sent, so unknown or
    out-of-range fields raise LucentError naming the field without a round
    trip; errors of the server raise LucentError with its code, field and text."""

    def __init__(self, url="http://127.0.0.1:8080", token=None, timeout=300):
        self.url = url.rstrip("/")
        self.token = token
        self.timeout = timeout
        self._schema = None

    # ---- HTTP

    def _open(self, method, path, body=None, timeout=None):
        data = None
        headers = {}
        if body is not None:
            data = json.dumps(body).encode()
            headers["Content-Type"] = "application/json"
        if self.token:
            headers["Authorization"] = "Bearer " + self.token
        req = urllib.request.Request(self.url + path, data=data, headers=headers, method=method)
        try:
            return urllib.request.urlopen(req, timeout=timeout or self.timeout)
        except urllib.error.HTTPError as e:
            raise _server_error(e) from None
        except urllib.error.URLError as e:
            raise LucentError("unreachable", "%s: %s" % (self.url, e.reason)) from None

    def _json(self, method, path, body=None):
        with self._open(method, path, body) as r:
            return json.loads(r.read() or b"null")

    def _bytes(self, method, path, body=None):
        with self._open(method, path, body) as r:
            return r.read(), {k.lower(): v for k, v in r.getheaders()}

    # ---- reference data

    def health(self):
        return self._json("GET", "/api/v1/health")

    def schema(self):
        """The server's request schema (a Schema), fetched once."""
        if self._schema is None:
            self._schema = Schema(self._json("GET", "/api/v1/schema"))
        return self._schema

    def datasets(self):
        """The served datasets: a list of dicts (name, counts, bounds, attributes)."""
        return self._json("GET", "/api/v1/datasets")["datasets"]

    def dataset(self, name):
        return self._json("GET", "/api/v1/datasets/" + urllib.parse.quote(name, safe=":"))

    def validate(self, req):
        """Raises LucentError naming the first field the server would refuse."""
        return self.schema().validate(req)

    # ---- cameras

    def fit(self, dataset, direction=None, up=None, camera=None):
        """The camera the server uses when a request has none: the dataset's
        suggested view (if it has one) or -Z with +Y up, fitted to its bounds."""
        d = self.dataset(dataset)
        view = d.get("view") or {}
        return cameras.fit(d["bounds"], direction or view.get("direction", (0, 0, -1)),
                           up or view.get("up", (0, 1, 0)), camera=camera)

    def from_url(self, state):
        """(dataset, camera, update) from the web page's URL state, with the
        server's own flat aliases."""
        aliases = {f["alias"]: (f["section"], f["name"]) for f in self.schema().fields}
        return cameras.from_url(state, aliases)

    # ---- renders

    def render(self, dataset=None, camera=None, params=None, size=None, format="array", **fields):
        """Renders one image (POST /api/v1/render). Keyword arguments mirror
        the request: camera, params, importance, color, style dicts; size=(w,
        h); method, quality, ... format: "array" (numpy (H, W, 3) uint8, the
        default), "pil" (PIL image), "png" or "jpeg" (the encoded bytes)."""
        if format not in FORMATS:
            raise LucentError("bad_field", "format: %r is not one of %s" % (format, ", ".join(FORMATS)), "format")
        req = build_request(dataset, camera, params, size, **fields)
        req["format"] = "jpeg" if format == "jpeg" else "png"
        self.validate(req)
        data, headers = self._bytes("POST", "/api/v1/render", req)
        if headers.get("x-lucent-warning"):  # e.g. the colormap's highest values lost in the background
            warnings.warn(headers["x-lucent-warning"], LucentWarning, stacklevel=2)
        if format in ("png", "jpeg"):
            return data
        return decode_image(data, format)

    def session(self, dataset=None, size=(640, 480), **request):
        """A frame-coherent session over the WebSocket (see Session)."""
        from .session import Session
        return Session(self, dataset, size, **request)

    # ---- movies

    def movie(self, dataset=None, out=None, path="turntable", keyframes=None, camera=None, duration=10.0, fps=30,
              size=(960, 540), codec="h264", params=None, wait=True, progress=None, poll=0.5, frames=None,
              degrees=None, elevation=None, **fields):
        """Renders a movie on the server (POST /api/v1/movies) and, with wait
        (the default), waits for it and writes the file to `out` (default
        movie.mp4 / movie.webm); returns out. Without wait returns the job's
        status dict (id, state, progress). path: "turntable" (about the
        camera's view-up, starting at `camera` or the server's fit), "orbit",
        or "keyframes" with keyframes=[camera dicts or URL states]. codec:
        "h264" (MP4) or "vp9" (WebM). frames=N instead of a duration; degrees
        (of the turn, 360) and elevation (orbit's tilt, 20). progress(status)
        is called while waiting."""
        body = {"path": path, "fps": fps, "width": size[0], "height": size[1], "codec": codec}
        if frames is not None:
            body["frames"] = frames
        else:
            body["duration"] = duration
        if degrees is not None:
            body["degrees"] = degrees
        if elevation is not None:
            body["elevation"] = elevation
        if keyframes is not None:
            body["keyframes"] = [k for k in keyframes]
            body["path"] = "keyframes"
        req = build_request(dataset, camera, params, None, **fields)
        self.validate(req)
        body["request"] = req
        job = self._json("POST", "/api/v1/movies", body)
        if not wait:
            return job
        job = self.wait_movie(job["id"], progress, poll)
        out = out or ("movie.webm" if codec == "vp9" else "movie.mp4")
        data, _ = self._bytes("GET", "/api/v1/movies/%s/file" % job["id"])
        with open(out, "wb") as f:
            f.write(data)
        return out

    def movie_status(self, job_id):
        return self._json("GET", "/api/v1/movies/" + job_id)

    def wait_movie(self, job_id, progress=None, poll=0.5):
        """Polls a movie job until it is done; raises LucentError if it failed
        or was cancelled."""
        while True:
            st = self.movie_status(job_id)
            if progress:
                progress(st)
            if st["state"] == "done":
                return st
            if st["state"] in ("failed", "cancelled"):
                raise LucentError(st.get("error", {}).get("code", st["state"]),
                                  st.get("error", {}).get("message", "movie " + st["state"]),
                                  st.get("error", {}).get("field"))
            time.sleep(poll)

    def cancel_movie(self, job_id):
        return self._json("DELETE", "/api/v1/movies/" + job_id)


def _server_error(e):
    """LucentError from an HTTPError with the server's JSON error body."""
    text = e.read().decode("utf-8", "replace")
    try:
        err = json.loads(text)["error"]
        return LucentError(err.get("code", "http_%d" % e.code), err.get("message", text), err.get("field"), e.code)
    except (ValueError, KeyError, TypeError):
        return LucentError("http_%d" % e.code, "HTTP %d: %s" % (e.code, text.strip()[:500]), None, e.code)


__all__ = ["Client", "LucentError", "SECTIONS", "decode_image", "build_request"]
