// The constraint colouring (sim/solver/constraint_graph.hpp) and the threaded contact stages: a colour
// never holds two constraints on one moving body; up to 32 levels the colours are the sequential
// order's wavefront (each body meets its constraints in list order, so the solve is the
// sequential one); and a world gives the same bits with 1, 2 and 3 threads, resumed or straight.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <sstream>
#include <vector>

#include "sim/mass/primitives.hpp"
#include "sim/solver/constraint_graph.hpp"
#include "sim/world/world_impl.hpp"
#include "tests/fixtures/reference_scenes.hpp"
#include "tests/sim/collision/trimesh_fixtures.hpp"
#include "tests/sim/solver/contact_fixtures.hpp"

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
  for (const Contact& c : probe.impl().contacts())
    on_plank += c.count > 0 && (c.body_a == 0 || c.body_b == 0);
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

// The same bits with 1, 2 and 3 threads, across saves: the one-thread run is the reference; its
// state after `from` steps, saved, is resumed on two and on three threads for `window` steps more,
// and the two-thread run is saved again halfway and resumed on three threads; all three must end
// with the one-thread run's bits. The threaded runs never back off (WorldConfig::thread_backoff),
// so every stage with enough work is split (each scene has at least 64 pairs to collide and 128
// constraints to solve: sim/world/contact_set.cpp, sim/solver/contact_solver.hpp) however busy the machine,
// which makes them slow there: hence the short window at the scene's moment of interest. `seen` is
// called on the one-thread world after every step, to check that the scene does what it is for.
template <class Seen>
void expect_same_bits_for_any_thread_count(const std::vector<BodyDef>& bodies, WorldConfig cfg, int from,
                                           int window, Seen&& seen) {
  cfg.threads = 1;
  World one(cfg, bodies);
  std::stringstream at_from;
  for (int k = 0; k < from + window; ++k) {
    if (k == from) one.save_state(at_from);
    one.step();
    seen(one);
  }
  const uint64_t h1 = state_hash(one);
  cfg.thread_backoff = false;
  cfg.threads = 2;
  World two(cfg, bodies);
  two.restore_state(at_from);
  std::stringstream halfway;
  for (int k = 0; k < window; ++k) {
    if (k == window / 2) two.save_state(halfway);
    two.step();
  }
  EXPECT_EQ(h1, state_hash(two)) << "two threads";
  EXPECT_GT(two.profile().pool_runs, 0);
  EXPECT_EQ(two.profile().pool_alone_runs, 0);
  cfg.threads = 3;
  World three(cfg, bodies);
  at_from.seekg(0);
  three.restore_state(at_from);
  for (int k = 0; k < window; ++k) three.step();
  EXPECT_EQ(h1, state_hash(three)) << "three threads";
  World resumed(cfg, bodies);
  resumed.restore_state(halfway);
  for (int k = window / 2; k < window; ++k) resumed.step();
  EXPECT_EQ(h1, state_hash(resumed)) << "saved on two threads, resumed on three";
}

int touching(const World& w) {
  int n = 0;
  for (const Contact& c : w.impl().contacts()) n += c.count > 0;
  return n;
}

// Bullets (continuous collision, sim/world/continuous.cpp): 12 steel balls at 60 to 120 m/s, half of them
// flagged `bullet`, shot into 144 small cubes standing in front of a thin static wall. Their
// pairs are fast (collide_ahead's manifolds taken at the predicted impact, carried back with an
// offset) and the continuous stage moves some back to their time of impact.
TEST(ContactThreads, BulletsAreTheSameForAnyThreadCount) {
  std::vector<BodyDef> v;
  v.push_back(contact_test::box(Vec3(0.01, 3, 1), Vec3(1.6, 0, 0.5), 0.6, 0.2, 2700, Quat::Identity(),
                                BodyType::static_body));
  for (int j = 0; j < 12; ++j)
    for (int i = 0; i < 12; ++i)
      v.push_back(
          contact_test::box(Vec3::Constant(0.08), Vec3(0.2 + 0.1 * i, -0.55 + 0.1 * j, 0.04), 0.6, 0.1, 600));
  SplitMix64 rng(7);
  for (int k = 0; k < 12; ++k) {
    BodyDef b = contact_test::sphere(
        0.012, Vec3(-0.5 - 0.05 * k, rng.uniform(-0.6, 0.6), rng.uniform(0.03, 0.2)), 0.6, 0.4, 7800);
    b.v_W = Vec3(rng.uniform(60, 120), rng.uniform(-5, 5), rng.uniform(-1, 1));
    b.bullet = k % 2 == 0;
    v.push_back(b);
  }
  v.push_back(contact_test::ground());
  WorldConfig cfg;
  cfg.dt = kR3Dt;
  cfg.contacts.substeps = 4;  // (automatic: up to 64 for the balls' spin, slow on a busy machine)
  int most = 0, ahead = 0;
  long hits_before = 0;
  expect_same_bits_for_any_thread_count(v, cfg, 3, 4, [&](const World& w) {
    if (w.steps() <= 3) hits_before = w.profile().toi_hits;
    most = std::max(most, touching(w));
    for (const Contact& c : w.impl().contacts())  // manifolds taken ahead, at a fast pair's impact
      for (int j = 0; j < c.count; ++j) ahead += w.steps() > 3 && c.points[j].offset_W.norm() > 0;
  });
  EXPECT_GT(ahead, 0) << "fast pairs must be collided ahead while the threads run";
  World probe(cfg, v);
  for (int k = 0; k < 7; ++k) probe.step();
  EXPECT_GT(probe.profile().toi_hits, hits_before) << "bodies must be moved back while the threads run";
  EXPECT_GE(most, 128);
}

// A static triangle mesh (sim/world/mesh_pairs.cpp: several records per pair, packed after the
// threads): 81 stacks of two bodies (a cube under a cube, ball, capsule or cylinder) in the valleys
// of a ridged terrain of 800 triangles, where each cube touches two slopes (two manifolds, one
// pair), sleeping on. They fall asleep; six heavy balls dropped from 3 to 6 m then land on them
// between 0.78 and 1.1 s and wake stacks (kept records collided again where the sequential pass
// would).
TEST(ContactThreads, TriangleMeshIsTheSameForAnyThreadCount) {
  std::vector<BodyDef> v;
  // Vertices 0.1 m apart, every other row of them 2 cm up: valleys 0.2 m apart along x, slopes 0.2.
  v.push_back(trimesh_test::mesh_body(trimesh_test::grid(20, 20, 0.1, -1.0, -1.0, [](double x, double) {
    return std::lround((x + 1.0) / 0.1) % 2 == 1 ? 0.02 : 0.0;
  })));
  for (int j = 0; j < 9; ++j)
    for (int i = 0; i < 9; ++i) {
      const double x = -0.8 + 0.2 * i, y = -0.8 + 0.2 * j;
      v.push_back(contact_test::box(Vec3::Constant(0.08), Vec3(x, y, 0.008 + 0.04 + 0.005)));
      const double top = 0.008 + 0.08 + 0.01;
      switch ((i + j) % 4) {
        case 0:
          v.push_back(contact_test::box(Vec3::Constant(0.06), Vec3(x, y, top + 0.03)));
          break;
        case 1:
          v.push_back(contact_test::sphere(0.03, Vec3(x, y, top + 0.03)));
          break;
        case 2: {
          BodyDef b = contact_test::capsule(0.02, 0.08, Vec3(x, y, top + 0.02));
          b.q_WB = Quat(Eigen::AngleAxisd(0.5 * std::numbers::pi, Vec3::UnitX()));
          v.push_back(b);
          break;
        }
        default: {
          BodyDef b;
          b.name = "cylinder";
          b.p_WB = Vec3(x, y, top + 0.025);
          Collider c;
          c.shape = ShapeKind::cylinder;
          c.radius = 0.03;
          c.height = 0.05;
          c.props_C = cylinder_mass(0.03, 0.05, 1000);
          b.add_collider(c);
          v.push_back(b);
        }
      }
    }
  SplitMix64 rng(3);
  for (int k = 0; k < 6; ++k)
    v.push_back(contact_test::sphere(
        0.06, Vec3(rng.uniform(-0.8, 0.8), rng.uniform(-0.8, 0.8), 3.0 + 0.6 * k), 0.6, 0.0, 3000));
  WorldConfig cfg;
  cfg.dt = kR3Dt;
  int most_asleep = 0, most_touching = 0, most_shared = 0, wakes = 0, last_asleep = 0;
  // Threads from 0.75 s (all asleep) to 0.96 s: the first three balls land.
  expect_same_bits_for_any_thread_count(v, cfg, 180, 50, [&](const World& w) {
    wakes += w.steps() > 180 && w.sleeping_count() < last_asleep;
    last_asleep = w.sleeping_count();
    if (w.steps() <= 180) most_asleep = std::max(most_asleep, w.sleeping_count());
    most_touching = std::max(most_touching, touching(w));
    int shared = 0;  // records of a mesh pair after its first
    for (size_t k = 1; k < w.impl().contacts().size(); ++k)
      shared += w.impl().contacts()[k].key() == w.impl().contacts()[k - 1].key();
    most_shared = std::max(most_shared, shared);
  });
  EXPECT_EQ(most_asleep, 162) << "the stacks must be asleep when the threads start";
  EXPECT_GE(wakes, 2) << "the dropped balls must wake stacks while the threads run";
  EXPECT_GE(most_touching, 128);
  EXPECT_GT(most_shared, 40) << "cubes in the valleys must touch both slopes";
}

// Rim contacts (sim/solver/contact_solver.cpp refresh_rim: found again after every substep's move, on
// the threads after a barrier): 72 Euler's disks spinning on their rims on the ground and 72 on
// dynamic slabs lying on it, leaning 15 to 35 degrees.
TEST(ContactThreads, RollingDisksAreTheSameForAnyThreadCount) {
  std::vector<BodyDef> v;
  v.push_back(contact_test::ground());
  const double a = 0.05, h = 0.0005, g = 9.80665;
  for (int j = 0; j < 12; ++j)
    for (int i = 0; i < 12; ++i) {
      const double alpha = (15 + 20.0 * ((i * 7 + j * 3) % 12) / 11) * std::numbers::pi / 180;
      const Vec3 base(0.3 * i, 0.3 * j, 0);
      const bool on_slab = (i + j) % 2 == 1;
      double lift = 0;
      if (on_slab) {
        v.push_back(contact_test::box(Vec3(0.24, 0.24, 0.02), base + Vec3(0, 0, 0.01), 0.6, 0.0, 2000));
        lift = 0.02;
      }
      // Moffatt's steady motion of a thin disk: G at rest, Omega^2 sin(alpha) = 4 g / a.
      const double s = std::sin(alpha), c = std::cos(alpha), W = std::sqrt(4 * g / (a * s));
      const Vec3 e1(c, 0, s), e3(-s, 0, c);
      BodyDef b;
      b.name = "disk";
      b.q_WB = Quat(Eigen::AngleAxisd(-alpha, Vec3::UnitY()));
      b.p_WB = base + Vec3(0, 0, lift + a * s + h * c - 1e-4);
      b.w_W = W * s * e1 + W * (h * s) / a * e3;
      Collider col;
      col.shape = ShapeKind::cylinder;
      col.radius = a;
      col.height = 2 * h;
      col.props_C = cylinder_mass(a, 2 * h, 7800);
      col.friction = 0.6;
      b.add_collider(col);
      v.push_back(b);
    }
  WorldConfig cfg;
  cfg.dt = kR3Dt;
  cfg.contacts.sleep = false;
  int most_one_point = 0;
  expect_same_bits_for_any_thread_count(v, cfg, 100, 10, [&](const World& w) {
    int n = 0;
    for (const Contact& c : w.impl().contacts())
      n += c.count == 1 && (w.impl().shapes()[c.shape_a].geom.kind == CollideKind::cylinder ||
                            w.impl().shapes()[c.shape_b].geom.kind == CollideKind::cylinder);
    most_one_point = std::max(most_one_point, n);
  });
  EXPECT_GE(most_one_point, 128) << "the disks must touch with one rim point each";
}

// Tracked contacts of every other kind (sim/collision/tracked_contacts.hpp) on the threads: 169 bodies on the
// ground, rattlebacks (an ellipsoid with a product of inertia, spun either way and tilted) and
// tippe tops (a sphere whose centre is 5 mm off the centre of mass, spun at 40 rad/s), each
// tracked per substep with its gyroscopic term after the warm start (a barrier, fixed shares).
TEST(ContactThreads, TrackedEllipsoidsAndTopsAreTheSameForAnyThreadCount) {
  std::vector<BodyDef> v;
  v.push_back(contact_test::ground(2.0));
  for (int j = 0; j < 13; ++j)
    for (int i = 0; i < 13; ++i) {
      BodyDef b;
      Collider c;
      const Vec3 base(0.5 * i, 0.5 * j, 0);
      if ((i + j) % 3 == 0) {
        b.name = "top";
        c.shape = ShapeKind::sphere;
        c.radius = 0.025;
        c.props_C = sphere_mass(0.025, 1000);
        c.friction = 0.3;
        b.mass_override = MassProperties{0.02, Vec3(0, 0, -0.005), Vec3(5e-6, 5e-6, 6e-6).asDiagonal()};
        b.q_WB = Quat(Eigen::AngleAxisd((5 + i) * std::numbers::pi / 180, Vec3::UnitX()) *
                      Eigen::AngleAxisd((3 + j) * std::numbers::pi / 180, Vec3::UnitY()));
        b.p_WB = base + Vec3(0, 0, 0.025);
        b.w_W = Vec3(0, 0, 40 + i);
      } else {
        b.name = "celt";
        c.shape = ShapeKind::ellipsoid;
        c.radii = Vec3(0.2, 0.03, 0.02);
        c.props_C = ellipsoid_mass(c.radii, 1000);
        c.friction = 2.0;
        Mat3 I;
        I << 2e-4, -2e-5, 0, -2e-5, 1.6e-3, 0, 0, 0, 1.7e-3;
        b.mass_override = MassProperties{1.0, Vec3(0, 0, -0.01), I};
        b.q_WB = Quat(Eigen::AngleAxisd(10.0 * j * std::numbers::pi / 180, Vec3::UnitZ()) *
                      Eigen::AngleAxisd((0.3 + 0.1 * (i % 5)) * std::numbers::pi / 180, Vec3::UnitY()) *
                      Eigen::AngleAxisd(0.5 * std::numbers::pi / 180, Vec3::UnitX()));
        b.p_WB = base + Vec3(0, 0, 0.0201);
        b.w_W = Vec3(0, 0, (i + j) % 2 ? 5.0 : -5.0);
      }
      b.append_collider(c);
      v.push_back(b);
    }
  WorldConfig cfg;
  cfg.dt = kR3Dt;
  cfg.contacts.sleep = false;
  // The solver's tracked rows: the celts would otherwise roll (sim/solver/rolling_contact.hpp,
  // stepped one by one on the calling thread).
  cfg.contacts.rolling = false;
  int most_one_point = 0;
  expect_same_bits_for_any_thread_count(v, cfg, 20, 10, [&](const World& w) {
    int n = 0;
    for (const Contact& c : w.impl().contacts()) {
      const CollideKind ka = w.impl().shapes()[c.shape_a].geom.kind,
                        kb = w.impl().shapes()[c.shape_b].geom.kind;
      n += c.count == 1 && (ka == CollideKind::ellipsoid || kb == CollideKind::ellipsoid ||
                            ka == CollideKind::sphere || kb == CollideKind::sphere);
    }
    most_one_point = std::max(most_one_point, n);
  });
  EXPECT_GE(most_one_point, 128) << "the bodies must touch the ground with one point each";
}

}  // namespace
}  // namespace simreel
