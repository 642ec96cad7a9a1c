// A static bounding-volume tree over boxes (the triangles of a static mesh collider), built once
// and then only queried: a flat array of nodes in depth-first order, each inner node's left child
// right after it, so a query walks the array with a fixed stack and allocates nothing.
//
// Build: top-down, each node split at the median of its items' box centres along the longest
// axis of those centres (std::nth_element with ties broken by item index: the tree depends only
// on the input, never on the standard library's pivot choice), leaves of at most kLeafSize items.
// Median splits keep the tree balanced (depth <= log2(n / kLeafSize) + 2), which bounds the query
// stack; for the triangles of a terrain or a bowl, whose sizes are alike, the surface-area
// heuristic would gain little over the median.
#pragma once
#include <cstdint>
#include <vector>

#include <simreel/math.hpp>

namespace simreel {

class Bvh {
 public:
  static constexpr int kLeafSize = 4;
  struct Node {
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  ///< m, box of the node's items
    int first = 0;  ///< leaf: first slot in items(); inner: index of the right child
    int count = 0;  ///< leaf: item count (> 0); inner: 0 (the left child is this node + 1)
  };

  Bvh() = default;
  // Builds over n boxes [lo[i], hi[i]].
  void build(const std::vector<Vec3>& lo, const std::vector<Vec3>& hi);

  // Calls visit(item) for every item whose box overlaps [lo, hi], in a fixed (depth-first) order.
  template <typename F>
  void query(const Vec3& lo, const Vec3& hi, F&& visit) const;
  // Calls visit(item) for every item whose box passes test(lo, hi), walking down through the nodes
  // that pass it: a test that passes a box must pass every box around it (an overlap test with a
  // box in another frame, a plane's side).
  template <typename Test, typename F>
  void query_if(Test&& test, F&& visit) const;

  const std::vector<Node>& nodes() const { return nodes_; }
  const std::vector<int>& items() const { return items_; }  ///< item indices in leaf order
  int depth() const { return depth_; }

 private:
  static constexpr int kMaxDepth = 64;
  std::vector<Node> nodes_;
  std::vector<int> items_;
  std::vector<Vec3> item_lo_, item_hi_;  ///< per item (original index)
  int depth_ = 0;
};

template <typename F>
void Bvh::query(const Vec3& lo, const Vec3& hi, F&& visit) const {
  query_if(
      [&](const Vec3& a, const Vec3& b) {
        return !(a.x() > hi.x() || lo.x() > b.x() || a.y() > hi.y() || lo.y() > b.y() || a.z() > hi.z() ||
                 lo.z() > b.z());
      },
      visit);
}

template <typename Test, typename F>
void Bvh::query_if(Test&& test, F&& visit) const {
  if (nodes_.empty()) return;
  int stack[kMaxDepth];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& nd = nodes_[stack[--top]];
    if (!test(nd.lo, nd.hi)) continue;
    if (nd.count > 0) {
      for (int k = nd.first; k < nd.first + nd.count; ++k) {
        const int it = items_[k];
        if (test(item_lo_[it], item_hi_[it])) visit(it);
      }
      continue;
    }
    // Left child (next in the array) is visited first: push the right one below it.
    stack[top++] = nd.first;
    stack[top++] = (int)(&nd - nodes_.data()) + 1;
  }
}

}  // namespace simreel
