"""The issue's acceptance check of the client package: installed offline with
pip (Debian 12's python3-pip and python3-setuptools, no index) into a fresh
virtual environment that sees the apt packages (numpy, Pillow, websockets),
then `python3 -c "import lucent; c = lucent.Client(URL); a = c.render(
'demo:tornado', size=(640, 480)); print(a.shape)"` prints (480, 640, 3) and a
bad field raises an exception naming it. The package is copied first so the
build leaves nothing in the source tree."""
import os
import shutil
import subprocess
import sys
import tempfile

from lucent_server import Check, Server, skip

binary = sys.argv[1]
here = os.path.dirname(os.path.abspath(__file__))
check = Check()
python = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable
try:
    subprocess.run([python, "-c", "import ensurepip, numpy, PIL"], check=True, capture_output=True)
except subprocess.CalledProcessError:
    skip("python3-venv, python3-numpy or python3-pil is not installed")

with tempfile.TemporaryDirectory() as tmp:
    src = os.path.join(tmp, "src")
    shutil.copytree(os.path.join(here, ".."), src, ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__"))
    venv = os.path.join(tmp, "venv")
    # --without-pip and Debian's own pip pointed at the environment (--python):
    # the same install as the README's, without copying pip into the venv.
    r = subprocess.run([python, "-m", "venv", "--without-pip", "--system-site-packages", venv], capture_output=True,
                       text=True)
    check(r.returncode == 0, "python3 -m venv --system-site-packages (%s)" % r.stderr.strip()[-300:])
    pip = [python, "-m", "pip", "--python", os.path.join(venv, "bin", "python")]
    r = subprocess.run(pip + ["install", "--no-index", "--no-build-isolation", src], capture_output=True, text=True,
                       env=dict(os.environ, PIP_DISABLE_PIP_VERSION_CHECK="1"))
    check(r.returncode == 0 and "Successfully installed lucent" in r.stdout,
          "pip --python VENV install --no-index --no-build-isolation clients/python: %s" % (r.stdout + r.stderr).strip()[-400:])
    vpy = os.path.join(venv, "bin", "python")
    with Server(binary, data=("demo:tornado",), demo_size=120) as srv:
        env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
        code = ("import lucent; c = lucent.Client('%s'); a = c.render('demo:tornado', size=(640, 480)); "
                "print(a.shape)" % srv.base)
        r = subprocess.run([vpy, "-c", code], capture_output=True, text=True, cwd=tmp, env=env, timeout=120)
        check(r.returncode == 0 and r.stdout.strip() == "(480, 640, 3)", "the acceptance one-liner prints %r %s"
              % (r.stdout.strip(), r.stderr.strip()[-300:]))
        code = ("import lucent\ntry:\n lucent.Client('%s').render('demo:tornado', params={'bandz': 3})\n"
                "except lucent.LucentError as e:\n print(e.field, '|', e)\n" % srv.base)
        r = subprocess.run([vpy, "-c", code], capture_output=True, text=True, cwd=tmp, env=env, timeout=60)
        check(r.stdout.strip() == "params.bandz | params.bandz: unknown field",
              "a bad field raises naming it: %r" % r.stdout.strip())
        r = subprocess.run([vpy, "-c", "import lucent; print(lucent.__file__)"], capture_output=True, text=True,
                           cwd=tmp, env=env)
        check(r.stdout.startswith(venv), "lucent is imported from the installed copy: %s" % r.stdout.strip())
        check(srv.stop() == 0, "daemon exits cleanly")
check.done()
