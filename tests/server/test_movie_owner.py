"""Movie jobs belong to the client that made them: a second client (another
loopback address) neither sees the job in GET /api/v1/movies nor reads, fetches
or deletes it by its ID (404, as an unknown ID), while its maker can; the
maker's list holds only its own jobs."""
import http.client
import json
import sys
import time

from lucent_server import Check, Server

binary = sys.argv[1]
check = Check()


def call(srv, source, method, path, body=None):
    """(status, parsed JSON or raw bytes) from the client at address `source`."""
    conn = http.client.HTTPConnection(srv.host, srv.port, timeout=60, source_address=(source, 0))
    conn.request(method, path, body=json.dumps(body) if body is not None else None,
                 headers={"Content-Type": "application/json"} if body is not None else {})
    r = conn.getresponse()
    data = r.read()
    conn.close()
    try:
        return r.status, json.loads(data)
    except ValueError:
        return r.status, data


A, B = "127.0.0.1", "127.0.0.2"
with Server(binary) as srv:
    st, job = call(srv, A, "POST", "/api/v1/movies", {"frames": 3, "width": 64, "height": 48})
    check(st == 202 and job.get("id"), "A queues a movie: %d %r" % (st, job))
    jid = job.get("id", "x")
    st, other = call(srv, B, "POST", "/api/v1/movies", {"frames": 2, "width": 64, "height": 48})
    check(st == 202, "B queues one too: %d" % st)
    # A's job, done (a state; the deadline only bounds a stuck job)
    end = time.time() + 120
    while True:
        st, j = call(srv, A, "GET", "/api/v1/movies/" + jid)
        if j.get("state") in ("done", "failed", "cancelled") or time.time() > end:
            break
        time.sleep(0.2)
    check(j.get("state") == "done", "A's job finishes: %r" % j)
    st, lst = call(srv, A, "GET", "/api/v1/movies")
    ids = [x["id"] for x in lst.get("movies", [])]
    check(st == 200 and ids == [jid], "A's list holds A's job only: %s" % ids)
    st, lst = call(srv, B, "GET", "/api/v1/movies")
    ids = [x["id"] for x in lst.get("movies", [])]
    check(st == 200 and jid not in ids and other.get("id") in ids, "B's list holds B's job, not A's: %s" % ids)
    for method, path in (("GET", "/api/v1/movies/" + jid), ("GET", "/api/v1/movies/%s/file" % jid),
                         ("DELETE", "/api/v1/movies/" + jid)):
        st, e = call(srv, B, method, path)
        check(st == 404 and isinstance(e, dict) and e.get("error", {}).get("code") == "not_found",
              "B: %s %s -> 404 (%d)" % (method, path, st))
    st, data = call(srv, A, "GET", "/api/v1/movies/%s/file" % jid)
    check(st == 200 and isinstance(data, bytes) and len(data) > 100, "A fetches its file: %d" % st)
    st, e = call(srv, A, "DELETE", "/api/v1/movies/" + jid)
    check(st == 200 and e.get("state") == "deleted", "A deletes its job: %d %r" % (st, e))
check.done()
