"""container.dockerfile: docker/Dockerfile cannot drift from what is tested.
No Docker engine runs the suite, so container.rootfs (test_rootfs.sh) proves
the image's runtime stage in a debootstrap'd root. This check makes sure that
what it proves is what the Dockerfile does:
- every package the Dockerfile, scripts/setup.sh and the container test install
  comes from scripts/packages/*.txt through scripts/packages/names (no package
  names written anywhere else);
- the build stage builds with scripts/build.sh into build/ (the command
  scripts/test.sh builds the tested binary with), only adding -DLUCENT_TESTS=OFF;
- the runtime stage is docker/runtime-setup.sh, which the test runs too, and the
  binary and the entry point land where the test puts them;
- the user, port, listen address, health check, entry point and NVIDIA settings
  agree between the Dockerfile, runtime-setup.sh, entrypoint.sh, the test and
  docker/compose.yaml.
Usage: check_dockerfile.py SOURCE_DIR"""
import os
import re
import shlex
import sys

src = os.path.abspath(sys.argv[1])
failures = []
checks = 0


def check(ok, msg):
    global checks
    checks += 1
    if not ok:
        failures.append(msg)
        print("FAIL:", msg, file=sys.stderr)


def read(rel):
    with open(os.path.join(src, rel), encoding="utf-8") as f:
        return f.read()


def package_names(rel):
    """The names scripts/packages/names prints for one list."""
    names = []
    for line in read(rel).splitlines():
        line = re.sub(r"#.*", "", line)
        line = re.sub(r"\s", "", line)
        if line:
            names.append(line)
    return names


# ---- the lists themselves
LISTS = {k: "scripts/packages/%s.txt" % k for k in ("build", "runtime", "test")}
pkgs = {k: package_names(v) for k, v in LISTS.items()}
for kind, names in pkgs.items():
    check(names, "%s is empty" % LISTS[kind])
    for n in names:
        check(re.fullmatch(r"[a-z0-9][a-z0-9+.-]+", n), "%s: %r is not a Debian package name" % (LISTS[kind], n))
    check(len(names) == len(set(names)), "%s lists a package twice" % LISTS[kind])
for n in pkgs["runtime"]:
    check(not n.endswith("-dev") and n not in ("build-essential", "cmake", "pkg-config", "gcc", "clang"),
          "runtime.txt has a build package: %s" % n)
check(not set(pkgs["build"]) & set(pkgs["runtime"]),
      "build.txt and runtime.txt overlap: %s" % sorted(set(pkgs["build"]) & set(pkgs["runtime"])))
check("debootstrap" in pkgs["test"], "test.txt lacks debootstrap (container.rootfs needs it)")

# ---- Dockerfile: instructions (continuation lines joined), split into stages
text = read("docker/Dockerfile")
joined = re.sub(r"\\\n", " ", text)
instrs = []
for line in joined.splitlines():
    line = line.strip()
    if line and not line.startswith("#"):
        word, _, rest = line.partition(" ")
        instrs.append((word.upper(), rest.strip()))
stages = []
for word, rest in instrs:
    if word == "FROM":
        stages.append({"from": rest, "instrs": []})
    elif stages:
        stages[-1]["instrs"].append((word, rest))
check(len(stages) == 2, "docker/Dockerfile has %d stages, expected build and runtime" % len(stages))
build, runtime = stages[0], stages[-1]
check(re.match(r"debian:(12|bookworm)\b", build["from"]), "build stage is not Debian 12: %s" % build["from"])
check(re.match(r"debian:(12|bookworm)-slim\b", runtime["from"]), "runtime stage is not Debian 12 slim: %s"
      % runtime["from"])


def runs(stage):
    return [rest for word, rest in stage["instrs"] if word == "RUN"]


def by_word(stage, word):
    return [rest for w, rest in stage["instrs"] if w == word]


# Every apt-get install in the Dockerfile takes its packages from the lists only.
for m in re.finditer(r"apt-get\s+install\s+([^&;|]*)", joined):
    words = [w for w in m.group(1).split() if not w.startswith("-")]
    listed = " ".join(words)
    check(re.fullmatch(r"\$\(\S*scripts/packages/names(\s+\S*scripts/packages/\w+\.txt)+\)", listed),
          "docker/Dockerfile installs packages not through scripts/packages/names: %s" % listed)
build_installs = re.findall(r"scripts/packages/(\w+)\.txt", " ".join(runs(build)))
check(build_installs == ["build"], "the build stage should install scripts/packages/build.txt, installs %s"
      % build_installs)
check(any("apt-get" in r and "--no-install-recommends" in r for r in runs(build)),
      "the build stage installs recommends")

# The build command: scripts/build.sh build, as scripts/test.sh builds the tested binary.
build_cmds = [r for r in runs(build) if "scripts/build.sh" in r]
check(len(build_cmds) == 1, "the build stage should run scripts/build.sh once")
check(not any(re.search(r"(^|[\s;&])(cmake|make|ninja|gcc|cc)\s", r) for r in runs(build)),
      "the build stage calls the compiler or CMake directly instead of scripts/build.sh")
if build_cmds:
    call = shlex.split(build_cmds[0].split("&&")[0])
    check(call[:2] == ["scripts/build.sh", "build"], "the build stage runs %s, not scripts/build.sh build" % call)
    check(call[2:] == ["-DLUCENT_TESTS=OFF"], "the build stage passes options the tested build lacks: %s" % call[2:])
check(re.search(r"^scripts/build\.sh build$", read("scripts/test.sh"), re.M),
      "scripts/test.sh no longer builds the tested binary with 'scripts/build.sh build'")
check("option(LUCENT_TESTS" in read("CMakeLists.txt"), "CMakeLists.txt has no LUCENT_TESTS option")
# Sources copied into the build stage exist (a rename would break only the image).
for rest in by_word(build, "COPY") + by_word(runtime, "COPY"):
    if rest.startswith("--from"):
        continue
    for path in shlex.split(rest)[:-1]:
        check(os.path.exists(os.path.join(src, path)), "docker/Dockerfile copies %s, which does not exist" % path)

# The runtime stage: runtime-setup.sh and nothing else installs anything.
check(runs(runtime) and all("docker/runtime-setup.sh" in r for r in runs(runtime)),
      "the runtime stage should be docker/runtime-setup.sh only: %s" % runs(runtime))
check(not any("apt-get" in r for r in runs(runtime)), "the runtime stage runs apt-get itself")
copies = " ".join(by_word(runtime, "COPY"))
check(re.search(r"--from=build /lucent /usr/local/bin/lucent\b", copies),
      "the runtime stage should install the binary as /usr/local/bin/lucent")
check("docker/entrypoint.sh /usr/local/bin/lucent-entrypoint" in copies,
      "the runtime stage should install docker/entrypoint.sh as /usr/local/bin/lucent-entrypoint")

setup = read("docker/runtime-setup.sh")
check("scripts/packages/names" in setup and "scripts/packages/runtime.txt" in setup,
      "docker/runtime-setup.sh does not install scripts/packages/runtime.txt")
check("--no-install-recommends" in setup, "docker/runtime-setup.sh installs recommends")
check(re.search(r"useradd\b.*\blucent\b", setup.replace("\\\n", " ")), "docker/runtime-setup.sh creates no user lucent")
check("/usr/share/glvnd/egl_vendor.d/10_nvidia.json" in setup and "libEGL_nvidia.so.0" in setup,
      "docker/runtime-setup.sh does not register NVIDIA's EGL with glvnd")

# User, port, listen address, health check, entry point, NVIDIA.
check(by_word(runtime, "USER") == ["lucent"], "the runtime stage does not run as user lucent")
env = " ".join(by_word(runtime, "ENV"))
listen = re.search(r"LUCENT_LISTEN=(\S+)", env)
check(listen and listen.group(1).startswith("0.0.0.0:"), "ENV LUCENT_LISTEN should listen on 0.0.0.0 in the image")
port = listen.group(1).rsplit(":", 1)[1] if listen else None
check(by_word(runtime, "EXPOSE") == [port], "EXPOSE %s does not match LUCENT_LISTEN's port %s"
      % (by_word(runtime, "EXPOSE"), port))
check(re.search(r"NVIDIA_DRIVER_CAPABILITIES=\S*graphics", env), "NVIDIA_DRIVER_CAPABILITIES lacks graphics")
check("LUCENT_DATA=/data" in env, "ENV LUCENT_DATA=/data missing")
health = " ".join(by_word(runtime, "HEALTHCHECK"))
check('CMD ["/usr/local/bin/lucent-entrypoint", "health"]' in health,
      "HEALTHCHECK should run lucent-entrypoint health (the command container.rootfs runs)")
check(by_word(runtime, "ENTRYPOINT") == ['["/usr/local/bin/lucent-entrypoint"]'],
      "ENTRYPOINT should be /usr/local/bin/lucent-entrypoint")
entry = read("docker/entrypoint.sh")
check("/api/v1/health" in entry, "docker/entrypoint.sh health does not ask /api/v1/health")
check("LUCENT_LISTEN:-0.0.0.0:%s" % port in entry, "docker/entrypoint.sh's default listen address differs")

# The container test runs the same steps.
test = read("tests/container/test_rootfs.sh")
for needle, what in [("scripts/packages/runtime.txt", "the runtime list"),
                     ("/opt/lucent-setup/docker/runtime-setup.sh", "docker/runtime-setup.sh"),
                     ('"$root/usr/local/bin/lucent"', "the binary at /usr/local/bin/lucent"),
                     ('"$src/docker/entrypoint.sh" "$root/usr/local/bin/lucent-entrypoint"', "the entry point"),
                     ("--userspec=lucent:lucent", "the user lucent"),
                     ("lucent-entrypoint health", "the HEALTHCHECK command"),
                     ("--variant=minbase", "a minbase root (what debian:12-slim is)")]:
    check(needle in test, "tests/container/test_rootfs.sh does not use %s (%s)" % (what, needle))
for var in re.findall(r"(NVIDIA_\w+=\S+)", env):
    check(var in test, "the container test does not set the image's %s" % var)

# scripts/setup.sh reads the same lists.
setup_sh = read("scripts/setup.sh")
for kind in LISTS:
    check(LISTS[kind] in setup_sh, "scripts/setup.sh does not read %s" % LISTS[kind])
check("scripts/packages/names" in setup_sh, "scripts/setup.sh does not read the lists with scripts/packages/names")
code = re.sub(r"#.*", "", setup_sh)
for n in pkgs["build"] + pkgs["runtime"]:
    check(not re.search(r"(?<![\w.-])%s(?![\w.-])" % re.escape(n), code),
          "scripts/setup.sh names %s itself instead of reading it from the lists" % n)

# docker/compose.yaml: a CPU and a GPU service on this Dockerfile, /data, the token.
try:
    import yaml
except ImportError:
    yaml = None
if yaml is None:
    print("note: python3-yaml missing; docker/compose.yaml not checked")
else:
    compose = yaml.safe_load(read("docker/compose.yaml"))
    services = compose.get("services", {})
    check(set(services) == {"lucent-cpu", "lucent-gpu"}, "compose services: %s" % sorted(services))
    for name, svc in services.items():
        b = svc.get("build", {})
        check(os.path.normpath(os.path.join(src, "docker", b.get("context", ""), b.get("dockerfile", "")))
              == os.path.join(src, "docker", "Dockerfile"), "%s does not build docker/Dockerfile" % name)
        check(any((v.get("target") if isinstance(v, dict) else v.split(":")[1]) == "/data"
                  for v in svc.get("volumes", [])), "%s mounts no /data" % name)
        check("LUCENT_TOKEN" in svc.get("environment", {}), "%s sets no LUCENT_TOKEN" % name)
        check(any(str(p).endswith(":%s" % port) for p in svc.get("ports", [])), "%s does not publish %s" % (name, port))
    devices = (services.get("lucent-gpu", {}).get("deploy", {}).get("resources", {}).get("reservations", {})
               .get("devices", []))
    check(any(d.get("driver") == "nvidia" and "gpu" in d.get("capabilities", []) for d in devices),
          "lucent-gpu reserves no NVIDIA GPU")
    check("deploy" not in services.get("lucent-cpu", {}), "lucent-cpu reserves devices")

print("%d passed, %d failed" % (checks - len(failures), len(failures)))
sys.exit(1 if failures else 0)
