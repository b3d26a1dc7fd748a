"""Checks the layout rules of docs/ARCHITECTURE.md "Layers" on the source tree:
- every quoted #include of render/, protocol/ and server/ resolves within the
  including folder or the folders below it (the same rule the CMake include
  paths enforce, stated here so that a reader sees it in one place);
- no circle of modules that include or call each other (a module is a
  folder's x.c and x.h together, as a reader sees them; a call is read from
  the link-level symbols of the built libraries, so that a call made through
  a macro or a header's inline wrapper counts too: module A calls B when A's
  object file needs a global symbol that B's object file defines);
- no C file there is longer than 900 lines, none in server/ longer than 700;
- no tracked text file cites a path outside the repository (../shared, /work/);
- docs/ARCHITECTURE.md "File map" is the one file map: every C file and header
  of render/, protocol/ and server/, every shader, the page's files (web/*.html,
  .css, .js and web/js/*.js), the Python package's modules, scripts/*.sh and
  scripts/*.py and every folder of tests/ stands in the first column of one of
  its table rows, exactly once; and every repository path the section names in
  backticks exists.
Usage: check_layout.py SOURCE_DIR [FOLDER=LIBRARY.a ...]
(each FOLDER=LIBRARY.a names the static library built from that folder; the
call circles are checked over the libraries given)"""
import os
import re
import subprocess
import sys

src = os.path.abspath(sys.argv[1])
# folder -> the folders its files may include from (besides itself)
LAYERS = {
    "render/base": [],
    "render/math": ["render/base"],
    "render/field": ["render/base"],
    "render/scene": ["render/field", "render/base"],
    "render/io": ["render/scene", "render/field", "render/base"],
    "render/image": ["render/base"],
    "render/gl": ["render/scene", "render/field", "render/math", "render/image", "render/base"],
    "protocol": ["render/base"],
    "server/mpi": ["render/gl", "render/scene", "render/math", "render/image", "render/base"],
    "server/daemon": ["server/mpi", "render/gl", "render/io", "render/scene", "render/field", "render/math", "render/image", "render/base", "protocol"],
    "server/cli": ["server/mpi", "render/gl", "render/io", "render/scene", "render/field", "render/math", "render/image", "render/base", "protocol"],
    "server": ["server/cli", "server/daemon", "server/mpi", "render/gl", "render/io", "render/scene", "render/field", "render/math", "render/image",
               "render/base", "protocol"],
}
# server/daemon's rooms (http/, stream/, pool/) share its layer; which of them
# stands above which is the circle check's to say.
DAEMON_ROOMS = ["server/daemon/http", "server/daemon/stream", "server/daemon/pool", "server/daemon/data", "server/daemon/start"]
for room in DAEMON_ROOMS:
    LAYERS[room] = ["server/daemon"] + [r for r in DAEMON_ROOMS if r != room] + LAYERS["server/daemon"]
LAYERS["server/daemon"] = DAEMON_ROOMS + LAYERS["server/daemon"]
LAYERS["server"] = DAEMON_ROOMS + LAYERS["server"]
MAX_LINES = 900
# Folders moving to a tighter cap (the longest file first to split by role).
MAX_LINES_IN = {"server": 700}
failures = []
checks = 0


def fail(msg):
    failures.append(msg)
    print("FAIL:", msg, file=sys.stderr)


def files_in(folder):
    d = os.path.join(src, folder)
    return sorted(f for f in os.listdir(d) if f.endswith((".c", ".h")) and os.path.isfile(os.path.join(d, f)))


headers = {folder: set(f for f in files_in(folder) if f.endswith(".h")) for folder in LAYERS}
edges = {}  # module -> set(module); module = folder/stem
for folder in LAYERS:
    for name in files_in(folder):
        path = os.path.join(src, folder, name)
        with open(path, encoding="utf-8") as f:
            text = f.read()
        rel = "%s/%s" % (folder, name)
        checks += 1
        cap = next((n for top, n in MAX_LINES_IN.items() if folder == top or folder.startswith(top + "/")), MAX_LINES)
        if name.endswith(".c") and text.count("\n") > cap:
            fail("%s has %d lines (at most %d)" % (rel, text.count("\n"), cap))
        module = "%s/%s" % (folder, os.path.splitext(name)[0])
        edges.setdefault(module, set())
        for inc in re.findall(r'^\s*#\s*include\s+"([^"]+)"', text, re.M):
            checks += 1
            home = next((d for d in [folder] + LAYERS[folder] if inc in headers[d]), None)
            if home is None:
                owner = next((d for d in LAYERS if inc in headers[d]), None)
                if owner:
                    fail("%s includes %s from %s, which is not below it" % (rel, inc, owner))
                continue  # generated or system-like header (e.g. from the build folder)
            target = "%s/%s" % (home, os.path.splitext(inc)[0])
            if target != module:
                edges[module].add(target)

# Calls between modules, from the built libraries' symbols (nm): an object
# file's undefined global symbols against the ones each object file defines.
kinds = {}  # (a, b) -> "include" / "call" / both, for the message
for a, targets in edges.items():
    for b in targets:
        kinds[(a, b)] = "includes"
libraries = [arg.split("=", 1) for arg in sys.argv[2:]]
defined, needed = {}, {}  # symbol -> module; module -> set(symbol)
for folder, lib in libraries:
    checks += 1
    if not os.path.isfile(lib):
        fail("%s (the library of %s) is not built" % (lib, folder))
        continue
    out = subprocess.check_output(["nm", "-A", "--defined-only", "-g", lib], text=True)
    und = subprocess.check_output(["nm", "-A", "-u", lib], text=True)
    for text, table in ((out, "def"), (und, "und")):
        for line in text.splitlines():
            # "lib.a:member.c.o:0000000000000000 T name" or "lib.a:member.c.o:                 U name"
            parts = line.split(":")
            if len(parts) < 3:
                continue
            member, fields = parts[-2], parts[-1].split()
            if not member.endswith(".c.o") or not fields:
                continue
            stem = member[:-len(".c.o")]
            # The library of a folder also holds its rooms' subfolders (server/daemon/http, ...).
            home = next((f for f in [folder] + [r for r in LAYERS if r.startswith(folder + "/")]
                         if os.path.isfile(os.path.join(src, f, stem + ".c"))), None)
            if home is None:
                continue  # generated (embedded shaders, web files)
            module = "%s/%s" % (home, stem)
            if table == "def":
                defined.setdefault(fields[-1], set()).add(module)
            else:
                needed.setdefault(module, set()).add(fields[-1])
for a, symbols in needed.items():
    for sym in symbols:
        owners = defined.get(sym, set())
        if len(owners) != 1:
            continue  # a system symbol, or a name defined twice (lc_mpi.c and lc_mpi_none.c)
        b = next(iter(owners))
        if b != a:
            edges.setdefault(a, set()).add(b)
            if "calls" not in kinds.get((a, b), ""):
                kinds[(a, b)] = "includes and calls" if kinds.get((a, b)) == "includes" else "calls"
            kinds.setdefault(("sym", a, b), sym)

# Circles: Tarjan's strongly connected components.
index, low, stack, on, comps, counter = {}, {}, [], set(), [], [0]


def visit(v):
    index[v] = low[v] = counter[0]
    counter[0] += 1
    stack.append(v)
    on.add(v)
    for w in edges.get(v, ()):
        if w not in index:
            visit(w)
            low[v] = min(low[v], low[w])
        elif w in on:
            low[v] = min(low[v], index[w])
    if low[v] == index[v]:
        comp = []
        while True:
            w = stack.pop()
            on.discard(w)
            comp.append(w)
            if w == v:
                break
        if len(comp) > 1:
            comps.append(sorted(comp))


sys.setrecursionlimit(10000)
for v in list(edges):
    if v not in index:
        visit(v)
checks += 1
for comp in comps:
    ties = ["%s %s %s%s" % (a, kinds.get((a, b), "->"), b,
                            " (%s)" % kinds[("sym", a, b)] if ("sym", a, b) in kinds else "")
            for a in comp for b in sorted(edges.get(a, ())) if b in comp]
    fail("modules include or call each other in a circle: " + " <-> ".join(comp) + ": " + "; ".join(ties))

# Paths outside the repository.
tracked = subprocess.check_output(["git", "-C", src, "ls-files"], text=True).split("\n")
outside = re.compile(r"\.\./shared|/work/")
for rel in tracked:
    if not rel or rel.startswith("tests/tools/check_layout.py") or rel.startswith("tests/fuzz/corpus"):
        continue
    path = os.path.join(src, rel)
    if not os.path.isfile(path) or os.path.getsize(path) > 2_000_000:
        continue
    with open(path, "rb") as f:
        data = f.read()
    if b"\0" in data:
        continue
    checks += 1
    m = outside.search(data.decode("utf-8", "replace"))
    if m:
        fail("%s cites a path outside the repository (%s)" % (rel, m.group(0)))

# The file map: docs/ARCHITECTURE.md's section "## File map" up to the next "## ".
MAP_DOC = "docs/ARCHITECTURE.md"
MAP_TOPS = ("render/", "protocol/", "server/", "web/", "clients/", "scripts/", "tests/", "docker/", "cmake/", "docs/",
            ".ci/", "CMakeLists.txt", ".clang-format")


def map_required():
    """The source files (and tests/ folders) the file map must list, as repository paths."""
    out = set()

    def add(folder, ends, recurse=True):
        top = os.path.join(src, folder)
        for root, dirs, names in os.walk(top):
            dirs[:] = sorted(d for d in dirs if not d.startswith((".", "__")) and d != "node_modules") if recurse else []
            for name in names:
                if name.endswith(ends) and not name.startswith("."):
                    out.add(os.path.relpath(os.path.join(root, name), src))

    add("render", (".c", ".h", ".glsl"))
    add("protocol", (".c", ".h"))
    add("server", (".c", ".h"))
    add("web", (".html", ".css", ".js"), recurse=False)
    add("web/js", (".js",))
    add("clients/python/lucent", (".py",))
    add("scripts", (".sh", ".py"), recurse=False)
    tests = os.path.join(src, "tests")
    out.update("tests/%s/" % d for d in os.listdir(tests)
               if os.path.isdir(os.path.join(tests, d)) and not d.startswith((".", "__")))
    return out


with open(os.path.join(src, MAP_DOC), encoding="utf-8") as f:
    doc = f.read().split("\n")
start = next((i for i, line in enumerate(doc) if line.strip() == "## File map"), None)
checks += 1
if start is None:
    fail('%s has no section "## File map"' % MAP_DOC)
else:
    end = next((i for i in range(start + 1, len(doc)) if doc[i].startswith("## ")), len(doc))
    listed, named = {}, set()
    for line in doc[start:end]:
        for p in re.findall(r"`([^`\s]+)`", line):
            if p.startswith(MAP_TOPS) and "*" not in p:
                named.add(p)
        cells = line.split("|")
        if line.startswith("|") and len(cells) > 2 and not set(cells[1].strip()) <= set("-: "):
            for p in re.findall(r"`([^`\s]+)`", cells[1]):
                if p.startswith(MAP_TOPS):
                    listed[p] = listed.get(p, 0) + 1
    for p in sorted(map_required()):
        checks += 1
        if p not in listed:
            fail("%s is missing from the file map (%s \"File map\"): add a row with its role" % (p, MAP_DOC))
    for p, n in sorted(listed.items()):
        checks += 1
        if n > 1:
            fail("%s is listed %d times in the file map (%s): once" % (p, n, MAP_DOC))
    for p in sorted(named):
        checks += 1
        full = os.path.join(src, p)
        if not (os.path.isdir(full) if p.endswith("/") else os.path.exists(full)):
            fail("the file map (%s) names %s, which does not exist" % (MAP_DOC, p))

print("%d passed, %d failed" % (checks - len(failures), len(failures)))
sys.exit(1 if failures else 0)
