"""clients/python/examples/quickstart.ipynb executed headless (nbclient,
Debian's python3-nbclient and python3-ipykernel) against the real daemon:
every cell runs without error, the still displays as an image, the
interactive view (ipywidgets) displays and receives frames for its orbit and
parameter changes, and the movie cell writes a file."""
import os
import sys
import tempfile

from lucent_server import Check, Server, skip

try:
    import nbformat
    from nbclient import NotebookClient
    import ipywidgets  # noqa: F401  (the kernel imports it too)
except ImportError:  # pragma: no cover
    skip("python3-nbclient, python3-nbformat, python3-ipykernel or python3-ipywidgets is not installed")

binary = sys.argv[1]
here = os.path.dirname(os.path.abspath(__file__))
package = os.path.abspath(os.path.join(here, ".."))
check = Check()



class Client(NotebookClient):
    """Debian 12's nbclient (0.7) reads widget models in the message format of
    ipywidgets 7+ (`data.state`); Debian 12's ipywidgets (6.0) opens them with
    the state at the top level. The test is the front end here: it takes
    either form."""

    def on_comm_open_jupyter_widget(self, msg):
        data = msg["content"]["data"]
        if "state" not in data:
            return None
        return super().on_comm_open_jupyter_widget(msg)


with open(os.path.join(package, "examples", "quickstart.ipynb")) as f:
    nb = nbformat.read(f, as_version=4)

with Server(binary, data=("demo:tornado",), demo_size=120) as srv, tempfile.TemporaryDirectory() as tmp:
    os.environ["LUCENT_URL"] = srv.base
    os.environ["PYDEVD_DISABLE_FILE_VALIDATION"] = "1"  # the kernel's debugger notes on stderr
    os.environ["PYTHONPATH"] = package + os.pathsep + os.environ.get("PYTHONPATH", "")
    client = Client(nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": tmp}})
    try:
        client.execute()
        check(True, "every cell of quickstart.ipynb runs")
    except Exception as e:  # noqa: BLE001 (the failing cell's traceback is in the message)
        check(False, "quickstart.ipynb runs: %s" % str(e)[-1500:])
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]
    text = "".join(o.get("text", "") for o in outputs if o.get("output_type") == "stream")
    datas = [o.get("data", {}) for o in outputs if "data" in o]
    check(any("image/png" in d for d in datas), "the still displays as an image")
    check(any("application/vnd.jupyter.widget-view+json" in d for d in datas), "the interactive view displays")
    check("(240, 320, 3) uint8" in text, "the array cell prints its shape")
    check("refused before sending: params.bandz: unknown field" in text, "a bad field is refused naming it")
    check("4 (240, 320, 3)" in text, "the session gives one frame per turntable camera")
    frames = [l for l in text.splitlines() if l.startswith("frames:")]
    words = frames[0].split() if frames else []
    n = int(words[1]) if frames else 0
    seq = int(words[words.index("seq:") + 1]) if "seq:" in words else 0
    check(n >= 3 and seq >= 1, "the view received frames, one for its orbit: %s" % frames)
    check(os.path.getsize(os.path.join(tmp, "tornado.mp4")) > 1000 if os.path.exists(os.path.join(tmp, "tornado.mp4"))
          else False, "the movie cell wrote tornado.mp4")
    check(srv.stop() == 0, "daemon exits cleanly")
check.done()
