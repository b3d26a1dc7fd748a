"""The ordered shutdown under connections, repeated: SIGTERM while a WebSocket
session streams and HTTP keep-alive connections sit idle ends the daemon with
status 0 every time.

Why repeated, and the epoll check: with epoll and its own threads,
libmicrohttpd 0.9.75's quiesce (the shutdown's first step) races each worker
thread's removal of the listening socket from that worker's epoll set, and the
loser panics (a fresh-clone CI run aborted a shutdown with "Failed to remove
listen FD from epoll set"). The daemon therefore runs libmicrohttpd on poll();
the one epoll instance it holds is the WebSocket loop's (server/daemon/stream/
ws.c), which a /proc listing checks deterministically, where the race itself
shows only now and then."""
import asyncio
import http.client
import json
import sys

from lucent_server import DEADLINE, Check, Server, skip, websockets

if websockets is None:
    skip("python3-websockets is not installed")

binary = sys.argv[1]
check = Check()
ROUNDS = 12


async def round_(r):
    srv = Server(binary)
    if r == 0:
        n = srv.open_files().count("anon_inode:[eventpoll]")
        check(n == 1, "libmicrohttpd runs on poll: one epoll instance, the WebSocket loop's (%d)" % n)
    idle = []
    for _ in range(3):  # keep-alive connections that have had an answer and stay open
        c = http.client.HTTPConnection(srv.host, srv.port, timeout=60)
        c.request("GET", "/api/v1/health")
        c.getresponse().read()
        idle.append(c)
    ws = await websockets.connect(srv.ws_url, max_size=None)
    await ws.send(json.dumps({"type": "hello", "dataset": "demo:points", "width": 96, "height": 64}))
    while not isinstance(await asyncio.wait_for(ws.recv(), DEADLINE), bytes):  # the session streams
        pass
    rc = await asyncio.get_running_loop().run_in_executor(None, srv.stop)
    for c in idle:
        c.close()
    await ws.close()
    return check(rc == 0, "round %d: SIGTERM with a streaming session and idle connections: status 0 (%s)" %
                 (r + 1, rc))


async def main():
    for r in range(ROUNDS):
        if not await round_(r):
            break


asyncio.run(main())
check.done()
