#!/usr/bin/env python3
"""Writes the field cases of tests/data/fields (valid/ and invalid/): small
VTK legacy STRUCTURED_POINTS / RECTILINEAR_GRID files read by
tests/unit/test_field.c through cases.txt. Rerun after editing; the files are
checked in."""
import os
import struct

here = os.path.dirname(os.path.abspath(__file__))


def write(rel, data):
    with open(os.path.join(here, rel), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def head(kind, fmt="ASCII"):
    return "# vtk DataFile Version 3.0\nfield case\n%s\nDATASET %s\n" % (fmt, kind)


def linear_a(x, y, z):  # the uniform cases' field: v = (x, y, z)
    return (x, y, z)


def linear_b(x, y, z):  # the rectilinear cases' field
    return (2 * x - y, z + 1, 3.0)


def nodes(xs, ys, zs):
    return [(x, y, z) for z in zs for y in ys for x in xs]


# valid/uniform_ascii.vtk: 3 x 2 x 2 nodes, spacing (0.5, 1, 2), v = (x, y, z).
xs, ys, zs = [0, 0.5, 1], [0, 1], [0, 2]
vals = "\n".join("%g %g %g" % linear_a(*p) for p in nodes(xs, ys, zs))
write("valid/uniform_ascii.vtk", head("STRUCTURED_POINTS") + "DIMENSIONS 3 2 2\nORIGIN 0 0 0\nSPACING 0.5 1 2\n"
      "POINT_DATA 12\nSCALARS p float 1\nLOOKUP_TABLE default\n" + " ".join(["1"] * 12) + "\n"
      "VECTORS velocity float\n" + vals + "\n")

# valid/rectilinear_be.vtk: binary, uneven axes, a FIELD array and CELL_DATA to skip.
xs, ys, zs = [0.0, 1.0, 3.0], [-1.0, 0.0, 2.0], [0.0, 1.0]
b = head("RECTILINEAR_GRID", "BINARY").encode() + b"DIMENSIONS 3 3 2\n"
for name, axis in (("X", xs), ("Y", ys), ("Z", zs)):
    b += ("%s_COORDINATES %d double\n" % (name, len(axis))).encode() + struct.pack(">%dd" % len(axis), *axis) + b"\n"
b += b"CELL_DATA 4\nVECTORS cellv float\n" + struct.pack(">12f", *([0.5] * 12)) + b"\n"
b += b"POINT_DATA 18\nFIELD extra 1\nweight 1 18 float\n" + struct.pack(">18f", *([2.0] * 18)) + b"\n"
b += b"VECTORS wind float\n" + struct.pack(">54f", *[c for p in nodes(xs, ys, zs) for c in linear_b(*p)]) + b"\n"
write("valid/rectilinear_be.vtk", b)

# invalid cases: each names the line (ASCII) or byte offset (binary) and the reason.
sp = head("STRUCTURED_POINTS")
write("invalid/huge_dims.vtk", sp + "DIMENSIONS 400 400 400\nPOINT_DATA 64000000\nVECTORS v float\n0 0 0\n")
write("invalid/too_many_nodes.vtk", sp + "DIMENSIONS 1000 1000 1000\n")
write("invalid/flat_axis.vtk", sp + "DIMENSIONS 4 4 1\n")
write("invalid/point_data_mismatch.vtk", sp + "DIMENSIONS 2 2 2\nPOINT_DATA 7\n")
write("invalid/no_vectors.vtk", sp + "DIMENSIONS 2 2 2\nPOINT_DATA 8\nSCALARS s float\n1 2 3 4 5 6 7 8\n")
write("invalid/bad_number.vtk", sp + "DIMENSIONS 2 2 2\nPOINT_DATA 8\nVECTORS v float\n" + "0 0 0\n" * 3
      + "0 abc 0\n" + "0 0 0\n" * 4)
write("invalid/truncated_vectors_be.vtk", head("STRUCTURED_POINTS", "BINARY").encode()
      + b"DIMENSIONS 2 2 2\nPOINT_DATA 8\nVECTORS v float\n" + struct.pack(">20f", *([1.0] * 20)))
write("invalid/bad_spacing.vtk", sp + "DIMENSIONS 2 2 2\nSPACING 1 0 1\n")
write("invalid/polydata.vtk", head("POLYDATA") + "POINTS 1 float\n0 0 0\n")
write("invalid/not_increasing.vtk", head("RECTILINEAR_GRID") + "DIMENSIONS 3 2 2\nX_COORDINATES 3 float\n0 2 1\n")
write("invalid/coordinates_count.vtk", head("RECTILINEAR_GRID") + "DIMENSIONS 3 2 2\nX_COORDINATES 2 float\n0 1\n")
write("invalid/no_dataset.vtk", "# vtk DataFile Version 3.0\nx\nASCII\nDIMENSIONS 2 2 2\n")
write("invalid/missing_axis.vtk", head("RECTILINEAR_GRID") + "DIMENSIONS 2 2 2\nX_COORDINATES 2 float\n0 1\n"
      "Y_COORDINATES 2 float\n0 1\nPOINT_DATA 8\nVECTORS v float\n" + "1 0 0\n" * 8)
