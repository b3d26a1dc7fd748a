"""Helpers of the MPI tests (label mpi): mpirun's command line, image RMSE via
`lucent ssim`, the pixels of a PNG. mpirun refuses root unless told; the tests allow it through
Open MPI's environment variables so that the same command works as any user."""
import os
import re
import shutil
import subprocess

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
    import struct
    import zlib
    with open(path, "rb") as f:
        data = f.read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path + ": not a PNG"
    i, idat, w, h, ch = 8, b"", 0, 0, 3
    while i < len(data):
        n, kind = struct.unpack(">I4s", data[i:i + 8])
        body = data[i + 8:i + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and ctype in (2, 6), "%s: PNG type %d depth %d" % (path, ctype, depth)
            ch = 3 if ctype == 2 else 4
        elif kind == b"IDAT":
            idat += body
        i += 12 + n
    raw, stride, prev, pixels = zlib.decompress(idat), w * ch, bytearray(w * ch), []
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - ch] if x >= ch else 0
            b, c = prev[x], prev[x - ch] if x >= ch else 0
            p = {0: 0, 1: a, 2: b, 3: (a + b) // 2}.get(f)
            if p is None:  # Paeth
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                p = a if pa <= pb and pa <= pc else b if pb <= pc else c
            line[x] = (line[x] + p) & 255
        pixels += [tuple(line[x * ch:x * ch + 3]) for x in range(w)]
        prev = line
    return w, h, pixels
