// Broad phase (sim/collision/broad_phase.hpp): the dynamic tree against brute force on random boxes, and
// the broad phase's pairs against the brute-force list of overlapping pairs over a random history
// (shapes moving, resting, asleep, planes), whatever the history, the order or a fresh start.
#include "sim/collision/broad_phase.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>
#include <numeric>
#include <vector>

#include "tests/fixtures/reference_scenes.hpp"

namespace simreel {
namespace {

Aabb random_box(SplitMix64& r, double extent, double size_max) {
  const Vec3 c(r.uniform(-extent, extent), r.uniform(-extent, extent), r.uniform(-extent, extent));
  const Vec3 h(r.uniform(0.01, size_max), r.uniform(0.01, size_max), r.uniform(0.01, size_max));
  return Aabb{c - h, c + h};
}

std::vector<int> brute_query(const std::vector<Aabb>& boxes, const std::vector<char>& present,
                             const Aabb& q) {
  std::vector<int> out;
  for (int i = 0; i < (int)boxes.size(); ++i)
    if (present[i] && boxes[i].overlaps(q)) out.push_back(i);
  return out;
}

// Inserts, moves, enlargements in place and removes at random: the tree stays valid (parents,
// heights, enclosing boxes, AVL balance) and every query returns exactly the brute-force set.
TEST(AabbTree, QueriesEqualBruteForceThroughInsertMoveRemove) {
  SplitMix64 r(7);
  const int n = 600;
  AabbTree t;
  std::vector<Aabb> boxes(n);
  std::vector<int> leaf(n, -1);
  std::vector<char> present(n, 0);
  for (int round = 0; round < 4000; ++round) {
    const int i = (int)(r.next() % n);
    const double op = r.uniform();
    if (!present[i]) {
      boxes[i] = random_box(r, 20, 2);
      leaf[i] = t.insert(boxes[i], i);
      present[i] = 1;
    } else if (op < 0.35) {
      boxes[i] = random_box(r, 20, 2);
      t.move(leaf[i], boxes[i]);
    } else if (op < 0.7) {  // anywhere, as a new fat box may be (the ancestors only grow)
      boxes[i] = random_box(r, 20, 2);
      t.enlarge(leaf[i], boxes[i]);
    } else {
      t.remove(leaf[i]);
      present[i] = 0;
    }
    if (round % 200 == 0 || round == 3999) {
      ASSERT_TRUE(t.valid()) << "round " << round;
      EXPECT_EQ(t.size(), std::count(present.begin(), present.end(), 1));
      for (int k = 0; k < 20; ++k) {
        const Aabb q = random_box(r, 20, 4);
        std::vector<int> got;
        t.query(q, [&](int u) { got.push_back(u); });
        std::sort(got.begin(), got.end());
        ASSERT_EQ(got, brute_query(boxes, present, q)) << "round " << round;
      }
    }
  }
  // Balanced: AVL height is at most 1.44 log2(n + 2).
  EXPECT_LE(t.height(), (int)(1.45 * std::log2(t.size() + 2.0)) + 1);
}

// A random world of shapes: 0..n-1 boxes (a few static), then two planes. Each step some shapes
// move (a random walk, or a jump), some stay put but are still listed as active (awake, at rest),
// and some are not listed at all (asleep: their boxes do not change).
struct RandomScene {
  int n;
  std::vector<Aabb> boxes;
  std::vector<int> sweep, planes;
  std::vector<Pose> plane_poses;
  std::vector<char> moving, asleep;
  SplitMix64 r{11};

  explicit RandomScene(int count) : n(count), boxes(count + 2), moving(count + 2, 0), asleep(count + 2, 0) {
    for (int i = 0; i < n; ++i) {
      boxes[i] = random_box(r, 10, 0.8);
      moving[i] = r.uniform() > 0.1;  // one in ten static
      sweep.push_back(i);
    }
    planes = {n, n + 1};
    Pose floor;
    floor.p = Vec3(0, 0, -6);
    Pose wall;  // the plane x = 7, solid beyond it: normal -x
    wall.p = Vec3(7, 0, 0);
    wall.R = Eigen::AngleAxisd(-0.5 * 3.14159265358979, Vec3::UnitY()).toRotationMatrix();
    plane_poses = {floor, wall};
  }
  // Allowed: different "bodies" (i / 3, so shapes 3k..3k+2 are one body), not two static ones, and a
  // filter that leaves out one pair in seven.
  bool allowed(int a, int b) const {
    if (a / 3 == b / 3 && a < n && b < n) return false;
    if (!moving[a] && !moving[b]) return false;
    return (a * 31 + b * 17) % 7 != 0;
  }
  void step(std::vector<int>& active) {
    active.clear();
    for (int i = 0; i < n; ++i) {
      if (!moving[i]) continue;
      if (r.uniform() < 0.02) asleep[i] = !asleep[i];
      if (asleep[i]) continue;
      active.push_back(i);
      const double u = r.uniform();
      if (u < 0.3) {
        const Vec3 d(r.uniform(-0.15, 0.15), r.uniform(-0.15, 0.15), r.uniform(-0.15, 0.15));
        boxes[i].lo += d;
        boxes[i].hi += d;
      } else if (u < 0.32) {
        boxes[i] = random_box(r, 10, 0.8);
      }
    }
  }
  std::vector<uint64_t> brute() const {
    std::vector<uint64_t> out;
    auto key = [](int a, int b) { return ((uint64_t)a << 32) | (uint32_t)b; };
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n; ++b)
        if (allowed(a, b) && boxes[a].overlaps(boxes[b])) out.push_back(key(a, b));
    for (size_t k = 0; k < planes.size(); ++k) {
      const Vec3 nrm = plane_poses[k].R.col(2);
      const double d = nrm.dot(plane_poses[k].p);
      for (int a = 0; a < n; ++a) {
        if (!allowed(a, planes[k])) continue;
        // Some corner of the box on the plane's solid side.
        double lowest = 1e300;
        for (int c = 0; c < 8; ++c) {
          const Vec3 p((c & 1) ? boxes[a].hi.x() : boxes[a].lo.x(),
                       (c & 2) ? boxes[a].hi.y() : boxes[a].lo.y(),
                       (c & 4) ? boxes[a].hi.z() : boxes[a].lo.z());
          lowest = std::min(lowest, nrm.dot(p));
        }
        if (lowest <= d) out.push_back(key(a, planes[k]));
      }
    }
    std::sort(out.begin(), out.end());
    return out;
  }
};

// The broad phase's whole output: the live pairs and the dormant ones, in key order.
std::vector<uint64_t> all(const BroadPhase& bp, const std::vector<uint64_t>& live) {
  std::vector<uint64_t> out;
  std::set_union(live.begin(), live.end(), bp.dormant_pairs().begin(), bp.dormant_pairs().end(),
                 std::back_inserter(out));
  return out;
}

// Over 300 steps of a random history the pairs equal the brute-force list every step; a broad
// phase started afresh on the last step's boxes (with the shapes listed in another order) gives
// the same list, as a resumed run would.
TEST(BroadPhase, PairsEqualBruteForceWhateverTheHistory) {
  RandomScene s(400);
  BroadPhase bp;
  std::vector<uint64_t> pairs;
  std::vector<int> active;
  auto allowed = [&](int a, int b) { return s.allowed(a, b); };
  bp.update(s.boxes, s.sweep, s.sweep, s.planes, s.plane_poses, s.moving, allowed, pairs);
  ASSERT_EQ(all(bp, pairs), s.brute());
  size_t total = 0, dormant = 0;
  int moved = 0;
  for (int k = 0; k < 300; ++k) {
    s.step(active);
    bp.update(s.boxes, active, s.sweep, s.planes, s.plane_poses, s.moving, allowed, pairs);
    moved += bp.moved_last_update();
    ASSERT_EQ(all(bp, pairs), s.brute()) << "step " << k;
    // Live: every pair has an active shape; dormant: none has.
    std::vector<char> on(s.boxes.size(), 0);
    for (int i : active) on[i] = 1;
    for (uint64_t key : pairs) ASSERT_TRUE(on[pair_first(key)] || on[pair_second(key)]);
    for (uint64_t key : bp.dormant_pairs()) ASSERT_TRUE(!on[pair_first(key)] && !on[pair_second(key)]);
    total += pairs.size();
    dormant += bp.dormant_pairs().size();
  }
  EXPECT_GT(total, 300u * 50);   // the scene is crowded enough to mean something
  EXPECT_GT(dormant, 300u * 5);  // with sleeping pairs among them
  EXPECT_GT(moved, 300 * 20);    // and shapes do leave their fat boxes
  const std::vector<uint64_t> last = all(bp, pairs);
  BroadPhase fresh;
  std::vector<int> reversed(s.sweep.rbegin(), s.sweep.rend());
  std::vector<uint64_t> again;
  fresh.update(s.boxes, reversed, reversed, s.planes, s.plane_poses, s.moving, allowed, again);
  EXPECT_EQ(all(fresh, again), last);
  // reset() forgets the history too.
  bp.reset();
  bp.update(s.boxes, active, s.sweep, s.planes, s.plane_poses, s.moving, allowed, again);
  EXPECT_EQ(all(bp, again), last);
}

// Fat boxes led along each shape's expected motion (set_drift) change which shapes leave them,
// never the pairs: the same random history with random drifts (some far larger than the steps)
// gives the brute-force list every step.
TEST(BroadPhase, DriftShapesFatBoxesNotPairs) {
  for (double lead : {0.0, 0.05, 3.0}) {
    RandomScene s(300);
    BroadPhase bp;
    std::vector<Vec3> drift(s.boxes.size(), Vec3::Zero());
    SplitMix64 r(5);
    for (Vec3& d : drift) d = lead * Vec3(r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1));
    bp.set_drift(&drift);
    std::vector<uint64_t> pairs;
    std::vector<int> active;
    auto allowed = [&](int a, int b) { return s.allowed(a, b); };
    bp.update(s.boxes, s.sweep, s.sweep, s.planes, s.plane_poses, s.moving, allowed, pairs);
    ASSERT_EQ(all(bp, pairs), s.brute());
    for (int k = 0; k < 200; ++k) {
      s.step(active);
      bp.update(s.boxes, active, s.sweep, s.planes, s.plane_poses, s.moving, allowed, pairs);
      ASSERT_EQ(all(bp, pairs), s.brute()) << "lead " << lead << " step " << k;
    }
  }
}

// A rebuilt tree (binned SAH, depth-first layout, new leaf ids) answers every query as the
// reinserted one did, and keeps working through later moves and removals.
TEST(AabbTree, RebuildKeepsQueriesAndRemapsLeaves) {
  SplitMix64 r(3);
  const int n = 500;
  AabbTree t;
  std::vector<Aabb> boxes(n);
  std::vector<int> leaf(n);
  std::vector<char> present(n, 1);
  for (int i = 0; i < n; ++i) leaf[i] = t.insert(boxes[i] = random_box(r, 20, 2), i);
  for (int round = 0; round < 6; ++round) {
    ASSERT_TRUE(t.rebuild());
    for (int i = 0; i < n; ++i)
      if (present[i]) leaf[i] = t.remap()[leaf[i]];
    ASSERT_TRUE(t.valid());
    EXPECT_EQ(t.size(), std::count(present.begin(), present.end(), 1));
    for (int k = 0; k < 50; ++k) {
      const Aabb q = random_box(r, 20, 4);
      std::vector<int> got;
      t.query(q, [&](int u) { got.push_back(u); });
      std::sort(got.begin(), got.end());
      ASSERT_EQ(got, brute_query(boxes, present, q)) << "round " << round;
    }
    for (int k = 0; k < 200; ++k) {  // then a history of moves and removals on the rebuilt tree
      const int i = (int)(r.next() % n);
      if (!present[i]) {
        leaf[i] = t.insert(boxes[i] = random_box(r, 20, 2), i);
        present[i] = 1;
      } else if (r.uniform() < 0.8) {
        t.move(leaf[i], boxes[i] = random_box(r, 20, 2));
      } else {
        t.remove(leaf[i]);
        present[i] = 0;
      }
    }
    ASSERT_TRUE(t.valid());
  }
  // A rebuilt tree of uniformly spread boxes is shallow: SAH splits near the middle.
  ASSERT_TRUE(t.rebuild());
  EXPECT_LE(t.height(), (int)(2.0 * std::log2(t.size() + 2.0)) + 2);
}

// Shapes not listed as active are not looked at: with nothing active and nothing moved, the
// candidates stay, no shape moves, and every pair is dormant.
TEST(BroadPhase, InactiveShapesCostNoMoves) {
  RandomScene s(200);
  BroadPhase bp;
  std::vector<uint64_t> pairs, again;
  auto allowed = [&](int a, int b) { return s.allowed(a, b); };
  bp.update(s.boxes, s.sweep, s.sweep, s.planes, s.plane_poses, s.moving, allowed, pairs);
  EXPECT_EQ(bp.moved_last_update(), 200);
  const size_t cand = bp.candidates();
  bp.update(s.boxes, {}, s.sweep, s.planes, s.plane_poses, s.moving, allowed, again);
  EXPECT_EQ(bp.moved_last_update(), 0);
  EXPECT_EQ(bp.candidates(), cand);
  EXPECT_TRUE(again.empty());
  EXPECT_EQ(bp.dormant_pairs(), pairs);
  EXPECT_FALSE(pairs.empty());
}

}  // namespace
}  // namespace simreel
