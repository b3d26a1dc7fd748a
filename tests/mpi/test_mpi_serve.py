"""`mpirun -np N lucent serve --mpi` against the single-process daemon: HTTP
renders of lines, points, a surface and a plane, a scripted session whose
opacities fade while the camera moves (the fading history travels with each
frame), a WebSocket session, layers[] (points and lines; a plane as opaque
context through lines) in HTTP renders, a scripted session and a WebSocket
session, bad layers answered as one process does, /datasets; then killing one
rank during a session ends the service within seconds with a message naming
the rank, and the render in flight is answered 503 with a message; ranks that
see different dataset lists refuse to start; a hung rank ends the job after
LUCENT_MPI_TIMEOUT seconds, with the request that waited for it answered 503
and a WebSocket session told why.
Usage: test_mpi_serve.py LUCENT RANKS"""
import asyncio
import json
import math
import os
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
sys.path.insert(0, os.path.join(os.path.dirname(here), "server"))
from lucent_server import Check, Server, skip, unpack_frame, wait_for_stream_done, websockets  # noqa: E402
from mpi_util import MAX_RMSE, mpirun, mpirun_env, rmse  # noqa: E402

lucent, ranks = sys.argv[1], int(sys.argv[2])
launcher = mpirun(ranks)
if not launcher:
    skip("mpirun not found (apt-get install openmpi-bin)")
DEMO_SIZE = 120
tmp = tempfile.mkdtemp(prefix="lucent-mpi-serve-")
# A line file each rank reads only its share of (docs/MPI.md "Loading").
from line_files import write_all  # noqa: E402
TRK = write_all(tmp, 120)["trk"]
# Its sidecar sets an element budget: the ranks rebuild their parts' elements together.
with open(os.path.join(tmp, "helices.lucent.json"), "w") as f:
    json.dump({"elements": 500, "params": {"q": 80}}, f)
# A plane z = 0.5 over the left half of the tornado (one element: one rank holds it), as opaque context.
PLANE = os.path.join(tmp, "plane.obj")
with open(PLANE, "w") as f:
    f.write("v -0.2 -0.2 0.5\nv 0.5 -0.2 0.5\nv 0.5 1.2 0.5\nv -0.2 1.2 0.5\nf 1 2 3\nf 1 3 4\n")
DATA = ["demo:tornado", "demo:surface", "demo:points", TRK, PLANE]
check = Check()


class MpiServer(Server):
    """Server's helpers around `mpirun -np N lucent serve --mpi`."""

    def __init__(self, binary, n, data, demo_size, timeout=120, env=None, args=()):
        self.binary = binary
        cmd = mpirun(n) + [binary, "serve", "--mpi", "--listen", "127.0.0.1:0", "--demo-size", str(demo_size)]
        cmd += list(args)
        for d in data:
            cmd += ["--data", d]
        self.log = []
        self.proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                     stderr=subprocess.STDOUT, env=dict(mpirun_env(), **(env or {})), text=True)
        self._port = None
        self._ready = threading.Event()
        self._drainer = threading.Thread(target=self._drain, daemon=True)
        self._drainer.start()
        if not self._ready.wait(timeout) or self._port is None:
            self.proc.kill()
            raise RuntimeError("mpirun serve did not start:\n" + "\n".join(self.log))
        self.port, self.host = self._port, "127.0.0.1"
        self.base = "http://127.0.0.1:%d" % self.port
        self.ws_url = "ws://127.0.0.1:%d/api/v1/ws" % self.port

    def rank_pid(self, rank, timeout=120):
        """The rank's pid from its log line (polled: the line may come after "listening")."""
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            for line in list(self.log):
                m = re.search(r"rank %d \(pid (\d+)\): following" % rank, line)
                if m:
                    return int(m.group(1))
            time.sleep(0.1)
        return None

    def full_log(self, timeout=60):
        """The log once mpirun has exited and its output is all read."""
        self._drainer.join(timeout)
        return "\n".join(self.log)


def save(name, data):
    path = os.path.join(tmp, name)
    with open(path, "wb") as f:
        f.write(data)
    return path


def compare(what, one, many, limit=MAX_RMSE):
    e = rmse(lucent, save(what + "-1.img", one), save(what + "-n.img", many))
    check(e <= limit, "%s: rmse %.6f <= %.6f" % (what, e, limit))


def session_frames(what, pairs, cameras):
    """Renders each camera in turn on each (server, session id) of pairs, the
    one-process daemon's first, and compares the two frames."""
    for i, cam in enumerate(cameras):
        imgs = []
        for srv, sid in pairs:
            st, _, img = srv.request("POST", "/api/v1/sessions/%s/render" % sid, {"dt": 1 / 30, "camera": cam})
            imgs.append(img if st == 200 else None)
        if check(all(imgs), "%s %d rendered by both" % (what, i)):
            compare("%s-%d" % (what, i), imgs[0], imgs[1])


async def ws_last_frame(srv, scene=None):
    """The frame that ends the stream (converged, a final still) and the number of frames, however long it takes."""
    async with websockets.connect(srv.ws_url, max_size=None) as ws:
        await ws.send(json.dumps(dict({"type": "hello", "width": 96, "height": 72, "devicePixelRatio": 1,
                                       "params": {"lod": 0}}, **(scene or {"dataset": "demo:surface"}))))
        got = await wait_for_stream_done(ws, deadline=300, skip=("stats", "progress", "ready"))
        frames = [m for m in got if m["type"] == "frame"]
        return (frames[-1]["image"] if got.reached else None), len(frames)


# Start-up: the last rank sees another dataset list (MPMD) -> every rank
# refuses to start, naming the difference.
cmd = launcher[:-1] + [str(ranks - 1), lucent, "serve", "--mpi", "--listen", "127.0.0.1:0", "--demo-size", "50",
                       "--data", "demo:points", ":", "-np", "1", lucent, "serve", "--mpi", "--listen",
                       "127.0.0.1:0", "--demo-size", "50", "--data", "demo:abc"]
t0 = time.time()
r = subprocess.run(cmd, capture_output=True, text=True, env=mpirun_env(), timeout=120)
out = r.stdout + r.stderr
check(r.returncode != 0 and "ranks see different dataset lists" in out and "rank %d has [demo:abc" % (ranks - 1) in out
      and "listening on" not in out,
      "different dataset lists: every rank refuses to start in %.1f s (exit %d)" % (time.time() - t0, r.returncode))

# Start-up: the last rank cannot open a file before a line file the others
# read in parts -> every rank learns it at that file's agreement and ends
# promptly (not by the watchdog after LUCENT_MPI_TIMEOUT: its message, "has
# waited", is absent), naming the file.
cmd = launcher[:-1] + [str(ranks - 1), lucent, "serve", "--mpi", "--listen", "127.0.0.1:0", "--data", TRK, ":",
                       "-np", "1", lucent, "serve", "--mpi", "--listen", "127.0.0.1:0", "--data",
                       os.path.join(tmp, "missing.ply"), "--data", TRK]
t0 = time.time()
r = subprocess.run(cmd, capture_output=True, text=True, env=mpirun_env(), timeout=120)
out = r.stdout + r.stderr
check(r.returncode != 0 and "missing.ply" in out and "listening on" not in out and "has waited" not in out,
      "a rank that cannot load before a file read in parts: every rank ends in %.1f s (exit %d)" %
      (time.time() - t0, r.returncode))

# Float vertex buffers on both sides: the compact layout quantizes surface and
# line shards in other chunks than one process does (docs/MPI.md "Limits"),
# which on the surface alone comes near the 1/255 bound.
single = Server(lucent, "--exact-positions", data=DATA, demo_size=DEMO_SIZE)
multi = MpiServer(lucent, ranks, DATA, DEMO_SIZE, args=("--exact-positions",))
try:
    # One-shot HTTP renders of every kind of geometry.
    for src in DATA:
        ds = "helices" if src == TRK else "plane" if src == PLANE else src
        req = {"dataset": ds, "width": 160, "height": 120, "format": "png"}
        if ds == "demo:surface":  # surface levels of detail are simplified per shard (docs/MPI.md)
            req["params"] = {"lod": 0}
        s1, h1, a = single.request("POST", "/api/v1/render", req)
        s2, h2, b = multi.request("POST", "/api/v1/render", req)
        check(s1 == 200 and s2 == 200, "%s: HTTP render 200 from both (%d, %d)" % (ds, s1, s2))
        if s1 == 200 and s2 == 200:
            compare("http-" + ds.replace(":", "_"), a, b)
            v1 = [float(x) for x in re.findall(r"=([0-9.]+)", h1.get("x-lucent-visibility", ""))]
            v2 = [float(x) for x in re.findall(r"=([0-9.]+)", h2.get("x-lucent-visibility", ""))]
            check(len(v1) >= 4 and len(v1) == len(v2) and max(abs(x - y) for x, y in zip(v1, v2)) <= 0.01,
                  "%s: X-Lucent-Visibility %s vs %s" % (ds, h1.get("x-lucent-visibility"),
                                                         h2.get("x-lucent-visibility")))
    # A scripted session: the camera orbits and the opacities fade (dt).
    sessions = []
    for srv in (single, multi):
        st, _, info = srv.json("POST", "/api/v1/sessions", {"dataset": "demo:tornado", "width": 160, "height": 120,
                                                             "format": "png", "params": {"fadeHalfLife": 0.3}})
        sessions.append(info["session"] if st in (200, 201) else None)
    check(all(sessions), "sessions created on both")
    session_frames("session-frame", list(zip((single, multi), sessions)), [
        {"position": [0.5 + 2.2 * math.cos(0.4 * i), 0.5 + 2.2 * math.sin(0.4 * i), 0.9],
         "focalPoint": [0.5, 0.5, 0.5], "viewUp": [0, 0, 1]} for i in range(4)])
    # layers[] (docs/MPI.md "Layers"): the ranks draw their shards of each
    # layer; the plane as opaque context is combined over the ranks (its
    # nearest depth on every rank, its colour once), looked at down -z with
    # lines in front of it and behind it. HTTP renders and a session whose
    # fading history spans the layers.
    LAYERS = [{"dataset": "demo:points", "style": {"pointSize": 4}}, {"dataset": "demo:tornado"}]
    CONTEXT = [{"dataset": "plane", "role": "context"}, {"dataset": "demo:tornado"}]
    DOWN_Z = {"position": [0.5, 0.5, 3.2], "focalPoint": [0.5, 0.5, 0.5], "viewUp": [0, 1, 0]}
    for what, layers in (("layers", LAYERS), ("context", CONTEXT)):
        req = {"layers": layers, "width": 160, "height": 120, "format": "png", "camera": DOWN_Z}
        (s1, _, a), (s2, _, b) = single.request("POST", "/api/v1/render", req), multi.request("POST", "/api/v1/render",
                                                                                                req)
        if check(s1 == 200 and s2 == 200, "HTTP render of %s: 200 from both (%d, %d%s)" %
                 (what, s1, s2, "" if s2 == 200 else ": %s" % b[:200])):
            compare("http-" + what, a, b)
    # Bad layers: the one-process answer, naming the field; the ranks go on serving.
    for body, status, field in (({"layers": [LAYERS[0], {"dataset": "nonesuch"}]}, 404, "layers[1].dataset"),
                                ({"layers": [dict(LAYERS[0], role="context"), LAYERS[1]]}, 400, "layers[0].role")):
        answers = [srv.request("POST", "/api/v1/render", dict(body, width=64, height=48)) for srv in (single, multi)]
        fields = [json.loads(b or b"{}").get("error", {}).get("field") for _, _, b in answers]
        check([a[0] for a in answers] == [status] * 2 and fields == [field] * 2,
              "bad layers answered %d naming %s by both: %s" % (status, field, [(a[0], a[2][:120]) for a in answers]))
    sessions = []
    for srv in (single, multi):
        st, _, info = srv.json("POST", "/api/v1/sessions", {"layers": CONTEXT, "width": 160, "height": 120,
                                                             "format": "png", "params": {"fadeHalfLife": 0.3}})
        sessions.append(info.get("session") if st in (200, 201) and info else None)
    if check(all(sessions), "sessions of layers created on both"):
        session_frames("session-layers", list(zip((single, multi), sessions)),
                       [dict(DOWN_Z, position=[0.5 + 0.4 * i, 0.5, 3.2]) for i in range(3)])
    # A WebSocket session: the last frame (still, converged) of each.
    if websockets:
        (a, na), (b, nb) = asyncio.run(ws_last_frame(single)), asyncio.run(ws_last_frame(multi))
        if check(a is not None and b is not None, "WebSocket frames from both (%d, %d)" % (na, nb)):
            compare("websocket-last-frame", a, b, 2.0 / 255.0)  # JPEG on top of the rendering
        # ... and one of layers (the render worker's stream path announces them too).
        (a, na), (b, nb) = (asyncio.run(ws_last_frame(srv, {"layers": LAYERS})) for srv in (single, multi))
        if check(a is not None and b is not None, "WebSocket frames of layers from both (%d, %d)" % (na, nb)):
            compare("websocket-layers-last-frame", a, b, 2.0 / 255.0)
    # /datasets describes the whole datasets, not rank 0's shards.
    _, _, d1 = single.json("GET", "/api/v1/datasets")
    _, _, d2 = multi.json("GET", "/api/v1/datasets")
    # gpuBytes and memory are this rank's (its shard's) buffers.
    strip = lambda d: [{k: v for k, v in x.items() if k not in ("gpuBytes", "memory")} for x in d["datasets"]]  # noqa: E731
    check(strip(d1) == strip(d2), "/api/v1/datasets equal but for gpuBytes and memory")
    hel = [x for x in d2["datasets"] if x["name"] == "helices"]
    check(hel and hel[0]["elements"] == 500 and hel[0]["vertices"] == [x for x in d1["datasets"]
                                                                        if x["name"] == "helices"][0]["vertices"],
          "the sidecar's element budget on the parts read by the ranks, the whole's vertex count: %s" %
          ({k: hel[0].get(k) for k in ("elements", "vertices")} if hel else None))
    check(any("rank %d of %d" % (ranks - 1, ranks) in line for line in multi.log), "per-rank memory in the log")
    check(any("helices: rank %d of %d" % (ranks - 1, ranks) in line and "its share read from the file" in line
              for line in multi.log), "the line file read in parts (log: %s)" %
          [line for line in multi.log if "helices: rank" in line][:1])

    # Kill the last rank during a session: the job ends within seconds and
    # mpirun's message names the rank.
    victim = multi.rank_pid(ranks - 1)
    if check(victim is not None, "rank %d logged its pid" % (ranks - 1)):
        stop = threading.Event()
        st, _, info = multi.json("POST", "/api/v1/sessions", {"dataset": "demo:tornado", "width": 200,
                                                               "height": 150, "format": "png"})
        check(st in (200, 201), "a session for the kill test")
        sid = info.get("session") if info else None

        answers = []  # (status, body) of each render after the kill
        before = []  # statuses of the renders before it

        def load():  # a scripted session orbiting the data, frame after frame
            i = 0
            while not stop.is_set():
                a = 0.3 * i
                cam = {"position": [0.5 + 2.2 * math.cos(a), 0.5 + 2.2 * math.sin(a), 0.9],
                       "focalPoint": [0.5, 0.5, 0.5], "viewUp": [0, 0, 1]}
                i += 1
                try:
                    st, _, body = multi.request("POST", "/api/v1/sessions/%s/render" % sid,
                                                {"dt": 1 / 30, "camera": cam}, timeout=120)
                    if killed.is_set():
                        answers.append((st, body))
                    else:
                        before.append(st)
                except Exception as e:
                    if killed.is_set():
                        answers.append((None, repr(e).encode()))
                    time.sleep(0.1)
        killed = threading.Event()
        t = threading.Thread(target=load, daemon=True)
        t.start()
        # The session is under way (two frames rendered, however long they take): the kill comes mid-stream.
        end = time.monotonic() + 120
        while before.count(200) < 2 and time.monotonic() < end:
            time.sleep(0.05)
        check(before.count(200) >= 2, "the session renders before the kill (%s)" % before[:5])
        killed.set()
        os.kill(victim, signal.SIGKILL)
        t0 = time.time()
        try:
            rc = multi.proc.wait(120)
        except subprocess.TimeoutExpired:
            rc = None
        took = time.time() - t0
        stop.set()
        t.join(120)  # its last request is answered (or refused) once the job is gone
        text = multi.full_log()
        # Ended by the dead rank (mpirun's message, below), not by the watchdog after LUCENT_MPI_TIMEOUT.
        check(rc is not None and "has waited" not in text, "killing rank %d ends the job (in %.1f s, exit %s), "
              "not by the watchdog" % (ranks - 1, took, rc))
        check(re.search(r"rank %d .*exited on signal 9" % (ranks - 1), text) is not None,
              "mpirun's message names the dead rank")
        check("ending the service" in text, "rank 0 logs that the service ends")
        # The render that waited for the dead rank is answered, not dropped (a
        # frame whose reductions were done before the kill still succeeds).
        first = next((a for a in answers if a[0] != 200), (None, b"no failed render after the kill"))
        check(first[0] == 503 and b"MPI job is ending" in first[1],
              "the render that waited for the dead rank is answered %s: %s" % (first[0], first[1][:160]))

    # A rank that hangs (stopped, not dead: the runtime sees nothing) holds
    # rank 0's next reduction; the watchdog ends the job after
    # LUCENT_MPI_TIMEOUT seconds with a message.
    hung = MpiServer(lucent, ranks, ["demo:points"], DEMO_SIZE, env={"LUCENT_MPI_TIMEOUT": "3"})
    ws_frames, ws_errors, ws_streaming = [0], [], threading.Event()

    def ws_client():  # a WebSocket session that keeps asking for frames while the rank hangs
        async def run():
            async with websockets.connect(hung.ws_url, max_size=None) as ws:
                await ws.send(json.dumps({"type": "hello", "dataset": "demo:points", "width": 96, "height": 72,
                                          "devicePixelRatio": 1}))
                seq, end = 0, time.time() + 300  # until the job ends the connection
                while time.time() < end:
                    try:
                        m = await asyncio.wait_for(ws.recv(), 2.0)  # paces the camera messages
                    except asyncio.TimeoutError:
                        m = None
                    if isinstance(m, (bytes, bytearray)):
                        header, _ = unpack_frame(m)
                        ws_frames[0] += 1
                        ws_streaming.set()
                        await ws.send(json.dumps({"type": "ack", "frame": header["frame"]}))
                    elif m is not None and json.loads(m).get("type") == "error":
                        ws_errors.append(json.loads(m))
                    seq += 1
                    await ws.send(json.dumps({"type": "camera", "seq": seq, "camera": {
                        "position": [0.5, 0.5, 2.0 + 0.01 * seq], "focalPoint": [0.5, 0.5, 0.5], "viewUp": [0, 1, 0]}}))
        try:
            asyncio.run(run())
        except Exception as e:  # the connection ends with the job
            ws_errors.append({"exception": repr(e)})
    try:
        victim = hung.rank_pid(ranks - 1)
        if websockets:
            threading.Thread(target=ws_client, daemon=True).start()
            check(ws_streaming.wait(120), "a WebSocket session streams before the rank hangs")
        os.kill(victim, signal.SIGSTOP)
        t0 = time.time()
        try:
            answer = hung.request("POST", "/api/v1/render", {"dataset": "demo:points", "width": 64, "height": 48,
                                                             "format": "png"}, timeout=120)
        except Exception as e:
            answer = (None, {}, repr(e).encode())
        try:
            rc = hung.proc.wait(120)
        except subprocess.TimeoutExpired:
            rc = None
        took = time.time() - t0
        text = hung.full_log()
        # The watchdog's own message says it ended the job after 3 s of waiting (took: a figure).
        check(rc is not None and "has waited 3 s for the other ranks" in text,
              "a hung rank: the watchdog ends the job in %.1f s (exit %s): %s" %
              (took, rc, next((line for line in hung.log if "has waited" in line), "no message")))
        check(answer[0] == 503 and b"MPI job is ending" in answer[2],
              "the request that waited for the hung rank is answered %s: %s" % (answer[0], answer[2][:160]))
        if websockets:
            check(any("MPI job is ending" in e.get("message", "") for e in ws_errors),
                  "the WebSocket session (%d frames) is told why: %s" % (ws_frames[0], ws_errors[:2]))
    finally:
        if hung.proc.poll() is None:
            hung.proc.kill()
            hung.proc.wait()
finally:
    single.stop()
    if multi.proc.poll() is None:
        multi.proc.send_signal(signal.SIGTERM)
        try:
            multi.proc.wait(20)
        except subprocess.TimeoutExpired:
            multi.proc.kill()
check.done()
