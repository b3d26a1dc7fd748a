"""Server-side movies (POST /api/v1/movies) through the Python client against
the real daemon: a turntable of the tornado as H.264/MP4 that ffprobe counts
and sizes as asked, whose first, middle and last frames match HTTP renders of
the client's turntable cameras (which keep the view-up: no pole crossing);
VP9/WebM; a keyframe path given as the web page's URL states; clear errors for
bad movie requests; a bounded queue (429 beyond it) whose cancelled jobs free
their session and file; shutdown with a job running.

The suite runs a 2-second 15 fps turntable at 320x180; LUCENT_MOVIE_FULL=1 runs
the issue's full check (10 s at 30 fps, 960x540: 300 frames)."""
import glob
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

from lucent_server import Check, Server, skip, wait_until

try:
    import numpy as np
except ImportError:  # pragma: no cover
    skip("python3-numpy is not installed")
if not shutil.which("ffprobe") or not shutil.which("ffmpeg"):
    skip("ffmpeg (ffprobe) is not installed")

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, ".."))
import lucent  # noqa: E402
from imgcheck import ssim  # noqa: E402

binary = sys.argv[1]
check = Check()
FULL = os.environ.get("LUCENT_MOVIE_FULL") == "1"
DURATION, FPS, SIZE = (10, 30, (960, 540)) if FULL else (2, 12, (320, 180))
N = DURATION * FPS
# The suite's short movie turns 96 degrees, 4 a frame, as the full one's 1.2 a
# frame at twice the frame rate lags about as far behind with its fading opacities.
DEGREES = 360 if FULL else 96


def probe(path):
    r = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                        "stream=codec_name,width,height,nb_read_frames,pix_fmt:format=duration", "-of", "json", path],
                       capture_output=True, text=True)
    d = json.loads(r.stdout or "{}")
    s = (d.get("streams") or [{}])[0]
    return {"codec": s.get("codec_name"), "width": s.get("width"), "height": s.get("height"),
            "frames": int(s.get("nb_read_frames", -1)), "duration": float(d.get("format", {}).get("duration", -1))}


def clean_exit(r):
    """Exit 0, or (in a sanitizer build) 1 with only LeakSanitizer's report of
    blocks the GL driver keeps, none of them allocated by lucent's own code
    (`lucent render` exits the same way there)."""
    if r.returncode == 0:
        return True
    root = os.path.dirname(os.path.dirname(os.path.dirname(here)))
    text = r.stderr
    return ("ERROR: LeakSanitizer" in text and "ERROR: AddressSanitizer" not in text and "runtime error:" not in text
            and root + os.sep not in text and binary not in text)


def frames_of(path, indices, size):
    """The decoded frames at indices as (H, W, 3) uint8 arrays."""
    sel = "+".join("eq(n\\,%d)" % i for i in indices)
    r = subprocess.run(["ffmpeg", "-v", "error", "-i", path, "-vf", "select=" + sel, "-vsync", "0", "-f", "rawvideo",
                        "-pix_fmt", "rgb24", "-"], capture_output=True)
    w, h = size
    a = np.frombuffer(r.stdout, dtype=np.uint8)
    return a.reshape(-1, h, w, 3) if a.size and a.size % (w * h * 3) == 0 else np.zeros((0, h, w, 3), np.uint8)


tmp = tempfile.mkdtemp(prefix="lucent-movie-test-")
movie_tmp = os.path.join(tmp, "server")
os.mkdir(movie_tmp)
try:
    # The full check renders the tornado at its default size (500 streamlines).
    with Server(binary, data=("demo:tornado",), demo_size=0 if FULL else 120, env={"TMPDIR": movie_tmp}) as srv:
        c = lucent.Client(srv.base)
        check(not glob.glob(os.path.join(movie_tmp, "lucent-movies-*")),
              "a daemon that has made no movie has no movie folder (a killed one leaves none)")
        start = c.fit("demo:tornado")
        cams = lucent.turntable(start, N, DEGREES)
        check(all(cam["viewUp"] == cams[0]["viewUp"] for cam in cams), "the turntable keeps one view-up vector")

        t0 = time.time()
        out = c.movie("demo:tornado", os.path.join(tmp, "turntable.mp4"), duration=DURATION, fps=FPS, size=SIZE,
                      codec="h264", degrees=DEGREES)
        took = time.time() - t0
        print("note: %d frames at %dx%d took %.1f s (%.0f ms a frame)" % (N, SIZE[0], SIZE[1], took, 1000 * took / N))
        p = probe(out)
        check(p["codec"] == "h264" and (p["width"], p["height"]) == SIZE, "ffprobe: H.264 of %dx%d (%s)" % (SIZE + (p,)))
        check(p["frames"] == N, "ffprobe counts %d frames (%d)" % (N, p["frames"]))
        check(abs(p["duration"] - DURATION) < 0.5 / FPS, "the duration is %g s (%.3f)" % (DURATION, p["duration"]))
        idx = [0, N // 2, N - 1]
        got = frames_of(out, idx, SIZE)
        check(len(got) == 3, "frames %s decode" % idx)
        for k, i in enumerate(idx[:len(got)]):
            ref = c.render("demo:tornado", size=SIZE, camera=cams[i])
            s = ssim(got[k], ref)
            check(s >= 0.95, "movie frame %d matches the HTTP render of turntable camera %d: SSIM %.4f" % (i, i, s))
        if len(got) == 3:
            s = ssim(got[0], got[2])
            check(s < 0.95, "and the camera moved between them (first vs last SSIM %.4f)" % s)

        # VP9 in WebM.
        webm = c.movie("demo:tornado", os.path.join(tmp, "t.webm"), frames=6, fps=12, size=(160, 96), codec="vp9")
        p = probe(webm)
        check(p["codec"] == "vp9" and p["frames"] == 6 and (p["width"], p["height"]) == (160, 96),
              "VP9/WebM: 6 frames of 160x96 (%s)" % p)

        # Keyframes as the web page's URL states: slerp + log-linear zoom.
        near = dict(cams[N // 4])
        near["position"] = [f + 0.6 * (x - f) for x, f in zip(near["position"], near["focalPoint"])]
        links = ["http://h/#dataset=demo:tornado&" + "&".join(
            "%s=%s" % (k, ",".join("%.12g" % x for x in cam[k])) for k in ("position", "focalPoint", "viewUp"))
            for cam in (cams[0], near)]
        kf = c.movie("demo:tornado", os.path.join(tmp, "k.mp4"), keyframes=links, frames=5, fps=10, size=(320, 192),
                     params={"fadeHalfLife": 0})  # no fading: each frame shows its camera's targets
        got = frames_of(kf, [0, 2, 4], (320, 192))
        want = [cams[0], lucent.interpolate(cams[0], near, 0.5), near]
        sims = [ssim(g, c.render("demo:tornado", size=(320, 192), camera=w, params={"fadeHalfLife": 0}))
                for g, w in zip(got, want)]
        check(len(sims) == 3 and min(sims) >= 0.95,
              "keyframe movie: first, middle (slerp, log-linear zoom) and last frames match (SSIM %s)"
              % ", ".join("%.4f" % s for s in sims))

        # Bad movie requests: a clear error naming the field, before any work.
        bad = [({"frames": 0}, "frames"), ({"duration": 0}, "duration"), ({"width": 15360, "height": 8640}, "width"),
               ({"codec": "av1"}, "codec"), ({"keyframes": [links[0]]}, "keyframes"),
               ({"keyframes": [links[0], "#bandz=3"]}, "keyframes[1].bandz"), ({"width": 321}, "width"),
               ({"request": {"params": {"bandz": 1}}}, "request.params.bandz"), ({"fps": 1000}, "fps"),
               ({"request": {"dataset": "demo:nope"}}, "request.dataset"), ({"loop": True}, "loop")]
        for body, field in bad:
            st, _, e = srv.json("POST", "/api/v1/movies", body)
            err = (e or {}).get("error", {})
            check(st in (400, 404) and err.get("field") == field and err.get("message", "").startswith(field),
                  "%s -> %d naming %s: %s" % (json.dumps(body)[:60], st, field, err.get("message")))
        try:
            c.movie("demo:tornado", os.path.join(tmp, "x.mp4"), frames=0)
            check(False, "client.movie(frames=0) raises")
        except lucent.LucentError as ex:
            check(ex.field == "frames", "client.movie(frames=0) raises LucentError naming frames: %s" % ex)

        # Bounded queue; cancel frees the session and the file.
        ids = []
        for i in range(lucent_limit := 4):
            st, _, j = srv.json("POST", "/api/v1/movies", {"frames": 400, "fps": 30, "width": 64, "height": 48})
            ids.append(j["id"] if st == 202 else None)
        check(all(ids), "%d long jobs accepted (202)" % lucent_limit)
        st, h, e = srv.json("POST", "/api/v1/movies", {"frames": 10, "width": 64, "height": 48})
        check(st == 429 and "retry-after" in h, "a fifth active job -> 429 with Retry-After: %s" % (e,))
        # The runner picks the first job up (a state: polled, however long a busy machine takes).
        wait_until(lambda: srv.json("GET", "/api/v1/movies/" + ids[0])[2]["state"] != "queued", 120, 0.05)
        states = [srv.json("GET", "/api/v1/movies/" + i)[2]["state"] for i in ids]
        check(states[0] == "running" and states[1:] == ["queued"] * 3, "one runs, the others queue: %s" % states)
        wait_until(lambda: srv.json("GET", "/api/v1/movies/" + ids[0])[2]["framesDone"] >= 2, 120, 0.2)
        st, _, health = srv.json("GET", "/api/v1/health")
        check(health["sessions"]["http"] == 1, "the running job holds one session: %s" % health["sessions"])
        files = glob.glob(os.path.join(movie_tmp, "lucent-movies-*", ids[0] + ".*"))
        check(len(files) == 1, "and its partial file: %s" % files)
        for i in ids:
            st, _, j = srv.json("DELETE", "/api/v1/movies/" + i)
            check(st == 200 and j["state"] in ("cancelled", "cancelling"), "DELETE cancels %s (%s)" % (i[:8], j["state"]))
        # A running job is cancelled asynchronously (its frame in hand finishes), and the
        # runner may have started a queued one before that one's DELETE came: wait for all.
        deadline = time.time() + 120
        while True:
            states = [srv.json("GET", "/api/v1/movies/" + i)[2]["state"] for i in ids]
            if states == ["cancelled"] * 4 or time.time() > deadline:
                break
            time.sleep(0.2)
        check(states == ["cancelled"] * 4, "all cancelled: %s" % states)
        st, _, health = srv.json("GET", "/api/v1/health")
        check(health["sessions"]["http"] == 0, "the cancelled job's session is gone: %s" % health["sessions"])
        files = glob.glob(os.path.join(movie_tmp, "lucent-movies-*", "*"))
        done = [f for f in files if not any(i in f for i in ids)]
        check(len(done) == len(files), "the cancelled jobs' files are gone (%d files left, all finished movies)"
              % len(files))
        check(not [f for f in srv.open_files() if "lucent-movies" in f], "the daemon holds no movie file open")
        st, _, e = srv.json("GET", "/api/v1/movies/%s/file" % ids[1])
        check(st == 409 and e["error"]["code"] == "not_ready", "a cancelled job has no file (409)")
        st, _, e = srv.json("GET", "/api/v1/movies/nope")
        check(st == 404, "unknown movie -> 404")

        # Shutdown while a job runs: clean exit, temporary folder removed.
        st, _, j = srv.json("POST", "/api/v1/movies", {"frames": 400, "width": 64, "height": 48})
        # the job is under way (a frame done) before the daemon is stopped
        running = wait_until(lambda: srv.json("GET", "/api/v1/movies/" + j["id"])[2]["framesDone"] >= 1, 120, 0.1) \
            if st == 202 else False
        check(running, "the job runs (%d)" % st)
        check(srv.stop() == 0, "the daemon exits cleanly with a movie running")
        check(not glob.glob(os.path.join(movie_tmp, "lucent-movies-*")), "its temporary folder is removed")

    # `lucent movie` offline: the same request, frame 0 = `lucent render` of the fitted camera.
    spec = os.path.join(tmp, "m.json")
    with open(spec, "w") as f:
        json.dump({"frames": 3, "fps": 10, "width": 128, "height": 96,
                   "degrees": 90}, f)
    mp4 = os.path.join(tmp, "cli.mp4")
    small = "demo:tornado?count=120"
    r = subprocess.run([binary, "movie", spec, "-o", mp4, "--input", small], capture_output=True, text=True,
                       timeout=120)
    p = probe(mp4)
    check(clean_exit(r) and p["frames"] == 3 and (p["width"], p["height"]) == (128, 96),
          "lucent movie writes 3 frames of 128x96: %s %s" % (p, r.stderr.strip()[-200:]))
    png = os.path.join(tmp, "f0.png")
    subprocess.run([binary, "render", "--input", small, "--size", "128x96", "-o", png], capture_output=True)
    got = frames_of(mp4, [0], (128, 96))
    if check(len(got) == 1 and os.path.exists(png), "frame 0 and the still decode"):
        from PIL import Image
        s = ssim(got[0], np.asarray(Image.open(png).convert("RGB")))
        check(s >= 0.95, "lucent movie's frame 0 matches lucent render of the same camera (SSIM %.4f)" % s)
    with open(spec, "w") as f:
        json.dump({"keyframes": [{"position": [0, 0, 5]}]}, f)
    r = subprocess.run([binary, "movie", spec, "-o", mp4], capture_output=True, text=True, timeout=120)
    check(r.returncode == 2 and "keyframes: a path needs at least two keyframes" in r.stderr,
          "lucent movie refuses one keyframe naming the field: %s" % r.stderr.strip())
finally:
    shutil.rmtree(tmp, ignore_errors=True)
check.done()
