#!/usr/bin/env python3
"""Writes the binary (big-endian) VTK cases of tests/data/loaders/vtk (run
from that folder). The files are committed; this script documents how they
were made."""
import struct

PTS = [(0, 0, 0), (1, 0, 0), (2, 0, 0), (2, 1, 0), (2, 2, 1)]


def head(title):
    return ("# vtk DataFile Version 3.0\n%s\nBINARY\nDATASET POLYDATA\n" % title).encode()


def points(pts, t="float", fmt=">3f"):
    out = ("POINTS %d %s\n" % (len(pts), t)).encode()
    for p in pts:
        out += struct.pack(fmt, *p)
    return out + b"\n"


def lines_be():
    """Binary twin of valid/lines_ascii.vtk."""
    out = head("binary twin of lines_ascii.vtk") + points(PTS)
    out += b"LINES 2 7\n" + struct.pack(">7i", 3, 0, 1, 2, 2, 2, 3) + b"\n"
    out += b"POINT_DATA 5\nSCALARS speed float 1\nLOOKUP_TABLE default\n" + struct.pack(">5f", 1, 2, 3, 4, 5) + b"\n"
    out += b"VECTORS velocity double\n" + struct.pack(">15d", 3, 4, 0, 0, 0, 1, 1, 0, 0, 0, 0, 0, 0, 0, 2) + b"\n"
    out += b"FIELD FieldData 2\ntemp 1 5 double\n" + struct.pack(">5d", 10, 20, 30, 40, 50) + b"\n"
    out += b"uv 2 5 float\n" + struct.pack(">10f", *([0] * 10)) + b"\n"
    out += b"CELL_DATA 2\nSCALARS cell_id int 1\nLOOKUP_TABLE default\n" + struct.pack(">2i", 7, 8) + b"\n"
    out += b"NORMALS cell_normals float\n" + struct.pack(">6f", 0, 0, 1, 0, 0, 1) + b"\n"
    return out


def surface_v51_be():
    """5.1 binary: int64 offsets, a quad and a triangle, uchar colours, a
    LOOKUP_TABLE of uchar RGBA and METADATA after an array."""
    out = b"# vtk DataFile Version 5.1\nbinary 5.1 surface\nBINARY\nDATASET POLYDATA\n"
    out += points([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], "double", ">3d")
    out += b"POLYGONS 3 7\nOFFSETS vtktypeint64\n" + struct.pack(">3q", 0, 4, 7) + b"\n"
    out += b"CONNECTIVITY vtktypeint64\n" + struct.pack(">7q", 0, 1, 2, 3, 0, 2, 3) + b"\n"
    out += b"POINT_DATA 4\nSCALARS height short\nLOOKUP_TABLE lut\n" + struct.pack(">4h", -1, 0, 1, 300) + b"\n"
    out += b"METADATA\nINFORMATION 0\n\n"
    out += b"COLOR_SCALARS rgb 3\n" + bytes([255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255]) + b"\n"
    out += b"LOOKUP_TABLE lut 2\n" + bytes([0, 0, 0, 255, 255, 255, 255, 255]) + b"\n"
    out += b"FIELD FieldData 2\nid 1 4 int\n" + struct.pack(">4i", 1, 2, 3, 4) + b"\nMETADATA\nINFORMATION 0\n\n"
    out += b"w 1 4 float\n" + struct.pack(">4f", 0.5, 0.5, 0.5, 0.5) + b"\n"
    return out


def huge_points_be():
    return head("lying point count") + b"POINTS 4000000000 float\n" + struct.pack(">6f", 0, 0, 0, 1, 1, 1)


def index_out_of_range_be():
    out = head("point id 5 of 5") + points(PTS)
    return out + b"LINES 1 3\n" + struct.pack(">3i", 2, 0, 5) + b"\n"


def nan_point_be():
    return head("NaN coordinate") + points([(0, 0, 0), (float("nan"), 0, 0)])


def truncated_offsets_be():
    out = b"# vtk DataFile Version 5.1\ntruncated connectivity\nBINARY\nDATASET POLYDATA\n" + points(PTS)
    out += b"LINES 2 3\nOFFSETS vtktypeint64\n" + struct.pack(">2q", 0, 3) + b"\n"
    return out + b"CONNECTIVITY vtktypeint64\n" + struct.pack(">2q", 0, 1)


def write(path, data):
    with open(path, "wb") as f:
        f.write(data)


write("valid/lines_be.vtk", lines_be())
write("valid/surface_v51_be.vtk", surface_v51_be())
write("invalid/huge_points_be.vtk", huge_points_be())
write("invalid/index_out_of_range_be.vtk", index_out_of_range_be())
write("invalid/nan_point_be.vtk", nan_point_be())
write("invalid/truncated_offsets_be.vtk", truncated_offsets_be())
