"""Helpers of the MPI tests (label mpi): mpirun's command line, image RMSE via
`lucent ssim`, the pixels of a PNG. mpirun refuses root unless told; the tests allow it through
Open MPI's environment variables so that the same command works as any user."""
import os
import re
import shutil
import subprocess
import sys

MAX_RMSE = 1.0 / 255.0


def mpirun_env():
    env = dict(os.environ)
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    env.setdefault("OMPI_MCA_rmaps_base_oversubscribe", "1")
    # Shared memory without cross-process copies (CMA): containers often deny
    # process_vm_readv, and the tests' images are small.
    env.setdefault("OMPI_MCA_btl_vader_single_copy_mechanism", "none")
    return env


def mpirun(n):
    """The launcher prefix for n ranks on this host (more ranks than cores allowed)."""
    exe = shutil.which("mpirun")
    if not exe:
        return None
    return [exe, "--oversubscribe", "--bind-to", "none", "-np", str(n)]


def rmse(lucent, a, b):
    out = subprocess.run([lucent, "ssim", a, b], capture_output=True, text=True, check=True).stdout
    return float(re.search(r"rmse\s+([0-9.eE+-]+)", out).group(1))


def read_png(path):
    """An 8-bit RGB/RGBA PNG file -> (width, height, [(r, g, b) per pixel, rows top-down])."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "server"))
    from lucent_server import decode_png
    with open(path, "rb") as f:
        w, h, ch, rows = decode_png(f.read())
    return w, h, [tuple(row[x * ch:x * ch + 3]) for row in rows for x in range(w)]
