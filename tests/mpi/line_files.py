"""Writes one set of helical streamlines as .binlines (with a speed attribute
that has a few far outliers), .tck (positions only), .trk (a per-point
scalar and a per-track property) and .trx (a stored zip: float32 positions,
uint32 offsets, speed per vertex, group per streamline), the line formats
`lucent render --mpi` reads in parts. Lines of varying length, a one-point line (dropped by every reader) and
a line with a NaN point (binlines and tck drop the point) exercise the
readers' filtering, which must give the same lines in parts as whole.
Usage: line_files.py FOLDER [LINES]  (also imported by the MPI tests)."""
import math
import os
import json
import struct
import sys
import zipfile

NAN = float("nan")


def make_lines(count=300):
    lines = []
    for k in range(count):
        n = 8 + (k * 37) % 90  # 8..97 points
        r = 0.2 + 0.8 * ((k * 0.618) % 1.0)
        phase = k * 0.9
        z0 = -1.0 + 2.0 * ((k * 0.377) % 1.0)
        pts, speed = [], []
        for i in range(n):
            t = i / (n - 1)
            a = phase + 6.0 * t
            pts.append((r * math.cos(a), r * math.sin(a), z0 + 0.6 * t))
            speed.append(r * (1.0 + t) if k % 97 else 1e4)  # lines 0, 97, 194: far outliers
        lines.append((pts, speed, float(k % 7)))
    lines.insert(5, ([(0.0, 0.0, 0.0)], [1.0], 0.0))  # one point: dropped
    pts, speed, prop = lines[40]
    pts = list(pts)
    pts[3] = (NAN, 0.0, 0.0)  # dropped by binlines and tck; trk refuses non-finite points
    lines[40] = (pts, speed, prop)
    return lines


def write_binlines(path, lines):
    with open(path, "wb") as f:
        f.write(struct.pack("<III", 2, len(lines), 1))
        name = b"speed"
        f.write(struct.pack("<I", len(name)) + name)
        for pts, speed, _ in lines:
            f.write(struct.pack("<I%df" % (4 * len(pts)), len(pts), *[c for p in pts for c in p], *speed))


def write_tck(path, lines):
    body = []
    for pts, _, _ in lines:
        body.append(struct.pack("<%df" % (3 * len(pts) + 3), *[c for p in pts for c in p], NAN, NAN, NAN))
    body.append(struct.pack("<3f", math.inf, math.inf, math.inf))
    body = b"".join(body)
    head = "mrtrix tracks\ncount: %d\ndatatype: Float32LE\n" % len(lines)
    off = 0
    while True:
        text = head + "file: . %d\nEND\n" % off
        if len(text) == off:
            break
        off = len(text)
    with open(path, "wb") as f:
        f.write(text.encode() + body)


def write_trk(path, lines):
    h = bytearray(1000)
    h[0:6] = b"TRACK\0"
    struct.pack_into("<3h", h, 6, 100, 100, 100)  # dim
    struct.pack_into("<3f", h, 12, 1.0, 1.0, 1.0)  # voxel size
    struct.pack_into("<h", h, 36, 1)  # n_scalars
    h[38:38 + 5] = b"speed"
    struct.pack_into("<h", h, 238, 1)  # n_properties
    h[240:240 + 5] = b"group"
    for i in range(4):  # vox_to_ras: identity
        struct.pack_into("<f", h, 440 + 4 * (5 * i), 1.0)
    h[948:952] = b"LAS\0"
    h[952:956] = b"LAS\0"
    count = sum(1 for pts, _, _ in lines)
    struct.pack_into("<i", h, 988, count)
    struct.pack_into("<i", h, 992, 2)  # version
    struct.pack_into("<i", h, 996, 1000)  # hdr_size
    body = [bytes(h)]
    for pts, speed, prop in lines:
        values = []
        for p, s in zip(pts, speed):
            p = tuple(0.0 if math.isnan(c) else c for c in p)
            # voxmm: shift into the positive octant (the reader maps voxmm to RAS+ mm)
            values += [50 + 40 * p[0], 50 + 40 * p[1], 50 + 40 * p[2], s]
        body.append(struct.pack("<i%df" % (len(values) + 1), len(pts), *values, prop))
    with open(path, "wb") as f:
        f.write(b"".join(body))


def write_trx(path, lines):
    pos, off, speed, group = [], [], [], []
    nv = 0
    for pts, sp, prop in lines:
        off.append(nv)
        pos += [c for p in pts for c in p]  # NaN stays: the reader drops the point
        speed += sp
        group.append(prop)
        nv += len(pts)
    header = {"NB_VERTICES": nv, "NB_STREAMLINES": len(lines), "DIMENSIONS": [1, 1, 1],
              "VOXEL_TO_RASMM": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}
    with zipfile.ZipFile(path, "w", zipfile.ZIP_STORED) as z:
        z.writestr("header.json", json.dumps(header))
        z.writestr("positions.3.float32", struct.pack("<%df" % len(pos), *pos))
        z.writestr("offsets.uint32", struct.pack("<%dI" % len(off), *off))
        z.writestr("dpv/speed.float32", struct.pack("<%df" % len(speed), *speed))
        z.writestr("dps/group.float32", struct.pack("<%df" % len(group), *group))


def write_all(folder, count=300):
    lines = make_lines(count)
    paths = {}
    for ext, writer in (("binlines", write_binlines), ("tck", write_tck), ("trk", write_trk), ("trx", write_trx)):
        paths[ext] = os.path.join(folder, "helices." + ext)
        writer(paths[ext], lines)
    return paths


if __name__ == "__main__":
    for p in write_all(sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 300).values():
        print(p)
