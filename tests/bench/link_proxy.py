#!/usr/bin/env python3
"""An emulated wide-area link: a TCP proxy with a round-trip delay and a bottleneck rate.

Each direction of each connection is a link of its own: bytes read from one side wait in a
bounded queue (the bottleneck's buffer), leave it at the link rate (serialization), and reach
the other side one-way delay (RTT/2) later. A full queue stops the proxy reading, so the sender's
socket fills and it sees back-pressure, as behind a real bottleneck. The proxy's own sockets have
small buffers so that back-pressure is not hidden in them.

  link = Link(rtt_ms=100, mbit=5)                       # mbit 0: no rate limit
  port = link.start("127.0.0.1", 8080)                  # a thread of its own; connect to 127.0.0.1:port
  ... link.stats()["down_bytes"] ...                    # bytes delivered server -> client
  link.stop()

  tests/bench/link_proxy.py --rtt 100 --rate 5 --target 127.0.0.1:8080 --port 9090   (stand-alone)
"""
import argparse
import asyncio
import collections
import socket
import threading
import time

CHUNK = 4096           # bytes read at a time (about three packets)
SOCK_BUF = 64 << 10    # the proxy's socket buffers


class _Direction:
    """One direction of a connection: queue -> serializer -> delay line -> writer."""

    def __init__(self, link, reader, writer, counter):
        self.link, self.reader, self.writer, self.counter = link, reader, writer, counter
        self.queue = collections.deque()
        self.queued = 0
        self.room = asyncio.Event()
        self.room.set()
        self.ready = asyncio.Event()
        self.wire = asyncio.Queue()

    async def read(self):
        try:
            while True:
                data = await self.reader.read(CHUNK)
                if not data:
                    break
                while self.queued + len(data) > self.link.queue_bytes and self.queued > 0:
                    self.room.clear()
                    await self.room.wait()
                self.queue.append(data)
                self.queued += len(data)
                self.ready.set()
        finally:
            self.queue.append(None)
            self.ready.set()

    async def serialize(self):
        loop = asyncio.get_running_loop()
        free_at = loop.time()
        while True:
            while not self.queue:
                self.ready.clear()
                await self.ready.wait()
            data = self.queue.popleft()
            if data is None:
                await self.wire.put((free_at + self.link.delay, None))
                return
            now = loop.time()
            free_at = max(free_at, now) + (len(data) / self.link.rate if self.link.rate else 0.0)
            if free_at > now:
                await asyncio.sleep(free_at - now)
            self.queued -= len(data)
            self.room.set()
            await self.wire.put((free_at + self.link.delay, data))

    async def deliver(self):
        loop = asyncio.get_running_loop()
        try:
            while True:
                due, data = await self.wire.get()
                wait = due - loop.time()
                if wait > 0:
                    await asyncio.sleep(wait)
                if data is None:
                    break
                self.writer.write(data)
                self.counter[0] += len(data)
                await self.writer.drain()
        except (ConnectionError, OSError):
            pass
        finally:
            try:
                self.writer.close()
            except Exception:
                pass


class Link:
    """A link of rtt_ms round trip and mbit Mbit/s each way (0: unlimited), queue_ms of buffer at that rate."""

    def __init__(self, rtt_ms=0.0, mbit=0.0, queue_ms=100.0):
        self.rtt_ms, self.mbit = rtt_ms, mbit
        self.delay = rtt_ms / 2000.0
        self.rate = mbit * 1e6 / 8 if mbit else 0.0
        self.queue_bytes = max(16 << 10, int(self.rate * queue_ms / 1000.0)) if self.rate else 1 << 20
        self.down, self.up = [0], [0]   # bytes delivered server -> client, client -> server
        self.loop = self.thread = self.server = None

    def label(self):
        if not self.rtt_ms and not self.mbit:
            return "loopback"
        return "%g ms, %s" % (self.rtt_ms, "%g Mbit/s" % self.mbit if self.mbit else "no rate limit")

    def stats(self):
        return {"down_bytes": self.down[0], "up_bytes": self.up[0]}

    async def _handle(self, creader, cwriter, host, port):
        sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, SOCK_BUF)
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, SOCK_BUF)
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        sock.setblocking(False)
        try:
            await asyncio.get_running_loop().sock_connect(sock, (host, port))
        except OSError:
            sock.close()
            cwriter.close()
            return
        sreader, swriter = await asyncio.open_connection(sock=sock, limit=CHUNK)
        csock = cwriter.get_extra_info("socket")
        if csock is not None:
            csock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        tasks = []
        for d in (_Direction(self, sreader, cwriter, self.down), _Direction(self, creader, swriter, self.up)):
            tasks += [d.read(), d.serialize(), d.deliver()]
        await asyncio.gather(*tasks, return_exceptions=True)

    def start(self, host, port, listen_port=0):
        """Starts the proxy on a thread; returns the port it listens on (127.0.0.1)."""
        started = threading.Event()

        def main():
            self.loop = asyncio.new_event_loop()
            lsock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
            lsock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            lsock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, SOCK_BUF)  # inherited by accepted sockets
            lsock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, SOCK_BUF)
            lsock.bind(("127.0.0.1", listen_port))
            self.server = self.loop.run_until_complete(asyncio.start_server(
                lambda r, w: self._handle(r, w, host, port), sock=lsock, limit=CHUNK))
            self.port = lsock.getsockname()[1]
            started.set()
            self.loop.run_forever()

        self.thread = threading.Thread(target=main, daemon=True)
        self.thread.start()
        started.wait()
        return self.port

    def stop(self):
        if not self.loop:
            return

        async def close():
            self.server.close()
            tasks = [t for t in asyncio.all_tasks() if t is not asyncio.current_task()]
            for t in tasks:
                t.cancel()
            await asyncio.gather(*tasks, return_exceptions=True)

        asyncio.run_coroutine_threadsafe(close(), self.loop).result(10)
        self.loop.call_soon_threadsafe(self.loop.stop)
        self.thread.join(5)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rtt", type=float, default=100, help="round trip, ms")
    ap.add_argument("--rate", type=float, default=5, help="Mbit/s each way (0: unlimited)")
    ap.add_argument("--queue-ms", type=float, default=100, help="bottleneck buffer, ms at the rate")
    ap.add_argument("--target", default="127.0.0.1:8080")
    ap.add_argument("--port", type=int, default=9090)
    a = ap.parse_args()
    host, port = a.target.rsplit(":", 1)
    link = Link(a.rtt, a.rate, a.queue_ms)
    print("listening on 127.0.0.1:%d -> %s (%s)" % (link.start(host, int(port), a.port), a.target, link.label()))
    try:
        while True:
            time.sleep(1)
    except KeyboardInterrupt:
        link.stop()


if __name__ == "__main__":
    main()
