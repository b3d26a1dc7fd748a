#!/usr/bin/env python3
"""Writes the binary PLY cases of tests/data/loaders (run from that folder).
The files are committed; this script documents how they were made."""
import struct

TETRA = [((0, 0, 0), (255, 0, 0), 0.5), ((1, 0, 0), (0, 255, 0), 1.0),
         ((0, 1, 0), (0, 0, 255), 0.25), ((0, 0, 1), (255, 255, 255), 0.0)]
FACES = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


def header(fmt, body):
    return ("ply\nformat %s 1.0\n%send_header\n" % (fmt, body)).encode()


def tetra(fmt, e):
    out = header(fmt, "comment binary twin of tetra_ascii.ply\nelement vertex 4\nproperty float x\n"
                 "property float y\nproperty float z\nproperty uchar red\nproperty uchar green\n"
                 "property uchar blue\nproperty float importance\nelement face 4\n"
                 "property list uchar int vertex_indices\n")
    for p, c, imp in TETRA:
        out += struct.pack(e + "3f3Bf", *p, *c, imp)
    for f in FACES:
        out += struct.pack(e + "B3i", 3, *f)
    return out


def skip_elements():
    """Unknown elements with and without lists around the real ones, a list on
    the vertex and extra face properties: all must be skipped byte-exactly."""
    out = header("binary_little_endian",
                 "element material 2\nproperty uchar kind\nproperty list ushort double params\n"
                 "property int id\n"
                 "element vertex 3\nproperty double x\nproperty list uchar short junk\nproperty float y\n"
                 "property float z\nproperty uint16 label\n"
                 "element fixed 3\nproperty double a\nproperty short b\n"
                 "element face 1\nproperty uchar flags\nproperty list int uint vertex_indices\n"
                 "property list uchar float texcoord\n"
                 "element empty 5\n")
    out += struct.pack("<BH2di", 1, 2, 1.5, 2.5, 7) + struct.pack("<BHi", 2, 0, 8)
    verts = [(0.0, 0.0, 0.0, 10), (1.0, 0.0, 0.0, 20), (0.0, 1.0, 0.0, 30)]
    for i, (x, y, z, label) in enumerate(verts):
        junk = list(range(i))
        out += struct.pack("<dB", x, len(junk)) + struct.pack("<%dh" % len(junk), *junk)
        out += struct.pack("<ffH", y, z, label)
    for i in range(3):
        out += struct.pack("<dh", i * 0.5, -i)
    out += struct.pack("<Bi3I", 9, 3, 0, 1, 2) + struct.pack("<B6f", 6, 0, 0, 1, 0, 0, 1)
    return out


def write(path, data):
    with open(path, "wb") as f:
        f.write(data)


write("valid/tetra_le.ply", tetra("binary_little_endian", "<"))
write("valid/tetra_be.ply", tetra("binary_big_endian", ">"))
write("valid/skip_elements_le.ply", skip_elements())

vertex3 = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
tri = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
write("invalid/huge_vertex_count_le.ply",
      header("binary_little_endian", "element vertex 4000000000\nproperty float x\nproperty float y\n"
             "property float z\n") + tri)
write("invalid/inf_coordinate_le.ply",
      header("binary_little_endian", vertex3) + struct.pack("<9f", 0, 0, 0, 1, float("inf"), 0, 0, 1, 0))
write("invalid/truncated_le.ply", header("binary_little_endian", vertex3) + tri[:30])
write("invalid/truncated_list_be.ply",
      header("binary_big_endian", vertex3 + "element face 1\nproperty list uchar int vertex_indices\n")
      + struct.pack(">9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack(">B2i", 3, 0, 1))
write("invalid/index_out_of_range_be.ply",
      header("binary_big_endian", vertex3 + "element face 1\nproperty list uchar int vertex_indices\n")
      + struct.pack(">9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack(">B3i", 3, 0, 1, 3))
write("invalid/huge_list_le.ply",
      header("binary_little_endian", vertex3 + "element line 1\nproperty list uint uint vertex_indices\n")
      + tri + struct.pack("<I2I", 0xFFFFFFF0, 0, 1))
