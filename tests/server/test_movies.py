"""Movies of layers[] (docs/ALGORITHM.md §24) against the real daemon: POST /api/v1/movies with a
request of two layers (the points demo and the tornado lines, no dataset named) is queued with both
layers in its status, renders every frame, and its file is a video of that many frames whose first
frame is the HTTP render of the same layered request (the camera path starts where a request without
camera looks: fitted to both layers), not the tornado's alone. An unknown layer dataset is a 404 naming
request.layers[1].dataset; a context layer of points fails the job with an error naming layers[0].role;
the daemon goes on serving. Under --max-cost a movie's layered frame is charged as the HTTP render of the
layers: under twice its cost, 800 times its pixels is refused naming layers. A movie of method
surface-layers is refused naming request.method. Frames are counted and decoded with ffprobe/ffmpeg where installed (scripts/packages/test.txt)."""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

from lucent_server import Check, Server, skip

binary = sys.argv[1]
check = Check()
SIZE = {"width": 160, "height": 128}
LAYERS = [{"dataset": "demo:points", "style": {"pointSize": 5}},
          {"dataset": "demo:tornado", "color": {"colormap": "coolwarm"}}]


def wait(srv, job, timeout=120):
    """The job's status once done, failed or cancelled (a state, polled; timeout only bounds a stuck job)."""
    end = time.time() + timeout
    while True:
        st, _, data = srv.request("GET", "/api/v1/movies/" + job)
        j = json.loads(data) if st == 200 else {}
        if j.get("state") in ("done", "failed", "cancelled") or time.time() > end:
            return j
        time.sleep(0.2)


def ssim(a, b):
    words = subprocess.run([binary, "ssim", a, b], capture_output=True, text=True).stdout.split()
    return float(dict(zip(words[0::2], words[1::2])).get("ssim", -1))


tmp = tempfile.mkdtemp()
with Server(binary, data=("demo:points", "demo:tornado"), demo_size=150) as srv:
    st, _, data = srv.request("POST", "/api/v1/movies", dict(SIZE, request={"layers": LAYERS}, frames=4, fps=4))
    job = json.loads(data) if st in (202, 400) else {}
    if st == 400 and job.get("error", {}).get("field") == "codec":
        skip("this server cannot encode movies: " + job["error"]["message"])
    check(st == 202 and job.get("layers") == ["demo:points", "demo:tornado"] and job.get("dataset") == "demo:points",
          "a movie of two layers is queued, its status lists them (%d %s)" % (st, data[:300]))
    done = wait(srv, job.get("id", "none"))
    check(done.get("state") == "done" and done.get("framesDone") == 4,
          "it renders its 4 layered frames (%s)" % json.dumps(done)[:300])
    st, hdrs, video = srv.request("GET", "/api/v1/movies/%s/file" % job.get("id"))
    check(st == 200 and video[4:8] == b"ftyp", "its file is an MP4 (%d, %d bytes)" % (st, len(video)))
    path = os.path.join(tmp, "layers.mp4")
    with open(path, "wb") as f:
        f.write(video)
    if shutil.which("ffprobe") and shutil.which("ffmpeg"):
        out = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-show_entries",
                              "stream=nb_read_frames,width,height", "-of", "json", path],
                             capture_output=True, text=True).stdout
        stream = (json.loads(out or "{}").get("streams") or [{}])[0]
        check(stream.get("nb_read_frames") == "4" and (stream.get("width"), stream.get("height")) == (160, 128),
              "the file holds 4 frames of 160x128 (%s)" % stream)
        frame0 = os.path.join(tmp, "frame0.png")
        subprocess.run(["ffmpeg", "-v", "error", "-y", "-i", path, "-frames:v", "1", frame0], check=False)
        refs = {}
        for name, body in (("layers", {"layers": LAYERS}), ("tornado", {"layers": [LAYERS[1]]})):
            st, _, img = srv.request("POST", "/api/v1/render", dict(SIZE, **body))
            refs[name] = os.path.join(tmp, name + ".png")
            with open(refs[name], "wb") as f:
                f.write(img)
        both, alone = (ssim(frame0, refs["layers"]), ssim(frame0, refs["tornado"])) if os.path.exists(frame0) \
            else (-1, -1)
        check(both >= 0.97 and both > alone + 0.02,
              "the first frame is the HTTP render of the two layers (SSIM %.4f after H.264), not the tornado's "
              "alone (%.4f)" % (both, alone))
    else:
        print("skip decoding the frames: ffprobe/ffmpeg not installed")

    st, _, data = srv.request("POST", "/api/v1/movies",
                              dict(SIZE, request={"layers": [LAYERS[0], {"dataset": "demo:nope"}]}, frames=2))
    e = json.loads(data).get("error", {}) if data else {}
    check(st == 404 and e.get("field") == "request.layers[1].dataset",
          "an unknown layer dataset -> 404 naming request.layers[1].dataset (%d %s)" % (st, data[:200]))
    st, _, data = srv.request("POST", "/api/v1/movies",
                              dict(SIZE, request={"layers": [dict(LAYERS[0], role="context"), LAYERS[1]]}, frames=2))
    e = json.loads(data).get("error", {}) if data else {}
    check(st == 400 and e.get("field") == "layers[0].role",
          "a context layer of points is refused when the movie is asked for, naming layers[0].role (%d %s)" %
          (st, data[:300]))
    # A movie of method surface-layers (a field's surface, no dataset) is refused when asked for, not at its first frame.
    st, _, data = srv.request("POST", "/api/v1/movies", dict(SIZE, frames=2, request={
        "method": "surface-layers", "surface": {"field": "demo:abc-flow", "seed": [[3, 1, 3], [3, 5, 3]]}}))
    e = json.loads(data).get("error", {}) if data else {}
    check(st == 400 and e.get("field") == "request.method",
          "a surface-layers movie is refused naming request.method (%d %s)" % (st, data[:200]))
    # Bounded jobs: a frame at most 4K, frames x pixels at most a minute of 4K at 30 fps.
    for body, field, what in (({"width": 8192, "height": 4608, "frames": 2}, "width", "an 8192x4608 movie frame"),
                              ({"width": 1920, "height": 1080, "frames": 18000}, "frames", "18,000 frames of 1080p"),
                              ({"width": 3840, "height": 2160, "duration": 120}, "duration", "two minutes of 4K")):
        st, _, data = srv.request("POST", "/api/v1/movies", dict(body, request={"dataset": "demo:points"}))
        e = json.loads(data).get("error", {}) if data else {}
        check(st == 400 and e.get("field") == field, "%s is refused naming %s (%d %s)" % (what, field, st, data[:200]))
    st, hdrs, _ = srv.request("POST", "/api/v1/render", dict(SIZE, layers=LAYERS))
    check(st == 200, "the daemon goes on serving (%d)" % st)
    cost = float(hdrs.get("x-lucent-cost", 0))

# --max-cost: a movie's layered frame costs the sum of its layers' (as an HTTP render of the layers).
with Server(binary, "--max-cost", "%g" % (2 * cost), data=("demo:points", "demo:tornado"), demo_size=150) as srv:
    st, _, data = srv.request("POST", "/api/v1/movies", dict(SIZE, request={"layers": LAYERS}, frames=1))
    check(st == 202, "under --max-cost of twice its frame, the small movie of layers is queued (%d)" % st)
    wait(srv, json.loads(data).get("id", "none") if st == 202 else "none")
    st, _, data = srv.request("POST", "/api/v1/movies", {"request": {"layers": LAYERS}, "frames": 1,
                                                         "width": 3840, "height": 2160})
    e = json.loads(data).get("error", {}) if data else {}
    check(st == 400 and e.get("code") == "too_expensive" and e.get("field") == "layers",
          "a 3840x2160 movie of the layers is too expensive, naming layers (%d %s)" % (st, data[:200]))

shutil.rmtree(tmp, ignore_errors=True)
check.done()
