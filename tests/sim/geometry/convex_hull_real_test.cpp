// Convex hulls of real-world meshes (../shared/meshes/real, label real_meshes; registered only when
// that folder exists): time, a valid polyhedron, and mass properties equal to the exact hull's
// (rational arithmetic, tests/sim/geometry/hull_exact.hpp) to 1e-12.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "app/scene/mesh_import.hpp"
#include "sim/geometry/convex_hull.hpp"
#include "tests/sim/geometry/hull_exact.hpp"

namespace simreel {
namespace {

const std::string kDir = SIMREEL_REAL_MESHES;

void check_real(const std::string& file, double max_seconds) {
  SCOPED_TRACE(file);
  const TriangleMesh mesh = import_mesh(kDir + "/" + file).mesh;
  const auto t0 = std::chrono::steady_clock::now();
  const TriangleMesh h = convex_hull(mesh.vertices);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(secs, max_seconds);
  const ConvexPolyhedron p = convex_polyhedron(mesh.vertices);
  // Every rule but "no coplanar neighbours" (1.4e-6 rad): real CAD hulls have neighbours closer
  // than that which are not planar to 1e-9 together (see convex_polyhedron()).
  const std::string bad = polyhedron_problem(p);
  if (bad.find("joins two coplanar faces") == std::string::npos) {
    EXPECT_EQ(bad, "");
  }

  MeshMassOptions o;
  o.mode = MassMode::hull;
  o.density = 1.0;
  const MeshReport r = analyze_mesh(mesh, o);
  // The exact hull of the points near the surface (the rest are inside by far more than rounding).
  double size = 0;
  for (const Vec3& v : p.vertices) size = std::max(size, (v - p.centroid).norm());
  std::vector<Vec3> near;
  for (const Vec3& v : mesh.vertices) {
    double out = -INFINITY;
    for (const auto& f : p.faces) out = std::max(out, f.normal.dot(v) - f.offset);
    if (out > -1e-9 * size) near.push_back(v);
  }
  const test::ExactSolid ex = test::exact_solid(test::exact_hull(near));
  const double dv = std::fabs(r.volume - ex.volume) / ex.volume;
  const double dc = (r.props.com - ex.centroid).norm() / size;
  const double di = (r.props.inertia - ex.inertia).norm() / ex.inertia.norm();
  EXPECT_LT(dv, 1e-12);
  EXPECT_LT(dc, 1e-12);
  EXPECT_LT(di, 1e-12);
  std::printf(
      "%s: %zu points, hull %zu triangles, polyhedron %zu vertices %zu faces %d edges, %.3f s; "
      "vs exact hull: volume %.1e, centroid %.1e, inertia %.1e\n",
      file.c_str(), mesh.vertices.size(), h.triangles.size(), p.vertices.size(), p.faces.size(),
      p.edge_count(), secs, dv, dc, di);
}

TEST(ConvexHullReal, CycloidalGear) {
  check_real("tm_cycloidal.ply", 1.0);
}
TEST(ConvexHullReal, GearRepros) {
  check_real("repro/cycloidal_98pts_hull_open.obj", 0.1);
  check_real("repro/cycloidal_668pts_hull_open.obj", 0.1);
}
TEST(ConvexHullReal, OtherMeshes) {
  for (const char* f : {"tm_box.STL", "tm_bunny.ply", "tm_torus.STL", "tm_featuretype.STL", "acj_spot.obj",
                        "igl_fertility.off", "acj_rocker-arm.obj"})
    check_real(f, 1.0);
}

}  // namespace
}  // namespace simreel
