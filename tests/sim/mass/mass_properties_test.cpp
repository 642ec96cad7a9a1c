// Mass properties against closed forms. Tolerances: the polyhedral formulas are exact, so the
// only error is rounding: ~1e-14 relative for meshes of a few dozen faces near unit size.
#include <gtest/gtest.h>

#include <simreel/body.hpp>
#include "sim/geometry/convex_hull.hpp"
#include <simreel/error.hpp>
#include "sim/mass/primitives.hpp"
#include "tests/sim/mass/mesh_fixtures.hpp"

namespace simreel {
namespace {
using test::rel_err;

constexpr double kExact = 1e-14;  // rounding of a few dozen products of O(1) numbers

MeshReport solid(const TriangleMesh& m, double rho = 1.0) {
  MeshMassOptions o;
  o.density = rho;
  return analyze_mesh(m, o);
}

TEST(MeshMass, UnitCubeIsExact) {
  const MeshReport r = solid(test::box_mesh(Vec3::Ones()));
  EXPECT_NEAR(r.volume, 1.0, kExact);
  EXPECT_NEAR(r.props.mass, 1.0, kExact);
  EXPECT_LT((r.props.com - Vec3::Constant(0.5)).norm(), kExact);
  EXPECT_LT(rel_err(r.props.inertia, Mat3::Identity() / 6.0), kExact);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.consistently_oriented);
  EXPECT_TRUE(r.warnings.empty());
}

TEST(MeshMass, TetrahedronMatchesDirectIntegration) {
  // Integrals over the unit tetrahedron by slicing: int x^2 = B(3,3)/2 = 1/60, int xy = 1/120.
  // About the origin Ixx = 2/60, Ixy = -1/120; shifted to the centroid (1/4,1/4,1/4), mass 1/6:
  // Ixx = 1/30 - 1/48 = 1/80, Ixy = -1/120 + 1/96 = 1/480.
  const MeshReport r = solid(test::unit_tetrahedron(), 1.0);
  EXPECT_NEAR(r.volume, 1.0 / 6.0, kExact);
  EXPECT_LT((r.props.com - Vec3::Constant(0.25)).norm(), kExact);
  Mat3 I;
  I << 1.0 / 80, 1.0 / 480, 1.0 / 480, 1.0 / 480, 1.0 / 80, 1.0 / 480, 1.0 / 480, 1.0 / 480, 1.0 / 80;
  EXPECT_LT(rel_err(r.props.inertia, I), kExact);
}

TEST(MeshMass, NonConvexLPrismMatchesTwoBoxes) {
  // L = box A [0,2]x[0,1]x[0,1] (mass 2) + box B [0,1]x[1,2]x[0,1] (mass 1), density 1.
  // Each box m/12 (b^2 + c^2) about its centre, then Steiner to the common centre (5/6, 5/6, 1/2).
  const MeshReport r = solid(test::l_prism());
  const Vec3 c(5.0 / 6.0, 5.0 / 6.0, 0.5);
  auto box = [&](double m, const Vec3& s, const Vec3& ctr) {
    const Vec3 d = ctr - c;
    Mat3 I = Vec3(m / 12 * (s.y() * s.y() + s.z() * s.z()), m / 12 * (s.x() * s.x() + s.z() * s.z()),
                  m / 12 * (s.x() * s.x() + s.y() * s.y()))
                 .asDiagonal();
    return Mat3(I + m * (d.dot(d) * Mat3::Identity() - d * d.transpose()));
  };
  const Mat3 I = box(2, Vec3(2, 1, 1), Vec3(1, 0.5, 0.5)) + box(1, Vec3(1, 1, 1), Vec3(0.5, 1.5, 0.5));
  EXPECT_NEAR(r.volume, 3.0, 3 * kExact);
  EXPECT_LT((r.props.com - c).norm(), kExact);
  EXPECT_LT(rel_err(r.props.inertia, I), kExact);
}

TEST(MeshMass, TessellatedSphereConvergesQuadratically) {
  // An inscribed UV sphere's error in volume and in I/(m r^2) against 4/3 pi r^3 and 2/5 falls
  // as the square of the angular step: halving it divides the error by ~4.
  double prev_v = 0, prev_i = 0;
  for (int n : {16, 32, 64, 128}) {
    const MeshReport r = solid(test::uv_sphere(2.0, n));
    const double ev = std::fabs(r.volume / sphere_volume(2.0) - 1.0);
    const double ei = std::fabs(r.props.inertia(0, 0) / (r.props.mass * 4.0) - 0.4) / 0.4;
    if (prev_v > 0) {
      EXPECT_NEAR(prev_v / ev, 4.0, 0.3) << "n = " << n;
      EXPECT_NEAR(prev_i / ei, 4.0, 0.3) << "n = " << n;
    }
    prev_v = ev, prev_i = ei;
  }
  EXPECT_LT(prev_i, 1e-3);
}

TEST(MeshMass, FarFromOriginKeepsPrecision) {
  // A rotated unit cube 1e5 m away: coordinates carry ~1e-11 m rounding, so the inertia is good
  // to ~1e-10 relative. Integrating about the world origin instead would lose (1e5)^2 * eps ~ 1e-6.
  const Quat q = Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()));
  TriangleMesh m = test::box_mesh(Vec3::Ones(), Vec3::Constant(-0.5));
  const Vec3 far(1e5, -2e5, 1e5);
  for (Vec3& v : m.vertices) v = far + q * v;
  const MeshReport r = solid(m);
  EXPECT_NEAR(r.volume, 1.0, 1e-9);
  EXPECT_LT((r.props.com - far).norm(), 1e-9);
  EXPECT_LT(rel_err(r.props.inertia, Mat3::Identity() / 6.0), 1e-9);
}

TEST(MeshMass, InsideOutIsFlippedAndReported) {
  TriangleMesh m = test::box_mesh(Vec3(3, 2, 1));
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  const MeshReport r = solid(m);
  EXPECT_TRUE(r.inverted);
  EXPECT_NEAR(r.volume, 6.0, 6 * kExact);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("inside-out"), std::string::npos);
}

TEST(MeshMass, OneFlippedTriangleIsRepaired) {
  // MuJoCo 2.2.2 rejects this mesh; the winding is recoverable from the neighbours.
  TriangleMesh m = test::l_prism();
  std::swap(m.triangles[3][1], m.triangles[3][2]);
  const MeshReport r = solid(m);
  EXPECT_FALSE(r.consistently_oriented);
  EXPECT_TRUE(r.closed);
  EXPECT_EQ(r.reoriented_faces, 1);
  EXPECT_NEAR(r.volume, 3.0, 3 * kExact);
}

TEST(MeshMass, OpenMeshIsAnErrorThatSuggestsShellOrHull) {
  TriangleMesh m = test::box_mesh(Vec3::Ones());
  m.triangles.pop_back();
  m.triangles.pop_back();  // remove the x = 1 face: a square hole
  try {
    solid(m);
    FAIL() << "open mesh accepted as a solid";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("open"), std::string::npos) << msg;
    EXPECT_NE(msg.find("shell"), std::string::npos) << msg;
    EXPECT_NE(msg.find("hull"), std::string::npos) << msg;
  }
  MeshMassOptions hull;
  hull.mode = MassMode::hull;
  hull.density = 1.0;
  const MeshReport h = analyze_mesh(m, hull);
  EXPECT_NEAR(h.volume, 1.0, kExact);  // the hull of the open box's corners is the whole cube
  EXPECT_FALSE(h.closed);
}

TEST(MeshMass, ShellCubeMatchesThinWalledClosedForm) {
  // Thin-walled cube of side a and mass M: I = 5/18 M a^2 about any centroidal axis.
  MeshMassOptions o;
  o.mode = MassMode::shell;
  o.density = 2.0;
  o.thickness = 0.01;
  const MeshReport r = analyze_mesh(test::box_mesh(Vec3::Constant(2.0)), o);
  const double M = 6 * 4.0 * 2.0 * 0.01;
  EXPECT_NEAR(r.props.mass, M, 1e-15);
  EXPECT_LT(rel_err(r.props.inertia, Mat3::Identity() * (5.0 / 18.0 * M * 4.0)), kExact);
}

TEST(MeshMass, UnweldedStlStyleCubeIsClosed) {
  const TriangleMesh welded = test::box_mesh(Vec3::Ones());
  TriangleMesh soup;
  for (const auto& t : welded.triangles) {
    const int b = (int)soup.vertices.size();
    for (int k = 0; k < 3; ++k) soup.vertices.push_back(welded.vertices[t[k]]);
    soup.triangles.push_back({b, b + 1, b + 2});
  }
  const MeshReport r = solid(soup);
  EXPECT_TRUE(r.closed);
  EXPECT_EQ(r.welded_vertices, 36 - 8);
  EXPECT_NEAR(r.volume, 1.0, kExact);
}

TEST(MeshMass, DegenerateFacesAreSkippedAndReported) {
  TriangleMesh m = test::box_mesh(Vec3::Ones());
  m.triangles.push_back({0, 0, 1});
  m.triangles.push_back({0, 1, 3});
  m.triangles.back() = {0, 1, 1};
  const MeshReport r = solid(m);
  EXPECT_EQ(r.degenerate_faces, 2);
  EXPECT_NEAR(r.volume, 1.0, kExact);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings[0].find("degenerate"), std::string::npos);
}

TEST(MeshMass, BrokenInputIsAnErrorNotACrash) {
  TriangleMesh none;
  none.vertices = {Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY()};
  EXPECT_THROW(solid(none), InputError);  // a point cloud
  TriangleMesh bad_index = test::unit_tetrahedron();
  bad_index.triangles[2][1] = 17;
  EXPECT_THROW(solid(bad_index), InputError);
  TriangleMesh nan = test::unit_tetrahedron();
  nan.vertices[1].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(solid(nan), InputError);
  TriangleMesh flat;  // a doubly covered square: closed, but it encloses nothing
  flat.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  flat.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 2, 1}, {0, 3, 2}};
  try {
    solid(flat);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("flat"), std::string::npos) << e.what();
  }
}

TEST(ConvexHull, CubeCornersWithInteriorPoints) {
  std::vector<Vec3> pts = test::box_mesh(Vec3::Ones()).vertices;
  for (int i = 1; i < 50; ++i)
    pts.push_back(Vec3(0.02 * i, 0.5 + 0.3 * std::sin(i), 0.5 + 0.3 * std::cos(i)));
  const TriangleMesh h = convex_hull(pts);
  EXPECT_EQ(h.vertices.size(), 8u);
  MeshMassOptions o;
  o.density = 1.0;
  const MeshReport r = analyze_mesh(h, o);
  EXPECT_NEAR(r.volume, 1.0, kExact);
  EXPECT_LT(rel_err(r.props.inertia, Mat3::Identity() / 6.0), kExact);
}

TEST(Primitives, CapsuleIsCylinderPlusSphere) {
  // Volume: pi r^2 L + 4/3 pi r^3; Izz = m_cyl r^2/2 + 2/5 m_sph r^2.
  const MassProperties c = capsule_mass(0.5, 3.0, 1.0);
  const double L = 2.0, mc = std::numbers::pi * 0.25 * L, ms = 4.0 / 3.0 * std::numbers::pi * 0.125;
  EXPECT_NEAR(c.mass, mc + ms, 1e-15);
  EXPECT_NEAR(c.inertia(2, 2), 0.5 * mc * 0.25 + 0.4 * ms * 0.25, 1e-15);
  // A capsule of height 2r is a sphere.
  const MassProperties s = capsule_mass(0.5, 1.0, 1.0), t = sphere_mass(0.5, 1.0);
  EXPECT_LT(rel_err(s.inertia, t.inertia), kExact);
}

TEST(Composite, TwoBoxesEqualTheirUnion) {
  BodyDef b;
  for (double x : {0.5, 1.5}) {
    Collider c;
    c.size = Vec3::Ones();
    c.props_C = box_mass(c.size, 1.0);
    c.p_BC = Vec3(x, 0.5, 0.5);
    b.add_collider(c);
  }
  const MassProperties one = box_mass(Vec3(2, 1, 1), 1.0);
  EXPECT_NEAR(b.mass_B().mass, 2.0, kExact);
  EXPECT_LT((b.mass_B().com - Vec3(1, 0.5, 0.5)).norm(), kExact);
  EXPECT_LT(rel_err(b.mass_B().inertia, one.inertia), kExact);
}

TEST(Composite, RotatedColliderRotatesItsInertia) {
  // A 3 x 2 x 1 box turned 90 degrees about z is a 2 x 3 x 1 box.
  BodyDef b;
  Collider c;
  c.size = Vec3(3, 2, 1);
  c.props_C = box_mass(c.size, 1.0);
  c.q_BC = Quat(Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitZ()));
  c.p_BC = Vec3(1, 2, 3);
  b.add_collider(c);
  EXPECT_LT(rel_err(b.mass_B().inertia, box_mass(Vec3(2, 3, 1), 1.0).inertia), kExact);
  EXPECT_LT((b.mass_B().com - Vec3(1, 2, 3)).norm(), kExact);
  // An arbitrary rotation keeps the principal moments.
  c.q_BC = Quat(Eigen::AngleAxisd(0.3, Vec3(1, -2, 0.5).normalized()));
  BodyDef b2;
  b2.add_collider(c);
  const Vec3 m = principal_axes(b2.mass_B().inertia).moments;
  const Vec3 m0 = principal_axes(c.props_C.inertia).moments;
  EXPECT_LT((m - m0).norm() / m0.norm(), kExact);
}

TEST(Validity, TriangleInequalityAndPositivity) {
  EXPECT_EQ(inertia_problem(box_mass(Vec3(3, 2, 1), 1).inertia), "");
  EXPECT_NE(inertia_problem(Vec3(1, 1, 3).asDiagonal()), "");
  EXPECT_NE(inertia_problem(Vec3(0, 1, 1).asDiagonal()), "");
}

}  // namespace
}  // namespace simreel
