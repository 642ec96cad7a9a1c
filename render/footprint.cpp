#include "render/footprint.hpp"

#include <algorithm>
#include <cmath>

namespace simreel {

void min_area_rectangle(const Eigen::Vector2f* p, int n, float margin, Eigen::Vector2f corners[4]) {
  Eigen::Vector2f best_u(1, 0);
  float best_area = INFINITY;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const Eigen::Vector2f d = p[j] - p[i];
      const float len = d.norm();
      if (!(len > 1e-6f)) continue;
      const Eigen::Vector2f u = d / len, v(-u.y(), u.x());
      float a0 = INFINITY, a1 = -INFINITY, b0 = INFINITY, b1 = -INFINITY;
      for (int k = 0; k < n; ++k) {
        const float a = u.dot(p[k]), b = v.dot(p[k]);
        a0 = std::min(a0, a), a1 = std::max(a1, a), b0 = std::min(b0, b), b1 = std::max(b1, b);
      }
      const float area = (a1 - a0) * (b1 - b0);
      if (area < best_area) best_area = area, best_u = u;
    }
  // The chosen orientation (axis-aligned if every point coincides), widened by the margin.
  const Eigen::Vector2f u = best_u, v(-u.y(), u.x());
  float a0 = INFINITY, a1 = -INFINITY, b0 = INFINITY, b1 = -INFINITY;
  for (int k = 0; k < n; ++k) {
    const float a = u.dot(p[k]), b = v.dot(p[k]);
    a0 = std::min(a0, a), a1 = std::max(a1, a), b0 = std::min(b0, b), b1 = std::max(b1, b);
  }
  a0 -= margin, a1 += margin, b0 -= margin, b1 += margin;
  corners[0] = u * a0 + v * b0;
  corners[1] = u * a1 + v * b0;
  corners[2] = u * a1 + v * b1;
  corners[3] = u * a0 + v * b1;
}

}  // namespace simreel
