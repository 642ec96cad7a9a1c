#!/usr/bin/env python3
"""Writes the hostile inputs into this folder (run it here; the files are committed).

Each file is small and reproduces one finding; tests/fuzz/replay_test.cpp replays every file in this
folder through the normal reader API (an InputError or a mesh, never a crash), and
tests/app/scene/mesh_import_test.cpp checks the message of each."""
import struct


def write(name, data):
    with open(name, "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def ply_binary(vertex_props, name):
    """A 530-byte binary PLY: a header whose vertex element has broken properties, then zeros.
    assimp 5.2 (Debian 12) aborts in Triangulate on these (and SIGBUS in SortByPType, PR #5138)."""
    h = "ply\nformat binary_little_endian 1.0\nelement vertex 3\n" + vertex_props
    h += "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
    b = h.encode()
    write(name, b + b"\0" * (530 - len(b)))


# 1. malformed PLY headers that used to reach assimp
ply_binary("property float x\nproperty float x\nproperty float y\nproperty float z\n",
           "ply_duplicate_property.ply")
ply_binary("property float x\nproperty float y\nproperty float z\nproperty float\n",
           "ply_nameless_property.ply")
# 2. claims the bytes cannot hold
quad = "0 0 0\n1 0 0\n0.2 0.2 0\n0 1 0\n4 0 1 2 3\n"  # four vertices, one non-convex quad
write("off_claims_1.5e9_faces.off", "OFF\n4 1500000000 0\n" + quad)
write("off_claims_1e9_vertices.off", "OFF\n1000000000 1 0\n" + quad)
write("off_claims_9.2e18_vertices.off", "OFF\n9200000000000000000 1 0\n" + quad)
write("ply_claims_2e9_vertices.ply",
      "ply\nformat binary_little_endian 1.0\nelement vertex 2000000000\nproperty double x\n"
      "property double y\nproperty double z\nend_header\n" + "\0" * 48)
stl = b"solid binary with a wrong count".ljust(80, b" ") + struct.pack("<I", 1000000000)
for tri in ([0, 0, 0, 1, 0, 0, 0, 1, 0], [0, 0, 0, 0, 1, 0, 0, 0, 1]):
    stl += struct.pack("<12fH", 0, 0, 1, *tri, 0)
write("stl_wrong_count.stl", stl)
# 3. a zero-size element with a huge count
write("ply_junk_element_huge.ply",
      "ply\nformat ascii 1.0\nelement junk 9223372036854775807\nend_header\n")
write("ply_junk_element_then_mesh.ply",
      b"ply\nformat binary_little_endian 1.0\nelement junk 9223372036854775807\nelement vertex 3\n"
      b"property float x\nproperty float y\nproperty float z\nelement face 1\n"
      b"property list uchar int vertex_indices\nend_header\n" + struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
      + b"\x03" + struct.pack("<3i", 0, 1, 2))
# 4. non-finite or out-of-range values converted to integers
v3 = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
hdr = ("ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
       "property float z\nelement face 1\nproperty list {} {} vertex_indices\nend_header\n")
write("ply_float_list_count.ply", hdr.format("float", "int").encode() + v3 +
      struct.pack("<f", float("nan")) + struct.pack("<3i", 0, 1, 2))
write("ply_nan_index.ply", hdr.format("uchar", "float").encode() + v3 + b"\x03" +
      struct.pack("<3f", 0, float("nan"), 2))
write("ply_huge_index.ply", hdr.format("uchar", "double").encode() + v3 + b"\x03" +
      struct.pack("<3d", 0, 1e300, 2))
write("ply_huge_list_count.ply", hdr.format("uint", "int").encode() + v3 + struct.pack("<I", 0xFFFFFFFF))
write("off_face_count_long_max.off", "OFF\n4 9223372036854775807 0\n" + quad)
write("off_face_corner_count_long_max.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n9223372036854775807 0 1 2\n")
# 5. a material library name too long for the file system (the mesh still loads)
tet = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
write("obj_long_mtllib.obj", "mtllib " + "m" * 5000 + ".mtl\n" + tet)
# 16. extreme scales
def tetra_off(s):
    return "OFF\n4 4 0\n0 0 0\n{0} 0 0\n0 {0} 0\n0 0 {0}\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n".format(s)
write("tetra_1e120.off", tetra_off("1e120"))
write("tetra_1e-200.off", tetra_off("1e-200"))
write("tetra_1e308.off", tetra_off("1e308"))
write("tetra_1e80.off", tetra_off("1e80"))
