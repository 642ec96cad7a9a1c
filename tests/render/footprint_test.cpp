// Shadow footprints: the smallest rectangle around a body's projected bounding-box corners.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "render/footprint.hpp"

namespace simreel {
namespace {

using V2 = Eigen::Vector2f;

float area(const V2 c[4]) {
  return (c[1] - c[0]).norm() * (c[3] - c[0]).norm();
}

// Signed distance of q inside the rectangle's side from c[i] to c[i + 1] (corners go round it,
// either way): positive inside.
float inside(const V2 c[4], int i, const V2& q) {
  const V2 e = (c[(i + 1) % 4] - c[i]).normalized(), in = c[(i + 2) % 4] - c[(i + 1) % 4];
  V2 nrm(-e.y(), e.x());
  if (nrm.dot(in) < 0) nrm = -nrm;
  return nrm.dot(q - c[i]);
}

// A box's 8 corners seen from straight above: its 4 corners twice. Rotated by 30 degrees, the
// smallest rectangle is the box itself (the axis-aligned box around it is 1.87x larger), widened
// by the margin on every side: every corner is at least the margin inside every side, the nearest
// exactly the margin; and the rectangle's sides are square to each other.
TEST(Footprint, SmallestRectangleOfARotatedBox) {
  const float w = 2.0f, h = 0.5f, margin = 0.1f;
  const Eigen::Rotation2Df r(0.5235988f);
  V2 p[8];
  for (int k = 0; k < 8; ++k) p[k] = r * V2((k & 1) ? w / 2 : -w / 2, (k & 2) ? h / 2 : -h / 2) + V2(3, -1);
  V2 c[4];
  min_area_rectangle(p, 8, margin, c);
  EXPECT_NEAR(area(c), (w + 2 * margin) * (h + 2 * margin), 1e-4f);
  EXPECT_NEAR((c[1] - c[0]).dot(c[3] - c[0]), 0.0f, 1e-4f);
  for (int i = 0; i < 4; ++i) {
    float nearest = INFINITY;
    for (const V2& q : p) nearest = std::fmin(nearest, inside(c, i, q));
    EXPECT_NEAR(nearest, margin, 1e-4f) << "side " << i;
  }
}

// Scattered points: everything at least the margin inside, and no larger than the axis-aligned
// box around the points (one of the directions tried is close to it; the widened box is the
// bound).
TEST(Footprint, HoldsScatteredPointsWithTheirMargin) {
  uint32_t state = 12345;
  auto rnd = [&] { return (state = state * 1664525u + 1013904223u) / 4294967296.0f; };
  for (int trial = 0; trial < 200; ++trial) {
    V2 p[8];
    V2 lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
    for (V2& q : p) {
      q = V2(10 * rnd() - 5, 4 * rnd() - 2);
      lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
    }
    const float margin = 0.05f;
    V2 c[4];
    min_area_rectangle(p, 8, margin, c);
    for (const V2& q : p)
      for (int i = 0; i < 4; ++i) EXPECT_GE(inside(c, i, q), margin - 1e-4f);
    const V2 box = hi - lo + V2(2 * margin, 2 * margin);
    EXPECT_LE(area(c), box.x() * box.y() * (1 + 1e-5f));
  }
}

// All corners at one point (a body seen edge-on to a degenerate mesh): a square of side twice the
// margin around it.
TEST(Footprint, DegeneratePointsGiveTheMarginSquare) {
  V2 p[8];
  for (V2& q : p) q = V2(1, 2);
  V2 c[4];
  min_area_rectangle(p, 8, 0.25f, c);
  EXPECT_NEAR(area(c), 0.25f, 1e-6f);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(inside(c, i, p[0]), 0.25f, 1e-6f);
}

}  // namespace
}  // namespace simreel
