#!/usr/bin/env python3
"""Writes the LineVis .binlines cases of tests/data/loaders/binlines (run from
that folder). The files are committed; this script documents how they were made."""
import struct

# Two lines with attributes "speed" and "vorticity", and a one-point line (dropped).
LINES = [([(0, 0, 0), (1, 0, 0), (2, 0, 0)], [[1, 2, 3], [0.5, 0.5, 0.5]]),
         ([(0, 1, 0), (0, 2, 1.5)], [[4, 5], [0.25, 0.25]]),
         ([(9, 9, 9)], [[7], [7]])]
NAMES = [b"speed", b"vorticity"]


def binlines(version, lines, names, nattr=None, count=None):
    nattr = len(names) if nattr is None else nattr
    out = struct.pack("<3I", version, len(lines) if count is None else count, nattr)
    if version >= 2:
        for n in names:
            out += struct.pack("<I", len(n)) + n
    for pts, attrs in lines:
        out += struct.pack("<I", len(pts))
        for p in pts:
            out += struct.pack("<3f", *p)
        for a in attrs:
            out += struct.pack("<%df" % len(a), *a)
    return out


def write(path, data):
    with open(path, "wb") as f:
        f.write(data)


write("valid/v1.binlines", binlines(1, LINES, NAMES))
write("valid/v2.binlines", binlines(2, LINES, NAMES))
write("valid/v2_same_names.binlines", binlines(2, LINES, [b"a b", b"a b"]))
write("valid/v2_nan_point.binlines",
      binlines(2, [([(0, 0, 0), (float("nan"), 0, 0), (2, 0, 0), (1, 0, 0)], [[1, 9, 2, 3], [0, 0, 0, 0]])] + LINES[1:],
               NAMES))
write("valid/no_attributes.binlines", binlines(1, [(p, []) for p, _ in LINES], [], 0))
write("invalid/short.binlines", struct.pack("<2I", 1, 1))
write("invalid/bad_version.binlines", binlines(3, LINES, NAMES))
write("invalid/huge_line_count.binlines", binlines(1, LINES, NAMES, count=4000000000))
write("invalid/huge_point_count.binlines", struct.pack("<4I", 1, 1, 0, 0x7FFFFFFF) + b"\0" * 24)
write("invalid/truncated.binlines", binlines(2, LINES, NAMES)[:-9])
write("invalid/huge_name.binlines", struct.pack("<4I", 2, 1, 1, 1 << 20) + b"x" * 40)
write("invalid/name_past_end.binlines", struct.pack("<4I", 2, 1, 1, 100) + b"speed")
write("invalid/too_many_attributes.binlines", struct.pack("<3I", 1, 1, 100000) + b"\0" * 64)
write("invalid/no_lines.binlines", binlines(2, LINES[2:], NAMES))
write("invalid/missing_line.binlines", binlines(1, LINES, NAMES, count=4))
