// Approximate convex decomposition (sim/geometry/convex_decomposition.hpp): parts cover the solid
// and lie in it up to their concavity, an L splits exactly at its inner corner, the result is the
// same every time and the same when rebuilt from its points (a cache).
#include <gtest/gtest.h>

#include <cmath>

#include <simreel/error.hpp>
#include <simreel/mesh.hpp>
#include "sim/geometry/convex_decomposition.hpp"
#include "tests/sim/mass/mesh_fixtures.hpp"

namespace simreel {
namespace {

// An L of legs 0.1 thick, 0.4 long, 0.1 tall. The fan from corner 0 = (0, 0) covers it exactly
// (the polygon is star-shaped from that corner).
TriangleMesh thin_l() {
  return test::prism({{0, 0}, {0.4, 0}, {0.4, 0.1}, {0.1, 0.1}, {0.1, 0.4}, {0, 0.4}}, 0.1);
}

TriangleMesh torus(double R, double r, int nu, int nv) {
  TriangleMesh m;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * M_PI * i / nu, v = 2 * M_PI * j / nv;
      m.vertices.emplace_back((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u),
                              r * std::sin(v));
    }
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const int a = i * nv + j, b = ((i + 1) % nu) * nv + j, c = ((i + 1) % nu) * nv + (j + 1) % nv,
                d = i * nv + (j + 1) % nv;
      m.triangles.push_back({a, b, c});
      m.triangles.push_back({a, c, d});
    }
  return m;
}

TEST(ConvexDecomposition, AnLSplitsExactlyIntoItsTwoLegs) {
  const Decomposition d = convex_decomposition(thin_l());
  ASSERT_EQ(d.parts.size(), 2u);
  EXPECT_NEAR(d.solid_volume, 0.007, 1e-15);
  EXPECT_NEAR(d.excess(), 0, 1e-12);  // its convex hull would hold 64% more
}

// A torus's hull is a disc (its hole filled); decomposed, the hole stays open: no part reaches
// the axis, and the parts hold the solid within a few percent.
TEST(ConvexDecomposition, ATorusKeepsItsHole) {
  const TriangleMesh t = torus(0.5, 0.15, 32, 16);
  DecompositionOptions opt;
  const Decomposition d = convex_decomposition(t, opt);
  EXPECT_GE((int)d.parts.size(), 8);
  EXPECT_LE((int)d.parts.size(), opt.max_parts);
  EXPECT_LT(std::fabs(d.excess()), 0.03);
  for (const auto& p : d.parts) {
    double nearest = 1e9;
    for (const Vec3& v : p->vertices) nearest = std::min(nearest, Vec3(v.x(), v.y(), 0).norm());
    EXPECT_GT(nearest, 0.5 - 0.15 - 1e-9 - 0.13);  // no part spans the hole (radius 0.35)
  }
  // The same every time, and the same rebuilt from its points (what the cache keeps).
  const Decomposition again = convex_decomposition(t, opt);
  const Decomposition rebuilt = decomposition_from_points(d.points, d.solid_volume, opt.max_hull_vertices);
  ASSERT_EQ(again.parts.size(), d.parts.size());
  for (size_t i = 0; i < d.parts.size(); ++i) {
    EXPECT_EQ(again.parts[i]->vertices, d.parts[i]->vertices);
    EXPECT_EQ(rebuilt.parts[i]->vertices, d.parts[i]->vertices);
  }
  EXPECT_EQ(rebuilt.hull_volume, d.hull_volume);
}

// A scan with a hole (one face of the L missing) is read as the solid it nearly bounds.
TEST(ConvexDecomposition, AnOpenMeshIsReadAsTheSolidItNearlyBounds) {
  TriangleMesh m = thin_l();
  m.triangles.pop_back();
  const Decomposition d = convex_decomposition(m);
  EXPECT_FALSE(d.closed);
  ASSERT_EQ(d.parts.size(), 2u);
  EXPECT_NEAR(d.hull_volume, 0.007, 1e-12);
  const MassProperties mp = decomposition_mass(d);  // the L's own, as its two legs
  EXPECT_NEAR(mp.mass, 0.007, 1e-12);
  EXPECT_NEAR(mp.com.x(), (0.004 * 0.2 + 0.003 * 0.05) / 0.007, 1e-12);  // the leg along x, the other
  TriangleMesh flat;
  flat.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  flat.triangles = {{0, 1, 2}};
  EXPECT_THROW(convex_decomposition(flat), InputError);
}

}  // namespace
}  // namespace simreel
