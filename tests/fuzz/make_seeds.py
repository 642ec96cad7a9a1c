#!/usr/bin/env python3
"""Writes the small committed seeds (run here): PLY files (assets/ has none) and mass-harness
inputs (fuzz_mass.cpp's byte format). The other harnesses also take scenes/, assets/ and
tests/data/hostile/ as seed folders (tests/fuzz/CMakeLists.txt)."""
import os
import struct

os.makedirs("seeds/ply", exist_ok=True)
os.makedirs("seeds/mass", exist_ok=True)
# Corner i of the unit box has x from bit 0, y from bit 1, z from bit 2; quads wound outward.
Q = [(0, 4, 6, 2), (1, 3, 7, 5), (0, 1, 5, 4), (2, 6, 7, 3), (0, 2, 3, 1), (4, 5, 7, 6)]
V = [((i >> 0) & 1, (i >> 1) & 1, (i >> 2) & 1) for i in range(8)]
hdr = ("ply\nformat {}\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 6\nproperty list uchar int vertex_indices\nend_header\n")
with open("seeds/ply/box_ascii.ply", "w") as f:
    f.write(hdr.format("ascii 1.0"))
    for v in V:
        f.write("%d %d %d\n" % v)
    for q in Q:
        f.write("4 %d %d %d %d\n" % q)
for order, fmt in (("<", "binary_little_endian 1.0"), (">", "binary_big_endian 1.0")):
    with open("seeds/ply/box_%s.ply" % fmt.split("_")[1], "wb") as f:
        f.write(hdr.format(fmt).encode())
        for v in V:
            f.write(struct.pack(order + "3f", *v))
        for q in Q:
            f.write(struct.pack(order + "B4i", 4, *q))
with open("seeds/ply/strips.ply", "w") as f:
    f.write("ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
            "property double z\nproperty float nx\nproperty float ny\nproperty float nz\n"
            "element tristrips 1\nproperty list int int vertex_indices\nend_header\n"
            "0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n0 0 1 0 0 1\n6 0 1 2 -1 0 3\n")
# mass: mode byte, exponent byte, vertex count, int16 coordinates, index triples
tri = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
for mode in range(3):
    for exp, name in ((0, "1"), (-16, "tiny"), (16, "huge")):
        data = bytes([mode + 3, exp & 0xFF, 4]) + b"".join(
            struct.pack("<3h", *(c * 1000 for c in v)) for v in V[:3] + [V[4]])
        data += bytes(sum(tri, ()))
        with open("seeds/mass/tetra_%d_%s.bin" % (mode, name), "wb") as f:
            f.write(data)
    box = bytes([mode + 3, 0, 8]) + b"".join(struct.pack("<3h", *(c * 100 for c in v)) for v in V)
    for q in Q:
        box += bytes([q[0], q[1], q[2], q[0], q[2], q[3]])
    with open("seeds/mass/box_%d.bin" % mode, "wb") as f:
        f.write(box)
    raw = bytes([mode, 0, 4]) + b"".join(struct.pack("<3d", *v) for v in V[:3] + [V[4]]) + bytes(sum(tri, ()))
    with open("seeds/mass/tetra_%d_raw.bin" % mode, "wb") as f:
        f.write(raw)
