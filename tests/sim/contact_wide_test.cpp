// The contact solver's wide path (sim/contact_wide.cpp) against statics: resting boxes take it
// (plain manifolds: no restitution, rolling or tracked point), and at rest each manifold's
// accumulated normal impulse per substep is the weight it carries times the substep.
#include <gtest/gtest.h>

#include "sim/world.hpp"
#include "tests/sim/contact_fixtures.hpp"

namespace simreel {
namespace {
using namespace contact_test;

// A manifold's points' impulses (N s, the last substep's) between bodies a and b.
double manifold_impulse(const World& w, int a, int b, double* least = nullptr, double* most = nullptr) {
  for (const Contact& c : w.contacts()) {
    if (!((c.body_a == a && c.body_b == b) || (c.body_a == b && c.body_b == a))) continue;
    double sum = 0, lo = 1e300, hi = -1e300;
    for (int j = 0; j < c.count; ++j) {
      sum += c.points[j].normal_impulse;
      lo = std::min(lo, c.points[j].normal_impulse);
      hi = std::max(hi, c.points[j].normal_impulse);
    }
    if (least) *least = lo;
    if (most) *most = hi;
    return sum;
  }
  return 0;
}

// A cube resting flat: four corners, each a quarter of m g h (by symmetry; the soft contact's
// spring makes the share-out unique although four points on a face are three degrees of
// freedom). Tolerance 1e-6 relative: at rest the block solve is exact to rounding, and the cube
// rests to 1e-6 m/s.
TEST(ContactWide, CubeRestingFlatSharesItsWeightEqually) {
  SKIP_WITHOUT(has_box_box(), "box-box");
  WorldConfig cfg;
  cfg.dt = 1.0 / 240;
  cfg.contacts.sleep = false;
  World w(cfg, {ground(), box(Vec3(0.5, 0.5, 0.5), Vec3(0, 0, 0.25))});
  while (w.time() < 1.0) w.step();
  const double m = 0.5 * 0.5 * 0.5 * 1000.0;
  const double h = cfg.dt / w.substeps();
  double lo = 0, hi = 0;
  const double total = manifold_impulse(w, 0, 1, &lo, &hi);
  EXPECT_NEAR(total, m * 9.81 * h, 1e-6 * m * 9.81 * h);
  EXPECT_NEAR(lo, hi, 1e-6 * m * 9.81 * h);
}

// A column of five cubes, each resting on the one below: the contact under cube i carries the
// weight of the cubes from i up. Tolerance 1e-4 relative: the passes' own tolerance (the column
// is solved one manifold at a time, Gauss-Seidel, and each manifold to 1e-4).
TEST(ContactWide, ColumnCarriesTheWeightAbove) {
  SKIP_WITHOUT(has_box_box(), "box-box");
  WorldConfig cfg;
  cfg.dt = 1.0 / 240;
  cfg.contacts.sleep = false;
  std::vector<BodyDef> bodies = {ground()};
  for (int i = 0; i < 5; ++i) bodies.push_back(box(Vec3(0.5, 0.5, 0.5), Vec3(0, 0, 0.25 + 0.5 * i)));
  World w(cfg, bodies);
  while (w.time() < 2.0) w.step();
  const double m = 0.5 * 0.5 * 0.5 * 1000.0;
  const double h = cfg.dt / w.substeps();
  for (int i = 1; i <= 5; ++i) {
    const double carried = (6 - i) * m * 9.81 * h;
    EXPECT_NEAR(manifold_impulse(w, i - 1, i), carried, 1e-4 * carried) << "contact under cube " << i;
  }
}

}  // namespace
}  // namespace simreel
