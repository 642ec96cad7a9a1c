// Where a body's shadow can fall on the ground, as one rectangle (two triangles).
#pragma once
#include <Eigen/Core>

namespace simreel {

// The smallest-area rectangle, of any orientation, holding the n points `p` (2 <= n <= 16)
// widened by `margin` on every side; its corners in order around it. One of its sides lies along
// a side of the points' convex hull (Freeman and Shapira 1975), so every direction between two of
// the points is tried: n (n - 1) / 2 candidates, no allocation.
void min_area_rectangle(const Eigen::Vector2f* p, int n, float margin, Eigen::Vector2f corners[4]);

}  // namespace simreel
