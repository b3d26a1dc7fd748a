"""Every numeric flag of every `lucent` command refuses garbage and out-of-range
values with exit status 2 and a message that names the flag. The flags come
from the commands' own option tables (`lucent CMD --list-flags`); the ranges of
the flags that set request fields come from `lucent schema`, the protocol's
field table. A valid value of each flag must pass (followed by --list-flags,
which ends the command with status 0 before it does any work), so the test
cannot pass by refusing everything.
Usage: test_flags.py LUCENT"""
import concurrent.futures
import json
import subprocess
import sys

lucent = sys.argv[1]
COMMANDS = ["render", "bench", "compare", "gen", "info", "serve", "movie"]
# Valid values of the numeric flags whose value is not a plain number.
SAMPLES = {"--size": "64x48", "--sizes": "64x48,32x24", "--max-memory": "1G", "--listen": "127.0.0.1:0",
           "--background": "0,0.5,1"}
failures = []
checks = 0


def run(args):
    try:
        p = subprocess.run([lucent] + args, capture_output=True, text=True, timeout=60)
    except subprocess.TimeoutExpired:
        return None, "timed out (the value was taken and the command started)"
    return p.returncode, p.stdout + p.stderr


def fail(msg):
    failures.append(msg)
    print("FAIL:", msg, file=sys.stderr)


def schema_fields():
    rc, out = run(["schema"])
    if rc != 0:
        sys.exit("lucent schema failed: %s" % out)
    return {f["alias"]: f for f in json.loads(out) if f.get("alias")}


schema = schema_fields()
# (command, flag, kind, lo, hi) of every numeric flag. The shared table of
# render, bench and compare (cli.c) is checked once, under render.
flags, seen_shared, jobs = [], set(), []
for cmd in COMMANDS:
    rc, out = run([cmd, "--list-flags"])
    if rc != 0:
        fail("%s --list-flags: exit %s: %s" % (cmd, rc, out))
        continue
    lines = out.splitlines()
    own = lines[: next((i for i, l in enumerate(lines) if l.startswith("--request ")), len(lines))]
    for line in lines:
        name, kind, lo, hi, key = line.split()
        if line not in own:
            if name in seen_shared:
                continue
            seen_shared.add(name)
        if kind in ("int", "real"):
            lo, hi = float(lo), float(hi)
        elif kind == "call" and key in schema and schema[key]["type"] in ("int", "num", "color"):
            lo, hi = schema[key].get("min"), schema[key].get("max")
            kind = "int" if schema[key]["type"] == "int" else "real"
        elif kind == "number":
            lo, hi = None, None
        else:
            continue
        flags.append((cmd, name, kind, lo, hi))

for cmd, name, kind, lo, hi in flags:
    bad = ["abc", "1e999", "12junk"]
    if lo is None or lo > -1:
        bad.append("-1")  # the table's range says where -1 is valid (then it is skipped)
    if hi is not None and hi < 1e19:
        bad.append("99999999999999999999")
    if kind == "int":
        bad.append("1.5")
    for value in bad:
        jobs.append((cmd, name, value, False))
    good = SAMPLES.get(name)
    if good is None:  # the top of the range, else one above the bottom (some minima are exclusive)
        top = hi if hi is not None else (lo or 0) + 1
        good = "%d" % top if kind == "int" else repr(top)
    jobs.append((cmd, name, good, True))
for cmd in COMMANDS:  # --flag=value is the same flag
    first = next((f for f in flags if f[0] == cmd), None)
    if first:
        jobs.append((cmd, first[1] + "=abc", None, False))


def check(job):
    cmd, name, value, valid = job
    args = [cmd, name] + ([] if value is None else [value]) + (["--list-flags"] if valid else [])
    rc, out = run(args)
    flag = name.split("=")[0]
    if valid and rc != 0:
        return "lucent %s (a valid value): exit %s, %s" % (" ".join(args), rc, out.strip()[:200])
    if not valid and (rc != 2 or flag not in out):
        return "lucent %s: exit %s, %s" % (" ".join(args), rc, out.strip()[:200] or "no message")
    return None


with concurrent.futures.ThreadPoolExecutor(4) as pool:
    for msg in pool.map(check, jobs):
        checks += 1
        if msg:
            fail(msg)

if len(flags) < 40:
    fail("only %d numeric flags listed; the tables were not read" % len(flags))
print("%d numeric flags of %d commands, %d checks, %d failures" % (len(flags), len(COMMANDS), checks, len(failures)))
sys.exit(1 if failures else 0)
