// Broad phase: which pairs of shapes are close enough to need the narrow phase. Sort and sweep
// along x over each shape's world box (expanded by the speculative distance and by how far the
// shape can move this step), then the y and z intervals; planes are tested against every moving
// shape's box. The sort order persists between steps, so the insertion sort that restores it is
// near linear when bodies move coherently. The output is sorted by (shape a, shape b), a < b: the
// order never depends on the previous order, the thread count or addresses.
// (Issue 15 replaces the sweep with a dynamic tree for 10^4+ bodies; the interface stays.)
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "sim/shapes.hpp"

namespace simreel {

class BroadPhase {
 public:
  // boxes[i]: world box of shape i (ignored for planes and shapes not in `sweep`).
  // sweep: the non-plane shapes to consider; planes: the plane shapes with their world pose.
  // allowed(a, b): whether shapes a < b may touch (bodies, filters, ignore list).
  // Appends nothing: `pairs` is cleared and refilled with keys (a << 32 | b).
  template <typename Allowed>
  void update(const std::vector<Aabb>& boxes, const std::vector<int>& sweep, const std::vector<int>& planes,
              const std::vector<Pose>& plane_poses, const std::vector<char>& moving, Allowed&& allowed,
              std::vector<uint64_t>& pairs);

 private:
  std::vector<int> order_;  ///< `sweep` sorted by box lo.x, ties by index
};

template <typename Allowed>
void BroadPhase::update(const std::vector<Aabb>& boxes, const std::vector<int>& sweep,
                        const std::vector<int>& planes, const std::vector<Pose>& plane_poses,
                        const std::vector<char>& moving, Allowed&& allowed, std::vector<uint64_t>& pairs) {
  pairs.clear();
  if (order_.size() != sweep.size()) order_ = sweep;
  // Insertion sort by (lo.x, index): a total order, so the result is the same from any start.
  auto less = [&](int a, int b) {
    const double xa = boxes[a].lo.x(), xb = boxes[b].lo.x();
    return xa < xb || (xa == xb && a < b);
  };
  for (size_t i = 1; i < order_.size(); ++i) {
    const int v = order_[i];
    size_t j = i;
    while (j > 0 && less(v, order_[j - 1])) {
      order_[j] = order_[j - 1];
      --j;
    }
    order_[j] = v;
  }
  for (size_t i = 0; i < order_.size(); ++i) {
    const int a = order_[i];
    const Aabb& A = boxes[a];
    for (size_t j = i + 1; j < order_.size(); ++j) {
      const int b = order_[j];
      const Aabb& B = boxes[b];
      if (B.lo.x() > A.hi.x()) break;
      if (!moving[a] && !moving[b]) continue;
      if (A.lo.y() > B.hi.y() || B.lo.y() > A.hi.y() || A.lo.z() > B.hi.z() || B.lo.z() > A.hi.z()) continue;
      const int lo = a < b ? a : b, hi = a < b ? b : a;
      if (allowed(lo, hi)) pairs.push_back(((uint64_t)lo << 32) | (uint32_t)hi);
    }
  }
  // Planes (z = 0 of their frame, solid below) against each moving shape's box: the box's lowest
  // corner along the plane normal must reach the plane's side.
  for (size_t k = 0; k < planes.size(); ++k) {
    const int p = planes[k];
    const Vec3 n = plane_poses[k].R.col(2);
    const double d = n.dot(plane_poses[k].p);
    for (int s : sweep) {
      if (!moving[s]) continue;
      const Aabb& B = boxes[s];
      const Vec3 c = 0.5 * (B.lo + B.hi), e = 0.5 * (B.hi - B.lo);
      if (n.dot(c) - e.dot(n.cwiseAbs()) > d) continue;
      const int lo = p < s ? p : s, hi = p < s ? s : p;
      if (allowed(lo, hi)) pairs.push_back(((uint64_t)lo << 32) | (uint32_t)hi);
    }
  }
  std::sort(pairs.begin(), pairs.end());
}

}  // namespace simreel
