// The review report of `simreel check` / `simreel diff`: one self-contained HTML page
// (images as data: URIs, CSS and JS inline, nothing fetched) that a reviewer opens from a CI
// artifact. Failures first, each frame a card with the physics-versus-rendering attribution, the
// image metrics and a viewer (side by side, slider, blink, heat map with the cluster boxes).
//
// The page tests itself in a real browser when opened as index.html#selftest (see report_page.hpp
// and tests/app/report/report_test.cpp).
#pragma once
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace simreel {

struct ReportFrame {
  std::string scene;  // scene name
  int frame = 0;      // frame index; -1 for a moment between frames of the plan (shown by time only)
  double time = 0;    // s
  std::string label;  // how links name it ("" : "#frame", or "t=...s" for a moment between frames)
  // "pass", "fail", "new" (golden written), "missing" (no golden, not written), "updated"
  std::string status;
  // What changed: "" | "physics" | "rendering" | "size" (check) | "pixels" | "count" (diff: a
  // frame of only one side).
  std::string kind;
  std::vector<std::string> messages;  // e.g. "physics changed: body 'ball' position x by 0.05 m (rel 3.2e-2)"
  // Metrics. The doubles are NaN when not computed (no golden to compare with); the page then shows
  // no metrics table. The counts are shown only when diff_ratio is computed.
  long differing = 0, antialiased = 0;
  double diff_ratio = std::numeric_limits<double>::quiet_NaN();  // differing / (width * height)
  int largest_cluster = 0;                                       // pixels
  double psnr = std::numeric_limits<double>::quiet_NaN();        // dB, +inf when identical
  double ssim = std::numeric_limits<double>::quiet_NaN();
  struct Box {
    int x0, y0, x1, y1;  // pixels, inclusive, in the actual image
    int pixels;
  };
  std::vector<Box> clusters;
  int width = 0, height = 0;  // of the actual image (the expected one's when there is no actual)
  std::vector<uint8_t> expected_png, actual_png, diff_png;  // encoded PNG bytes; any may be empty
};

struct ReportInput {
  std::string title;           // "simreel check" / "simreel diff"
  std::string command;         // the exact command run
  std::string accept_command;  // the exact command that accepts the change (shown with a copy button)
  // key, value (renderer, GL version, llvmpipe width, CPU features, simreel version, scene hash ...)
  std::vector<std::pair<std::string, std::string>> golden_fingerprint, actual_fingerprint;
  std::vector<ReportFrame> frames;
  std::string summary;  // one line, e.g. "3 of 15 frames differ (2 physics, 1 rendering)"
  // What the two images are called on the cards (simreel diff: "A: old.mp4", "B: new.mp4").
  std::string expected_label = "Expected (golden)", actual_label = "Actual";
};

// The whole page as a string (write_report writes this).
std::string report_html(const ReportInput& in);

// Writes DIR/index.html (creating DIR); throws std::runtime_error naming the path on failure.
// Written to a temp file and renamed so a failed write leaves no half page.
std::string write_report(const std::string& dir, const ReportInput& in);  // returns the page's path

// &, <, >, " and ' as entities: safe in text and in attribute values (either quote).
std::string html_escape(const std::string&);
// RFC 4648 base64 with padding, no line breaks.
std::string base64(const std::vector<uint8_t>&);

}  // namespace simreel
