"""Token, limits and error statuses one by one: 401 (header, query, WebSocket upgrade),
413, 400 too_deep, 405, 404, session cap (503 + Retry-After, WebSocket 1013 /
upgrade 503), render queue overload (503 + Retry-After), idle session timeout."""
import asyncio
import json
import sys
import threading

from lucent_server import Check, Server, skip, wait_until, websockets

if websockets is None:
    skip("python3-websockets is not installed")

binary = sys.argv[1]
check = Check()
TOKEN = "s3cret-token"
AUTH = {"Authorization": "Bearer " + TOKEN}

# --idle-timeout 5: the session cap is checked right after the two sessions
# are made, well within it, and their expiry is then waited for as a state.
# --pass-delay 150: a render takes over a second (eight passes), so the 8
# concurrent renders below overflow --max-queue 1 however fast the renderer.
with Server(binary, "--max-sessions", "2", "--max-body", "2048", "--max-queue", "1", "--idle-timeout", "5",
            "--pass-delay", "150", env={"LUCENT_TOKEN": TOKEN}) as srv:
    st, _, _ = srv.request("GET", "/api/v1/health")
    check(st == 200, "health needs no token")
    st, h, e = srv.json("GET", "/api/v1/datasets")
    check(st == 401 and e["error"]["code"] == "unauthorized" and "www-authenticate" in h, "no token -> 401")
    st, _, _ = srv.json("GET", "/api/v1/datasets", headers={"Authorization": "Bearer wrong"})
    check(st == 401, "wrong bearer token -> 401")
    st, _, _ = srv.json("GET", "/api/v1/datasets", headers=AUTH)
    check(st == 200, "Authorization: Bearer -> 200 (token from LUCENT_TOKEN)")
    st, _, _ = srv.request("GET", "/api/v1/render?width=32&height=32&format=jpeg&token=" + TOKEN)
    check(st == 200, "GET render with ?token= -> 200 (for <img>)")
    st, _, _ = srv.request("GET", "/metrics")
    check(st == 401, "metrics need the token")

    st, _, e = srv.json("POST", "/api/v1/render", "{" + " " * 4000 + "}", headers=AUTH)
    check(st == 413 and e["error"]["code"] == "too_large", "body above --max-body -> 413")
    deep = "[" * 40 + "]" * 40
    st, _, e = srv.json("POST", "/api/v1/render", '{"params":' + deep + "}", headers=AUTH)
    check(st == 400 and e["error"]["code"] == "too_deep", "JSON nesting 40 -> 400 too_deep")
    st, _, e = srv.json("POST", "/api/v1/render", {"width": 8192, "height": 4609}, headers=AUTH)
    check(st == 400 and e["error"]["field"] in ("width", "height", ""), "8192x4609 -> 400 (%s)" % e["error"]["message"])
    st, h, e = srv.json("POST", "/api/v1/health")
    check(st == 405 and h.get("allow") == "GET", "POST /api/v1/health -> 405")
    st, _, e = srv.json("GET", "/api/v1/sessions/0123456789abcdef0123456789abcdef", headers=AUTH)
    check(st == 404 and e["error"]["code"] == "not_found", "unknown session -> 404")

    # Session cap: two sessions, the third is refused.
    ids = []
    for i in range(2):
        st, _, s = srv.json("POST", "/api/v1/sessions", {"width": 32, "height": 32}, headers=AUTH)
        ids.append(s["session"])
    st, h, e = srv.json("POST", "/api/v1/sessions", {}, headers=AUTH)
    check(st == 503 and "retry-after" in h and e["error"]["code"] == "overloaded",
          "third session over --max-sessions 2 -> 503 with Retry-After")

    async def ws_checks():
        try:
            await websockets.connect(srv.ws_url + "?token=" + TOKEN)
            status = 101
        except websockets.InvalidStatusCode as ex:
            status = ex.status_code
        check(status == 503, "WebSocket upgrade while sessions are full -> 503 (%s)" % status)

    asyncio.run(ws_checks())

    # Idle timeout (5 s) frees the HTTP sessions: wait until health (which
    # touches no session) counts none, then the session's id is unknown.
    def http_sessions():
        st, _, health = srv.json("GET", "/api/v1/health")
        return health["sessions"]["http"] if st == 200 else -1
    gone = wait_until(lambda: http_sessions() == 0, 120, 0.25)
    check(gone, "the idle sessions expire (%d left)" % http_sessions())
    st, _, _ = srv.json("POST", "/api/v1/sessions/%s/render" % ids[0], {"dt": 0.1}, headers=AUTH)
    check(st == 404, "session unused past --idle-timeout is gone (404)")

    async def ws_auth():
        try:
            await websockets.connect(srv.ws_url + "?token=wrong")
            status = 101
        except websockets.InvalidStatusCode as ex:
            status = ex.status_code
        check(status == 401, "WebSocket with a wrong ?token= -> 401 (%s)" % status)
        # The upgrade itself needs the token (issue 12): hello alone is too late.
        try:
            await websockets.connect(srv.ws_url)
            status = 101
        except websockets.InvalidStatusCode as ex:
            status = ex.status_code
        check(status == 401, "WebSocket upgrade without a token -> 401 at the handshake (%s)" % status)
        async with websockets.connect(srv.ws_url, extra_headers=AUTH) as ws:
            await ws.send(json.dumps({"type": "hello", "dataset": "demo:points", "width": 32, "height": 32}))
            r = json.loads(await asyncio.wait_for(ws.recv(), 60))
            check(r["type"] == "ready", "token in the upgrade's Authorization header -> ready")

    asyncio.run(ws_auth())

    # Render queue overload: --max-queue 1, 8 concurrent requests of over a second each.
    results = []

    def one():
        st, h, body = srv.request("POST", "/api/v1/render", {"width": 256, "height": 256, "format": "jpeg"},
                                  headers=AUTH)
        results.append((st, h.get("retry-after"), h.get("content-type")))

    threads = [threading.Thread(target=one) for _ in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    ok = [r for r in results if r[0] == 200 and r[2] == "image/jpeg"]
    over = [r for r in results if r[0] == 503 and r[1]]
    check(len(ok) + len(over) == 8, "8 concurrent renders: each an image or 503+Retry-After (%s)" %
          sorted(r[0] for r in results))
    check(len(ok) >= 1 and len(over) >= 1, "%d images, %d overloaded" % (len(ok), len(over)))
    check(srv.stop() == 0, "clean exit")

check.done()
