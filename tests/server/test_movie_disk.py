"""The movie folder holds --movie-disk bytes: finished movies are deleted
oldest first to make room for a new one, and a movie that alone outgrows the
budget fails with too_large (its partial file deleted) while the server goes on
making others."""
import sys
import time

from lucent_server import Check, Server

binary = sys.argv[1]
check = Check()
SMALL = {"frames": 3, "width": 64, "height": 48}


def finish(srv, job):
    """The job's final state (waits for a state; the deadline only bounds a stuck job)."""
    end = time.time() + 180
    while True:
        st, _, j = srv.json("GET", "/api/v1/movies/" + job["id"])
        if j.get("state") in ("done", "failed", "cancelled") or time.time() > end:
            return j
        time.sleep(0.2)


def make(srv, spec):
    st, _, job = srv.json("POST", "/api/v1/movies", spec)
    check(st == 202, "movie %dx%d x%d queued: %d %s" % (spec["width"], spec["height"], spec["frames"], st, job))
    return finish(srv, job) if st == 202 else {}


with Server(binary) as srv:
    size = make(srv, SMALL).get("bytes", 0)
check(size > 0, "a small movie takes %d bytes" % size)

budget = size * 5 // 2  # two small movies fit, a third does not
with Server(binary, "--movie-disk", str(budget)) as srv:
    jobs = [make(srv, SMALL) for _ in range(3)]
    check(all(j.get("state") == "done" for j in jobs), "three small movies done: %s" % [j.get("state") for j in jobs])
    st, _, lst = srv.json("GET", "/api/v1/movies")
    ids = [x["id"] for x in lst.get("movies", [])]
    check(ids == [jobs[1]["id"], jobs[2]["id"]], "the oldest was deleted to make room: %s" % ids)
    check(sum(x.get("bytes", 0) for x in lst.get("movies", [])) <= budget, "the folder holds at most the budget")
    st, _, _ = srv.json("GET", "/api/v1/movies/" + jobs[0]["id"])
    check(st == 404, "the deleted movie is gone: %d" % st)
    big = make(srv, {"frames": 24, "width": 320, "height": 240})
    err = big.get("error", {})
    check(big.get("state") == "failed" and err.get("code") == "too_large" and "--movie-disk" in err.get("message", ""),
          "a movie larger than the budget fails with too_large: %s" % big)
    after = make(srv, SMALL)
    check(after.get("state") == "done", "the next movie is made: %s" % after.get("state"))
check.done()
