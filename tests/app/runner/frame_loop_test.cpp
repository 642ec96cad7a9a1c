// The one frame loop (app/runner/frame_loop.hpp): the frame spec grammar (app/scene/frame_plan.hpp),
// and that what a command asks to see never changes the run it sees.
#include "app/runner/frame_loop.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "tests/fixtures/reference_scenes.hpp"

namespace simreel {
namespace {

// 2 s at 10 fps with dt = 0.01: frames 0..20 at steps 0, 10, ..., 200.
struct Fixture {
  FramePlan plan = plan_frames(2.0, 0.01, 10);
  FrameTargets parse(const std::string& s, bool plan_only = false) {
    return parse_frame_spec(s, plan, 10, 0.01, 2.0, plan_only);
  }
};

TEST(FrameSpec, NumbersRangesTimesAndShares) {
  Fixture f;
  auto t = f.parse("3, 5:7, 20");
  ASSERT_EQ(t.size(), 5u);
  EXPECT_EQ(t[0].index, 3);
  EXPECT_EQ(t[0].step, 30);
  EXPECT_DOUBLE_EQ(t[0].time, 0.3);
  EXPECT_EQ(t[1].index, 5);
  EXPECT_EQ(t[3].index, 7);
  EXPECT_EQ(t[4].index, 20);
  EXPECT_EQ(t[4].step, 200);
  // Open ranges, duplicates merged and sorted by step.
  EXPECT_EQ(f.parse("18:").size(), 3u);
  EXPECT_EQ(f.parse(":2").size(), 3u);
  EXPECT_EQ(f.parse("4,2,4").size(), 2u);
  EXPECT_EQ(f.parse("4,2,4")[0].index, 2);
  // A time on a frame is that frame; between frames it is its own moment at the first step
  // reaching it; shares are of the duration.
  t = f.parse("0.5s");
  EXPECT_EQ(t[0].index, 5);
  t = f.parse("0.537s");
  EXPECT_EQ(t[0].index, -1);
  EXPECT_EQ(t[0].step, 54);
  EXPECT_DOUBLE_EQ(t[0].time, 0.537);
  t = f.parse("50%, 0%, 100%");
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t[0].index, 0);
  EXPECT_EQ(t[1].index, 10);
  EXPECT_EQ(t[2].index, 20);
  // For a video every frame is a frame of the plan: a time takes the frame at or after it.
  t = f.parse("0.537s", true);
  EXPECT_EQ(t[0].index, 6);
  EXPECT_EQ(t[0].step, 60);
}

TEST(FrameSpec, BadItemsAreNamed) {
  Fixture f;
  for (const char* bad : {"", "3,,4", "x", "21", "5:3", "2.5", "-1s", "3s", "101%", "1:x", "1e3"}) {
    try {
      f.parse(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_FALSE(std::string(e.what()).empty());
    }
  }
  try {
    f.parse("21");
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("frames 0 to 20"), std::string::npos) << e.what();
  }
}

// A tumbling box under gravity: a run with energy and momentum to measure.
FrameLoop make_loop() {
  WorldConfig c;
  c.dt = 0.01;
  BodyDef b = box_body("box", Vec3(3, 2, 1), 6.0);
  b.w_W = Vec3(0.1, 3, 0.1);
  return FrameLoop(c, {b}, 2.0, 10);
}

// Which frames a command draws does not change the run: the same final state, step count, drift
// figures and step count whether every frame, a few or none are taken.
TEST(FrameLoop, WhatIsDrawnDoesNotChangeTheRun) {
  FrameLoop all = make_loop(), few = make_loop(), none = make_loop();
  long seen = 0;
  FrameLoop::Hooks count;
  count.frame = [&](const FrameTarget& t, const World& w) {
    EXPECT_EQ(w.steps(), t.step);
    ++seen;
  };
  EXPECT_EQ(all.run(all.all_frames(), count, true), 21);
  EXPECT_EQ(seen, 21);
  Fixture f;
  EXPECT_EQ(few.run(f.parse("3,0.537s,17"), count, true), 3);
  EXPECT_EQ(none.run({}, {}, true), 0);
  for (FrameLoop* l : {&few, &none}) {
    EXPECT_EQ(l->world().steps(), all.world().steps());
    EXPECT_EQ(l->world().steps(), 200);
    EXPECT_EQ(l->world().linear_velocity(0), all.world().linear_velocity(0));
    EXPECT_EQ(l->world().angular_velocity(0), all.world().angular_velocity(0));
    EXPECT_EQ(l->drift().energy_rel(), all.drift().energy_rel());
    EXPECT_EQ(l->drift().momentum_rel(), all.drift().momentum_rel());
  }
  EXPECT_GT(all.drift().energy_rel(), 0);  // something was measured
}

// Sub-frame samples (motion blur) are taken at the steps asked for, in order, before their frame,
// and change nothing: the state at every frame and at the end is the run without them, bit for bit.
TEST(FrameLoop, SubFrameSamplesAreTakenOnTheWayAndChangeNothing) {
  FrameLoop plain = make_loop(), sampled = make_loop();
  std::vector<Vec3> v_plain, v_sampled;
  FrameLoop::Hooks a;
  a.frame = [&](const FrameTarget&, const World& w) { v_plain.push_back(w.angular_velocity(0)); };
  plain.run(plain.all_frames(), a, true);
  std::vector<std::pair<long, long>> seen;  // (frame, step)
  FrameLoop::Hooks b;
  b.sample_steps = [](const FrameTarget& t, std::vector<long>& steps) {
    for (long s : {t.step - 7, t.step - 3, t.step - 1}) steps.push_back(s);  // before step 0: skipped
  };
  b.sample = [&](const FrameTarget& t, const World& w) { seen.emplace_back(t.index, w.steps()); };
  b.frame = [&](const FrameTarget&, const World& w) { v_sampled.push_back(w.angular_velocity(0)); };
  sampled.run(sampled.all_frames(), b, true);
  EXPECT_EQ(v_plain, v_sampled);
  EXPECT_EQ(plain.world().linear_velocity(0), sampled.world().linear_velocity(0));
  EXPECT_EQ(plain.drift().energy_rel(), sampled.drift().energy_rel());
  ASSERT_EQ(seen.size(), 20u * 3);  // frame 0 has no step before it
  EXPECT_EQ(seen[0], std::make_pair(1L, 3L));
  EXPECT_EQ(seen[2], std::make_pair(1L, 9L));
  EXPECT_EQ(seen.back(), std::make_pair(20L, 199L));
}

// Without to_end the physics stops at the last frame asked for; a stop request ends it between
// steps, not only between frames.
TEST(FrameLoop, StopsAtTheLastTargetOrWhenAsked) {
  FrameLoop l = make_loop();
  Fixture f;
  l.run(f.parse("4"), {}, false);
  EXPECT_EQ(l.world().steps(), 40);
  std::atomic<int> stop{0};
  FrameLoop m = make_loop();
  FrameLoop::Hooks h;
  h.stop = &stop;
  h.frame = [&](const FrameTarget& t, const World&) {
    if (t.index == 2) stop = 15;
  };
  EXPECT_EQ(m.run(m.all_frames(), h, true), 3);
  EXPECT_TRUE(m.interrupted());
  EXPECT_EQ(m.world().steps(), 20);
  std::atomic<int> at_once{2};
  FrameLoop n = make_loop();
  FrameLoop::Hooks g;
  g.stop = &at_once;
  EXPECT_EQ(n.run(f.parse("19"), g, true), 0);
  EXPECT_EQ(n.world().steps(), 0) << "the stop must be seen before the first step";
}

}  // namespace
}  // namespace simreel
