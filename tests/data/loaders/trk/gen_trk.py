#!/usr/bin/env python3
"""Writes the TrackVis cases of tests/data/loaders/trk (run from that folder).
The files are committed; this script documents how they were made."""
import math
import struct


def name_table(names):
    out = b""
    for n in names[:10]:
        out += n.ljust(20, b"\0")[:20]
    return out.ljust(200, b"\0")


def header(e="<", n_scalars=0, scalar_names=(), n_properties=0, property_names=(), n_count=0, hdr_size=1000,
           magic=b"TRACK\0", voxel_size=(2.0, 2.0, 3.0), order=b"LAS", vox_to_ras=(2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 3, 0, 0, 0, 0, 1),
           version=2):
    h = magic + struct.pack(e + "3h3f3f", 64, 64, 32, *voxel_size, 0, 0, 0)
    h += struct.pack(e + "h", n_scalars) + name_table(list(scalar_names))
    h += struct.pack(e + "h", n_properties) + name_table(list(property_names))
    h += struct.pack(e + "16f", *vox_to_ras)
    h += b"\0" * 444 + order.ljust(4, b"\0") + b"\0" * 4 + struct.pack(e + "6f", 1, 0, 0, 0, 1, 0) + b"\0" * 2 + b"\0" * 6
    h += struct.pack(e + "3i", n_count, version, hdr_size)
    assert len(h) == 1000, len(h)
    return h


def track(e, points, props=()):
    out = struct.pack(e + "i", len(points))
    for p in points:
        out += struct.pack(e + "%df" % len(p), *p)
    return out + struct.pack(e + "%df" % len(props), *props)


# x y z, then fa and a 3-value "col" scalar; one "length" property per track.
TRACKS = [([(0, 0, 0, 0.1, 1, 2, 3), (1, 0, 0, 0.2, 1, 2, 3), (2, 0, 0, 0.3, 1, 2, 3)], [10.0]),
          ([(5, 5, 5, 0.9, 0, 0, 0)], [1.0]),  # one point: dropped
          ([(0, 1, 0, 0.4, 4, 5, 6), (0, 2, 0, 0.5, 4, 5, 6), (0, 3, 0, 0.6, 4, 5, 6), (0, 4, 1, 0.7, 4, 5, 6)],
           [20.0])]


def tracts(e, n_count):
    out = header(e, 4, [b"fa", b"col\0003"], 1, [b"length"], n_count)
    for pts, props in TRACKS:
        out += track(e, pts, props)
    return out


def write(path, data):
    with open(path, "wb") as f:
        f.write(data)


write("valid/tracts_le.trk", tracts("<", 3))
write("valid/tracts_be.trk", tracts(">", 0))
write("valid/unnamed.trk", header("<", 1, [], 0, [], 1) + track("<", [(0, 0, 0, 7), (1, 1, 1, 8)]))
write("invalid/short.trk", header()[:500])
write("invalid/bad_magic.trk", header(magic=b"TRACX\0") + track("<", [(0, 0, 0), (1, 1, 1)]))
write("invalid/bad_hdr_size.trk", header(hdr_size=999) + track("<", [(0, 0, 0), (1, 1, 1)]))
write("invalid/huge_n_count.trk", header(n_count=2000000000) + track("<", [(0, 0, 0), (1, 1, 1)]))
write("invalid/huge_track.trk", header() + struct.pack("<i", 100000000) + struct.pack("<6f", 0, 0, 0, 1, 1, 1))
write("invalid/negative_points.trk", header() + struct.pack("<i", -3))
write("invalid/negative_scalars.trk", header(n_scalars=-1) + track("<", [(0, 0, 0), (1, 1, 1)]))
write("invalid/truncated.trk", header() + track("<", [(0, 0, 0), (1, 1, 1)]) +
      struct.pack("<i", 4) + struct.pack("<9f", 0, 0, 0, 1, 1, 1, 2, 2, 2))
write("invalid/trailing_bytes.trk", header() + track("<", [(0, 0, 0), (1, 1, 1)]) + b"\1\0")
write("invalid/nan_point.trk", header(">") + track(">", [(0, 0, 0), (1, math.inf, 1)]))
write("invalid/no_tracks.trk", header() + track("<", [(1, 2, 3)]))

# World space (nibabel's rules): a rotated, shifted vox_to_ras whose axes run
# P, S, L (voxel order "PSL"), stored in RAS voxel order; no vox_to_ras (v1);
# an empty voxel order (LPS); and headers that cannot be mapped.
PAIR = track("<", [(1, 2, 3), (4, 5, 6.5)])
write("valid/rotated.trk", header("<", voxel_size=(1.0, 2.0, 0.5), order=b"RAS",
                                  vox_to_ras=(0, 0, -0.5, 10, -1, 0, 0, 20, 0, 2, 0, -30, 0, 0, 0, 1), n_count=1)
      + PAIR)
write("valid/version1.trk", header("<", version=1, n_count=1) + PAIR)
write("valid/no_voxel_order.trk", header(">", order=b"", n_count=1) + track(">", [(1, 2, 3), (4, 5, 6.5)]))
write("invalid/zero_voxel_size.trk", header(voxel_size=(2.0, 0.0, 3.0)) + PAIR)
write("invalid/bad_voxel_order.trk", header(order=b"LAL") + PAIR)
write("invalid/singular_vox_to_ras.trk", header(vox_to_ras=(1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1)) + PAIR)
