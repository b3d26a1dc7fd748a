#!/usr/bin/env python3
"""Hostile dataset files of issue 32: small inputs that declare far more work
than their size. Writes them into OUT (default .): each is a valid container
(a deflated zip, a CSV) whose counts or contents are the attack.

  gen_hostile.py OUT [--large]

  zeros22.trx   24 KB TRX: 2^22 float16 vertices, all zero, in one streamline
  zeros24.trx   98 KB TRX: 2^24 of them (--large only)
  zeros16.trx   a 2^16 one, small enough for the fuzz corpus
  claims.trx    header.json declares 2^28 vertices, the arrays are empty
  zeros19.trx   2^19 zero vertices in one streamline: within the load
                budget, so it loads (level-of-detail and element stress)
"""
import json
import os
import struct
import sys
import zipfile


def trx(path, vertices, streamlines=1, positions=None):
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED, compresslevel=9) as z:
        z.writestr("header.json", json.dumps({"NB_VERTICES": vertices, "NB_STREAMLINES": streamlines,
                                              "DIMENSIONS": [1, 1, 1], "VOXEL_TO_RASMM": [[1, 0, 0, 0], [0, 1, 0, 0],
                                                                                          [0, 0, 1, 0], [0, 0, 0, 1]]}))
        z.writestr("positions.3.float16", bytes(vertices * 6) if positions is None else positions)
        offsets = [i * vertices // streamlines for i in range(streamlines)] + [vertices]
        z.writestr("offsets.uint64", b"".join(struct.pack("<Q", o) for o in offsets))


def write_all(out, large=False):
    os.makedirs(out, exist_ok=True)
    trx(os.path.join(out, "zeros22.trx"), 1 << 22)
    trx(os.path.join(out, "zeros16.trx"), 1 << 16)
    trx(os.path.join(out, "claims.trx"), 1 << 28, positions=b"")
    if large:
        trx(os.path.join(out, "zeros24.trx"), 1 << 24)
    trx(os.path.join(out, "zeros19.trx"), 1 << 19)


if __name__ == "__main__":
    write_all(sys.argv[1] if len(sys.argv) > 1 and sys.argv[1] != "--large" else ".", "--large" in sys.argv)
