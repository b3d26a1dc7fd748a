#!/usr/bin/env python3
"""Writes the TRX cases of tests/data/loaders/trx (run from that folder): zip
archives (stored and deflated) and one directory. The files are committed;
this script documents how they were made."""
import json
import os
import shutil
import struct
import zipfile

# Streamlines of 2, 3 and 1 points (the last is dropped by the reader).
POINTS = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 2, 0), (0, 3, 1.5), (9, 9, 9)]
OFFSETS = [0, 2, 5]
FA = [0.5, 0.25, 1, 2, 3, 4]
COLOR = [(255, 0, 0), (0, 255, 0), (1, 2, 3), (4, 5, 6), (7, 8, 9), (0, 0, 0)]
LENGTH = [10, 20, 30]


def arrays(pos_fmt="f", pos_name="positions.3.float32", off_fmt="Q", off_name="offsets.uint64", sentinel=False,
           nv=None, ns=None, points=POINTS, offsets=OFFSETS, extra=None):
    files = {"header.json": json.dumps({"DIMENSIONS": [10, 10, 10], "VOXEL_TO_RASMM": [[1, 0, 0, 0], [0, 1, 0, 0],
                                        [0, 0, 1, 0], [0, 0, 0, 1]], "NB_VERTICES": len(points) if nv is None else nv,
                                        "NB_STREAMLINES": len(offsets) if ns is None else ns}).encode()}
    files[pos_name] = b"".join(struct.pack("<3" + pos_fmt, *(int(c) if pos_fmt == "i" else c for c in p)) for p in points)
    offs = list(offsets) + ([len(points)] if sentinel else [])
    files[off_name] = struct.pack("<%d%s" % (len(offs), off_fmt), *offs)
    files["dpv/fa.float32"] = struct.pack("<%df" % len(FA), *FA)
    files["dpv/color.3.uint8"] = bytes(sum(COLOR, ()))
    files["dps/length.float64"] = struct.pack("<3d", *LENGTH)
    files["groups/bundle.uint32"] = struct.pack("<2I", 0, 1)
    files.update(extra or {})
    return files


def write_zip(path, files, method=zipfile.ZIP_STORED):
    with zipfile.ZipFile(path, "w", method) as z:
        for name, data in files.items():
            if data is not None:
                z.writestr(name, data)


def write_dir(path, files):
    shutil.rmtree(path, ignore_errors=True)
    for name, data in files.items():
        os.makedirs(os.path.dirname(os.path.join(path, name)) or path, exist_ok=True)
        with open(os.path.join(path, name), "wb") as f:
            f.write(data)


write_zip("valid/f32.trx", arrays())
write_zip("valid/f16_deflated.trx", arrays("e", "positions.3.float16", "I", "offsets.uint32", sentinel=True),
          zipfile.ZIP_DEFLATED)
write_dir("valid/dir.trx", arrays("d", "positions.3.float64", "i", "offsets.int32"))
write_zip("valid/nan_point.trx", {k: v for k, v in arrays(points=[(0, 0, 0), (float("nan"), 0, 0), (1, 0, 0)] +
                                                           POINTS[2:], offsets=[0, 3, 6]).items() if k[:2] != "dp"})
with open("invalid/not_zip.trx", "wb") as f:
    f.write(b"PK\3\4 this is not a zip archive")
write_zip("invalid/no_header.trx", {k: v for k, v in arrays().items() if k != "header.json"})
write_zip("invalid/bad_json.trx", arrays(extra={"header.json": b'{"NB_VERTICES": 6,'}))
write_zip("invalid/no_counts.trx", arrays(extra={"header.json": b'{"NB_VERTICES": 6}'}))
write_zip("invalid/short_positions.trx", arrays(nv=7))
write_zip("invalid/huge_vertices.trx", arrays(nv=10 ** 12))
write_zip("invalid/bad_offsets.trx", arrays(offsets=[0, 5, 2]))
write_zip("invalid/int_positions.trx", arrays("i", "positions.3.int32"))
write_zip("invalid/bad_dpv.trx", arrays(extra={"dpv/fa.float32": struct.pack("<5f", 1, 2, 3, 4, 5)}))
write_zip("invalid/no_positions.trx", {k: v for k, v in arrays().items() if not k.startswith("positions")})
write_zip("invalid/bad_dtype.trx", arrays(extra={"dps/weird.complex64": b"\0" * 24}))
