"""The scene cache through the daemon (--cache DIR): the first start of a data
file writes a cache file, the second starts from it and serves the same
description and the same image bit for bit; a damaged cache file, a truncated
one, a touched data file and a changed data file each give a rebuild (the log
says why) with the same image, never a crash; files under 1 MB and
--cache off write nothing."""
import glob
import os
import shutil
import subprocess
import sys
import tempfile
import time

from lucent_server import Check, Server

binary = sys.argv[1]
check = Check()
tmp = tempfile.mkdtemp()
data = os.path.join(tmp, "flow.ply")
small = os.path.join(tmp, "small.ply")
cache = os.path.join(tmp, "cache")
for path, count in ((data, 60), (small, 4)):
    gen = subprocess.run([binary, "gen", "tornado", "-o", path, "--count", str(count)], capture_output=True, text=True)
    check(gen.returncode == 0, "lucent gen wrote %s (%s)" % (path, gen.stderr.strip()))
check(os.path.getsize(data) >= 1 << 20 > os.path.getsize(small), "one file over 1 MB, one under")
RENDER = "/api/v1/render?dataset=flow&width=160&height=120&format=png"


def start(*extra):
    """One start: (the log, the dataset's description, a PNG of it)."""
    with Server(binary, "--cache", cache, *extra, data=(data, small), demo_size=0) as srv:
        st, _, body = srv.json("GET", "/api/v1/datasets")
        info = {d["name"]: d for d in body["datasets"]}.get("flow", {})
        info.pop("memory", None)  # resident figures are not the scene's
        st2, _, png = srv.request("GET", RENDER)
        check(st == 200 and st2 == 200, "datasets %d, render %d" % (st, st2))
        check(srv.stop() == 0, "the daemon exits cleanly")
        return "\n".join(srv.log), info, png


def cache_files():
    return sorted(glob.glob(os.path.join(cache, "*.lcscene")))


log, info, png = start()
check("no scene cache yet" in log and "scene cache written" in log, "the first start writes the cache")
files = cache_files()
check(len(files) == 1 and os.path.basename(files[0]).startswith("flow.ply-"),
      "one cache file, for the file over 1 MB only: %r" % files)
check(not glob.glob(os.path.join(cache, "*.tmp")), "no temporary file left")

log, info2, png2 = start()
check("from the scene cache" in log and "(scene cache)" in log, "the second start reads the cache")
check(info2 == info, "the same description from the cache:\n%r\n%r" % (info, info2))
check(png2 == png, "the same image bit for bit from the cache")


def rebuilt(why, reason):
    log, info3, png3 = start()
    check("rebuilding the scene cache" in log and reason in log and "scene cache written" in log,
          "%s: rebuilt (log says %r)" % (why, reason))
    check(info3 == info and png3 == png, "%s: the same description and image after the rebuild" % why)
    log, _, png4 = start()
    check("from the scene cache" in log and png4 == png, "%s: the rebuilt cache serves the next start" % why)


f = cache_files()[0]
with open(f, "r+b") as fh:  # a flipped bit in the middle of the payload
    fh.seek(os.path.getsize(f) // 2)
    b = fh.read(1)
    fh.seek(-1, 1)
    fh.write(bytes([b[0] ^ 0x10]))
rebuilt("a damaged cache file", "corrupt")
with open(f, "r+b") as fh:
    fh.truncate(os.path.getsize(f) - 1000)
rebuilt("a truncated cache file", "corrupt")
with open(f, "wb") as fh:
    fh.write(b"LCSCENE\n" + b"\xff" * 200)
rebuilt("a cache file of garbage", "corrupt")
st = os.stat(data)
os.utime(data, ns=(st.st_atime_ns, st.st_mtime_ns + 2_000_000_000))
rebuilt("a touched data file", "modification time")
with open(data, "r+b") as fh:  # the same size and mtime, other bytes: the first vertex's x moves out to 5
    head = fh.read(4096)
    fh.seek(head.index(b"end_header\n") + len(b"end_header\n"))
    fh.write(b"\x00\x00\xa0\x40")
os.utime(data, ns=(st.st_atime_ns, st.st_mtime_ns + 2_000_000_000))
log, info5, png5 = start()
check("rebuilding the scene cache" in log and "content changed" in log, "a changed data file: rebuilt")
check(png5 != png, "the changed file renders differently (the cache did not hide the change)")

# --cache off: nothing read or written.
for g in cache_files():
    os.unlink(g)
log, _, png6 = start("--cache", "off")  # the later flag wins
check(not cache_files() and "scene cache" not in log, "--cache off writes nothing")
check(png6 == png5, "the same image without the cache")
shutil.rmtree(tmp, ignore_errors=True)
check.done()
