// Broad phase: which pairs of shapes are close enough to need the narrow phase. Sort and sweep
// along x over each shape's world box (expanded by the speculative distance and by how far the
// shape can move this step), then the y and z intervals; planes are tested against every moving
// shape's box. The sort order persists between steps, so the insertion sort that restores it is
// near linear when bodies move coherently. The output is sorted by (shape a, shape b), a < b: the
// order never depends on the previous order, the thread count or addresses.
// The sweep runs over fat boxes (each shape's box grown by a margin) and keeps its pairs as
// candidates; a step re-sweeps only when some shape's box has left its fat box, and otherwise
// filters the candidates by this step's boxes. Every box lies in its fat box, so each overlapping
// pair is a candidate and the output is exactly the pairs whose boxes overlap, whatever the fat
// boxes' history (a resumed run gives the same pairs). A pile at rest never re-sweeps.
// (Issue 15 replaces the sweep with a dynamic tree for 10^4+ bodies; the interface stays.)
#pragma once
#include <algorithm>
#include <cstdint>
#include <functional>
#include <vector>

#include "sim/shapes.hpp"

namespace simreel {

class BroadPhase {
 public:
  // boxes[i]: world box of shape i (ignored for planes and shapes not in `sweep`).
  // sweep: the non-plane shapes to consider; planes: the plane shapes with their world pose.
  // allowed(a, b): whether shapes a < b may touch (bodies, filters, ignore list). It and `moving`
  // must not change over the broad phase's life (they are applied when the candidates are made).
  // Appends nothing: `pairs` is cleared and refilled with keys (a << 32 | b).
  template <typename Allowed>
  void update(const std::vector<Aabb>& boxes, const std::vector<int>& sweep, const std::vector<int>& planes,
              const std::vector<Pose>& plane_poses, const std::vector<char>& moving, Allowed&& allowed,
              std::vector<uint64_t>& pairs);

 private:
  std::vector<int> order_;            ///< `sweep` sorted by fat box lo.x, ties by index
  std::vector<Aabb> fat_;             ///< per shape: its box when last swept, grown by a margin
  std::vector<uint64_t> candidates_;  ///< allowed pairs whose fat boxes overlap, sorted
  bool valid_ = false;                ///< candidates_ were made for this `sweep`
};

// Fat box margin: a tenth of the box's largest side (at least 1 mm), so a shape at rest stays in
// its fat box and a falling one leaves it every few steps.
inline Aabb fatten(const Aabb& b) {
  const double m = std::max(1e-3, 0.1 * (b.hi - b.lo).maxCoeff());
  return Aabb{b.lo - Vec3::Constant(m), b.hi + Vec3::Constant(m)};
}

inline bool contains(const Aabb& fat, const Aabb& b) {
  return fat.lo.x() <= b.lo.x() && fat.lo.y() <= b.lo.y() && fat.lo.z() <= b.lo.z() &&
         b.hi.x() <= fat.hi.x() && b.hi.y() <= fat.hi.y() && b.hi.z() <= fat.hi.z();
}

template <typename Allowed>
void BroadPhase::update(const std::vector<Aabb>& boxes, const std::vector<int>& sweep,
                        const std::vector<int>& planes, const std::vector<Pose>& plane_poses,
                        const std::vector<char>& moving, Allowed&& allowed, std::vector<uint64_t>& pairs) {
  pairs.clear();
  if (order_.size() != sweep.size()) {
    order_ = sweep;
    valid_ = false;
  }
  if (fat_.size() != boxes.size()) {
    fat_.assign(boxes.size(), Aabb{});
    valid_ = false;
  }
  // Shapes that left their fat box get a new one; then the candidates are made again.
  bool resweep = !valid_;
  for (int s : sweep) {
    if (!valid_ || !contains(fat_[s], boxes[s])) {
      fat_[s] = fatten(boxes[s]);
      resweep = true;
    }
  }
  if (resweep) {
    std::vector<uint64_t>& cand = candidates_;
    cand.clear();
    // Insertion sort by (lo.x, index): a total order, so the result is the same from any start.
    auto less = [&](int a, int b) {
      const double xa = fat_[a].lo.x(), xb = fat_[b].lo.x();
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
      const Aabb& A = fat_[a];
      for (size_t j = i + 1; j < order_.size(); ++j) {
        const int b = order_[j];
        const Aabb& B = fat_[b];
        if (B.lo.x() > A.hi.x()) break;
        if (!moving[a] && !moving[b]) continue;
        if (A.lo.y() > B.hi.y() || B.lo.y() > A.hi.y() || A.lo.z() > B.hi.z() || B.lo.z() > A.hi.z())
          continue;
        const int lo = a < b ? a : b, hi = a < b ? b : a;
        if (allowed(lo, hi)) cand.push_back(((uint64_t)lo << 32) | (uint32_t)hi);
      }
    }
    // Planes (z = 0 of their frame, solid below) against each moving shape's box: the box's lowest
    // corner along the plane normal must reach the plane's side.
    for (size_t k = 0; k < planes.size(); ++k) {
      const int p = planes[k];
      for (int s : sweep) {
        if (!moving[s]) continue;
        const int lo = p < s ? p : s, hi = p < s ? s : p;
        if (allowed(lo, hi)) cand.push_back(((uint64_t)lo << 32) | (uint32_t)hi);
      }
    }
    std::sort(cand.begin(), cand.end());
    valid_ = true;
  }
  // This step's pairs: the candidates whose boxes overlap (for a plane: reach its side).
  for (uint64_t key : candidates_) {
    const int a = (int)(key >> 32), b = (int)(key & 0xFFFFFFFFu);
    const auto pa = std::find(planes.begin(), planes.end(), a);
    const auto pb = pa == planes.end() ? std::find(planes.begin(), planes.end(), b) : planes.end();
    if (pa == planes.end() && pb == planes.end()) {
      if (boxes[a].overlaps(boxes[b])) pairs.push_back(key);
      continue;
    }
    const size_t k = pa != planes.end() ? pa - planes.begin() : pb - planes.begin();
    const Vec3 n = plane_poses[k].R.col(2);
    const double d = n.dot(plane_poses[k].p);
    const Aabb& B = boxes[pa != planes.end() ? b : a];
    const Vec3 c = 0.5 * (B.lo + B.hi), e = 0.5 * (B.hi - B.lo);
    if (n.dot(c) - e.dot(n.cwiseAbs()) > d) continue;
    pairs.push_back(key);
  }
}

}  // namespace simreel
