// The constraint colouring (sim/constraint_graph.hpp) and the threaded contact stages: a colour
// never holds two constraints on one moving body; up to 32 levels the colours are the sequential
// order's wavefront (each body meets its constraints in list order, so the solve is the
// sequential one); and a world gives the same bits with 1, 2 and 3 threads, resumed or straight.
#include <gtest/gtest.h>

#include <cstring>
#include <sstream>
#include <vector>

#include "sim/constraint_graph.hpp"
#include "sim/scene_builders.hpp"
#include "tests/sim/contact_fixtures.hpp"

namespace simreel {
namespace {

using contact_test::state_hash;

struct Edges {
  std::vector<int> a, b;
  void add(int x, int y) { a.push_back(x), b.push_back(y); }
  int size() const { return (int)a.size(); }
};

// Checks the colouring's invariants; returns the number of colour-order inversions, pairs of
// constraints on one moving body solved in the opposite of their list order.
int check_graph(const ConstraintGraph& g, const Edges& e, int bodies) {
  const int n = e.size();
  std::vector<int> seen(n, 0);
  for (int i = 0; i < n; ++i) {
    const int c = g.colour_of(i);
    EXPECT_GE(g.slot(i), g.begin(c));
    EXPECT_LT(g.slot(i), g.end(c));
    seen[g.slot(i)]++;
    if (i > 0 && g.colour_of(i - 1) == c) {
      EXPECT_EQ(g.slot(i), g.slot(i - 1) + 1);  // list order within a colour
    }
  }
  for (int s = 0; s < n; ++s) EXPECT_EQ(seen[s], 1) << "slot " << s;
  EXPECT_EQ(g.end(ConstraintGraph::kOverflow), n);
  // No colour (bar the overflow set) holds a moving body twice.
  for (int c = 0; c < ConstraintGraph::kColours; ++c) {
    std::vector<char> taken(bodies, 0);
    for (int i = 0; i < n; ++i) {
      if (g.colour_of(i) != c) continue;
      for (int body : {e.a[i], e.b[i]}) {
        if (body == 0) continue;
        EXPECT_FALSE(taken[body]) << "body " << body << " twice in colour " << c;
        taken[body] = 1;
      }
    }
  }
  // Solve order of each body's constraints against their list order.
  int inversions = 0;
  std::vector<int> last_slot(bodies, -1);
  for (int i = 0; i < n; ++i)
    for (int body : {e.a[i], e.b[i]}) {
      if (body == 0) continue;
      if (g.slot(i) < last_slot[body]) ++inversions;
      last_slot[body] = g.slot(i);
    }
  return inversions;
}

// A column of 10 bodies on the ground (the static body 0), listed bottom-up as the contact list
// has them: colour = depth in the chain, the ground contact beside the first joint.
TEST(ConstraintGraph, ColumnColoursAreItsLevels) {
  Edges e;
  e.add(1, 2);
  e.add(1, 0);
  for (int k = 2; k < 10; ++k) e.add(k, k + 1);
  ConstraintGraph g;
  g.build(11, e.size(), e.a.data(), e.b.data());
  EXPECT_EQ(check_graph(g, e, 11), 0);
  EXPECT_EQ(g.colour_of(0), 0);
  EXPECT_EQ(g.colour_of(1), 1);  // body 1's second constraint
  for (int k = 2; k < e.size(); ++k) EXPECT_EQ(g.colour_of(k), k - 1) << k;
  EXPECT_EQ((int)g.used().size(), 9);
  EXPECT_EQ(g.overflow_count(), 0);
}

// Random graphs shallow enough for 32 levels keep every body's list order (the sequential solve);
// deeper ones wrap round and stay valid colourings.
TEST(ConstraintGraph, RandomGraphsAreValidAndKeepTheOrderUpTo32Levels) {
  SplitMix64 rng(7);
  int wrapped = 0;
  for (int trial = 0; trial < 80; ++trial) {
    // Half sparse (mostly shallow), half dense (deep: they wrap round and overflow).
    const int bodies = 2 + (int)(rng.uniform() * (trial < 40 ? 300 : 20));
    const int n = (int)(rng.uniform() * (trial < 40 ? 3 : 30) * bodies);
    Edges e;
    for (int i = 0; i < n; ++i) {
      int x = (int)(rng.uniform() * bodies), y = (int)(rng.uniform() * bodies);
      if (x == y) y = 0;
      if (x == 0 && y == 0) x = 1 % bodies;
      e.add(x, y);
    }
    // Depth of the sequential order's dependency chains.
    std::vector<int> level(bodies, -1);
    int depth = 0;
    for (int i = 0; i < n; ++i) {
      int l = 0;
      for (int body : {e.a[i], e.b[i]})
        if (body != 0) l = std::max(l, level[body] + 1);
      for (int body : {e.a[i], e.b[i]})
        if (body != 0) level[body] = l;
      depth = std::max(depth, l + 1);
    }
    ConstraintGraph g;
    g.build(bodies, n, e.a.data(), e.b.data());
    const int inversions = check_graph(g, e, bodies);
    if (depth <= ConstraintGraph::kColours) {
      EXPECT_EQ(inversions, 0) << "trial " << trial << ", depth " << depth;
      EXPECT_EQ(g.overflow_count(), 0);
    } else {
      ++wrapped;
    }
  }
  EXPECT_GT(wrapped, 10);  // the deep cases were exercised
}

// A body touching 40 others: 32 colours, then the overflow set. The static body does not count:
// 40 bodies on the ground all fit in one colour.
TEST(ConstraintGraph, OverflowAndTheStaticBody) {
  Edges star, ground;
  for (int k = 2; k < 42; ++k) star.add(1, k), ground.add(k, 0);
  ConstraintGraph g;
  g.build(42, star.size(), star.a.data(), star.b.data());
  check_graph(g, star, 42);
  EXPECT_EQ(g.overflow_count(), 8);
  EXPECT_EQ((int)g.used().size(), 32);
  g.build(42, ground.size(), ground.a.data(), ground.b.data());
  check_graph(g, ground, 42);
  EXPECT_EQ((int)g.used().size(), 1);
  EXPECT_EQ(g.overflow_count(), 0);
}

uint64_t run(const std::vector<BodyDef>& bodies, double dt, int threads, int steps, bool sleep = false) {
  WorldConfig cfg;
  cfg.dt = dt;
  cfg.threads = threads;
  cfg.contacts.sleep = sleep;
  World w(cfg, bodies);
  for (int k = 0; k < steps; ++k) w.step();
  return state_hash(w);
}

// The R3 pile (1000 cubes: ten layers land on one another, 100 columns, 9 colours) for 400 steps
// of 1/240 s: the same bits with 1, 2 and 3 threads.
TEST(ContactThreads, PileHashIsTheSameForOneTwoAndThreeThreads) {
  const std::vector<BodyDef> pile = r3_pile();
  const uint64_t h1 = run(pile, kR3Dt, 1, 400);
  EXPECT_EQ(h1, run(pile, kR3Dt, 2, 400));
  EXPECT_EQ(h1, run(pile, kR3Dt, 3, 400));
}

// A pyramid 30 cubes wide (465 cubes): its rows are chains longer than 32 levels, so colours
// wrap round. Same bits with 1, 2 and 3 threads.
TEST(ContactThreads, PyramidWithWrappedColoursIsTheSameForAnyThreadCount) {
  const std::vector<BodyDef> pyramid = r3_pyramid(30);
  const uint64_t h1 = run(pyramid, kPyramidDt, 1, 30);
  EXPECT_EQ(h1, run(pyramid, kPyramidDt, 2, 30));
  EXPECT_EQ(h1, run(pyramid, kPyramidDt, 3, 30));
}

// 144 small cubes dropped onto one plank: the plank's constraints overflow the 32 colours (112 of
// them solved serially, last). Same bits with 1, 2 and 3 threads.
TEST(ContactThreads, OverflowSetIsTheSameForAnyThreadCount) {
  std::vector<BodyDef> v;
  v.push_back(contact_test::box(Vec3(14, 14, 0.2), Vec3(0, 0, 0.1), 0.5, 0.0, 1000));
  for (int j = 0; j < 12; ++j)
    for (int i = 0; i < 12; ++i)
      v.push_back(contact_test::box(Vec3::Constant(0.4), Vec3(-6.05 + 1.1 * i, -6.05 + 1.1 * j, 0.45), 0.5,
                                    0.0, 500));
  v.push_back(r3_ground());
  WorldConfig cfg;
  cfg.dt = kR3Dt;
  cfg.contacts.sleep = false;
  World probe(cfg, v);
  for (int k = 0; k < 30; ++k) probe.step();
  int on_plank = 0;
  for (const Contact& c : probe.contacts()) on_plank += c.count > 0 && (c.body_a == 0 || c.body_b == 0);
  ASSERT_GT(on_plank, ConstraintGraph::kColours + 100) << "the plank must overflow the colours";
  const uint64_t h1 = run(v, kR3Dt, 1, 120);
  EXPECT_EQ(h1, run(v, kR3Dt, 2, 120));
  EXPECT_EQ(h1, run(v, kR3Dt, 3, 120));
}

// Saved from a two-thread run mid-landing and resumed on three threads, the pile ends as a
// straight one-thread run does, bit for bit.
TEST(ContactThreads, PileResumedOnOtherThreadsEqualsStraightRun) {
  const std::vector<BodyDef> pile = r3_pile();
  WorldConfig c1, c2, c3;
  c1.dt = c2.dt = c3.dt = kR3Dt;
  c2.threads = 2;
  c3.threads = 3;
  World straight(c1, pile), first(c2, pile);
  for (int k = 0; k < 250; ++k) straight.step(), first.step();
  std::stringstream saved;
  first.save_state(saved);
  World resumed(c3, pile);
  resumed.restore_state(saved);
  for (int k = 0; k < 150; ++k) straight.step(), resumed.step();
  EXPECT_EQ(state_hash(straight), state_hash(resumed));
}

}  // namespace
}  // namespace simreel
