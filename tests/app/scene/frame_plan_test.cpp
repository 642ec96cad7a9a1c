// A run's plan and limits (app/scene/frame_plan.hpp): frames follow their closed form,
// nothing is sized by the number of frames, the frame targets read as the list they stand for,
// and long but legal runs are announced before they start.
#include "app/scene/frame_plan.hpp"

#include <gtest/gtest.h>
#include <malloc.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "app/runner/frame_loop.hpp"
#include "app/scene/scene.hpp"
#include "tests/fixtures/reference_scenes.hpp"
#include "tests/scratch.hpp"

namespace simreel {
namespace {

// Frame k is taken at the first step whose time reaches k / fps: with whole steps per frame,
// step(k) = k x (steps per frame) exactly; with 1.5 frames a step, ceil(k / 1.5).
TEST(FramePlan, StepsFollowTheClosedForm) {
  const FramePlan a = plan_frames(6.0, 1.0 / 240, 30);
  EXPECT_EQ(a.frames, 181);
  EXPECT_EQ(a.total_steps, 1440);
  for (long k = 0; k < a.frames; ++k) ASSERT_EQ(a.step(k), 8 * k) << k;
  const FramePlan b = plan_frames(1.0, 0.05, 30);  // two frames share a step every three
  EXPECT_EQ(b.frames, 31);
  for (long k = 0; k < b.frames; ++k) ASSERT_EQ(b.step(k), std::min(20L, (2 * k + 2) / 3)) << k;
  // Counts no long can hold saturate instead of overflowing (prepare_run refuses them later).
  const FramePlan c = plan_frames(1e300, 1e-300, 1e300);
  EXPECT_GT(c.frames, 1000000000000000000L);
  EXPECT_GT(c.total_steps, 1000000000000000000L);
}

// Bytes held on the heap now (in use from the arena and from mmap).
size_t heap_bytes() {
  const struct mallinfo2 m = mallinfo2();
  return m.uordblks + m.hblkhd;
}

// A plan of ten million frames costs what a plan of ten costs: the loop, every frame of it as
// targets, and a spec naming all of them (a table of steps per frame took 80 MB and the targets
// 240 MB). The heap held while they are alive is compared.
TEST(FramePlan, TenMillionFramesAreAsSmallAsTen) {
  auto held = [](double fps, size_t spec_extra) {
    WorldConfig c;
    c.dt = 1e-3;
    const size_t before = heap_bytes();
    FrameLoop loop(c, {box_body("box", Vec3(3, 2, 1), 6.0)}, 1e4, fps);
    const FrameTargets all = loop.all_frames();
    const FrameTargets spec = parse_frame_spec("0:, 5s, 12.3456s, 50%", loop.plan(), fps, c.dt, 1e4);
    EXPECT_EQ(all.size(), (size_t)loop.plan().frames);
    EXPECT_EQ(all.back().index, loop.plan().frames - 1);
    EXPECT_EQ(spec.size(), (size_t)loop.plan().frames + spec_extra);  // the times between frames
    return heap_bytes() - before;
  };
  // At 1000 fps 5 s and 50% are frames and 12.3456 s is not; at 0.001 fps only 50% is.
  const size_t ten = held(1e-3, 2), ten_million = held(1e3, 1);
  EXPECT_LT(ten_million, ten + 4096) << "ten frames: " << ten << " bytes, ten million: " << ten_million;
}

// The targets of a spec, as the list they stand for: every item expanded, sorted by step then
// time, duplicates dropped (the representation before runs). A time on a frame is that frame.
std::vector<FrameTarget> expanded(const std::string& spec, const FramePlan& plan) {
  std::vector<FrameTarget> out;
  size_t pos = 0;
  while (pos <= spec.size()) {
    const size_t comma = std::min(spec.find(',', pos), spec.size());
    const std::string item = spec.substr(pos, comma - pos);
    pos = comma + 1;
    if (const size_t colon = item.find(':'); colon != std::string::npos) {
      const long lo = colon ? std::stol(item.substr(0, colon)) : 0;
      const long hi = colon + 1 < item.size() ? std::stol(item.substr(colon + 1)) : plan.frames - 1;
      for (long k = lo; k <= hi; ++k) out.push_back(plan_target(plan, k, plan.fps));
    } else if (item.back() == 's') {
      const double t = std::stod(item), kf = t * plan.fps;
      const long k = std::lround(kf);
      if (std::fabs(kf - (double)k) <= 1e-9 * std::max(1.0, kf) && k < plan.frames)
        out.push_back(plan_target(plan, k, plan.fps));
      else
        out.push_back({-1, t, step_at(t, plan.dt, plan.total_steps)});
    } else {
      out.push_back(plan_target(plan, std::stol(item), plan.fps));
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const FrameTarget& a, const FrameTarget& b) {
    return a.step != b.step ? a.step < b.step : a.time < b.time;
  });
  out.erase(std::unique(out.begin(), out.end(),
                        [](const FrameTarget& a, const FrameTarget& b) {
                          return a.step == b.step && a.index == b.index && a.time == b.time;
                        }),
            out.end());
  return out;
}

// Random specs (numbers, ranges that overlap and touch, times on and between frames) on two plans,
// one with frames sharing steps: the runs read back as the expanded list, by index and iteration.
TEST(FrameTargets, ReadAsTheListTheyStandFor) {
  std::mt19937 rng(16);
  for (const auto& [dt, fps] : {std::pair{0.01, 10.0}, std::pair{0.05, 30.0}}) {
    const double duration = 2.0;
    const FramePlan plan = plan_frames(duration, dt, fps);
    std::uniform_int_distribution<long> frame(0, plan.frames - 1);
    std::uniform_real_distribution<double> time(0, duration);
    for (int trial = 0; trial < 300; ++trial) {
      std::string spec;
      const int items = 1 + (int)(rng() % 6);
      for (int i = 0; i < items; ++i) {
        if (i) spec += ",";
        switch (rng() % 5) {
          case 0:
            spec += std::to_string(frame(rng));
            break;
          case 1: {
            long a = frame(rng), b = frame(rng);
            spec += std::to_string(std::min(a, b)) + ":" + std::to_string(std::max(a, b));
            break;
          }
          case 2:
            spec += rng() % 2 ? std::to_string(frame(rng)) + ":" : ":" + std::to_string(frame(rng));
            break;
          case 3: {
            char b[32];
            std::snprintf(b, sizeof b, "%.4fs", time(rng));
            spec += b;
            break;
          }
          default: {
            char b[32];
            std::snprintf(b, sizeof b, "%gs", (double)frame(rng) / fps);  // on a frame
            spec += b;
          }
        }
      }
      const FrameTargets got = parse_frame_spec(spec, plan, fps, dt, duration);
      const std::vector<FrameTarget> want = expanded(spec, plan);
      ASSERT_EQ(got.size(), want.size()) << spec;
      size_t i = 0;
      for (const FrameTarget& t : got) {
        ASSERT_LT(i, want.size()) << spec;
        EXPECT_EQ(t.index, want[i].index) << spec << " #" << i;
        EXPECT_EQ(t.step, want[i].step) << spec << " #" << i;
        EXPECT_EQ(t.time, want[i].time) << spec << " #" << i;
        EXPECT_EQ(got[i].index, want[i].index) << spec << " #" << i;
        ++i;
      }
      EXPECT_EQ(i, want.size()) << spec;
    }
  }
}

Scene boxes(int n, bool collide, double duration) {
  Scene s;
  s.path = "boxes.yaml";
  s.duration = duration;
  s.timestep = 1.0 / 240;
  s.video.fps = 30;
  for (int i = 0; i < n; ++i) {
    BodyDef b = box_body(("b" + std::to_string(i)).c_str(), Vec3(1, 1, 1), 1.0);
    for (Collider& c : b.colliders) c.collide = collide;
    s.bodies.push_back(b);
  }
  return s;
}

bool announced(const Scene& s) {
  for (const std::string& n : s.notes)
    if (n.rfind("a long run", 0) == 0) return true;
  return false;
}

// More than 1e7 steps, more than 1e6 frames or an estimated 5 minutes of physics: a note says so
// before the run, with the counts, the estimate and how to stop it. The estimate is bodies x steps
// at the stated costs. No shipped scene is long.
TEST(PrepareRun, LongRunsAreAnnouncedBeforeTheyStart) {
  Scene many_steps = boxes(1, true, 1e5);  // 2.4e7 steps of one box
  prepare_run(many_steps);
  ASSERT_TRUE(announced(many_steps));
  const std::string& note = many_steps.notes.back();
  for (const char* part :
       {"2.4e+07 steps", "1 dynamic body", "3e+06 frames", "Ctrl-C", "simulation.timestep"})
    EXPECT_NE(note.find(part), std::string::npos) << part << " not in: " << note;

  Scene many_frames = boxes(1, true, 10);
  many_frames.video.fps = 2e5;  // 2e6 frames (and as many steps: the step shortens to the frame)
  many_frames.timestep = 5e-6;
  prepare_run(many_frames);
  EXPECT_TRUE(announced(many_frames));

  // 2000 boxes for 500 s at 1/240 s: 1.2e5 steps, under the step limit; with contacts
  // 1.2e5 x (1 + 2000 x 1.5) us = 360 s, without 1.2e5 x (1 + 2000 x 0.03) us = 7.3 s.
  Scene touching = boxes(2000, true, 500), apart = boxes(2000, false, 500);
  EXPECT_NEAR(estimate_physics_seconds(touching, 1.2e5), 1.2e5 * (1e-6 + 2000 * 1.5e-6), 1e-9);
  EXPECT_NEAR(estimate_physics_seconds(apart, 1.2e5), 1.2e5 * (1e-6 + 2000 * 0.03e-6), 1e-9);
  prepare_run(touching);
  prepare_run(apart);
  EXPECT_TRUE(announced(touching));
  EXPECT_FALSE(announced(apart));
  EXPECT_NE(touching.notes.back().find("6 min"), std::string::npos) << touching.notes.back();

  // Over the limits it is an error naming the keys, not a note.
  Scene tiny_step = boxes(1, true, 1);
  tiny_step.timestep = 1e-12;
  try {
    prepare_run(tiny_step);
    ADD_FAILURE() << "1e12 steps accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("simulation.timestep"), std::string::npos) << e.what();
  }

  int shipped = 0;
  for (const auto& e : std::filesystem::directory_iterator("scenes")) {
    if (e.path().extension() != ".yaml") continue;
    Scene s = load_scene(e.path().string());
    prepare_run(s);
    EXPECT_FALSE(announced(s)) << e.path();
    ++shipped;
  }
  EXPECT_GE(shipped, 10);
}

#ifdef SIMREEL_BIN
// Peak resident memory (MB) of one simreel command, and its exit code.
std::pair<double, int> peak_mb(const std::vector<std::string>& args) {
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> argv{const_cast<char*>(SIMREEL_BIN)};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    freopen("/dev/null", "w", stdout);
    freopen("/dev/null", "w", stderr);
    execv(SIMREEL_BIN, argv.data());
    _exit(127);
  }
  int st = 0;
  rusage u{};
  wait4(pid, &st, 0, &u);
  return {u.ru_maxrss / 1024.0, WIFEXITED(st) ? WEXITSTATUS(st) : -1};
}

// A very long scene, end to end: 1e7 frames (fps 1000 for 1e4 s), three of them rendered, peaks
// where a 3-frame scene does (a frame table and a list of targets for every frame take 551 MB).
TEST(PrepareRun, TenMillionFrameSceneRendersThreeFramesInTheMemoryOfAShortOne) {
  auto scene = [](double duration, double fps) {
    char text[400];
    std::snprintf(text, sizeof text,
                  "simulation: { duration: %g, timestep: 0.001 }\nvideo: { width: 64, height: 48, fps: %g }\n"
                  "bodies:\n  - { angular_velocity: [0.1, 3, 0.1], colliders: [ { shape: box, size: [0.3, "
                  "0.2, 0.1] } ] }\n",
                  duration, fps);
    return test::scratch_file(std::to_string(fps) + ".yaml", text);
  };
  const std::string dir = test::scratch("frames");
  const auto [long_mb, long_code] =
      peak_mb({"render", scene(1e4, 1e3), "--frames", "0:2", "--frames-dir", dir, "--no-video", "--quiet"});
  const auto [short_mb, short_code] = peak_mb({"render", scene(0.002, 1e3), "--frames", "0:2", "--frames-dir",
                                               dir, "--no-video", "--overwrite", "--quiet"});
  EXPECT_EQ(long_code, 0);
  EXPECT_EQ(short_code, 0);
  EXPECT_LT(long_mb, short_mb + 20) << "1e7 frames: " << long_mb << " MB, 3 frames: " << short_mb << " MB";
}
#endif

}  // namespace
}  // namespace simreel
