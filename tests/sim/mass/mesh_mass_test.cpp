// Mesh defects, each on a small self-made mesh: the cavity rule (2), shell mode on a
// surface solid mode refuses (5), consistent orientation of open meshes (6), closedness with a
// zero-area sliver at a T-junction (7), and the words used for what cannot be a solid (8).
#include <gtest/gtest.h>

#include <numbers>

#include <simreel/error.hpp>
#include "tests/sim/mass/mesh_fixtures.hpp"

namespace simreel {
namespace {

constexpr double kExact = 1e-13;

MeshReport run(const TriangleMesh& m, MassMode mode = MassMode::solid) {
  MeshMassOptions o;
  o.density = 1.0;
  o.mode = mode;
  o.thickness = 0.01;
  return analyze_mesh(m, o);
}

std::string error_of(const TriangleMesh& m, MassMode mode = MassMode::solid) {
  try {
    run(m, mode);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted";
  return "";
}

bool any_warning(const MeshReport& r, const std::string& part) {
  for (const std::string& w : r.warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

std::string all_warnings(const MeshReport& r) {
  std::string s;
  for (const std::string& w : r.warnings) s += w + "\n";
  return s;
}

// Appends b's faces to a, optionally inside-out.
void append(TriangleMesh& a, const TriangleMesh& b, bool inside_out) {
  const int base = (int)a.vertices.size();
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (auto t : b.triangles) {
    if (inside_out) std::swap(t[1], t[2]);
    a.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
}

// Torus about the z axis, radii R (centre line) and r (tube), n x m quads, outward.
TriangleMesh torus(double R, double r, int n, int m) {
  TriangleMesh t;
  const double tau = 2 * std::numbers::pi;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = tau * i / n, v = tau * j / m;
      t.vertices.push_back(
          Vec3((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)));
    }
  auto id = [&](int i, int j) { return (i % n) * m + (j % m); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      t.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      t.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return t;
}

// Defect 2: a small inside-out ball in the hole of a torus has its box inside the torus's box,
// but it is not inside the torus: it is flipped (and named), not taken as a cavity.
TEST(MeshDefects, InsideOutBallInATorusHoleIsFlippedNotACavity) {
  const TriangleMesh ring = torus(2.0, 0.5, 48, 24), ball = test::uv_sphere(0.5, 12);
  const double v_ring = run(ring).volume, v_ball = run(ball).volume;
  TriangleMesh m = ring;
  append(m, ball, true);
  const MeshReport r = run(m);
  EXPECT_NEAR(r.volume, v_ring + v_ball, kExact * (v_ring + v_ball)) << all_warnings(r);
  EXPECT_TRUE(r.inverted);
  EXPECT_TRUE(any_warning(r, "flipped 1 inside-out part")) << all_warnings(r);
  EXPECT_TRUE(any_warning(r, "part 2 (" + std::to_string(ball.triangles.size()) +
                                 " faces, the first is face " + std::to_string(ring.triangles.size()) + ")"))
      << all_warnings(r);
  EXPECT_FALSE(any_warning(r, "cavity")) << all_warnings(r);
}

TEST(MeshDefects, InsideOutBoxInsideABoxIsANamedCavity) {
  TriangleMesh m = test::box_mesh(Vec3::Constant(4.0));
  append(m, test::box_mesh(Vec3::Ones(), Vec3::Constant(1.5)), true);
  const MeshReport r = run(m);
  EXPECT_NEAR(r.volume, 63.0, 63 * kExact);
  EXPECT_FALSE(r.inverted);
  EXPECT_TRUE(any_warning(r, "as a cavity")) << all_warnings(r);
  EXPECT_TRUE(any_warning(r, "part 2 (12 faces, the first is face 12) in part 1")) << all_warnings(r);
}

TEST(MeshDefects, OutwardPartInsideAnotherIsWeighedTwiceAndSaidSo) {
  TriangleMesh m = test::box_mesh(Vec3::Constant(4.0));
  append(m, test::box_mesh(Vec3::Ones(), Vec3::Constant(1.5)), false);
  const MeshReport r = run(m);
  EXPECT_NEAR(r.volume, 65.0, 65 * kExact);
  EXPECT_TRUE(any_warning(r, "counted twice")) << all_warnings(r);
}

// A box and the same box reversed: closed, every edge shared by four faces, no volume.
TriangleMesh double_covered_box() {
  TriangleMesh m = test::box_mesh(Vec3(1, 2, 3));
  append(m, test::box_mesh(Vec3(1, 2, 3)), true);
  return m;
}

// Defect 5: shell mode weighs any surface, closed double-covered ones included.
TEST(MeshDefects, ShellModeNeedsOnlyASurface) {
  const MeshReport r = run(double_covered_box(), MassMode::shell);
  EXPECT_NEAR(r.area, 2 * 22.0, 44 * kExact);
  EXPECT_NEAR(r.props.mass, 0.01 * 44.0, 0.44 * kExact);
  EXPECT_NEAR((r.props.com - Vec3(0.5, 1, 1.5)).norm(), 0.0, kExact);
  EXPECT_TRUE(r.closed);
  EXPECT_EQ(r.nonmanifold_edges, 18);
  // An open, badly wound surface is a surface too.
  TriangleMesh open = test::box_mesh(Vec3::Ones());
  open.triangles.pop_back();
  std::swap(open.triangles[0][1], open.triangles[0][2]);
  const MeshReport o = run(open, MassMode::shell);
  EXPECT_FALSE(o.closed);
  EXPECT_FALSE(o.consistently_oriented);
  EXPECT_NEAR(o.area, 5.5, 5.5 * kExact);
}

// Defect 6: boundary edges do not count as disagreements.
TEST(MeshDefects, OpenMeshesCanBeConsistentlyOriented) {
  TriangleMesh tri;
  tri.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  tri.triangles = {{0, 1, 2}};
  EXPECT_TRUE(run(tri, MassMode::shell).consistently_oriented);
  TriangleMesh open = test::box_mesh(Vec3::Ones());
  open.triangles.resize(10);  // no x = 1 face
  const MeshReport r = run(open, MassMode::shell);
  EXPECT_FALSE(r.closed);
  EXPECT_TRUE(r.consistently_oriented);
  std::swap(open.triangles[4][1], open.triangles[4][2]);
  EXPECT_FALSE(run(open, MassMode::shell).consistently_oriented);
}

// Defect 7: a unit cube whose top face has a vertex in the middle of its front edge (a T-junction),
// closed by a zero-area sliver along that edge. Closed as given; the sliver is skipped and said.
TEST(MeshDefects, SliverAtATJunctionKeepsTheCubeClosed) {
  TriangleMesh m = test::box_mesh(Vec3::Ones());
  // box_mesh: vertex i has x from bit 0, y from bit 1, z from bit 2; top triangle {4, 5, 6}
  // uses the front top edge 4-5 (y = 0, z = 1).
  const int mid = (int)m.vertices.size();
  m.vertices.push_back(Vec3(0.5, 0, 1));
  auto it = std::find(m.triangles.begin(), m.triangles.end(), std::array<int, 3>{4, 5, 6});
  ASSERT_NE(it, m.triangles.end());
  *it = {4, mid, 6};
  m.triangles.push_back({mid, 5, 6});
  m.triangles.push_back({4, 5, mid});  // the sliver: 4 -> 5, 5 -> mid, mid -> 4
  const MeshReport r = run(m);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.consistently_oriented);
  EXPECT_EQ(r.degenerate_faces, 1);
  EXPECT_NEAR(r.volume, 1.0, kExact);
  EXPECT_NEAR((r.props.com - Vec3::Constant(0.5)).norm(), 0.0, kExact);
  EXPECT_TRUE(any_warning(r, "1 sliver")) << all_warnings(r);
  // Without the sliver the hole is real.
  m.triangles.pop_back();
  EXPECT_NE(error_of(m).find("mesh is open: 3 edges"), std::string::npos) << error_of(m);
}

// Defect 8: "flat" only for a planar surface; non-manifold edges counted; "vertices".
TEST(MeshDefects, WordsForWhatCannotBeASolid) {
  const std::string e = error_of(double_covered_box());
  EXPECT_EQ(e.find("flat"), std::string::npos) << e;
  EXPECT_NE(e.find("encloses no volume"), std::string::npos) << e;
  EXPECT_NE(e.find("18 edges shared by more than two faces"), std::string::npos) << e;
  TriangleMesh square;  // a doubly covered square: closed and planar
  square.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  square.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 2, 1}, {0, 3, 2}};
  EXPECT_NE(error_of(square).find("mesh is flat (all its vertices lie in one plane)"), std::string::npos);
  TriangleMesh cloud;
  cloud.vertices = square.vertices;
  EXPECT_NE(error_of(cloud).find("mesh has 4 vertices but no faces"), std::string::npos) << error_of(cloud);
  // Two tetrahedra sharing an edge: closed, weighed, and the non-manifold edge is said.
  TriangleMesh two = test::unit_tetrahedron();
  TriangleMesh other = test::unit_tetrahedron();
  for (Vec3& v : other.vertices) v = Vec3(v.x(), -v.y(), -v.z());  // a half-turn about x keeps edge 0-1
  append(two, other, false);
  const MeshReport r = run(two);
  EXPECT_EQ(r.nonmanifold_edges, 1);
  EXPECT_NEAR(r.volume, 1.0 / 3.0, kExact);
  EXPECT_TRUE(any_warning(r, "1 edge is shared by more than two faces (non-manifold)")) << all_warnings(r);
}

}  // namespace
}  // namespace simreel
