#!/usr/bin/env python3
"""Writes the MRtrix .tck cases of tests/data/loaders/tck (run from that folder).
The files are committed; this script documents how they were made."""
import struct

NAN = float("nan")
INF = float("inf")
# Three streamlines; the last has one point and is dropped by the reader.
LINES = [[(0, 0, 0), (1, 0, 0)], [(0, 1, 0), (0, 2, 0), (0, 3, 1.5)], [(9, 9, 9)]]


def tck(lines, fmt="<f", dtype="Float32LE", extra="", end=True, offset=None, terminate=True, count=None, nl="\n", pad=False):
    body = b""
    for line in lines:
        for p in line:
            body += struct.pack(fmt[0] + "3" + fmt[1], *p)
        if terminate:
            body += struct.pack(fmt[0] + "3" + fmt[1], NAN, NAN, NAN)
    if end:
        body += struct.pack(fmt[0] + "3" + fmt[1], INF, INF, INF)
    head = "mrtrix tracks\ncount: %s\ndatatype: %s\n%s" % (count if count is not None else len(lines), dtype, extra)
    # The offset line's own length changes the offset: iterate to a fixed point.
    off = 0
    while True:
        text = (head + "file: . %d\nEND\n" % (offset if offset is not None else off)).replace("\n", nl)
        if offset is not None or len(text) == off:
            break
        off = len(text)
    text = text.encode()
    if pad:
        text += b"\0" * (offset - len(text))  # MRtrix may leave room before the data
    return text + body


def write(path, data):
    with open(path, "wb") as f:
        f.write(data)


write("valid/lines_f32le.tck", tck(LINES))
write("valid/lines_f64be.tck", tck(LINES, ">d", "Float64BE", "timestamp: 1.5\nroi: seed.mif\nroi: mask.mif\n"))
write("valid/lines_f32be_crlf.tck", tck(LINES, ">f", "Float32BE", nl="\r\n"))
# The last streamline lost its NaN terminator and the Inf end marker: kept, with a warning.
write("valid/no_end_marker.tck", tck(LINES[:1], end=False, count=2) + struct.pack("<9f", *sum(LINES[1], ())))
write("valid/nonfinite_point.tck", tck([[(0, 0, 0), (1, NAN, 0), (1, 0, 0)], LINES[1]]))
write("valid/padded_offset.tck", tck(LINES, offset=200, pad=True))
write("invalid/no_magic.tck", tck(LINES).replace(b"mrtrix tracks", b"mrtrix images"))
write("invalid/no_end.tck", b"mrtrix tracks\ndatatype: Float32LE\nfile: . 60\n")
write("invalid/no_end_newline.tck", b"mrtrix tracks\ndatatype: Float32LE\nfile: . 60\nEND")
write("invalid/bad_datatype.tck", tck(LINES, dtype="Int16LE"))
write("invalid/no_datatype.tck", tck(LINES).replace(b"datatype: Float32LE\n", b"datatype_: Float32LE\n"))
write("invalid/other_file.tck", b"mrtrix tracks\ndatatype: Float32LE\nfile: tracks.dat 0\nEND\n")
write("invalid/offset_beyond.tck", tck(LINES, offset=100000))
write("invalid/offset_in_header.tck", tck(LINES, offset=10))
write("invalid/truncated.tck", tck(LINES)[:-14])
write("invalid/no_lines.tck", tck([[(1, 2, 3)]]))
