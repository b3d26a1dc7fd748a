"""Checks the layout rules of docs/ARCHITECTURE.md "Layers" on the source tree:
- every quoted #include of render/, protocol/ and server/ resolves within the
  including folder or the folders below it (the same rule the CMake include
  paths enforce, stated here so that a reader sees it in one place);
- no circle of modules that include each other (a module is a folder's x.c and
  x.h together, as a reader sees them);
- no C file there is longer than 900 lines;
- no tracked text file cites a path outside the repository (../shared, /work/).
Usage: check_layout.py SOURCE_DIR"""
import os
import re
import subprocess
import sys

src = os.path.abspath(sys.argv[1])
# folder -> the folders its files may include from (besides itself)
LAYERS = {
    "render/base": [],
    "render/math": ["render/base"],
    "render/scene": ["render/base"],
    "render/io": ["render/scene", "render/base"],
    "render/image": ["render/base"],
    "render/gl": ["render/scene", "render/math", "render/image", "render/base"],
    "protocol": ["render/base"],
    "server/mpi": ["render/gl", "render/scene", "render/math", "render/image", "render/base"],
    "server/daemon": ["server/mpi", "render/gl", "render/io", "render/scene", "render/math", "render/image", "render/base", "protocol"],
    "server/cli": ["server/mpi", "render/gl", "render/io", "render/scene", "render/math", "render/image", "render/base", "protocol"],
    "server": ["server/cli", "server/daemon", "server/mpi", "render/gl", "render/io", "render/scene", "render/math", "render/image",
               "render/base", "protocol"],
}
MAX_LINES = 900
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
        if name.endswith(".c") and text.count("\n") > MAX_LINES:
            fail("%s has %d lines (at most %d)" % (rel, text.count("\n"), MAX_LINES))
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
    fail("modules include each other in a circle: " + " <-> ".join(comp))

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

print("%d passed, %d failed" % (checks - len(failures), len(failures)))
sys.exit(1 if failures else 0)
