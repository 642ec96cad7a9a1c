// Broad phase: which pairs of shapes are close enough to need the narrow phase.
//
// Each non-plane shape has a fat box (its world box grown by a margin) in a dynamic bounding-volume
// tree (AabbTree: Box2D's b2DynamicTree, in 3D: leaves inserted where they grow the tree's surface
// area least, AVL rotations keep it balanced). A shape is looked at only when the caller lists it
// as active (its box may have changed: World lists the shapes of awake moving bodies); when its box
// has left its fat box it gets a new fat box, its leaf takes it in place (the ancestors grow to hold
// it; the tree is rebuilt once the moves since the last build reach the leaf count), and a query of
// the tree with the new fat box finds its new candidate pairs. (Removing and reinserting the leaf
// instead walked the tree's whole height twice per move: among 100,000 falling boxes the broad
// phase took 1.45x the time, among 1,000 1.6x; a pile's was the same.) Candidates persist from step to step
// in a sorted list: a pair leaves it only when one of its shapes moved and the two fat boxes no longer
// overlap. Planes are tested against the fat boxes of the moved shapes (the box's lowest corner along the
// normal must reach the plane's side). Shapes that do not move (asleep, static, at rest inside their fat box)
// cost nothing but their candidates' share of the final filter.
//
// The output is the candidates whose boxes overlap this step (for a plane: reach its side), sorted
// by (shape a, shape b), a < b, in two lists: the live pairs (a shape of the pair is active) and
// the dormant ones (neither is, so neither box changed: a sleeping stack on the floor costs
// nothing per step). Every box lies in its fat box, and every pair of overlapping fat boxes is a
// candidate, so the two lists together are exactly the allowed pairs whose boxes overlap: they do
// not depend on the fat boxes, the tree's shape, the order of updates, the thread count or a
// resume.
//
// Why a tree and not a sort and sweep (bench/results/broad_phase_*.csv):
// the sweep re-sorted and re-swept every shape whenever any box left its fat box, and a sweep
// along x visits a whole slab of the scene per shape (~N^(2/3) in a 3D crowd): 10,000 moving cubes
// took 37 ms of CPU a step in it. The tree touches only the shapes that moved, in O(log N) each.
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>

#include "sim/base/pair_key.hpp"
#include "sim/collision/shape_table.hpp"

namespace simreel {

// A dynamic tree of boxes, each leaf carrying a user index. Operations are deterministic: the same
// sequence of inserts, moves and removes gives the same tree. No allocation once grown.
class AabbTree {
 public:
  int insert(const Aabb& box, int user);  ///< returns the leaf's id
  void remove(int leaf);
  void move(int leaf, const Aabb& box);  ///< remove and insert again (the id stays valid)
  // The leaf's box replaced and its ancestors grown until one holds it (never shrunk, no change of
  // shape: Box2D v3's enlarge-in-place). A few nodes where move walks the whole height twice; the
  // tree loosens until the next rebuild.
  void enlarge(int leaf, const Aabb& box);
  // Every node anew by binned SAH, in depth-first order; leaves get new ids: remap()[old id].
  // False (nothing changed) under three leaves.
  bool rebuild();
  const std::vector<int>& remap() const { return remap_; }
  void clear();
  int size() const { return leaves_; }
  int height() const { return root_ < 0 ? 0 : nodes_[root_].height; }
  // f(user) for every leaf whose box overlaps `box`.
  template <typename F>
  void query(const Aabb& box, F&& f) const;
  // Checks the structure (parents, heights, enclosing boxes); for tests. (A rebuilt tree is
  // shaped by area, not height-balanced.)
  bool valid() const;

 private:
  struct Node {
    Aabb box;
    int parent = -1, child1 = -1, child2 = -1;  ///< child1 < 0: a leaf
    int height = 0;                             ///< 0 for a leaf
    int user = -1;                              ///< leaf: the user index; free node: next free
  };
  int allocate();
  void release(int node);
  void insert_leaf(int leaf);
  void remove_leaf(int leaf);
  int balance(int a);
  void refit(int index);  ///< boxes and heights from `index` up to the root, rebalancing
  bool valid(int index, int parent) const;
  int build(int begin, int end, int parent);  ///< rebuild's subtree over build_[begin, end), in fresh_

  std::vector<Node> nodes_;
  int root_ = -1, free_ = -1, leaves_ = 0;
  mutable std::vector<int> stack_;
  // A leaf's box travels with it through the build's partitions: reading it through the leaf's
  // id was a random access per leaf and level, most of the rebuild's time among 100,000 leaves.
  struct BuildItem {
    Aabb box;
    Vec3 c;  ///< the box's centre, doubled
    int leaf;
  };
  std::vector<BuildItem> build_;
  std::vector<int> remap_;
  std::vector<Node> fresh_;
};

template <typename F>
void AabbTree::query(const Aabb& box, F&& f) const {
  if (root_ < 0) return;
  stack_.clear();
  stack_.push_back(root_);
  while (!stack_.empty()) {
    const int i = stack_.back();
    stack_.pop_back();
    const Node& n = nodes_[i];
    if (!n.box.overlaps(box)) continue;
    if (n.child1 < 0) {
      f(n.user);
    } else {
      stack_.push_back(n.child2);
      stack_.push_back(n.child1);
    }
  }
}

class BroadPhase {
 public:
  // boxes[i]: world box of shape i (read for the shapes in `sweep`; those not in `active` must not
  // have changed since the last update). active: the shapes of `sweep` whose boxes may have
  // changed. sweep: the non-plane shapes to consider; planes: the plane shapes with their world
  // pose (fixed). allowed(a, b): whether shapes a < b may touch (bodies, filters, ignore list). It
  // and `moving` must not change over the broad phase's life (they are applied when the candidates
  // are made). `pairs` is cleared and refilled with the live pairs' keys (pair_key(a, b),
  // sim/base/pair_key.hpp); dormant_pairs() holds the others.
  template <typename Allowed>
  void update(const std::vector<Aabb>& boxes, const std::vector<int>& active, const std::vector<int>& sweep,
              const std::vector<int>& planes, const std::vector<Pose>& plane_poses,
              const std::vector<char>& moving, Allowed&& allowed, std::vector<uint64_t>& pairs);
  // Forget everything: the next update looks at every shape of `sweep` (after a restore).
  void reset() { valid_ = false; }
  // `pairs` holds the overlapping pairs with a shape in `active`; the others, whose boxes cannot
  // have changed since neither shape is active (a sleeping stack on the ground), are kept apart
  // here, sorted, and cost nothing per step: the two lists together are exactly the overlapping
  // pairs. dormant_changed(): the list changed in the last update.
  const std::vector<uint64_t>& dormant_pairs() const { return dormant_hits_; }
  bool dormant_changed() const { return dormant_changed_; }
  // Per shape: how far it is expected to move in a step (m, world), read when a shape gets a new
  // fat box, which then reaches kDriftSteps steps ahead along it. Shapes only: never changes
  // the pairs. nullptr: fat boxes grow alike on every side.
  void set_drift(const std::vector<Vec3>* drift) { drift_ = drift; }
  static constexpr double kDriftSteps = 32;
  size_t candidates() const { return candidates_.size() + dormant_.size(); }  ///< live and dormant
  // f(shape) for every shape whose fat box overlaps `box`: a superset of the shapes whose box of
  // the last update does (every box lies in its fat box).
  template <typename F>
  void query(const Aabb& box, F&& f) const {
    tree_.query(box, f);
  }
  int moved_last_update() const { return (int)moved_.size(); }
  // Plane shape p (one of update's `planes`, after an update): its unit normal and offset, the
  // side n . x <= d solid (box_reaches_plane).
  const Vec3& plane_normal(int p) const { return plane_n_[plane_slot_[p]]; }
  double plane_offset(int p) const { return plane_d_[plane_slot_[p]]; }

 private:
  template <typename Allowed>
  void find_new(const std::vector<int>& planes, const std::vector<char>& moving, Allowed& allowed);
  bool reaches_plane(int k, const Aabb& b) const;  ///< plane k (index into planes)

  AabbTree tree_;
  std::vector<Aabb> fat_;             ///< per shape: its box when last moved, grown by a margin
  std::vector<int> leaf_;             ///< per shape: its tree leaf, or -1
  std::vector<int> plane_slot_;       ///< per shape: index into `planes`, or -1
  std::vector<Vec3> plane_n_;         ///< per plane: unit normal, world
  std::vector<double> plane_d_;       ///< per plane: n . (point on the plane)
  std::vector<int> moved_;            ///< shapes that got a new fat box this update
  std::vector<char> moved_flag_;      ///< per shape: in moved_
  std::vector<uint64_t> candidates_;  ///< allowed pairs whose fat boxes overlap, sorted
  std::vector<uint64_t> found_, merged_;
  const std::vector<Vec3>* drift_ = nullptr;
  // Candidates with no active shape (sorted), those of them whose boxes overlap, and scratch.
  std::vector<uint64_t> dormant_, dormant_hits_, demoted_, woken_;
  std::vector<char> active_flag_, was_active_;  ///< per shape: in `active` this / last update
  std::vector<int> last_active_;
  bool dormant_changed_ = false;
  long moves_since_rebuild_ = 0;
  bool valid_ = false;
};

// Fat box margin: a tenth of the box's largest side (at least 1 mm), so a shape at rest stays in
// its fat box; and on the side it moves toward, as far as it moves in kDriftSteps steps (`ahead`),
// so a moving shape keeps its fat box for several steps without the box swelling toward the
// neighbours behind or beside it (Bullet's dbvt prediction). Among 10,000 boxes falling from rest
// for 1000 steps, 51% of body-steps left the isotropic fat box, 9.5% one reaching 8 steps ahead
// and 3.3% one reaching 32 (each exit is a tree walk and a query that miss the cache once the
// tree outgrows it); a shape at rest has no lead, so piles keep their pairs.
inline Aabb fatten(const Aabb& b, const Vec3& ahead = Vec3::Zero()) {
  const double m = std::max(1e-3, 0.1 * (b.hi - b.lo).maxCoeff());
  return Aabb{b.lo - Vec3::Constant(m) + ahead.cwiseMin(0.0), b.hi + Vec3::Constant(m) + ahead.cwiseMax(0.0)};
}

inline bool contains(const Aabb& fat, const Aabb& b) {
  return fat.lo.x() <= b.lo.x() && fat.lo.y() <= b.lo.y() && fat.lo.z() <= b.lo.z() &&
         b.hi.x() <= fat.hi.x() && b.hi.y() <= fat.hi.y() && b.hi.z() <= fat.hi.z();
}

// Whether box b reaches the side n . x <= d of a plane (n unit): its lowest corner along n does.
inline bool box_reaches_plane(const Vec3& n, double d, const Aabb& b) {
  const Vec3 c = 0.5 * (b.lo + b.hi), e = 0.5 * (b.hi - b.lo);
  return n.dot(c) - e.dot(n.cwiseAbs()) <= d;
}

inline bool BroadPhase::reaches_plane(int k, const Aabb& b) const {
  return box_reaches_plane(plane_n_[k], plane_d_[k], b);
}

// New candidates of the moved shapes: tree neighbours and planes reached. A pair of two moved
// shapes is found from the higher one's side only. Appends to found_, sorted and unique at the end.
template <typename Allowed>
void BroadPhase::find_new(const std::vector<int>& planes, const std::vector<char>& moving, Allowed& allowed) {
  found_.clear();
  for (int p : moved_) {
    tree_.query(fat_[p], [&](int q) {
      if (q == p || (moved_flag_[q] && q > p)) return;
      if (!moving[p] && !moving[q]) return;
      const int lo = p < q ? p : q, hi = p < q ? q : p;
      if (allowed(lo, hi)) found_.push_back(pair_key(lo, hi));
    });
    if (!moving[p]) continue;
    for (size_t k = 0; k < planes.size(); ++k) {
      if (!reaches_plane((int)k, fat_[p])) continue;
      const int q = planes[k];
      const int lo = p < q ? p : q, hi = p < q ? q : p;
      if (allowed(lo, hi)) found_.push_back(pair_key(lo, hi));
    }
  }
  std::sort(found_.begin(), found_.end());
  found_.erase(std::unique(found_.begin(), found_.end()), found_.end());
}

template <typename Allowed>
void BroadPhase::update(const std::vector<Aabb>& boxes, const std::vector<int>& active,
                        const std::vector<int>& sweep, const std::vector<int>& planes,
                        const std::vector<Pose>& plane_poses, const std::vector<char>& moving,
                        Allowed&& allowed, std::vector<uint64_t>& pairs) {
  pairs.clear();
  moved_.clear();
  dormant_changed_ = false;
  if (!valid_ || fat_.size() != boxes.size()) {
    dormant_.clear();
    dormant_hits_.clear();
    active_flag_.assign(boxes.size(), 0);
    was_active_.assign(boxes.size(), 0);
    last_active_.clear();
    dormant_changed_ = true;
    // From nothing: every shape moved.
    tree_.clear();
    candidates_.clear();
    fat_.assign(boxes.size(), Aabb{});
    leaf_.assign(boxes.size(), -1);
    moved_flag_.assign(boxes.size(), 0);
    plane_slot_.assign(boxes.size(), -1);
    plane_n_.clear();
    plane_d_.clear();
    for (size_t k = 0; k < planes.size(); ++k) {
      plane_slot_[planes[k]] = (int)k;
      plane_n_.push_back(plane_poses[k].R.col(2));
      plane_d_.push_back(plane_n_.back().dot(plane_poses[k].p));
    }
    for (int s : sweep) {
      fat_[s] = fatten(boxes[s]);
      leaf_[s] = tree_.insert(fat_[s], s);
      moved_.push_back(s);
    }
    moves_since_rebuild_ = tree_.size();
    valid_ = true;
  } else {
    for (int s : active) {
      if (contains(fat_[s], boxes[s])) continue;
      fat_[s] = drift_ ? fatten(boxes[s], kDriftSteps * (*drift_)[s]) : fatten(boxes[s]);
      moved_.push_back(s);
    }
    // In the tree's order (leaves are laid out depth first at each rebuild, so near in space):
    // consecutive enlargements and queries then walk the same upper nodes while they are still
    // in the cache. The pairs found do not depend on the order.
    std::sort(moved_.begin(), moved_.end(), [&](int a, int b) { return leaf_[a] < leaf_[b]; });
    for (int s : moved_) tree_.enlarge(leaf_[s], fat_[s]);
    moves_since_rebuild_ += (long)moved_.size();
  }
  // Rebuilt once the moves since the last build reach the number of leaves (and when made from
  // nothing): reinsertions scatter the nodes in memory and leave a tree whose queries visit three
  // times the nodes of a built one.
  for (int s : active) active_flag_[s] = 1;
  // A dormant pair one of whose shapes is active again (its body woke) is a live candidate again.
  bool woke = false;
  for (int s : active) woke = woke || !was_active_[s];
  if (woke && !dormant_.empty()) {
    woken_.clear();
    size_t kept = 0;
    for (uint64_t key : dormant_) {
      if (active_flag_[pair_first(key)] || active_flag_[pair_second(key)])
        woken_.push_back(key);
      else
        dormant_[kept++] = key;
    }
    if (!woken_.empty()) {
      dormant_.resize(kept);
      merged_.clear();
      std::set_union(candidates_.begin(), candidates_.end(), woken_.begin(), woken_.end(),
                     std::back_inserter(merged_));
      candidates_.swap(merged_);
      kept = 0;
      for (uint64_t key : dormant_hits_)
        if (!active_flag_[pair_first(key)] && !active_flag_[pair_second(key)]) dormant_hits_[kept++] = key;
      dormant_hits_.resize(kept);
      dormant_changed_ = true;
    }
  }
  if (moves_since_rebuild_ >= tree_.size()) {
    if (tree_.rebuild())
      for (int s : sweep)
        if (leaf_[s] >= 0) leaf_[s] = tree_.remap()[leaf_[s]];
    moves_since_rebuild_ = 0;
  }
  if (!moved_.empty()) {
    for (int s : moved_) moved_flag_[s] = 1;
    find_new(planes, moving, allowed);
    // Candidates of a moved shape whose fat boxes no longer overlap leave the list; the others stay.
    auto stale = [&](uint64_t key) {
      const int a = pair_first(key), b = pair_second(key);
      if (!moved_flag_[a] && !moved_flag_[b]) return false;
      if (plane_slot_[a] >= 0) return !reaches_plane(plane_slot_[a], fat_[b]);
      if (plane_slot_[b] >= 0) return !reaches_plane(plane_slot_[b], fat_[a]);
      return !fat_[a].overlaps(fat_[b]);
    };
    candidates_.erase(std::remove_if(candidates_.begin(), candidates_.end(), stale), candidates_.end());
    merged_.clear();
    std::set_union(candidates_.begin(), candidates_.end(), found_.begin(), found_.end(),
                   std::back_inserter(merged_));
    candidates_.swap(merged_);
    for (int s : moved_) moved_flag_[s] = 0;
  }
  // This step's pairs: the candidates whose boxes overlap (for a plane: reach its side); a
  // candidate with no active shape becomes dormant (with its overlap, which cannot change while
  // it stays dormant).
  auto hit = [&](int a, int b) {
    return plane_slot_[a] >= 0   ? reaches_plane(plane_slot_[a], boxes[b])
           : plane_slot_[b] >= 0 ? reaches_plane(plane_slot_[b], boxes[a])
                                 : boxes[a].overlaps(boxes[b]);
  };
  demoted_.clear();
  size_t kept = 0;
  for (uint64_t key : candidates_) {
    const int a = pair_first(key), b = pair_second(key);
    if (!active_flag_[a] && !active_flag_[b]) {
      demoted_.push_back(key);
      continue;
    }
    candidates_[kept++] = key;
    if (hit(a, b)) pairs.push_back(key);
  }
  candidates_.resize(kept);
  if (!demoted_.empty()) {
    merged_.clear();
    std::set_union(dormant_.begin(), dormant_.end(), demoted_.begin(), demoted_.end(),
                   std::back_inserter(merged_));
    dormant_.swap(merged_);
    kept = 0;
    for (uint64_t key : demoted_)
      if (hit(pair_first(key), pair_second(key))) demoted_[kept++] = key;
    demoted_.resize(kept);
    merged_.clear();
    std::set_union(dormant_hits_.begin(), dormant_hits_.end(), demoted_.begin(), demoted_.end(),
                   std::back_inserter(merged_));
    dormant_hits_.swap(merged_);
    dormant_changed_ = true;
  }
  for (int s : last_active_) was_active_[s] = 0;
  for (int s : active) was_active_[s] = 1, active_flag_[s] = 0;
  last_active_.assign(active.begin(), active.end());
}

}  // namespace simreel
