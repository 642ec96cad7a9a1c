// The workers' split of the contact solver's colours (sim/solver/worker_schedule.cpp): each colour shared
// out whole, and the items a worker solves after telling the others it may go on touch only its
// own bodies. A fault here is a race between the workers that the determinism tests
// (tests/sim/solver/constraint_graph_test.cpp) would catch only when the timing happens to hit it.
#include <gtest/gtest.h>

#include <vector>

#include "tests/fixtures/reference_scenes.hpp"
#include <simreel/world.hpp>
#include "sim/world/world_impl.hpp"

namespace simreel {
namespace {

struct Split {
  bool fractions = false;
  int faults = 0, workers = 0;
  long deferred = 0, items = 0;
};

Split split_after(const std::vector<BodyDef>& bodies, double dt, int threads, int steps) {
  WorldConfig cfg;
  cfg.dt = dt;
  cfg.threads = threads;
  cfg.contacts.sleep = false;
  World w(cfg, bodies);
  Split s;
  for (int k = 0; k < steps; ++k) {
    w.step();
    long deferred = 0, items = 0;
    s.faults += w.impl().contact_solver().split_faults(&deferred, &items);
    s.workers = w.impl().contact_solver().workers();
    s.fractions = w.impl().contact_solver().split_in_fractions();
    s.deferred = deferred, s.items = items;
  }
  return s;
}

// The R3 pile while its layers land (the split changes every step with the times), on two and
// three workers: no faults, and most items are solved without anyone waiting for them. Its
// colours are its layers, each in one span of bodies, so each colour is split in fractions.
TEST(ContactSplit, PileSplitHasNoSharedBodyAfterTheCount) {
  for (const int threads : {2, 3}) {
    const Split s = split_after(r3_pile(), kR3Dt, threads, 150);
    ASSERT_EQ(s.workers, threads);
    EXPECT_TRUE(s.fractions) << threads << " threads";
    EXPECT_EQ(s.faults, 0) << threads << " threads";
    EXPECT_GT(s.items, 0);
    EXPECT_GT(s.deferred, s.items / 2) << threads << " threads";
  }
}

// A pyramid 30 cubes wide: rows longer than the 32 colours wrap round. No faults.
TEST(ContactSplit, PyramidSplitHasNoSharedBodyAfterTheCount) {
  for (const int threads : {2, 3}) {
    const Split s = split_after(r3_pyramid(30), kPyramidDt, threads, 20);
    ASSERT_EQ(s.workers, threads);
    EXPECT_EQ(s.faults, 0) << threads << " threads";
  }
}

// The large pyramid (5,050 cubes): split in spans of bodies, which meet in a row or two of cubes,
// and with two workers nearly every item is solved without the other waiting for it (94%
// measured; 80% asked).
TEST(ContactSplit, LargePyramidLeavesFewItemsToWaitFor) {
  const Split s = split_after(r3_pyramid(100), kPyramidDt, 2, 10);
  ASSERT_EQ(s.workers, 2);
  EXPECT_FALSE(s.fractions);
  EXPECT_EQ(s.faults, 0);
  EXPECT_GT(s.deferred, 0.8 * s.items);
}

}  // namespace
}  // namespace simreel
