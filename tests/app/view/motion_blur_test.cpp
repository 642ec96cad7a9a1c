// Motion blur (app/view/motion_blur.hpp, render.motion_blur) as `render` and `check` draw it: the
// sub-frame moments land on the steps the shutter spans, images average in linear light with
// integer sums, a still scene blurs to its sharp frame byte for byte, and a blurred frame is
// exactly the average of the sharp frames at its sample steps (the physics untouched).
#include "app/view/motion_blur.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "app/view/panes.hpp"
#include "tests/scratch.hpp"

namespace simreel {
namespace {

TEST(MotionBlur, SamplesLandOnTheStepsTheShutterSpans) {
  MotionBlurSpec mb;
  mb.samples = 5, mb.shutter = 0.5;
  // 8 steps a frame, the shutter open for 4 of them: one sample a step, the frame's own last.
  std::vector<BlurSample> s = blur_samples(mb, 80, 72);
  ASSERT_EQ(s.size(), 5u);
  for (int j = 0; j < 5; ++j) {
    EXPECT_EQ(s[j].step, 76 + j);
    EXPECT_EQ(s[j].weight, 1);
  }
  // More samples than steps: moments that share a step are one sample of their count.
  mb.samples = 8;
  s = blur_samples(mb, 80, 72);
  int total = 0;
  for (const BlurSample& b : s) total += b.weight;
  EXPECT_EQ(total, 8);
  EXPECT_EQ(s.front().step, 76);
  EXPECT_EQ(s.back().step, 80);
  // The first frame, and a freeze frame (the same step as the frame before): sharp.
  s = blur_samples(mb, 0, 0);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].weight, 8);
  // Never before step 0.
  EXPECT_EQ(blur_samples(mb, 3, -8).front().step, 0);
}

TEST(MotionBlur, AveragesInLinearLightExactly) {
  const uint8_t black[4] = {0, 0, 0, 255}, white[4] = {255, 255, 255, 255}, grey[4] = {37, 120, 201, 255};
  uint8_t out[4];
  BlurAccumulator acc(4);
  acc.add(grey, 1, 1);
  acc.add(grey, 1, 3);
  EXPECT_EQ(acc.weight(), 4);
  acc.finish(out);
  EXPECT_EQ(std::vector<uint8_t>(out, out + 4), std::vector<uint8_t>(grey, grey + 4)) << "equal images";
  acc.add(black, 1, 2);
  acc.add(white, 1, 2);
  acc.finish(out);
  // Half the light of white, sRGB-encoded: 255 (1.055 0.5^(1 / 2.4) - 0.055) = 187.5 (a byte average
  // would give 128).
  EXPECT_EQ(out[0], 188);
  EXPECT_EQ(out[3], 255);
  // Every value averages to itself.
  for (int v = 0; v < 256; ++v) {
    const uint8_t px[4] = {(uint8_t)v, (uint8_t)v, (uint8_t)v, (uint8_t)v};
    BlurAccumulator a(64);
    a.add(px, 1, 64);
    a.finish(out);
    ASSERT_EQ(out[0], v);
    ASSERT_EQ(out[3], v);
  }
}

// A scene drawn through SceneFrames and FrameLoop as the commands draw it, blur hooks included.
std::map<long, std::vector<uint8_t>> render(const std::string& text, const std::vector<long>& ks) {
  Scene scene = load_scene_text(text, (test::scratch_dir() / "blur.yaml").string());
  prepare_run(scene);
  FrameLoop loop(scene, 1);
  ViewOptions o;
  SceneFrames frames(scene, loop, o);
  std::map<long, std::vector<uint8_t>> out;
  FrameTargets t;
  for (long k : ks) t.push_back(plan_target(loop.video_plan(), k, scene.video.fps));
  FrameLoop::Hooks h;
  h.step = frames.step_hook();
  frames.blur_hooks(h, loop.video_plan());
  h.frame = [&](const FrameTarget& f, const World& w) {
    const uint8_t* px = frames.draw(w, nullptr, f.index);
    out[f.index].assign(px, px + (size_t)frames.width() * frames.height() * 4);
  };
  loop.run(t, h, false);
  return out;
}

const char* kHead =
    "simulation: { duration: 1, timestep: 0.0125, gravity: [0, 0, 0] }\n"  // 8 steps a frame
    "video: { width: 96, height: 64, fps: 10 }\n"
    "camera: { position: [0, -8, 1], look_at: [0, 0, 0.5] }\n"
    "ground: true\n";
const char* kSharp = "render: { antialiasing: none }\n";

TEST(MotionBlur, AStillSceneBlursToItsSharpFrameAlsoInPanes) {
  const std::string bodies =
      "bodies:\n"
      "  - { name: box, position: [0, 0, 0.5], colliders: [ { shape: box, size: [1, 1, 1] } ] }\n";
  const std::string panes =
      "panes:\n  views:\n    - { title: a }\n    - { title: b, camera: { position: [6, 0, 2] } }\n";
  for (const std::string& extra : {std::string(), panes}) {
    const auto sharp = render(kHead + bodies + extra + kSharp, {0, 4, 9});
    const auto blurred = render(
        kHead + bodies + extra + "render: { antialiasing: none, motion_blur: { samples: 7, shutter: 1 } }\n",
        {0, 4, 9});
    for (long k : {0, 4, 9}) EXPECT_TRUE(sharp.at(k) == blurred.at(k)) << "frame " << k << " " << extra;
  }
}

TEST(MotionBlur, ABlurredFrameIsTheAverageOfTheSharpFramesAtItsSteps) {
  // 8 steps a frame and a shutter of 0.5 over 5 samples: frame k averages steps 8k - 4 .. 8k, one
  // a step, which are frames 8k - 4 .. 8k of the same run drawn at 80 frames a second.
  const std::string bodies =
      "bodies:\n"
      "  - { name: ball, position: [-2, 0, 0.5], linear_velocity: [4, 0, 0],\n"
      "      colliders: [ { shape: sphere, radius: 0.4 } ] }\n";
  const auto blurred = render(
      kHead + bodies + "render: { antialiasing: none, motion_blur: { samples: 5, shutter: 0.5 } }\n", {3, 6});
  const std::string fine = std::string(kHead).replace(std::string(kHead).find("fps: 10"), 7, "fps: 80");
  const auto sharp = render(fine + bodies + kSharp, {20, 21, 22, 23, 24, 44, 45, 46, 47, 48});
  for (long k : {3, 6}) {
    BlurAccumulator acc(5);
    for (long j = 0; j < 5; ++j) acc.add(sharp.at(8 * k - 4 + j).data(), 96 * 64, 1);
    std::vector<uint8_t> avg(96 * 64 * 4);
    acc.finish(avg.data());
    EXPECT_TRUE(avg == blurred.at(k)) << "frame " << k;
    EXPECT_FALSE(sharp.at(8 * k) == blurred.at(k)) << "frame " << k << " should be blurred";
  }
}

}  // namespace
}  // namespace simreel
