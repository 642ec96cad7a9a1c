// The review report of simreel check / diff (app/report/report.hpp): its text helpers, that the page
// is self-contained and escaped, and, in a real browser (Debian's chromium, headless), that the page
// works: its own #selftest drives the views, the slider and the blink as a user does, and a
// screenshot of it is not blank. The browser tests skip when chromium is not installed.
#include "app/report/report.hpp"

#include <gtest/gtest.h>
#include <png.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>

#include "tests/scratch.hpp"

namespace {

namespace fs = std::filesystem;
using simreel::ReportFrame;
using simreel::ReportInput;

// ---------------------------------------------------------------- hand-made frames

struct Rgb {
  int w, h;
  std::vector<uint8_t> px;  // RGB
  Rgb(int w_, int h_) : w(w_), h(h_), px(size_t(w_) * h_ * 3) {}
  uint8_t* at(int x, int y) { return &px[(size_t(y) * w + x) * 3]; }
};

std::vector<uint8_t> encode_png(const Rgb& img) {
  png_image im;
  std::memset(&im, 0, sizeof im);
  im.version = PNG_IMAGE_VERSION;
  im.width = img.w;
  im.height = img.h;
  im.format = PNG_FORMAT_RGB;
  png_alloc_size_t size = 0;
  EXPECT_TRUE(png_image_write_to_memory(&im, nullptr, &size, 0, img.px.data(), 0, nullptr));
  std::vector<uint8_t> out(size);
  EXPECT_TRUE(png_image_write_to_memory(&im, out.data(), &size, 0, img.px.data(), 0, nullptr));
  out.resize(size);
  return out;
}

// A sky, a floor, a soft-edged ball at (bx, by) and a box; box_red tints the box (a "shader change").
Rgb scene_image(int w, int h, double bx, double by, int box_red = 90) {
  Rgb img(w, h);
  const double r = h * 0.16;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      uint8_t* p = img.at(x, y);
      const bool floor = y > h * 0.72;
      p[0] = floor ? 120 : uint8_t(170 + 60 * y / h);
      p[1] = floor ? 110 : uint8_t(195 + 40 * y / h);
      p[2] = floor ? 100 : 235;
      if (x > w * 0.62 && x < w * 0.82 && y > h * 0.40 && !floor)
        p[0] = uint8_t(box_red), p[1] = 70, p[2] = 160;
      // Coverage of the ball's edge: the anti-aliased ring the metrics call "AA".
      const double cover = std::clamp(r + 0.5 - std::hypot(x + 0.5 - bx, y + 0.5 - by), 0.0, 1.0);
      const uint8_t ball[3] = {225, 85, 40};
      for (int c = 0; c < 3; ++c) p[c] = uint8_t(std::lround(p[c] * (1 - cover) + ball[c] * cover));
    }
  }
  return img;
}

// Differing pixels red, small differences yellow (as if anti-aliasing), the rest the expected image
// dimmed; the clusters are the boxes of the red pixels left and right of split_x.
struct Diff {
  Rgb img;
  long differing = 0, antialiased = 0;
  std::vector<ReportFrame::Box> clusters;
};
Diff diff_image(Rgb& exp, Rgb& act, int split_x) {
  Diff d{Rgb(exp.w, exp.h), 0, 0, {}};
  ReportFrame::Box boxes[2] = {{1 << 30, 1 << 30, -1, -1, 0}, {1 << 30, 1 << 30, -1, -1, 0}};
  for (int y = 0; y < exp.h; ++y) {
    for (int x = 0; x < exp.w; ++x) {
      const uint8_t *e = exp.at(x, y), *a = act.at(x, y);
      int delta = 0;
      for (int c = 0; c < 3; ++c) delta += std::abs(e[c] - a[c]);
      uint8_t* p = d.img.at(x, y);
      if (delta >= 40) {
        p[0] = 255, p[1] = 0, p[2] = 0;
        ++d.differing;
        ReportFrame::Box& b = boxes[x >= split_x];
        b.x0 = std::min(b.x0, x), b.y0 = std::min(b.y0, y), b.x1 = std::max(b.x1, x),
        b.y1 = std::max(b.y1, y);
        ++b.pixels;
      } else if (delta > 0) {
        p[0] = 255, p[1] = 255, p[2] = 0;
        ++d.antialiased;
      } else {
        const uint8_t g = uint8_t(40 + (e[0] + e[1] + e[2]) / 9);
        p[0] = p[1] = p[2] = g;
      }
    }
  }
  for (const ReportFrame::Box& b : boxes)
    if (b.pixels > 0) d.clusters.push_back(b);
  return d;
}

const char* kHostile = "ball <drop> & \"co\"'s";

// Seven frames, in no particular order: one of each status and kind, with and without images.
ReportInput sample() {
  const int w = 160, h = 90;
  ReportInput in;
  in.title = "simreel check";
  in.command = "simreel check scenes/ --golden golden/ --report out/report";
  in.accept_command = "simreel check scenes/ --golden golden/ --accept 'ball <drop>'";
  in.summary = "3 of 7 frames differ (1 physics, 1 rendering, 1 size)";
  in.golden_fingerprint = {{"simreel version", "0.1.0"},
                           {"renderer", "llvmpipe (LLVM 15.0.6, 256 bits)"},
                           {"GL version", "4.5 (Core Profile) Mesa 22.3.6"},
                           {"scene hash", "1f2e3d"},
                           {"CPU features", "sse4.2 avx2"}};
  in.actual_fingerprint = {{"simreel version", "0.1.0"},
                           {"renderer", "llvmpipe (LLVM 15.0.6, 128 bits)"},
                           {"GL version", "4.5 (Core Profile) Mesa 22.3.6"},
                           {"scene hash", "1f2e3d"},
                           {"note", "<script>alert(1)</script>"}};

  Rgb exp = scene_image(w, h, 50, 40), same = scene_image(w, h, 50, 40);
  ReportFrame pass;
  pass.scene = kHostile;
  pass.frame = 0;
  pass.status = "pass";
  pass.diff_ratio = 0;
  pass.psnr = std::numeric_limits<double>::infinity();
  pass.ssim = 1;
  pass.width = w, pass.height = h;
  pass.expected_png = encode_png(exp);
  pass.actual_png = encode_png(same);  // the same bytes: embedded once
  in.frames.push_back(pass);

  ReportFrame added;
  added.scene = "ramp";
  added.frame = 0;
  added.status = "new";
  added.width = w, added.height = h;
  added.actual_png = encode_png(scene_image(w, h, 30, 30));
  in.frames.push_back(added);

  Rgb moved_exp = scene_image(w, h, 50, 52), moved_act = scene_image(w, h, 62, 55);
  Diff d = diff_image(moved_exp, moved_act, 56);
  ReportFrame physics;
  physics.scene = kHostile;
  physics.frame = 12;
  physics.time = 0.4;
  physics.status = "fail";
  physics.kind = "physics";
  physics.messages = {"physics changed: body 'ball' position x by 0.05 m (rel 3.2e-2)",
                      "physics changed: body '<b>' velocity z by 0.2 m/s"};
  physics.differing = d.differing;
  physics.antialiased = d.antialiased;
  physics.diff_ratio = double(d.differing) / (w * h);
  physics.clusters = d.clusters;
  for (const auto& b : d.clusters) physics.largest_cluster = std::max(physics.largest_cluster, b.pixels);
  physics.psnr = 21.37;
  physics.ssim = 0.9412;
  physics.width = w, physics.height = h;
  physics.expected_png = encode_png(moved_exp);
  physics.actual_png = encode_png(moved_act);
  physics.diff_png = encode_png(d.img);
  in.frames.push_back(physics);

  ReportFrame missing;
  missing.scene = "tower";
  missing.frame = 30;
  missing.time = 1.0;
  missing.status = "missing";
  missing.width = w, missing.height = h;
  missing.actual_png = encode_png(scene_image(w, h, 120, 20));
  in.frames.push_back(missing);

  Rgb tint_exp = scene_image(w, h, 40, 60), tint_act = scene_image(w, h, 40, 60, 140);
  Diff t = diff_image(tint_exp, tint_act, w);
  ReportFrame rendering;
  rendering.scene = "tower";
  rendering.frame = 3;
  rendering.time = 0.1;
  rendering.status = "fail";
  rendering.kind = "rendering";
  rendering.messages = {"rendering changed: physics identical, 1 cluster"};
  rendering.differing = t.differing;
  rendering.diff_ratio = double(t.differing) / (w * h);
  rendering.clusters = t.clusters;
  rendering.largest_cluster = t.clusters.empty() ? 0 : t.clusters[0].pixels;
  rendering.psnr = 30.5;
  rendering.ssim = 0.98;
  rendering.width = w, rendering.height = h;
  rendering.expected_png = encode_png(tint_exp);
  rendering.actual_png = encode_png(tint_act);
  rendering.diff_png = encode_png(t.img);
  in.frames.push_back(rendering);

  ReportFrame size;
  size.scene = "dominoes";
  size.frame = 5;
  size.time = 0.2;
  size.status = "fail";
  size.kind = "size";
  size.messages = {"size changed: 160x90 golden, 128x72 actual"};
  size.width = 128, size.height = 72;
  size.expected_png = encode_png(scene_image(w, h, 80, 40));
  size.actual_png = encode_png(scene_image(128, 72, 64, 32));
  in.frames.push_back(size);

  ReportFrame updated;
  updated.scene = "spinner";
  updated.frame = 1;
  updated.time = 0.05;
  updated.status = "updated";
  in.frames.push_back(updated);
  return in;
}

size_t count(const std::string& s, const std::string& what) {
  size_t n = 0;
  for (size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + what.size())) ++n;
  return n;
}

// The card of frame index i (its position in ReportInput::frames).
std::string card(const std::string& html, size_t i) {
  const size_t b = html.find("id=\"f" + std::to_string(i) + "\"");
  if (b == std::string::npos) return "";
  return html.substr(b, html.find("</article>", b) - b);
}

// ---------------------------------------------------------------- text helpers

TEST(ReportText, HtmlEscape) {
  EXPECT_EQ(simreel::html_escape("plain text 1.5 m/s"), "plain text 1.5 m/s");
  EXPECT_EQ(simreel::html_escape("<a href=\"x\">&'"), "&lt;a href=&quot;x&quot;&gt;&amp;&#39;");
  EXPECT_EQ(simreel::html_escape("&amp;"), "&amp;amp;");  // not "already escaped"
  EXPECT_EQ(simreel::html_escape(""), "");
  EXPECT_EQ(simreel::html_escape("\xc3\xa9\xe2\x88\x9e"), "\xc3\xa9\xe2\x88\x9e");  // UTF-8 passes through
}

TEST(ReportText, Base64Rfc4648) {
  auto b64 = [](const std::string& s) { return simreel::base64(std::vector<uint8_t>(s.begin(), s.end())); };
  // RFC 4648 section 10.
  EXPECT_EQ(b64(""), "");
  EXPECT_EQ(b64("f"), "Zg==");
  EXPECT_EQ(b64("fo"), "Zm8=");
  EXPECT_EQ(b64("foo"), "Zm9v");
  EXPECT_EQ(b64("foob"), "Zm9vYg==");
  EXPECT_EQ(b64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(b64("foobar"), "Zm9vYmFy");
  // The alphabet's last two characters, and bytes >= 128.
  EXPECT_EQ(simreel::base64({0xfb}), "+w==");
  EXPECT_EQ(simreel::base64({0xff, 0xfe}), "//4=");
  EXPECT_EQ(simreel::base64({0x00, 0x10, 0x83, 0x10, 0x51, 0x87}), "ABCDEFGH");
  std::vector<uint8_t> all(256);
  for (int i = 0; i < 256; ++i) all[i] = uint8_t(i);
  const std::string s = simreel::base64(all);
  EXPECT_EQ(s.size(), 344u);
  EXPECT_EQ(s.substr(0, 8), "AAECAwQF");
  EXPECT_EQ(s.substr(s.size() - 8), "/P3+/w==");
}

// ---------------------------------------------------------------- the page, as text

TEST(ReportPage, SelfContained) {
  const std::string html = simreel::report_html(sample());
  EXPECT_EQ(html.find("http://"), std::string::npos);
  EXPECT_EQ(html.find("https://"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(html.find("@import"), std::string::npos);
  EXPECT_EQ(html.find("url("), std::string::npos);
  EXPECT_EQ(html.find("srcset"), std::string::npos);
  EXPECT_EQ(html.find("<iframe"), std::string::npos);
  EXPECT_EQ(count(html, "<script"), 1u);  // the inline one
  EXPECT_NE(html.find("<script>"), std::string::npos);
  size_t srcs = 0;
  for (size_t p = html.find("src=\""); p != std::string::npos; p = html.find("src=\"", p + 1), ++srcs)
    EXPECT_EQ(html.compare(p, 27, "src=\"data:image/png;base64,"), 0) << html.substr(p, 60);
  EXPECT_EQ(srcs, 11u);  // every image once: pass 1 (same bytes), new 1, physics 3, missing 1, tint 3, size 2
  EXPECT_EQ(count(html, "data:image/png;base64,"), 11u);
  EXPECT_NE(html.find("Content-Security-Policy"), std::string::npos);
}

TEST(ReportPage, EscapesEverything) {
  const std::string html = simreel::report_html(sample());
  EXPECT_EQ(html.find("<drop>"), std::string::npos);
  EXPECT_EQ(html.find("<b>"), std::string::npos);
  EXPECT_EQ(html.find("<script>alert"), std::string::npos);
  EXPECT_NE(html.find("ball &lt;drop&gt; &amp; &quot;co&quot;&#39;s"), std::string::npos);
  EXPECT_NE(html.find("&lt;script&gt;alert(1)&lt;/script&gt;"), std::string::npos);
  EXPECT_NE(html.find("--accept &#39;ball &lt;drop&gt;&#39;"), std::string::npos);
}

TEST(ReportPage, FailuresFirstPassesCollapsed) {
  const std::string html = simreel::report_html(sample());
  auto at = [&](size_t i) { return html.find("id=\"f" + std::to_string(i) + "\""); };
  // Failures in input order (physics 2, rendering 4, size 5), then missing 3, new 1, updated 6, pass 0.
  const size_t order[] = {2, 4, 5, 3, 1, 6, 0};
  for (size_t k = 0; k + 1 < std::size(order); ++k) {
    ASSERT_NE(at(order[k]), std::string::npos);
    EXPECT_LT(at(order[k]), at(order[k + 1])) << "frame " << order[k] << " before " << order[k + 1];
  }
  const size_t details = html.find("<details");
  ASSERT_NE(details, std::string::npos);
  EXPECT_LT(at(6), details);
  EXPECT_LT(details, at(0));
  EXPECT_EQ(html.find("<details open"), std::string::npos);
  EXPECT_NE(html.find("3 of 7 frames differ (1 physics, 1 rendering, 1 size)"), std::string::npos);
  EXPECT_NE(html.find("<button data-copy=\"cmd-accept\">"), std::string::npos);
}

TEST(ReportPage, CardsAttributeAndMeasure) {
  const std::string html = simreel::report_html(sample());
  const std::string physics = card(html, 2), rendering = card(html, 4), size = card(html, 5);
  const std::string added = card(html, 1), pass = card(html, 0), updated = card(html, 6);
  EXPECT_NE(physics.find("Physics changed"), std::string::npos);
  EXPECT_NE(physics.find("body &#39;ball&#39; position x by 0.05 m"), std::string::npos);
  EXPECT_NE(physics.find("frame 12 &middot; t = 0.400 s"), std::string::npos);
  EXPECT_NE(physics.find("badge st-fail"), std::string::npos);
  EXPECT_NE(physics.find("21.37 dB"), std::string::npos);
  EXPECT_NE(physics.find("0.9412"), std::string::npos);
  EXPECT_NE(physics.find("data-clusters=\"2\""), std::string::npos);
  EXPECT_EQ(count(physics, "<rect "), 2u);
  EXPECT_NE(physics.find("viewBox=\"0 0 160 90\""), std::string::npos);
  EXPECT_NE(rendering.find("Rendering changed"), std::string::npos);
  EXPECT_EQ(rendering.find("Physics changed"), std::string::npos);
  EXPECT_NE(size.find("Image size changed"), std::string::npos);
  EXPECT_NE(size.find("data-w=\"128\" data-h=\"72\""), std::string::npos);  // from the PNG header
  EXPECT_NE(pass.find("&infin; dB"), std::string::npos);
  EXPECT_NE(pass.find("badge st-pass"), std::string::npos);
  EXPECT_EQ(added.find("class=\"metrics\""), std::string::npos);  // NaN metrics: no table
  EXPECT_NE(added.find("No image: Expected (golden)"), std::string::npos);
  EXPECT_NE(updated.find("No images for this frame"), std::string::npos);
  EXPECT_EQ(updated.find("class=\"viewer\""), std::string::npos);
}

// simreel diff's kinds: two renders compared have no physics to blame, and a frame of one side
// only is no size change; its images are A and B, not golden and actual. The jump links can wrap
// (a space between them).
TEST(ReportPage, DiffKindsAndJumpLinks) {
  ReportInput in;
  for (const char* kind : {"pixels", "count", "pixels"}) {
    ReportFrame f;
    f.scene = std::string("t=1.000s ") + kind;
    f.status = "fail";
    f.kind = kind;
    in.frames.push_back(f);
  }
  in.frames[2].expected_png = in.frames[2].actual_png = encode_png(scene_image(16, 9, 4, 4));
  in.expected_label = "A: old <1>.mp4";
  in.actual_label = "B: new.mp4";
  const std::string html = simreel::report_html(in);
  EXPECT_NE(card(html, 2).find("<figcaption>A: old &lt;1&gt;.mp4</figcaption>"), std::string::npos);
  EXPECT_NE(card(html, 2).find("data-actual=\"B: new.mp4\""), std::string::npos);
  EXPECT_EQ(card(html, 2).find("golden"), std::string::npos);
  EXPECT_NE(card(html, 0).find("Pixels differ"), std::string::npos);
  EXPECT_EQ(card(html, 0).find("simulation"), std::string::npos);
  EXPECT_NE(card(html, 1).find("Frame on one side only"), std::string::npos);
  EXPECT_EQ(card(html, 1).find("size"), std::string::npos);
  EXPECT_NE(html.find("#0</a> <a href=\"#f1\">"), std::string::npos);
}

TEST(ReportPage, FingerprintsSideBySide) {
  const std::string html = simreel::report_html(sample());
  // renderer and the two keys only one side has differ; version, GL version and scene hash agree.
  EXPECT_NE(html.find("data-differ=\"3\""), std::string::npos);
  EXPECT_EQ(count(html, "<tr class=\"differ\">"), 3u);
  EXPECT_NE(html.find("3 keys differ between the golden and this run (renderer, CPU features, note)"),
            std::string::npos);
  EXPECT_NE(html.find("<tr class=\"differ\"><th>renderer</th><td>llvmpipe (LLVM 15.0.6, 256 bits)</td>"
                      "<td>llvmpipe (LLVM 15.0.6, 128 bits)</td></tr>"),
            std::string::npos);
  EXPECT_NE(html.find("<tr><th>scene hash</th><td>1f2e3d</td><td>1f2e3d</td></tr>"), std::string::npos);
  EXPECT_NE(html.find("<th>CPU features</th><td>sse4.2 avx2</td><td class=\"absent\">absent</td>"),
            std::string::npos);
}

TEST(ReportPage, EmptyInputStillAPage) {
  const std::string html = simreel::report_html(ReportInput{});
  EXPECT_NE(html.find("No frames were compared."), std::string::npos);
  EXPECT_NE(html.find("No fingerprint recorded."), std::string::npos);
  EXPECT_NE(html.find("</html>"), std::string::npos);
}

// ---------------------------------------------------------------- writing

std::string read_file(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

TEST(ReportWrite, CreatesTheFolderAndLeavesNoTemp) {
  const fs::path dir = simreel::test::scratch_dir() / "out" / "report";
  const ReportInput in = sample();
  const std::string page = simreel::write_report(dir.string(), in);
  EXPECT_EQ(fs::path(page), dir / "index.html");
  EXPECT_EQ(read_file(page), simreel::report_html(in));
  simreel::write_report(dir.string(), in);  // over an existing page
  size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    ++files;
    EXPECT_EQ(e.path().filename(), "index.html");
  }
  EXPECT_EQ(files, 1u);
}

TEST(ReportWrite, FailuresNameThePath) {
  const fs::path file = simreel::test::scratch("a-file");
  std::ofstream(file) << "x";
  try {
    simreel::write_report((file / "report").string(), sample());
    ADD_FAILURE() << "no error for a folder under a file";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find((file / "report").string()), std::string::npos) << e.what();
  }
  // index.html is a folder: the rename fails, and the temp file is gone.
  const fs::path dir = simreel::test::scratch_dir() / "blocked";
  fs::create_directories(dir / "index.html" / "x");
  try {
    simreel::write_report(dir.string(), sample());
    ADD_FAILURE() << "no error when index.html is a folder";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "index.html").string()), std::string::npos) << e.what();
  }
  size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    ++entries;
    EXPECT_EQ(e.path().filename(), "index.html");
  }
  EXPECT_EQ(entries, 1u);
}

// ---------------------------------------------------------------- in a real browser

// chromium: $SIMREEL_CHROMIUM, else what CMake found, else chromium or chromium-browser on PATH.
std::string chromium() {
  if (const char* e = std::getenv("SIMREEL_CHROMIUM"); e && *e) return e;
  if (std::string p = SIMREEL_CHROMIUM; !p.empty() && access(p.c_str(), X_OK) == 0) return p;
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    for (const char* name : {"chromium", "chromium-browser"}) {
      const std::string p = dir + "/" + name;
      if (!dir.empty() && access(p.c_str(), X_OK) == 0) return p;
    }
  }
  return "";
}

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string file_url(const fs::path& p) {
  std::string url = "file://";
  for (unsigned char c : fs::absolute(p).string()) {
    if (std::isalnum(c) || std::strchr("/-._~", c)) {
      url += char(c);
    } else {
      char buf[4];
      std::snprintf(buf, sizeof buf, "%%%02X", c);
      url += buf;
    }
  }
  return url;
}

struct Browser {
  int code = -1;
  std::string out;  // stdout (--dump-dom: the DOM)
  std::string log;  // stderr
};

// Headless chromium with a profile of its own (ctest -j runs tests side by side), at most 90 s.
Browser run_chromium(const std::string& args, const fs::path& work) {
  const fs::path log = work / "chromium.log";
  const std::string cmd =
      "timeout 90 " + quote(chromium()) +
      " --headless=new --no-sandbox --disable-gpu --no-first-run --no-default-browser-check"
      " --disable-extensions --disable-dev-shm-usage --hide-scrollbars --user-data-dir=" +
      quote((work / "profile").string()) + " " + args + " 2>" + quote(log.string());
  Browser b;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return b;
  char buf[65536];
  for (size_t n; (n = fread(buf, 1, sizeof buf, p)) > 0;) b.out.append(buf, n);
  const int st = pclose(p);
  b.code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  b.log = read_file(log);
  return b;
}

// The text of #selftest-result in a dumped DOM ("" if absent).
std::string selftest_result(const std::string& dom) {
  const size_t id = dom.find("id=\"selftest-result\"");
  if (id == std::string::npos) return "";
  const size_t open = dom.find('>', id), close = dom.find("</div>", id);
  if (open == std::string::npos || close == std::string::npos || close < open) return "";
  return dom.substr(open + 1, close - open - 1);
}

std::string selftest(const std::string& html, const fs::path& work) {
  fs::create_directories(work);
  std::ofstream(work / "index.html", std::ios::binary) << html;
  const Browser b = run_chromium(
      "--virtual-time-budget=5000 --dump-dom " + quote(file_url(work / "index.html") + "#selftest"), work);
  const std::string r = selftest_result(b.out);
  if (r.rfind("SELFTEST PASS", 0) != 0)
    std::cerr << "chromium exit " << b.code << ", log (last 2000 bytes):\n"
              << b.log.substr(b.log.size() > 2000 ? b.log.size() - 2000 : 0) << "\n";
  return r;
}

// Skips when there is no browser: CI installs chromium (.ci/setup), so there it runs.
#define REQUIRE_CHROMIUM()                                                         \
  if (const std::string c = chromium(); c.empty() || access(c.c_str(), X_OK) != 0) \
  GTEST_SKIP() << "chromium not found (" << (c.empty() ? "not on PATH" : c)        \
               << "; .ci/setup installs it, SIMREEL_CHROMIUM names another): browser test skipped"

TEST(ReportBrowser, SelfTestPasses) {
  REQUIRE_CHROMIUM();
  const fs::path dir = simreel::test::scratch_dir() / "report";
  const std::string page = simreel::write_report(dir.string(), sample());
  const Browser b =
      run_chromium("--virtual-time-budget=5000 --dump-dom " + quote(file_url(page) + "#selftest"), dir);
  const std::string r = selftest_result(b.out);
  EXPECT_EQ(r.rfind("SELFTEST PASS (", 0), 0u)
      << "result: '" << r << "'\nchromium exit " << b.code << ", log:\n"
      << b.log;
  std::cout << "[ selftest ] " << r << "\n";
  // The hostile scene name is text in the DOM, not markup.
  EXPECT_NE(b.out.find("ball &lt;drop&gt; &amp; \"co\"'s"), std::string::npos);
  EXPECT_EQ(b.out.find("<drop>"), std::string::npos);
}

// The self-test must be able to fail: a broken slider, a broken image, a broken script.
TEST(ReportBrowser, SelfTestCatchesBreakage) {
  REQUIRE_CHROMIUM();
  const std::string html = simreel::report_html(sample());
  auto broken = [&](const std::string& from, const std::string& to) {
    std::string h = html;
    const size_t p = h.find(from);
    EXPECT_NE(p, std::string::npos) << from;
    if (p != std::string::npos) h.replace(p, from.size(), to);
    return h;
  };
  const fs::path work = simreel::test::scratch_dir();
  // The slider's clip element renamed (as by a wrong id or class in the slider code).
  std::string clip = html;
  for (size_t p; (p = clip.find("<div class=\"clip\">")) != std::string::npos;)
    clip.replace(p, 18, "<div class=\"clop\">");
  const std::string r1 = selftest(clip, work / "slider");
  EXPECT_EQ(r1.rfind("SELFTEST FAIL: ", 0), 0u) << r1;
  EXPECT_NE(r1.find("slider"), std::string::npos) << r1;

  const std::string r2 =
      selftest(broken("data:image/png;base64,iVBOR", "data:image/png;base64,AAAAA"), work / "img");
  EXPECT_EQ(r2.rfind("SELFTEST FAIL: image not loaded", 0), 0u) << r2;

  const std::string r3 =
      selftest(broken("s.classList.toggle('show-expected', expected);", ""), work / "blink");
  EXPECT_EQ(r3.rfind("SELFTEST FAIL: ", 0), 0u) << r3;

  // A syntax error: the script never runs, the result stays as written.
  const std::string r4 =
      selftest(broken("function setView(v, name) {", "function setView(v, name) {{"), work / "js");
  EXPECT_EQ(r4, "SELFTEST NOT RUN");
}

struct Decoded {
  int w = 0, h = 0;
  std::vector<uint8_t> rgba;
};
Decoded decode_png(const std::string& path) {
  Decoded d;
  png_image im;
  std::memset(&im, 0, sizeof im);
  im.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&im, path.c_str())) return d;
  im.format = PNG_FORMAT_RGBA;
  d.rgba.resize(PNG_IMAGE_SIZE(im));
  if (!png_image_finish_read(&im, nullptr, d.rgba.data(), 0, nullptr)) return Decoded{};
  d.w = int(im.width);
  d.h = int(im.height);
  return d;
}

TEST(ReportBrowser, ScreenshotIsAPage) {
  REQUIRE_CHROMIUM();
  const fs::path dir = simreel::test::scratch_dir() / "report";
  const std::string page = simreel::write_report(dir.string(), sample());
  const fs::path shot = simreel::test::scratch_dir() / "screenshot.png";
  const Browser b =
      run_chromium("--virtual-time-budget=2000 --window-size=1280,1600 --screenshot=" + quote(shot.string()) +
                       " " + quote(file_url(page)),
                   dir);
  ASSERT_TRUE(fs::exists(shot)) << "chromium exit " << b.code << ", log:\n" << b.log;
  std::cout << "[ screenshot ] " << shot.string() << "\n";
  EXPECT_GT(fs::file_size(shot), 10000u);
  const Decoded d = decode_png(shot.string());
  ASSERT_EQ(d.w, 1280);
  ASSERT_EQ(d.h, 1600);
  std::map<uint32_t, long> colours;
  for (size_t i = 0; i < d.rgba.size(); i += 4)
    ++colours[uint32_t(d.rgba[i]) << 16 | uint32_t(d.rgba[i + 1]) << 8 | d.rgba[i + 2]];
  long most = 0;
  for (const auto& [c, n] : colours) most = std::max(most, n);
  EXPECT_GT(colours.size(), 200u);                   // text, badges and images, not one flat colour
  EXPECT_LT(double(most) / (long(d.w) * d.h), 0.9);  // the background is not everything
  // The red of the failure badge and the page's images are there: some strongly red pixels.
  long red = 0;
  for (size_t i = 0; i < d.rgba.size(); i += 4)
    red += d.rgba[i] > 150 && d.rgba[i + 1] < 80 && d.rgba[i + 2] < 80;
  EXPECT_GT(red, 100);
}

}  // namespace
