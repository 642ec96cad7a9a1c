// Mesh files: every reader gives the closed-form mass properties of a box, in double precision;
// glTF goes through assimp with its node transforms and material; broken files name file and line.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <bit>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>

#include <simreel/error.hpp>
#include "app/scene/mesh_import.hpp"
#include "tests/scratch.hpp"

namespace simreel {
namespace {

// A box with corners written as decimals, which float32 cannot hold: 0.1 as a float is
// 0.100000001490116..., which moves the volume by ~1e-8 relative. Double precision keeps it to
// rounding (~1e-16), so a 1e-13 tolerance tells the two apart by five orders of magnitude.
const Vec3 kLo(0.1, 0.2, -0.3), kHi(0.4, 0.9, 0.6);
const char* kLoText[3] = {"0.1", "0.2", "-0.3"};
const char* kHiText[3] = {"0.4", "0.9", "0.6"};
// Corner i has x from bit 0, y from bit 1, z from bit 2; faces counter-clockwise from outside.
const int kQuads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};

std::string corner_text(int i) {
  std::string s;
  for (int k = 0; k < 3; ++k) s += std::string(k ? " " : "") + ((i >> k) & 1 ? kHiText[k] : kLoText[k]);
  return s;
}

Vec3 corner(int i) {
  return Vec3(i & 1 ? kHi.x() : kLo.x(), i & 2 ? kHi.y() : kLo.y(), i & 4 ? kHi.z() : kLo.z());
}

std::string write(const std::string& name, const std::string& text) {
  const std::string p = test::scratch(name);
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

// Closed form, density 1: m = abc, I_xx = m (b^2 + c^2) / 12, ..., centroid at the middle.
void expect_decimal_box(const ImportedMesh& im, const std::string& reader) {
  SCOPED_TRACE(reader);
  EXPECT_EQ(im.reader, reader);
  EXPECT_TRUE(im.double_precision());
  MeshMassOptions opt;
  opt.density = 1;
  const MeshReport r = analyze_mesh(im.mesh, opt);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.warnings.empty());
  const Vec3 s = kHi - kLo;
  const double m = s.prod();
  EXPECT_NEAR(r.props.mass, m, 1e-13 * m);
  EXPECT_LT((r.props.com - 0.5 * (kLo + kHi)).norm(), 1e-15);
  const Vec3 I(m * (s.y() * s.y() + s.z() * s.z()) / 12, m * (s.x() * s.x() + s.z() * s.z()) / 12,
               m * (s.x() * s.x() + s.y() * s.y()) / 12);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.props.inertia(k, k), I[k], 1e-13 * I[k]);
  EXPECT_LT(r.props.inertia.norm() - r.props.inertia.diagonal().norm(), 1e-15);
}

TEST(MeshImport, FloatWouldNotPassTheDecimalBoxTolerance) {
  // The premise of the tests below: the same box through float32 is ~1e-8 off.
  const Vec3 sf = (kHi.cast<float>() - kLo.cast<float>()).cast<double>();
  const double m = (kHi - kLo).prod();
  EXPECT_GT(std::abs(sf.prod() - m), 1e-9 * m);
}

TEST(MeshImport, ObjQuadsNegativeIndicesNormalsAndMaterial) {
  std::string obj = "# decimal box\nmtllib box.mtl\no box\n";
  for (int i = 0; i < 8; ++i) obj += "v " + corner_text(i) + "\n";
  obj += "vn 0 0 1\nusemtl teal\ns off\n";
  for (const auto& q : kQuads) {  // relative indices, with a normal on every corner
    obj += "f";
    for (int k : q) obj += " " + std::to_string(k - 8) + "//1";
    obj += "\n";
  }
  write("box.mtl", "newmtl teal\nKa 0 0 0\nKd 0.1 0.5 0.6\n");
  const ImportedMesh im = import_mesh(write("box.obj", obj));
  expect_decimal_box(im, "obj");
  EXPECT_EQ(im.mesh.triangles.size(), 12u);
  ASSERT_TRUE(im.color.has_value());
  EXPECT_FLOAT_EQ((*im.color)[1], 0.5f);
  ASSERT_EQ(im.corner_normals.size(), 12u);
  EXPECT_EQ(im.corner_normals[0][0], Eigen::Vector3f(0, 0, 1));
}

TEST(MeshImport, ObjMissingMaterialLibraryIsANoteNotAnError) {
  std::string obj = "mtllib nowhere.mtl\nusemtl x\n";
  for (int i = 0; i < 8; ++i) obj += "v " + corner_text(i) + "\n";
  for (const auto& q : kQuads)
    obj += "f " + std::to_string(q[0] + 1) + " " + std::to_string(q[1] + 1) + " " + std::to_string(q[2] + 1) +
           " " + std::to_string(q[3] + 1) + "\n";
  const ImportedMesh im = import_mesh(write("nomtl.obj", obj));
  expect_decimal_box(im, "obj");
  EXPECT_FALSE(im.color.has_value());
  ASSERT_EQ(im.notes.size(), 1u);
  EXPECT_NE(im.notes[0].find("nowhere.mtl"), std::string::npos);
}

TEST(MeshImport, OffWithCommentsAndColours) {
  std::string off = "OFF\n# a box\n8 6 12\n";
  for (int i = 0; i < 8; ++i) off += corner_text(i) + "\n";
  for (const auto& q : kQuads)
    off += "4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) + " " +
           std::to_string(q[3]) + " 255 0 0\n";  // a face colour after the indices
  expect_decimal_box(import_mesh(write("box.off", off)), "off");
}

TEST(MeshImport, AsciiStlSoupIsWeldedAndExact) {
  std::string stl = "solid box\n";
  for (const auto& q : kQuads)
    for (int t = 0; t < 2; ++t) {
      const int c[3] = {q[0], q[1 + t], q[2 + t]};
      stl += "  facet normal 0 0 0\n    outer loop\n";
      for (int k : c) stl += "      vertex " + corner_text(k) + "\n";
      stl += "    endloop\n  endfacet\n";
    }
  stl += "endsolid box\n";
  const ImportedMesh im = import_mesh(write("box.stl", stl));
  EXPECT_EQ(im.mesh.vertices.size(), 36u);  // one set per face, as STL stores it
  expect_decimal_box(im, "stl-ascii");
}

// A binary STL cube as exporters write it, header beginning with "solid" (a classic trap).
TEST(MeshImport, BinaryStlCubeStartingWithSolid) {
  std::string bin(80, ' ');
  std::memcpy(bin.data(), "solid exported by a CAD tool", 28);
  const uint32_t n = 12;
  bin.append(reinterpret_cast<const char*>(&n), 4);
  for (const auto& q : kQuads)
    for (int t = 0; t < 2; ++t) {
      const int c[3] = {q[0], q[1 + t], q[2 + t]};
      float rec[12] = {0, 0, 0};
      for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j)
          rec[3 + 3 * k + j] = (float)(((c[k] >> j) & 1) ? 2.0 : -0.5);  // exact in float
      bin.append(reinterpret_cast<const char*>(rec), sizeof rec);
      bin.append(2, '\0');
    }
  const ImportedMesh im = import_mesh(write("cube.stl", bin));
  EXPECT_EQ(im.reader, "stl-binary");
  MeshMassOptions opt;
  opt.density = 1;
  const MeshReport r = analyze_mesh(im.mesh, opt);
  EXPECT_TRUE(r.closed);
  EXPECT_EQ(r.welded_vertices, 36 - 8);
  EXPECT_NEAR(r.props.mass, 2.5 * 2.5 * 2.5, 1e-13);
  EXPECT_LT((r.props.com - Vec3::Constant(0.75)).norm(), 1e-15);
  EXPECT_NEAR(r.props.inertia(0, 0), std::pow(2.5, 5) / 6, 1e-13);  // m a^2 / 6
}

TEST(MeshImport, PlyAsciiAndBinaryBothByteOrders) {
  std::string head =
      "ply\nformat ascii 1.0\ncomment decimal box\nelement vertex 8\nproperty double x\n"
      "property double y\nproperty double z\nproperty uchar red\nelement face 6\n"
      "property list uchar int vertex_indices\nend_header\n";
  std::string ascii = head;
  for (int i = 0; i < 8; ++i) ascii += corner_text(i) + " 200\n";
  for (const auto& q : kQuads)
    ascii += "4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) + " " +
             std::to_string(q[3]) + "\n";
  expect_decimal_box(import_mesh(write("ascii.ply", ascii)), "ply-ascii");

  for (const bool big : {false, true}) {
    std::string b = head;
    b.replace(b.find("ascii"), 5, big ? "binary_big_endian" : "binary_little_endian");
    auto put = [&](const void* p, int n) {
      std::string s(static_cast<const char*>(p), n);
      if (big == (std::endian::native == std::endian::little)) std::reverse(s.begin(), s.end());
      b += s;
    };
    for (int i = 0; i < 8; ++i) {
      for (int k = 0; k < 3; ++k) {
        const double x = corner(i)[k];
        put(&x, 8);
      }
      const uint8_t red = 200;
      put(&red, 1);
    }
    for (const auto& q : kQuads) {
      const uint8_t four = 4;
      put(&four, 1);
      for (int k : q) {
        const int32_t v = k;
        put(&v, 4);
      }
    }
    expect_decimal_box(import_mesh(write(big ? "big.ply" : "little.ply", b)), "ply-binary");
  }
}

std::string base64(const std::string& in) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < in.size(); i += 3) {
    uint32_t v = (uint8_t)in[i] << 16;
    if (i + 1 < in.size()) v |= (uint8_t)in[i + 1] << 8;
    if (i + 2 < in.size()) v |= (uint8_t)in[i + 2];
    out += t[v >> 18];
    out += t[(v >> 12) & 63];
    out += i + 1 < in.size() ? t[(v >> 6) & 63] : '=';
    out += i + 2 < in.size() ? t[v & 63] : '=';
  }
  return out;
}

// A unit cube in glTF 2.0, under a parent node translated by (0, 0, 5) and a child scaled by
// (2, 3, 4) and translated by (10, 0, 0): a 2 x 3 x 4 box with its centroid at (11, 1.5, 7).
TEST(MeshImport, GltfThroughAssimpAppliesNodeTransformsAndBaseColour) {
  std::string buf;
  for (int i = 0; i < 8; ++i)
    for (int k = 0; k < 3; ++k) {
      const float x = (float)((i >> k) & 1);
      buf.append(reinterpret_cast<const char*>(&x), 4);
    }
  for (const auto& q : kQuads)
    for (int k : {q[0], q[1], q[2], q[0], q[2], q[3]}) {
      const uint16_t v = (uint16_t)k;
      buf.append(reinterpret_cast<const char*>(&v), 2);
    }
  const std::string gltf = R"({
  "asset": {"version": "2.0"},
  "scene": 0, "scenes": [{"nodes": [0]}],
  "nodes": [{"translation": [0, 0, 5], "children": [1]},
            {"mesh": 0, "translation": [10, 0, 0], "scale": [2, 3, 4]}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
  "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1.0]}}],
  "buffers": [{"byteLength": 168, "uri": "data:application/octet-stream;base64,)" +
                           base64(buf) + R"("}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 96},
                  {"buffer": 0, "byteOffset": 96, "byteLength": 72}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 1]},
                {"bufferView": 1, "componentType": 5123, "count": 36, "type": "SCALAR"}]
})";
  ASSERT_EQ(buf.size(), 168u);
  const ImportedMesh im = import_mesh(write("cube.gltf", gltf));
  EXPECT_EQ(im.reader, "assimp");
  EXPECT_FALSE(im.double_precision());
  MeshMassOptions opt;
  opt.density = 1;
  const MeshReport r = analyze_mesh(im.mesh, opt);
  EXPECT_TRUE(r.closed);
  EXPECT_NEAR(r.props.mass, 24.0, 1e-12);  // every coordinate is exact in float32
  EXPECT_LT((r.props.com - Vec3(11, 1.5, 7)).norm(), 1e-12);
  EXPECT_NEAR(r.props.inertia(2, 2), 24.0 * (4 + 9) / 12, 1e-12);
  ASSERT_TRUE(im.color.has_value());
  EXPECT_NEAR((*im.color)[2], 0.6f, 1e-6);
}

// An L-shaped prism whose caps are single non-convex 7-gons, each with a
// corner in line with its neighbours, and decimal coordinates. Read by simreel's own reader (ear
// clipping in the polygon's plane, double precision): exact, no zero-area triangles, no welding.
TEST(MeshImport, NonConvexPolygonsAreEarClippedInDoublePrecision) {
  const char* L[7][2] = {{"0", "0"},     {"0.1", "0"},   {"0.2", "0"}, {"0.2", "0.1"},
                         {"0.1", "0.1"}, {"0.1", "0.3"}, {"0", "0.3"}};
  std::string obj;
  for (const char* z : {"0", "0.3"})
    for (const auto& p : L) obj += std::string("v ") + p[0] + " " + p[1] + " " + z + "\n";
  obj += "f 7 6 5 4 3 2 1\nf 8 9 10 11 12 13 14\n";
  for (int i = 0; i < 7; ++i) {
    const int a = i + 1, b = (i + 1) % 7 + 1;
    obj += "f " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(b + 7) + " " +
           std::to_string(a + 7) + "\n";
  }
  const ImportedMesh im = import_mesh(write("l.obj", obj));
  EXPECT_EQ(im.reader, "obj");
  EXPECT_TRUE(im.notes.empty());
  EXPECT_EQ(im.mesh.triangles.size(), 2u * 5 + 7 * 2);
  MeshMassOptions opt;
  opt.density = 1;
  const MeshReport r = analyze_mesh(im.mesh, opt);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.consistently_oriented);
  EXPECT_EQ(r.welded_vertices, 0);
  EXPECT_EQ(r.degenerate_faces, 0);
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_NEAR(r.props.mass, 0.012, 1e-13 * 0.012);  // area 0.02 + 0.02 times height 0.3
  EXPECT_LT((r.props.com - Vec3(0.075, 0.125, 0.15)).norm(), 1e-15);
}

// A binary PLY with a Blender-style header line (no "comment") and a tetrahedron as
// triangle strips: -1 restarts a strip, windings alternate, a repeated-corner join is left out.
TEST(MeshImport, PlyTriangleStripsAndExporterHeaderLines) {
  std::string b =
      "ply\nformat binary_little_endian 1.0\nCreated by Blender3D 247 - www.blender.org, source file: \n"
      "element vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
      "element tristrips 1\nproperty list int int vertex_indices\nend_header\n";
  auto put = [&](const void* p, int n) {
    std::string s(static_cast<const char*>(p), n);
    if (std::endian::native != std::endian::little) std::reverse(s.begin(), s.end());
    b += s;
  };
  const double v[4][3] = {{0, 0, 0}, {0, 0.1, 0}, {0.1, 0, 0}, {0, 0, 0.1}};
  for (const auto& p : v)
    for (double x : p) put(&x, 8);
  const int32_t strip[] = {0, 1, 2, 3, -1, 2, 3, 0, 1, -1, 0, 0, 1};
  const int32_t n = sizeof strip / sizeof strip[0];
  put(&n, 4);
  for (int32_t i : strip) put(&i, 4);
  const ImportedMesh im = import_mesh(write("strips.ply", b));
  EXPECT_EQ(im.reader, "ply-binary");
  ASSERT_EQ(im.notes.size(), 1u);
  EXPECT_EQ(im.notes[0],
            "read 4 triangles from triangle strips (left out 1 with a repeated corner, which only "
            "join strips)");
  MeshMassOptions opt;
  opt.density = 1;
  const MeshReport r = analyze_mesh(im.mesh, opt);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.consistently_oriented);
  EXPECT_FALSE(r.inverted);
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_NEAR(r.volume, 0.001 / 6, 1e-13 * 0.001);
}

// OFF faces (and vertices) that run over several lines, colours after them.
TEST(MeshImport, OffRecordsSplitAcrossLines) {
  std::string off = "OFF\n8 6 0\n";
  for (int i = 0; i < 8; ++i) {
    const std::string c = corner_text(i);
    const size_t sp = c.rfind(' ');
    off += c.substr(0, sp) + "\n " + c.substr(sp + 1) + " 0.5 0.5 0.5 1\n";  // z on its own line
  }
  for (const auto& q : kQuads)
    off += "4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + "\n  " + std::to_string(q[2]) + "\n" +
           std::to_string(q[3]) + " 255 0 0\n";
  expect_decimal_box(import_mesh(write("split.off", off)), "off");
}

std::string error_of(const std::string& name, const std::string& text) {
  try {
    import_mesh(write(name, text));
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << name << " was accepted";
  return "";
}

TEST(MeshImport, BrokenFilesNameFileAndLine) {
  EXPECT_NE(error_of("idx.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n")
                .find("idx.obj:4: face refers to vertex 4 but 3"),
            std::string::npos);
  EXPECT_NE(error_of("nan.obj", "v 0 0 0\nv nan 0 0\n").find("nan.obj:2: coordinate 'nan' is not finite"),
            std::string::npos);
  EXPECT_NE(error_of("word.off", "OFF\n3 1 0\n0 0 0\n1 zero 0\n").find("word.off:4: 'zero' is not a number"),
            std::string::npos);
  EXPECT_NE(error_of("short.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n").find("file ends after 2 of 4 vertices"),
            std::string::npos);
  EXPECT_NE(error_of("points.obj", "v 0 0 0\nv 1 0 0\np 1 2\nl 1 2\n")
                .find("has no triangles (only 2 points or lines)"),
            std::string::npos);
  EXPECT_NE(error_of("junk.stl", "this is not a mesh").find("neither ASCII STL"), std::string::npos);
  EXPECT_NE(
      error_of("loop.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n")
          .find("loop.stl:6: a facet loop needs 3 vertices, found 2"),
      std::string::npos);
  EXPECT_NE(error_of("face.ply",
                     "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                     "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                     "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")
                .find("face 0 refers to vertex 7 of 3"),
            std::string::npos);
  EXPECT_NE(error_of("trunc.ply",
                     "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                     "property float y\nproperty float z\nend_header\n\x01\x02")
                .find("binary data ends early"),
            std::string::npos);
  EXPECT_NE(error_of("empty.gltf", "{\"asset\": {\"version\": \"2.0\"}}").find("empty.gltf"),
            std::string::npos);
}

// ---- Hostile input ----------------------------------------------------------------------------

std::string hostile(const std::string& name) {
  return "tests/data/hostile/" + name;
}

std::string error_of_file(const std::string& path) {
  try {
    import_mesh(path);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << path << " was accepted";
  return "";
}

// Item 1: 530-byte binary PLY headers with a duplicate or a nameless property. assimp 5.2 aborts on
// them (Triangulate's assertion; SortByPType's stack write, SIGBUS). simreel's reader refuses them,
// and a file whose bytes say PLY goes to simreel's reader whatever its name: assimp never sees it.
TEST(MeshImport, MalformedPlyHeadersNeverReachAssimp) {
  const std::pair<const char*, const char*> cases[] = {
      {"ply_duplicate_property.ply", ":5: element 'vertex' has a second property named 'x'"},
      {"ply_nameless_property.ply", ":7: property needs a type and a name"}};
  for (const auto& [name, msg] : cases) {
    SCOPED_TRACE(name);
    EXPECT_NE(error_of_file(hostile(name)).find(msg), std::string::npos);
    // The same bytes under a name only assimp reads.
    const std::string dat = test::scratch(std::string(name) + ".glb");
    std::filesystem::copy_file(hostile(name), dat);
    EXPECT_NE(error_of_file(dat).find(msg), std::string::npos) << error_of_file(dat);
  }
  // A second element of the same name, and a list as a coordinate.
  EXPECT_NE(
      error_of("twice.ply",
               "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nelement vertex 0\nend_header\n")
          .find("twice.ply:5: a second element named 'vertex'"),
      std::string::npos);
  EXPECT_NE(
      error_of("listx.ply",
               "ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar float x\nproperty float y\n"
               "property float z\nend_header\n1 0 0 0\n")
          .find("vertex property 'x' is a list"),
      std::string::npos);
}

TEST(MeshImport, NativeFormatsAreSniffedFromTheirBytes) {
  EXPECT_EQ(detail::native_format("ply\nformat ascii 1.0\n", 20), "ply");
  EXPECT_EQ(detail::native_format("OFF\n4 4 0\n", 10), "off");
  EXPECT_EQ(detail::native_format("\n  ply\r\nformat ascii 1.0\n", 25), "ply");
  EXPECT_EQ(detail::native_format("off 4 4 0\n", 10), "off");
  EXPECT_EQ(detail::native_format("solid x\n facet normal 0 0 1\n", 28), "stl");
  std::string stl(84, ' ');
  const uint32_t one = 1;
  std::memcpy(&stl[80], &one, 4);
  EXPECT_EQ(detail::native_format(stl, 134), "stl");
  EXPECT_EQ(detail::native_format("{\"asset\": {}}", 13), "");
  EXPECT_EQ(detail::native_format("glTF\x02\0\0\0", 8), "");
  // An OFF file named .dae is read by simreel's reader (double precision), not by assimp.
  const ImportedMesh im = import_mesh(write("tetra.dae",
                                            "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                                            "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"));
  EXPECT_EQ(im.reader, "off");
}

// Item 1: assimp runs in a child process; whatever happens there becomes an InputError here.
TEST(MeshImport, AssimpCrashesAndHangsAreContained) {
  auto error = [](const std::function<detail::RawMesh()>& f, double seconds = 30) {
    try {
      detail::contained_read("x.glb", "assimp", f, seconds);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(error([]() -> detail::RawMesh {
              raise(SIGBUS);
              return {};
            }),
            "assimp could not read 'x.glb' (crashed: SIGBUS)");
  EXPECT_EQ(error([]() -> detail::RawMesh { std::abort(); }),
            "assimp could not read 'x.glb' (crashed: SIGABRT)");
  EXPECT_EQ(error([]() -> detail::RawMesh { _exit(7); }),
            "assimp could not read 'x.glb' (its reader process exited with status 7)");
  EXPECT_EQ(error([]() -> detail::RawMesh { throw InputError("x.glb: no meshes"); }), "x.glb: no meshes");
  EXPECT_EQ(error([]() -> detail::RawMesh { throw std::bad_alloc(); }),
            "assimp could not read 'x.glb' (ran out of memory)");
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(error(
                []() -> detail::RawMesh {
                  for (;;) pause();
                },
                0.3),
            "assimp could not read 'x.glb' (gave up after 0.3 s)");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5);
  // A mesh comes back whole.
  detail::RawMesh m;
  m.vertices = {Vec3(0.1, 0.2, 0.3), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  m.normals = {Eigen::Vector3f(0, 0, 1), Eigen::Vector3f(0, 0, 1), Eigen::Vector3f(0, 0, 1)};
  m.triangles = {{0, 1, 2}};
  m.triangle_material = {0};
  m.materials = {{0.5f, 0.25f, 1.f}};
  m.material_names = {"paint"};
  m.material_textures = {"*0"};
  m.embedded = {std::string("\x89PNG\0\x01", 6)};
  m.uvs = {Eigen::Vector2f(0, 0), Eigen::Vector2f(1, 0), Eigen::Vector2f(0, 1)};
  m.colors = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.points_and_lines = 3;
  m.notes = {"a note", ""};
  const detail::RawMesh r = detail::contained_read("x.glb", "assimp", [&] { return m; });
  EXPECT_EQ(r.material_names, m.material_names);
  EXPECT_EQ(r.material_textures, m.material_textures);
  EXPECT_EQ(r.embedded, m.embedded);
  EXPECT_EQ(r.uvs, m.uvs);
  EXPECT_EQ(r.colors, m.colors);
  EXPECT_EQ(r.vertices, m.vertices);
  EXPECT_EQ(r.normals, m.normals);
  EXPECT_EQ(r.triangles, m.triangles);
  EXPECT_EQ(r.triangle_material, m.triangle_material);
  EXPECT_EQ(r.materials, m.materials);
  EXPECT_EQ(r.points_and_lines, 3);
  EXPECT_EQ(r.notes, m.notes);
}

// The reply of the child is never trusted: every cut of a valid reply, counts that claim more than
// the bytes hold, and indices out of range are errors, not allocations or reads out of bounds.
TEST(MeshImport, ContainedReplyIsCheckedNotTrusted) {
  detail::RawMesh m;
  m.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  m.triangles = {{0, 1, 2}};
  const std::string good = detail::encode_mesh(m);
  EXPECT_EQ(detail::decode_mesh(good, "x", "assimp").triangles.size(), 1u);
  for (size_t n = 0; n < good.size(); ++n)
    EXPECT_THROW(detail::decode_mesh(std::string_view(good).substr(0, n), "x", "assimp"), InputError) << n;
  std::string huge = good;
  const uint64_t claim = ~0ull / 2;
  std::memcpy(&huge[4], &claim, 8);  // the vertex count
  EXPECT_THROW(detail::decode_mesh(huge, "x", "assimp"), InputError);
  detail::RawMesh bad = m;
  bad.triangles = {{0, 1, 3}};
  EXPECT_THROW(detail::decode_mesh(detail::encode_mesh(bad), "x", "assimp"), InputError);
  EXPECT_THROW(detail::decode_mesh(good + "x", "x", "assimp"), InputError);
  // Texture coordinates per corner index the list they come with; names go with materials.
  bad = m;
  bad.uvs = {Eigen::Vector2f(0, 0)};
  bad.triangle_uvs = {{0, 0, 1}};
  EXPECT_THROW(detail::decode_mesh(detail::encode_mesh(bad), "x", "assimp"), InputError);
  bad = m;
  bad.material_names = {"a", "b"};
  EXPECT_THROW(detail::decode_mesh(detail::encode_mesh(bad), "x", "assimp"), InputError);
}

// Items 2 and 4: header claims are never trusted for memory, and counts never overflow.
TEST(MeshImport, ClaimsTheFileCannotHoldAreErrorsNotAllocations) {
  const std::pair<const char*, const char*> cases[] = {
      {"off_claims_1.5e9_faces.off", ":7: file ends after 1 of 1500000000 faces"},
      {"off_claims_1e9_vertices.off", "file ends after 5 of 1000000000 vertices"},
      {"off_claims_9.2e18_vertices.off", ":2: more than 2147483647 vertices"},
      {"off_face_count_long_max.off", "file ends after 1 of 9223372036854775807 faces"},
      {"off_face_corner_count_long_max.off", "file ends after 0 of 1 faces"},
      {"ply_claims_2e9_vertices.ply",
       "binary data ends early (in vertex 3 of the 2000000000 the header claims)"},
      {"ply_huge_list_count.ply",
       "list length 4294967295 is not a whole number the rest of the file can hold"},
      {"stl_wrong_count.stl",
       "begins with 'solid' but holds binary data and no facets; read as a binary STL whose header claims "
       "1000000000 triangles (84 + 50 x 1000000000 = 50000000084 bytes) but the file has 184 bytes: the "
       "triangle count is wrong or the file is cut short"}};
  for (const auto& [name, msg] : cases) {
    SCOPED_TRACE(name);
    const std::string e = error_of_file(hostile(name));
    EXPECT_NE(e.find(msg), std::string::npos) << e;
  }
}

// Item 3: an element with no properties takes no bytes, whatever its count: skipped at once.
TEST(MeshImport, ZeroSizePlyElementsAreSkippedInConstantTime) {
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_NE(error_of_file(hostile("ply_junk_element_huge.ply")).find("has no triangles"), std::string::npos);
  const std::string text = detail::read_file(hostile("ply_junk_element_then_mesh.ply"));
  std::string kind;
  const detail::RawMesh m = detail::parse_ply(text, "x.ply", &kind);
  EXPECT_EQ(m.vertices.size(), 3u);
  EXPECT_EQ(m.triangles.size(), 1u);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1.0);
}

// Item 4: NaN, infinite and out-of-range values are checked before any conversion to an integer.
TEST(MeshImport, NonFiniteAndHugeCountsAndIndicesAreCheckedBeforeConversion) {
  const std::pair<const char*, const char*> cases[] = {
      {"ply_float_list_count.ply", ":8: a list's count type must be an integer type, not 'float'"},
      {"ply_nan_index.ply", "face 0 refers to vertex nan of 3"},
      {"ply_huge_index.ply", "face 0 refers to vertex 1.0000000000000001e+300 of 3"}};
  for (const auto& [name, msg] : cases) {
    SCOPED_TRACE(name);
    const std::string e = error_of_file(hostile(name));
    EXPECT_NE(e.find(msg), std::string::npos) << e;
  }
  EXPECT_NE(error_of("frac.ply",
                     "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                     "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                     "end_header\n0 0 0\n1 0 0\n0 1 0\n2.5 0 1 2\n")
                .find("list length 2.5 is not a whole number"),
            std::string::npos);
  EXPECT_NE(error_of("w.obj", "v 1 1 1 1e-320\n").find("w.obj:1: vertex x/w, y/w, z/w overflows"),
            std::string::npos);
}

// Item 5: a material library that cannot be opened, for whatever reason, is a note.
TEST(MeshImport, UnopenableMaterialLibrariesAreNotes) {
  const ImportedMesh im = import_mesh(hostile("obj_long_mtllib.obj"));
  EXPECT_EQ(im.mesh.triangles.size(), 4u);
  ASSERT_EQ(im.notes.size(), 1u);
  EXPECT_NE(im.notes[0].find("could not be opened (File name too long)"), std::string::npos) << im.notes[0];
  const std::string tet = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  std::filesystem::create_symlink("loop.mtl", test::scratch("loop.mtl"));
  std::filesystem::create_directory(test::scratch("dir.mtl"));
  const ImportedMesh loop = import_mesh(write("loop.obj", "mtllib loop.mtl dir.mtl\n" + tet));
  ASSERT_EQ(loop.notes.size(), 2u);
  EXPECT_NE(loop.notes[0].find("'loop.mtl' could not be opened (Too many levels of symbolic links)"),
            std::string::npos)
      << loop.notes[0];
  EXPECT_NE(loop.notes[1].find("'dir.mtl' could not be opened (not a regular file)"), std::string::npos);
}

// Item 16: what is wrong, said in its own words.
TEST(MeshImport, ExtremeScalesSayOverflowOrUnderflow) {
  const std::pair<const char*, const char*> cases[] = {
      {"tetra_1e120.off",
       "mesh has coordinates up to 1e+120 m: its mass properties (lengths to the 5th power) "
       "would overflow double precision"},
      {"tetra_1e308.off", "mesh has coordinates up to 1e+308 m"},
      {"tetra_1e80.off", "mesh has coordinates up to 1e+80 m"},
      {"tetra_1e-200.off",
       "mesh spans only 1e-200 m: its mass properties (lengths to the 5th power) would "
       "underflow double precision"}};
  for (const auto& [name, msg] : cases)
    for (MassMode mode : {MassMode::solid, MassMode::shell, MassMode::hull}) {
      SCOPED_TRACE(std::string(name) + " " + to_string(mode));
      const ImportedMesh im = import_mesh(hostile(name));
      MeshMassOptions opt;
      opt.mode = mode;
      try {
        analyze_mesh(im.mesh, opt);
        ADD_FAILURE() << "accepted";
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(msg), std::string::npos) << e.what();
      }
    }
  // In range, but the density takes the mass out of it: never a non-finite success.
  const ImportedMesh im = import_mesh("assets/tetra.off", Vec3::Constant(100));
  MeshMassOptions opt;
  opt.density = 1e308;
  EXPECT_THROW(analyze_mesh(im.mesh, opt), InputError);
  // A scale that overflows a coordinate says so.
  const std::string e = [&] {
    try {
      import_mesh(hostile("tetra_1e80.off"), Vec3::Constant(1e300));
    } catch (const InputError& x) {
      return std::string(x.what());
    }
    return std::string();
  }();
  EXPECT_NE(e.find("overflows double precision when scaled by"), std::string::npos) << e;
}

TEST(MeshImport, DirectoriesAndFifosAreNotMissingFiles) {
  const std::string dir = test::scratch("d.obj");
  std::filesystem::create_directory(dir);
  EXPECT_NE(error_of_file(dir).find("is a directory, not a file"), std::string::npos);
  const std::string fifo = test::scratch("f.obj");
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_NE(error_of_file(fifo).find("is not a regular file"), std::string::npos);
  EXPECT_NE(error_of_file(test::scratch("none.obj")).find("does not exist"), std::string::npos);
}

}  // namespace
}  // namespace simreel
