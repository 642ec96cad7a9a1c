// simreel check and simreel diff end to end, through the built binary: goldens written, checked
// clean, a moved body caught as a physics change, a colour as a rendering change, exit codes,
// JUnit, the report page, and diff over PNGs, folders and videos.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/cli_run.hpp"
#include "tests/scratch.hpp"

namespace {

namespace fs = std::filesystem;
using simreel::test::Result;
using simreel::test::slurp;

// CI is unset: --update's default must not depend on the environment the tests run in.
Result run(const std::string& args) {
  return simreel::test::run(args, "-u CI");
}

// A ball dropped on the ground beside a spinning box: contacts, shadows, motion.
std::string scene_text(const std::string& ball_x = "0.5", const std::string& box_color = "[0.8, 0.3, 0.2]",
                       const std::string& fps = "25") {
  return "simulation: { duration: 2, timestep: 0.005 }\n"
         "video: { width: 320, height: 180, fps: " +
         fps +
         " }\n"
         "camera: { position: [5, -5, 3], look_at: [0, 0, 0.5] }\n"
         "ground: {}\n"
         "test: { width: 160, height: 90 }\n"
         "bodies:\n"
         "  - { name: box, position: [-1, 0, 1.5], angular_velocity: [0.1, 3, 0.1], color: " +
         box_color +
         ",\n"
         "      colliders: [ { shape: box, size: [0.8, 0.5, 0.3] } ] }\n"
         "  - { name: ball, position: [" +
         ball_x + ", 0.5, 2], colliders: [ { shape: sphere, radius: 0.3 } ] }\n";
}

std::string write_scene(const fs::path& dir, const std::string& text) {
  fs::create_directories(dir);
  const fs::path p = dir / "drop.yaml";  // the same scene name in every variant: one golden folder
  std::ofstream(p) << text;
  return p.string();
}

TEST(Check, GoldensWrittenThenCheckedCleanThenChangesCaught) {
  const fs::path base = simreel::test::scratch_dir();
  const std::string goldens = (base / "goldens").string();
  const std::string scene = write_scene(base / "a", scene_text());

  // No goldens and no --update: exit 2, nothing written.
  Result r = run("check " + scene + " --goldens " + goldens + " --update none");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_FALSE(fs::exists(goldens));
  // --update missing writes them: five moments by time, a manifest.
  r = run("check " + scene + " --goldens " + goldens + " --update missing");
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* f : {"t0s.png", "t0.5s.png", "t1s.png", "t1.5s.png", "t2s.png", "manifest.json"})
    EXPECT_TRUE(fs::exists(fs::path(goldens) / "drop" / f)) << f << "\n" << r.out;
  const std::string manifest = slurp(fs::path(goldens) / "drop" / "manifest.json");
  for (const char* k : {"\"pixel_hash\"", "\"gl_renderer\"", "\"cpu_features\"", "\"angular_velocity\"",
                        "\"scene_hash\"", "\"simreel\""})
    EXPECT_NE(manifest.find(k), std::string::npos) << k;

  // Checked clean, with JUnit and a report.
  const std::string junit = (base / "junit.xml").string(), report = (base / "report").string();
  r = run("check " + scene + " --goldens " + goldens + " --junit " + junit + " --report " + report);
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("0 of 5 frames differ"), std::string::npos) << r.out;
  const std::string xml = slurp(junit);
  EXPECT_NE(xml.find("<testsuites"), std::string::npos);
  int cases = 0;
  for (size_t p = xml.find("<testcase "); p != std::string::npos; p = xml.find("<testcase ", p + 1)) ++cases;
  EXPECT_EQ(cases, 5);
  EXPECT_NE(xml.find("failures=\"0\""), std::string::npos) << xml;
  EXPECT_TRUE(fs::exists(fs::path(report) / "index.html"));

  // A new frame rate keeps the goldens valid: the moments are chosen by time (50 fps instead of 25: the 5 ms
  // step divides the frame interval, so the physics is the same).
  const std::string fps = write_scene(base / "fps", scene_text("0.5", "[0.8, 0.3, 0.2]", "50"));
  r = run("check " + fps + " --goldens " + goldens + " --update none");
  EXPECT_EQ(r.code, 0) << r.out;

  // The ball moved 5 cm: a physics change, naming the body.
  const std::string moved = write_scene(base / "moved", scene_text("0.55"));
  r = run("check " + moved + " --goldens " + goldens + " --update none --junit " + junit);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("physics changed: body 'ball' position.x"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("body 'box'"), std::string::npos) << "the box did not change\n" << r.out;
  EXPECT_NE(slurp(junit).find("<failure"), std::string::npos);

  // The box's colour changed: a rendering change, not a physics one.
  const std::string recolored = write_scene(base / "color", scene_text("0.5", "[0.2, 0.3, 0.8]"));
  r = run("check " + recolored + " --goldens " + goldens + " --update none --report " + report);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("rendering changed"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("physics changed"), std::string::npos) << r.out;
  {  // The page's jump links name the moments as the goldens do (by time), frame 0 as well as 0.5 s.
    const std::string page = slurp(fs::path(report) / "index.html");
    for (const char* l : {">drop t=0s</a>", ">drop t=0.5s</a>", ">drop t=2s</a>"})
      EXPECT_NE(page.find(l), std::string::npos) << l;
    EXPECT_EQ(page.find(">drop #"), std::string::npos) << "a link named by frame number";
  }
  EXPECT_NE(r.out.find("--update changed"), std::string::npos) << "the accept command is printed\n" << r.out;
  // ... as it was run (here by the binary's full path), so that it can be pasted.
  EXPECT_NE(r.out.find(std::string(SIMREEL_BIN) + " check "), std::string::npos) << r.out;
  // The same under the portable comparison: a colour change is no noise.
  r = run("check " + recolored + " --goldens " + goldens + " --update none --tolerance portable");
  EXPECT_EQ(r.code, 1) << r.out;

  // Accepted with --update changed; then it checks clean.
  r = run("check " + recolored + " --goldens " + goldens + " --update changed");
  EXPECT_EQ(r.code, 0) << r.out;
  r = run("check " + recolored + " --goldens " + goldens + " --update none");
  EXPECT_EQ(r.code, 0) << r.out;
}

// A changed mass is physics from frame 0 on (where nothing has moved yet); a wrong --goldens path
// is an error naming it; CI counts only when truthy, and a run that writes nothing says why; a
// frame of another size shows no metrics; two scenes with one file name coexist by their paths.
TEST(Check, MassesFoldersCiSizesAndNames) {
  const fs::path base = simreel::test::scratch_dir();
  const std::string goldens = (base / "goldens").string();
  const std::string scene = write_scene(base / "a", scene_text());
  Result r = run("check " + scene + " --goldens " + (base / "nowhere").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("nowhere': no such folder"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("since the output is not a terminal"), std::string::npos) << r.out;
  fs::create_directories(goldens);
  // CI=false is not CI: the reason given is the terminal; CI=1 is.
  r = simreel::test::run("check " + scene + " --goldens " + goldens, "CI=false");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("nothing was written since the output is not a terminal"), std::string::npos) << r.out;
  r = simreel::test::run("check " + scene + " --goldens " + goldens, "CI=1");
  EXPECT_NE(r.out.find("nothing was written since CI is set"), std::string::npos) << r.out;
  ASSERT_EQ(run("check " + scene + " --goldens " + goldens + " --update missing").code, 0);
  EXPECT_NE(slurp(fs::path(goldens) / "drop" / "manifest.json").find("\"masses\""), std::string::npos);

  // The box 10% denser, same shape: at t = 0 the bodies have not moved, and the change is physics.
  std::string denser = scene_text();
  denser.replace(denser.find("shape: box, size: [0.8, 0.5, 0.3]"), 33,
                 "shape: box, size: [0.8, 0.5, 0.3], density: 1100");
  r = run("check " + write_scene(base / "denser", denser) + " --goldens " + goldens +
          " --update none --frames 0%");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("FAIL drop t=0s (physics changed)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("physics changed: body 'box': mass 132 kg (golden 120 kg)"), std::string::npos)
      << r.out;

  // Another frame size: "size changed", and no PSNR or SSIM (nothing was compared).
  std::string wider = scene_text();
  wider.replace(wider.find("test: { width: 160"), 18, "test: { width: 200");
  r = run("check " + write_scene(base / "wider", wider) + " --goldens " + goldens +
          " --update none --frames 0%");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("size changed"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("PSNR"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("(0 physics, 1 of another size, 0 rendering)"), std::string::npos) << r.out;

  // Two drop.yaml in two folders: refused by name, checked by path (from the current folder).
  write_scene(base / "x", scene_text());
  write_scene(base / "y", scene_text("0.6"));
  const std::string in_base = "cd " + base.string() + " && env -u CI " + std::string(SIMREEL_BIN) +
                              " check x/drop.yaml y/drop.yaml --goldens g --update missing";
  auto sh = [](const std::string& cmd) { return simreel::test::shell(cmd); };
  r = sh(in_base);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("--golden-names path"), std::string::npos) << r.out;
  r = sh(in_base + " --golden-names path");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(fs::exists(base / "g" / "x" / "drop" / "manifest.json"));
  EXPECT_TRUE(fs::exists(base / "g" / "y" / "drop" / "manifest.json"));
}

// llvmpipe's vector width (128 or 256 bits: the CPU, or LP_NATIVE_VECTOR_WIDTH) changes the
// fingerprint, so pixels are compared portably; but it is the same rasterizer, measured drawing
// byte-identical frames, so the tight default tolerance applies, not the cross-renderer one that
// misses small colour changes. A green +0.03 on the box is caught.
// Goldens notice their inputs: scaling the scene's mesh file by 2% is named in a note (the scene
// file itself is unchanged), frame 0 is a physics change (the body's mass changed), and --update
// changed records the new hash.
TEST(Check, GoldensNoticeTheirInputFiles) {
  const fs::path base = simreel::test::scratch_dir();
  const std::string goldens = (base / "goldens").string();
  fs::create_directories(base / "a");
  fs::copy_file("assets/tetra.off", base / "a" / "tetra.off");
  const std::string scene =
      write_scene(base / "a",
                  "simulation: { duration: 1 }\nground: true\ntest: { width: 160, height: 90 }\n"
                  "camera: { position: [0.8, -0.8, 0.8], look_at: [0.1, 0.1, 0.5] }\n"
                  "bodies:\n  - { name: t, position: [0, 0, 0.5], colliders: [ { shape: mesh, "
                  "file: tetra.off } ] }\n");
  ASSERT_EQ(run("check " + scene + " --goldens " + goldens + " --update missing --quiet").code, 0);
  EXPECT_NE(simreel::test::slurp(fs::path(goldens) / "drop" / "manifest.json").find("\"tetra.off\""),
            std::string::npos);
  Result r = run("check " + scene + " --goldens " + goldens + " --update none");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(r.out.find("changed since"), std::string::npos) << r.out;
  // The same tetrahedron, 2% larger.
  std::ofstream(base / "a" / "tetra.off") << "OFF\n4 4 0\n0 0 0\n0.306 0 0\n0 0.306 0\n0 0 0.306\n"
                                             "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  r = run("check " + scene + " --goldens " + goldens + " --update none");
  EXPECT_NE(r.out.find("drop.yaml: tetra.off changed since its goldens were written"), std::string::npos)
      << r.out;
  // Frame 0: the bodies have not moved, but the tetrahedron weighs 6% more: physics, not rendering.
  EXPECT_NE(r.out.find("t=0s (physics changed)"), std::string::npos) << "frame 0 is not blamed on rendering\n"
                                                                     << r.out;
  EXPECT_NE(r.out.find("physics changed: body 't': mass"), std::string::npos) << r.out;
  EXPECT_EQ(r.code, 1) << r.out;  // and the frames differ
  r = run("check " + scene + " --goldens " + goldens + " --update changed --quiet");
  r = run("check " + scene + " --goldens " + goldens + " --update none");
  EXPECT_EQ(r.out.find("changed since"), std::string::npos) << r.out;
}

TEST(Check, VectorWidthAloneKeepsTheTightPortableTolerance) {
  const fs::path base = simreel::test::scratch_dir();
  const std::string goldens = (base / "goldens").string();
  const std::string scene = write_scene(base / "a", scene_text());
  Result r = simreel::test::run("check " + scene + " --goldens " + goldens + " --update missing",
                                "-u CI LP_NATIVE_VECTOR_WIDTH=128");
  ASSERT_EQ(r.code, 0) << r.out;
  ASSERT_NE(slurp(fs::path(goldens) / "drop" / "manifest.json").find("128 bits"), std::string::npos)
      << "llvmpipe should report its vector width in GL_RENDERER";
  r = simreel::test::run("check " + scene + " --goldens " + goldens + " --update none",
                         "-u CI LP_NATIVE_VECTOR_WIDTH=256");
  EXPECT_EQ(r.code, 0) << "the same scene under the other width passes\n" << r.out;
  const std::string greener = write_scene(base / "g", scene_text("0.5", "[0.8, 0.33, 0.2]"));
  r = simreel::test::run("check " + greener + " --goldens " + goldens + " --update none",
                         "-u CI LP_NATIVE_VECTOR_WIDTH=256");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("rendering changed (portable)"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("across renderers"), std::string::npos) << r.out;
}

// Scenes that cannot be checked are errors in the JUnit file and cards in the report, beside the
// frames that were checked; the exit code is 2.
TEST(Check, UncheckableScenesAreReportedInJunitAndReport) {
  const fs::path base = simreel::test::scratch_dir();
  const std::string goldens = (base / "goldens").string();
  const std::string scene = write_scene(base / "a", scene_text());
  const std::string twin = write_scene(base / "b", scene_text());  // the same name: one golden folder
  ASSERT_EQ(run("check " + scene + " --goldens " + goldens + " --update missing --quiet").code, 0);
  const std::string junit = (base / "j.xml").string(), report = (base / "r").string();
  const Result r = run("check " + scene + " " + twin + " --goldens " + goldens + " --update none --junit " +
                       junit + " --report " + report);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("1 scene could not be checked"), std::string::npos) << r.out;
  const std::string xml = slurp(junit);
  EXPECT_NE(xml.find("tests=\"6\""), std::string::npos) << xml;
  EXPECT_NE(xml.find("errors=\"1\""), std::string::npos) << xml;
  EXPECT_NE(xml.find("<error message=\"" + twin + ": another scene named &apos;drop&apos;"),
            std::string::npos)
      << xml;
  EXPECT_NE(xml.find("type=\"bad input\""), std::string::npos) << xml;
  const std::string page = slurp(fs::path(report) / "index.html");
  EXPECT_NE(page.find("could not be checked: " + twin), std::string::npos);
}

// chromium for the browser test: $SIMREEL_CHROMIUM, else chromium or chromium-browser on PATH.
std::string find_chromium() {
  if (const char* e = std::getenv("SIMREEL_CHROMIUM"); e && *e) return e;
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');)
    for (const char* name : {"chromium", "chromium-browser"})
      if (!dir.empty() && fs::exists(fs::path(dir) / name)) return (fs::path(dir) / name).string();
  return "";
}

// The page's own self-test (app/report/report_page.hpp: images decoded, views, slider, blink,
// heat map boxes) run in headless chromium on a page written by check or diff; its result line.
std::string browser_selftest(const fs::path& page, const fs::path& work) {
  const std::string cmd = "timeout 90 '" + find_chromium() +
                          "' --headless=new --no-sandbox --disable-gpu --no-first-run --disable-extensions "
                          "--disable-dev-shm-usage --user-data-dir='" +
                          (work / "profile").string() + "' --virtual-time-budget=5000 --dump-dom 'file://" +
                          fs::absolute(page).string() + "#selftest' 2>/dev/null";
  FILE* p = popen(cmd.c_str(), "r");
  std::string dom;
  char buf[65536];
  for (size_t n; p && (n = fread(buf, 1, sizeof buf, p)) > 0;) dom.append(buf, n);
  if (p) pclose(p);
  const size_t b = dom.find("id=\"selftest-result\"");
  if (b == std::string::npos) return "no #selftest-result in the DOM";
  const size_t t = dom.find('>', b) + 1;
  return dom.substr(t, dom.find('<', t) - t);
}

// The synthetic page is tested in tests/app/report/report_test.cpp; here the pages check and diff write
// for a real failure (a colour change: expected, actual, diff image, clusters) pass the same test.
TEST(Check, RealReportsPassTheBrowserSelfTest) {
  if (find_chromium().empty()) GTEST_SKIP() << "chromium not found (.ci/setup installs it)";
  const fs::path base = simreel::test::scratch_dir();
  const std::string goldens = (base / "goldens").string();
  const std::string scene = write_scene(base / "a", scene_text());
  const std::string recolored = write_scene(base / "color", scene_text("0.5", "[0.2, 0.3, 0.8]"));
  ASSERT_EQ(run("check " + scene + " --goldens " + goldens + " --update missing --quiet").code, 0);
  const fs::path check_report = base / "check_report";
  Result r = run("check " + recolored + " --goldens " + goldens + " --update none --quiet --report " +
                 check_report.string());
  ASSERT_EQ(r.code, 1) << r.out;
  std::string result = browser_selftest(check_report / "index.html", base / "c");
  EXPECT_EQ(result.rfind("SELFTEST PASS (", 0), 0u) << result;

  const fs::path fa = base / "fa", fb = base / "fb", diff_report = base / "diff_report";
  ASSERT_EQ(run("render " + scene + " --no-video --quiet --frames 0:4 --frames-dir " + fa.string()).code, 0);
  ASSERT_EQ(run("render " + recolored + " --no-video --quiet --frames 2:6 --frames-dir " + fb.string()).code,
            0);
  r = run("diff " + fa.string() + " " + fb.string() + " --quiet --out " + diff_report.string());
  ASSERT_EQ(r.code, 1) << r.out;
  result = browser_selftest(diff_report / "index.html", base / "d");
  EXPECT_EQ(result.rfind("SELFTEST PASS (", 0), 0u) << result;
}

TEST(Check, BadInputExitsWith2) {
  const fs::path base = simreel::test::scratch_dir();
  const std::string scene = write_scene(base / "a", scene_text());
  EXPECT_EQ(run("check " + scene).code, 2) << "--goldens is required";
  EXPECT_EQ(run("check " + scene + " --goldens " + (base / "g").string() + " --update sometimes").code, 2);
  EXPECT_EQ(run("check " + scene + " --goldens " + (base / "g").string() + " --frames 5s").code, 2);
  EXPECT_EQ(run("check " + (base / "none.yaml").string() + " --goldens " + (base / "g").string()).code, 2);
  fs::create_directories(base / "g" / "drop");
  std::ofstream(base / "g" / "drop" / "manifest.json") << "{ not json";
  const Result r = run("check " + scene + " --goldens " + (base / "g").string() + " --update none");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.out.find("manifest.json"), std::string::npos) << r.out;
}

TEST(Diff, PngsFoldersAndVideos) {
  const fs::path base = simreel::test::scratch_dir();
  const std::string a = write_scene(base / "a", scene_text());
  const std::string b = write_scene(base / "b", scene_text("0.5", "[0.2, 0.3, 0.8]"));
  const fs::path fa = base / "fa", fb = base / "fb", fc = base / "fc";
  ASSERT_EQ(run("render " + a + " --no-video --quiet --frames-dir " + fa.string()).code, 0);
  ASSERT_EQ(run("render " + a + " --no-video --quiet --frames-dir " + fc.string()).code, 0);
  ASSERT_EQ(run("render " + b + " --no-video --quiet --frames-dir " + fb.string()).code, 0);
  // Identical folders and files: exit 0, infinite PSNR.
  Result r = run("diff " + fa.string() + " " + fc.string() + " --quiet");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("0 of 51 frames differ"), std::string::npos) << r.out;
  r = run("diff " + (fa / "frame_00030.png").string() + " " + (fc / "frame_00030.png").string());
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("PSNR inf"), std::string::npos) << r.out;
  // A colour change: exit 1, diff images and a report.
  const fs::path out = base / "out";
  r = run("diff " + fa.string() + " " + fb.string() + " --quiet --out " + out.string());
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_TRUE(fs::exists(out / "index.html"));
  int diffs = 0;
  for (const auto& e : fs::directory_iterator(out))
    diffs += e.path().filename().string().rfind("diff_", 0) == 0;
  EXPECT_GE(diffs, 1);
  // A missing frame is reported, not crashed on.
  fs::remove(fc / "frame_00050.png");
  r = run("diff " + fa.string() + " " + fc.string() + " --quiet");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("only in A"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("frame count"), std::string::npos) << r.out;

  // Videos, matched by timestamp: the same scene twice is the same; a shorter clip is a mismatch.
  const std::string va = (base / "a.mp4").string(), vb = (base / "b.mp4").string(),
                    vs = (base / "s.mp4").string();
  ASSERT_EQ(run("render " + a + " --quiet -o " + va).code, 0);
  ASSERT_EQ(run("render " + a + " --quiet -o " + vb).code, 0);
  ASSERT_EQ(run("render " + a + " --quiet --duration 1 -o " + vs).code, 0);
  r = run("diff " + va + " " + vb + " --quiet");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("0 of 51 frames differ"), std::string::npos) << r.out;
  r = run("diff " + va + " " + vs + " --quiet");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("frame count: 51 in A, 26 in B"), std::string::npos) << r.out;
  // A video against its own PNG frames: lossy H.264 against the exact frames, within the portable tolerance?
  // Not asserted: H.264 at CRF 20 is not noise-free. Bad input is exit 2.
  // A partial render is aligned by its timestamps: frames 10-14 of a lossless video (--crf 0)
  // are frames 10-14 of the full one, exactly; the frames before and after are runs only in A,
  // and the gap does not make a frame-rate mismatch.
  const std::string lf = (base / "lf.mp4").string(), lp = (base / "lp.mp4").string();
  ASSERT_EQ(run("render " + a + " --quiet --crf 0 -o " + lf).code, 0);
  ASSERT_EQ(run("render " + a + " --quiet --crf 0 --frames 10:14,40 -o " + lp).code, 0);
  r = run("diff " + lf + " " + lp + " --tolerance exact");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("0 of 6 frames differ"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("t=0.400s                 same"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("t=0.000s .. t=0.360s     only in A (10 frames)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("frame count: 51 in A, 6 in B"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("frame rate"), std::string::npos) << r.out;
  // Frames of different sizes: said, with no metrics of pixels never compared.
  const fs::path small = base / "small";
  ASSERT_EQ(run("render " + a + " --no-video --quiet --width 200 --height 100 --frames 30 --frames-dir " +
                small.string())
                .code,
            0);
  r = run("diff " + (fa / "frame_00030.png").string() + " " + (small / "frame_00030.png").string());
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("DIFF  size differs"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("PSNR"), std::string::npos) << r.out;
  EXPECT_EQ(run("diff " + va + " " + (base / "nothing.mp4").string()).code, 2);
  std::ofstream(base / "junk.mp4") << "not a video";
  EXPECT_EQ(run("diff " + va + " " + (base / "junk.mp4").string()).code, 2);
}

}  // namespace
