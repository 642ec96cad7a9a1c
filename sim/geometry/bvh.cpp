#include "sim/geometry/bvh.hpp"

#include <algorithm>
#include <cmath>

#include <simreel/error.hpp>

namespace simreel {

void Bvh::build(const std::vector<Vec3>& lo, const std::vector<Vec3>& hi) {
  const int n = (int)lo.size();
  nodes_.clear();
  items_.resize(n);
  item_lo_ = lo;
  item_hi_ = hi;
  depth_ = 0;
  if (n == 0) return;
  for (int i = 0; i < n; ++i) items_[i] = i;
  std::vector<Vec3> centre(n);
  for (int i = 0; i < n; ++i) centre[i] = 0.5 * (lo[i] + hi[i]);
  nodes_.reserve(2 * (n / kLeafSize + 1));
  // Depth-first build with an explicit stack of jobs (node, items [begin, end), depth). A left
  // child is created right after its parent; a right child's job is pushed below its sibling's
  // and creates its node when popped, after the whole left subtree (node = -(parent + 1)).
  struct Job {
    int node, begin, end, depth;
  };
  std::vector<Job> jobs;
  nodes_.emplace_back();
  jobs.push_back({0, 0, n, 1});
  while (!jobs.empty()) {
    Job j = jobs.back();
    jobs.pop_back();
    if (j.node < 0) {
      const int parent = -j.node - 1;
      j.node = (int)nodes_.size();
      nodes_.emplace_back();
      nodes_[parent].first = j.node;
    }
    Vec3 blo = Vec3::Constant(INFINITY), bhi = Vec3::Constant(-INFINITY);
    Vec3 clo = blo, chi = bhi;
    for (int k = j.begin; k < j.end; ++k) {
      const int it = items_[k];
      blo = blo.cwiseMin(lo[it]);
      bhi = bhi.cwiseMax(hi[it]);
      clo = clo.cwiseMin(centre[it]);
      chi = chi.cwiseMax(centre[it]);
    }
    nodes_[j.node].lo = blo;
    nodes_[j.node].hi = bhi;
    depth_ = std::max(depth_, j.depth);
    if (j.end - j.begin <= kLeafSize) {
      nodes_[j.node].first = j.begin;
      nodes_[j.node].count = j.end - j.begin;
      continue;
    }
    int axis = 0;
    const Vec3 ext = chi - clo;
    if (ext.y() > ext[axis]) axis = 1;
    if (ext.z() > ext[axis]) axis = 2;
    const int mid = j.begin + (j.end - j.begin) / 2;
    std::nth_element(items_.begin() + j.begin, items_.begin() + mid, items_.begin() + j.end,
                     [&](int a, int b) {
                       const double ca = centre[a][axis], cb = centre[b][axis];
                       return ca < cb || (ca == cb && a < b);
                     });
    if (j.depth + 1 >= kMaxDepth) throw InputError("bounding-volume tree too deep");
    nodes_[j.node].count = 0;
    const int left = (int)nodes_.size();
    nodes_.emplace_back();
    jobs.push_back({-(j.node + 1), mid, j.end, j.depth + 1});
    jobs.push_back({left, j.begin, mid, j.depth + 1});
  }
}

}  // namespace simreel
