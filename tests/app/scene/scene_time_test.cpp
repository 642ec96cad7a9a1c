// Playback time (app/scene/scene_time.hpp): the map from video time to simulated time, the video's frame
// plan on the step grid, and the `time:` block's errors. The expected times are worked out by hand
// from the segments' definitions, not by the code under test.
#include "app/scene/scene_time.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "app/runner/frame_loop.hpp"
#include "app/scene/scene.hpp"
#include <simreel/error.hpp>

namespace simreel {
namespace {

const char* kBody = R"(
bodies:
  - name: ball
    linear_velocity: [1, 0, 0]
    colliders: [{ shape: sphere, radius: 0.1 }]
)";

Scene scene_with(const std::string& head) {
  return load_scene_text(
      "simulation: { duration: 4.0, timestep: 0.01, gravity: [0, 0, 0] }\nvideo: { fps: 10 }\n" + head +
          kBody,
      "t.yaml");
}

TEST(TimeMap, SpeedSegmentsAndHolds) {
  // Simulated 0-2 s at speed 1 (video 0-2 s), hold at 1.5 for 2 s of video (video 1.5-3.5 s),
  // 2-3 s at speed 0.2 (5 s of video: 4-9... see below), then speed 0.5 to the end (1 s -> 2 s).
  TimeSpec ts;
  ts.speed = 0.5;
  ts.segments = {{2.0, 1.0}, {3.0, 0.2}};
  ts.holds = {{1.5, 2.0}};
  const TimeMap m(ts, 4.0);
  // Video: 0-1.5 plays 0-1.5; 1.5-3.5 holds 1.5; 3.5-4.0 plays 1.5-2.0; 4.0-9.0 plays 2-3 at 0.2;
  // 9.0-11.0 plays 3-4 at 0.5.
  EXPECT_DOUBLE_EQ(m.video_duration(), 11.0);
  const double cases[][2] = {{0, 0},     {1.0, 1.0}, {1.5, 1.5}, {2.7, 1.5},  {3.5, 1.5},  {3.75, 1.75},
                             {4.0, 2.0}, {6.5, 2.5}, {9.0, 3.0}, {10.0, 3.5}, {11.0, 4.0}, {12.0, 4.0}};
  for (const auto& c : cases) EXPECT_NEAR(m.sim_time(c[0]), c[1], 1e-12) << "video " << c[0];
}

TEST(TimeMap, VideoPlanSamplesTheNearestStep) {
  Scene s = scene_with("time: { speed: 0.25, hold: { at: 1.0, for: 0.5 } }\n");
  prepare_run(s);
  FrameLoop loop(s, 1);
  const FramePlan& v = loop.video_plan();
  // 1 s simulated = 4 s video, a 0.5 s hold, then 3 s simulated = 12 s video: 16.5 s, 166 frames.
  EXPECT_DOUBLE_EQ(loop.video_duration(), 16.5);
  ASSERT_EQ((size_t)v.frames, 166u);
  // Frame k at video k / 10 s: before the hold simulated k / 40 s, 2.5 k steps of 0.01 s, rounded
  // to the nearest (odd k fall halfway: either step).
  for (long k = 0; k <= 40; k += 2) EXPECT_EQ(v.step(k), 5 * k / 2) << k;
  for (long k = 40; k <= 45; ++k) EXPECT_EQ(v.step(k), 100) << "held at t = 1 s, frame " << k;
  EXPECT_EQ(v.step(49), 110);  // video 4.9 s: sim 1 + 0.4 / 4 = 1.1 s
  EXPECT_EQ(v.step(165), 400);
  // The simulation plan (drift, simulate's CSV, check's times) is untouched: k / 10 s.
  ASSERT_EQ((size_t)loop.plan().frames, 41u);
  EXPECT_EQ(loop.plan().step(7), 70);
  // Every frame of the video is a frame the run delivers, in order, holds repeated.
  long count = 0, last = -1;
  bool ordered = true;
  FrameLoop::Hooks h;
  h.frame = [&](const FrameTarget& t, const World& w) {
    ordered = ordered && t.index == count && w.steps() == v.step(t.index) && w.steps() >= last;
    last = w.steps();
    ++count;
  };
  loop.run(loop.video_frames(), h, true);
  EXPECT_EQ(count, 166);
  EXPECT_TRUE(ordered);
  EXPECT_EQ(loop.video_frame_at_step(100), 40);
  EXPECT_EQ(loop.video_frame_at_step(101), -1);  // 1.01 s falls between frames at speed 0.25
  // simulate's frames stay those of the simulation plan.
  EXPECT_EQ(FrameLoop(s, 1).all_frames().size(), 41u);
}

TEST(TimeMap, UnevenSpeedsAreNoted) {
  Scene s = scene_with("time: { speed: 0.15 }\n");  // 0.15 / 10 fps = 15 ms a frame: 1.5 steps
  prepare_run(s);
  bool noted = false;
  for (const std::string& n : s.notes) noted = noted || n.find("speed 0.15 ") != std::string::npos;
  EXPECT_TRUE(noted);
  Scene even = scene_with("time: { speed: 0.5 }\n");  // 5 steps a frame
  prepare_run(even);
  EXPECT_TRUE(even.notes.empty());
}

TEST(TimeMap, BadBlocksNameTheKey) {
  struct Bad {
    const char* yaml;
    const char* says;
  };
  for (const Bad& b :
       {Bad{"time: { speed: 0 }\n", "time.speed"}, Bad{"time: { sped: 1 }\n", "did you mean 'speed'"},
        Bad{"time: { segments: [{ until: 2, speed: 1 }, { until: 1, speed: 2 }] }\n",
            "time.segments[1].until: must be after"},
        Bad{"time: { segments: [{ until: 9, speed: 1 }] }\n", "after the end of the run"},
        Bad{"time: { segments: [{ speed: 1 }] }\n", "needs 'until'"},
        Bad{"time: { hold: { at: 1 } }\n", "needs 'for'"},
        Bad{"time: { hold: [{ at: 1, for: 1 }, { at: 1, for: 2 }] }\n", "same moment"},
        Bad{"time: 2\n", "expected a mapping"}}) {
    try {
      scene_with(b.yaml);
      ADD_FAILURE() << "accepted " << b.yaml;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(b.says), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("t.yaml:"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace simreel
