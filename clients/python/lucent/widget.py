"""An interactive view for Jupyter (ipywidgets, Debian's python3-ipywidgets)
fed by a WebSocket session: the frames the server streams go into an Image
widget; sliders orbit (azimuth, elevation about the start camera's up and
right axes, so the view never crosses a pole), zoom (log scale) and set
parameters (q, r, lambda, bands); a label shows the stats line. Debian 12's
ipywidgets (6.x) has no mouse events on images, hence sliders and buttons for
the orbit rather than dragging.

Static fallback (no widgets): `client.render(..., format="pil")` displays as an
image in any notebook."""
import math
import threading

from . import camera as cameras


def _require_widgets():
    try:
        import ipywidgets
    except ImportError as e:  # pragma: no cover
        raise ImportError("lucent.widget needs ipywidgets (Debian: python3-ipywidgets); "
                          "without it, display client.render(..., format='pil')") from e
    return ipywidgets


class Viewer:
    """Viewer(client, dataset, size=(640, 480)).widget is the ipywidgets box
    to display; frames keep coming while the session's opacities fade.
    Programmatic control: .orbit(azimuth, elevation), .zoom(factor),
    .update(params=...), .wait_frame(timeout) -> the header of the next frame,
    .frames (count), .close()."""

    def __init__(self, client, dataset=None, size=(640, 480), camera=None, quality=85, **request):
        w = _require_widgets()
        self.client = client
        self.size = size
        self.start = camera or client.fit(dataset)
        self.session = client.session(dataset, size=size, camera=self.start, quality=quality, interactiveScale=1,
                                      **request)
        self.frames = 0
        self.last_header = None
        self._frame_event = threading.Condition()
        self._closed = False
        self._error = None
        self._mark = 0  # frames seen when the last change was sent: wait_frame waits past it
        d = self.session.defaults or {}
        p = d.get("params", {})
        self.image = w.Image(format="jpeg", width=size[0], height=size[1])
        self.azimuth = w.FloatSlider(value=0, min=-180, max=180, step=1, description="azimuth")
        self.elevation = w.FloatSlider(value=0, min=-85, max=85, step=1, description="elevation")
        self.zoom_slider = w.FloatSlider(value=0, min=-2, max=2, step=0.05, description="zoom (log2)")
        self.q = w.FloatSlider(value=p.get("q", 60), min=0, max=500, step=1, description="q")
        self.r = w.FloatSlider(value=p.get("r", 500), min=0, max=2000, step=5, description="r")
        self.lam = w.FloatSlider(value=p.get("lambda", 1), min=0, max=20, step=0.1, description="lambda")
        self.bands = w.IntSlider(value=p.get("bands", 5), min=1, max=8, description="bands")
        self.stats = w.Label(value="connecting ...")
        for s in (self.azimuth, self.elevation, self.zoom_slider):
            s.observe(lambda change: self._send_camera(), names="value")
        for s in (self.q, self.r, self.lam, self.bands):
            s.observe(lambda change: self._send_params(), names="value")
        reset = w.Button(description="reset view")
        reset.on_click(lambda b: self.reset())
        controls = w.VBox([self.azimuth, self.elevation, self.zoom_slider, reset, self.q, self.r, self.lam,
                           self.bands])
        self.widget = w.VBox([w.HBox([self.image, controls]), self.stats])
        self._thread = threading.Thread(target=self._pump, name="lucent-viewer", daemon=True)
        self._thread.start()

    # ---- camera and parameters

    def camera(self):
        """The camera of the sliders: the start camera turned by azimuth about
        its up axis, tilted by elevation about its right axis, distance scaled
        by 2^-zoom."""
        c = cameras.orbit(self.start, 1, 0, elevation=self.elevation.value)[0]
        c = _turn(c, self.start_up(), self.azimuth.value)
        f = 2.0 ** -self.zoom_slider.value
        fp = c["focalPoint"]
        c["position"] = [a + f * (b - a) for a, b in zip(fp, c["position"])]
        return c

    def start_up(self):
        return cameras.turntable(self.start, 1, 0)[0]["viewUp"]

    def _sent(self):
        with self._frame_event:
            self._mark = self.frames

    def _send_camera(self):
        if not self._closed:
            self._sent()
            self.session.camera(self.camera())

    def _send_params(self):
        if not self._closed:
            self._sent()
            self.session.update(params={"q": self.q.value, "r": self.r.value, "lambda": self.lam.value,
                                        "bands": self.bands.value})

    def orbit(self, azimuth=None, elevation=None):
        if azimuth is not None:
            self.azimuth.value = azimuth
        if elevation is not None:
            self.elevation.value = elevation

    def zoom(self, factor):
        self.zoom_slider.value = math.log2(factor)

    def update(self, **fields):
        self._sent()
        self.session.update(**fields)

    def reset(self):
        self.azimuth.value = 0
        self.elevation.value = 0
        self.zoom_slider.value = 0

    # ---- frames

    def _pump(self):
        while not self._closed:
            try:
                f = self.session.next_frame(timeout=1.0)
            except TimeoutError:
                continue
            except Exception as e:  # noqa: BLE001 (shown to the user, the view stops)
                if not self._closed:
                    self.stats.value = "error: %s" % e
                with self._frame_event:
                    self._error = e
                    self._frame_event.notify_all()
                return
            self.image.value = f.data
            with self._frame_event:
                self.frames += 1
                self.last_header = f.header
                self._frame_event.notify_all()
            st = self.session.stats or {}
            self.stats.value = "frame %d%s | %s fps | render %s ms | queue %s" % (
                f.header.get("frame", 0), " (converged)" if f.converged else "", st.get("fps", "-"),
                st.get("renderMs", "-"), st.get("queue", "-"))

    def wait_frame(self, after=None, timeout=60):
        """Waits for a frame that shows the last change sent: more than
        `after` frames in all (default: the count when the last camera or
        parameter change was sent, so a frame that arrived before this call
        counts), and, after an orbit or zoom, one rendered for that camera.
        Returns the newest frame's header; raises the view's error if its
        stream failed."""
        with self._frame_event:
            n = self._mark if after is None else after
            seq = self.session.seq

            def ready():
                if self._error is not None:
                    return True
                return self.frames > n and (self.last_header or {}).get("cameraSeq", 0) >= seq

            if not self._frame_event.wait_for(ready, timeout):
                raise TimeoutError("no frame within %s s (%d frames so far)" % (timeout, self.frames))
            if self._error is not None:
                raise self._error
            return self.last_header

    def close(self):
        self._closed = True
        self._thread.join(5)
        self.session.close()

    def _ipython_display_(self):
        from IPython.display import display
        display(self.widget)


def _turn(cam, up, degrees):
    """cam turned by degrees about the axis through its focal point along up."""
    fp = cam["focalPoint"]
    off = [p - f for p, f in zip(cam["position"], fp)]
    a = math.radians(degrees)
    pos = cameras.rotate(off, up, a)
    return dict(cam, position=[f + p for f, p in zip(fp, pos)], viewUp=cameras.rotate(list(cam["viewUp"]), up, a))
