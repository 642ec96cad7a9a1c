#include "app/report/report.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include "app/report/report_page.hpp"

namespace simreel {

std::string html_escape(const std::string& s) {
  std::string out;
  out.reserve(s.size() + s.size() / 8);
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string base64(const std::vector<uint8_t>& in) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 3 <= in.size(); i += 3) {
    const uint32_t v = uint32_t(in[i]) << 16 | uint32_t(in[i + 1]) << 8 | in[i + 2];
    out += kAlphabet[v >> 18];
    out += kAlphabet[v >> 12 & 63];
    out += kAlphabet[v >> 6 & 63];
    out += kAlphabet[v & 63];
  }
  if (const size_t rest = in.size() - i; rest > 0) {
    const uint32_t v = uint32_t(in[i]) << 16 | (rest == 2 ? uint32_t(in[i + 1]) << 8 : 0);
    out += kAlphabet[v >> 18];
    out += kAlphabet[v >> 12 & 63];
    out += rest == 2 ? kAlphabet[v >> 6 & 63] : '=';
    out += '=';
  }
  return out;
}

namespace {

template <class... A>
std::string fmt(const char* f, A... a) {
  char buf[128];
  const int n = std::snprintf(buf, sizeof buf, f, a...);
  return std::string(buf, n < 0 ? 0 : std::min<size_t>(size_t(n), sizeof buf - 1));
}

std::string grouped(long n) {  // 1234567 -> "1,234,567"
  std::string d = std::to_string(n < 0 ? -n : n), out;
  for (size_t i = 0; i < d.size(); ++i) {
    if (i > 0 && (d.size() - i) % 3 == 0) out += ',';
    out += d[i];
  }
  return (n < 0 ? "-" : "") + out;
}

// Order of the page's sections: failures (and any status this code does not know), missing goldens,
// new or updated goldens, passes.
int rank(const std::string& status) {
  if (status == "missing") return 1;
  if (status == "new" || status == "updated") return 2;
  if (status == "pass") return 3;
  return 0;
}

bool known_status(const std::string& s) {
  return s == "pass" || s == "fail" || s == "new" || s == "missing" || s == "updated";
}

std::string badge(const std::string& status) {
  const std::string cls = known_status(status) ? status : "fail";
  return "<span class=\"badge st-" + cls + "\">" + html_escape(status.empty() ? "?" : status) + "</span>";
}

// Width and height from a PNG's IHDR chunk, so each image is laid out at its own size before it
// loads (and the self-test can check what the browser decoded).
bool png_size(const std::vector<uint8_t>& p, int& w, int& h) {
  static const uint8_t kSig[8] = {137, 80, 78, 71, 13, 10, 26, 10};
  if (p.size() < 24 || std::memcmp(p.data(), kSig, 8) != 0 || std::memcmp(p.data() + 12, "IHDR", 4) != 0)
    return false;
  auto be32 = [&](size_t o) {
    return uint32_t(p[o]) << 24 | uint32_t(p[o + 1]) << 16 | uint32_t(p[o + 2]) << 8 | p[o + 3];
  };
  const uint32_t pw = be32(16), ph = be32(20);
  if (pw == 0 || ph == 0 || pw > (1u << 20) || ph > (1u << 20)) return false;
  w = int(pw);
  h = int(ph);
  return true;
}

// One image of a frame: where its bytes are embedded (id) and how big it is.
struct Image {
  const std::vector<uint8_t>* png = nullptr;
  std::string id;     // of the side-by-side <img> that carries the data: URI
  std::string alias;  // when the bytes equal another image's: that image's id (embedded once)
  std::string alt;
  int w = 0, h = 0;
  bool present() const { return png && !png->empty(); }
};

std::string pct(double part, double whole) {
  return fmt("%.6g", whole > 0 ? 100.0 * part / whole : 100.0);
}

// An <img> layer of a stage stage_w pixels wide. embed: this is the element carrying the data.
std::string layer(const Image& im, int stage_w, const std::string& cls, bool embed) {
  std::string s = "<img class=\"layer " + cls + "\" alt=\"" + im.alt + "\" draggable=\"false\"";
  s += " data-w=\"" + std::to_string(im.w) + "\" data-h=\"" + std::to_string(im.h) + "\"";
  s += " style=\"width:" + pct(im.w, stage_w) + "cqw\"";
  if (embed && im.alias.empty()) {
    s += " id=\"" + im.id + "\" src=\"data:image/png;base64," + base64(*im.png) + "\">";
  } else {
    s += " data-same=\"" + (im.alias.empty() ? im.id : im.alias) + "\">";
  }
  return s;
}

std::string stage_style(int w, int h) {
  return " style=\"--w:" + std::to_string(w) + ";--h:" + std::to_string(h) + "\"";
}

std::string placeholder(const std::string& text, int w, int h) {
  return "<div class=\"noimg\"" + stage_style(w, h) + ">" + text + "</div>";
}

std::string figure(const std::string& caption, const Image& im, const std::string& cls,
                   const std::string& none, int fw, int fh) {
  std::string s = "<figure><figcaption>" + caption + "</figcaption>";
  if (im.present()) {
    s += "<div class=\"stage\"" + stage_style(im.w, im.h) + ">" + layer(im, im.w, cls, true) + "</div>";
  } else {
    s += placeholder(none, fw, fh);
  }
  return s + "</figure>";
}

std::string viewer(const ReportFrame& f, const Image& exp, const Image& act, const Image& dif,
                   const ReportInput& in) {
  const std::string el = html_escape(in.expected_label), al = html_escape(in.actual_label);
  const int fw = std::max({exp.w, act.w, dif.w}), fh = std::max({exp.h, act.h, dif.h});
  std::string s = "<div class=\"viewer\" data-view=\"side\" data-flips=\"0\">";
  s += "<div class=\"tabs seg\" role=\"tablist\">";
  const char* tabs[4][2] = {
      {"side", "Side by side"}, {"slider", "Slider"}, {"blink", "Blink"}, {"heat", "Heat map"}};
  for (int i = 0; i < 4; ++i) {
    s += fmt(
        "<button class=\"tab\" role=\"tab\" data-view=\"%s\" aria-selected=\"%s\"><kbd>%d</kbd> %s</button>",
        tabs[i][0], i == 0 ? "true" : "false", i + 1, tabs[i][1]);
  }
  s += "</div>";

  // 1: side by side. These three <img> carry the data: URIs.
  s += "<div class=\"view\" data-view=\"side\"><div class=\"sbs\">";
  s += figure(el, exp, "expected", "No image: " + el, fw, fh);
  s += figure(al, act, "actual", "No image: " + al, fw, fh);
  s += figure("Difference", dif, "diff", "No difference image", fw, fh);
  s += "</div></div>";

  // 2: slider and 3: blink, the actual image over the expected one on a stage big enough for both.
  const bool both = exp.present() && act.present();
  const int sw = std::max(exp.w, act.w), sh = std::max(exp.h, act.h);
  const std::string need_both = "Needs both images: " + el + " and " + al;
  s += "<div class=\"view\" data-view=\"slider\" hidden>";
  if (both) {
    s += "<div class=\"stage slider-stage\"" + stage_style(sw, sh) + ">" + layer(exp, sw, "expected", false);
    s += "<div class=\"clip\">" + layer(act, sw, "actual", false) +
         "</div><div class=\"divider\"></div></div>";
    s += "<input class=\"range\" type=\"range\" min=\"0\" max=\"100\" step=\"0.1\" value=\"50\""
         " aria-label=\"Divider position\"" +
         stage_style(sw, sh) + ">";
    s += "<p class=\"caption\">Drag across the image or the bar: " + al + " on the left of the divider, " +
         el + " on the right</p>";
  } else {
    s += placeholder(need_both, fw, fh);
  }
  s += "</div>";

  s += "<div class=\"view\" data-view=\"blink\" hidden>";
  if (both) {
    s += "<div class=\"stage blink-stage show-expected\"" + stage_style(sw, sh) + ">" +
         layer(exp, sw, "expected", false) + layer(act, sw, "actual", false) + "</div>";
    s += "<div class=\"caption\"><span class=\"blink-label\" data-expected=\"" + el + "\" data-actual=\"" +
         al + "\">" + el +
         "</span>"
         "<button class=\"flip\">Flip</button>"
         "<label><input class=\"blink-auto\" type=\"checkbox\" checked> Alternate every 500 ms</label></div>";
  } else {
    s += placeholder(need_both, fw, fh);
  }
  s += "</div>";

  // 4: the difference heat map, with the clusters' boxes in image pixels (the viewBox) on top.
  s += "<div class=\"view\" data-view=\"heat\" hidden>";
  if (dif.present()) {
    s += "<div class=\"stage\"" + stage_style(dif.w, dif.h) + ">" + layer(dif, dif.w, "diff", false);
    s += fmt("<svg class=\"boxes\" viewBox=\"0 0 %d %d\" preserveAspectRatio=\"none\" data-clusters=\"%zu\">",
             dif.w, dif.h, f.clusters.size());
    for (size_t i = 0; i < f.clusters.size(); ++i) {
      const ReportFrame::Box& b = f.clusters[i];
      s += fmt("<rect x=\"%d\" y=\"%d\" width=\"%d\" height=\"%d\">", b.x0, b.y0, b.x1 - b.x0 + 1,
               b.y1 - b.y0 + 1);
      s += fmt("<title>cluster %zu: %s px, (%d, %d) to (%d, %d)</title></rect>", i + 1,
               grouped(b.pixels).c_str(), b.x0, b.y0, b.x1, b.y1);
    }
    s += "</svg></div>";
    s += "<div class=\"caption legend\"><span><i class=\"sw\" style=\"background:#f00\"></i>differing</span>"
         "<span><i class=\"sw\" style=\"background:#ff0\"></i>anti-aliasing (ignored)</span>"
         "<span><i class=\"sw\" style=\"border:2px solid #00b7ff\"></i>clusters (" +
         std::to_string(f.clusters.size()) + ")</span></div>";
  } else {
    s += placeholder("No difference image", fw, fh);
  }
  s += "</div></div>";
  return s;
}

std::string metrics(const ReportFrame& f) {
  auto num = [](double v, const char* format, const char* unit) {
    if (std::isnan(v)) return std::string("&mdash;");
    if (std::isinf(v)) return std::string(v > 0 ? "&infin;" : "-&infin;") + unit;
    return fmt(format, v) + unit;
  };
  std::string ratio = "&mdash;";
  if (!std::isnan(f.diff_ratio)) {
    const double p = 100 * f.diff_ratio;
    ratio = p == 0 ? "0 %" : fmt(p >= 0.01 ? "%.2f %%" : "%.2g %%", p);
  }
  std::string s =
      "<table class=\"metrics\"><tr><th>Differing pixels</th><th>Ratio</th><th>Clusters</th>"
      "<th>Largest cluster</th><th>AA ignored</th><th>PSNR</th><th>SSIM</th></tr><tr>";
  s += "<td>" + grouped(f.differing) + "</td><td>" + ratio + "</td>";
  s += "<td>" + std::to_string(f.clusters.size()) + "</td>";
  s += "<td>" + grouped(f.largest_cluster) + " px</td><td>" + grouped(f.antialiased) + " px</td>";
  // SSIM near 1 with six digits: a small change (0.999982) must not read as 1.0000.
  s += "<td>" + num(f.psnr, "%.2f", " dB") + "</td><td>" +
       num(f.ssim, f.ssim >= 0.9999 && f.ssim < 1 ? "%.6f" : "%.4f", "") + "</td></tr></table>";
  return s;
}

std::string attribution(const ReportFrame& f) {
  const char* what = nullptr;
  const char* why = "";
  if (f.kind == "physics") {
    what = "Physics changed";
    why = "the simulated state differs from the golden run; the pixels follow from it";
  } else if (f.kind == "rendering") {
    what = "Rendering changed";
    why = "the simulation matches the golden run; only the pixels differ";
  } else if (f.kind == "input") {
    what = "An input changed";
    why =
        "a file the scene reads (a mesh, an image) differs from when the goldens were written; the "
        "bodies are where they were";
  } else if (f.kind == "size") {
    what = "Image size changed";
    why = "the two images have different sizes";
  } else if (f.kind == "pixels") {  // simreel diff: two renders, no physics to blame
    what = "Pixels differ";
    why = "A and B differ in this frame";
  } else if (f.kind == "count") {
    what = "Frame on one side only";
    why = "A and B do not both have this frame";
  } else if (!f.kind.empty()) {
    what = "Changed";
  }
  if (!what && f.messages.empty()) return "";
  std::string s =
      "<div class=\"attrib" + (f.kind.empty() ? std::string() : " k-" + html_escape(f.kind)) + "\">";
  if (what) s += "<strong>" + std::string(what) + "</strong><span class=\"why\">" + why + "</span>";
  if (!f.messages.empty()) {
    s += "<ul>";
    for (const std::string& m : f.messages) s += "<li>" + html_escape(m) + "</li>";
    s += "</ul>";
  }
  return s + "</div>";
}

std::string card(const ReportFrame& f, size_t index, const ReportInput& in) {
  const std::string id = "f" + std::to_string(index);
  Image exp{&f.expected_png, id + "-e", "", "expected", f.width, f.height};
  Image act{&f.actual_png, id + "-a", "", "actual", f.width, f.height};
  Image dif{&f.diff_png, id + "-d", "", "difference", f.width, f.height};
  for (Image* im : {&exp, &act, &dif}) {
    if (!im->present()) continue;
    if (png_size(*im->png, im->w, im->h)) continue;
    if (im->w <= 0 || im->h <= 0) {  // not a PNG (the browser will say so): some room for the icon
      im->w = 320;
      im->h = 180;
    }
  }
  if (exp.present() && act.present() && *exp.png == *act.png) act.alias = exp.id;  // embed once

  const std::string cls = known_status(f.status) ? f.status : "fail";
  std::string s = "<article class=\"card st-" + cls + "\" id=\"" + id + "\"><div class=\"card-head\">";
  s += "<h3>" + html_escape(f.scene) + "</h3>";
  s += "<span class=\"meta\">" +
       (f.frame >= 0 ? "frame " + std::to_string(f.frame) + " &middot; " : std::string()) +
       "t = " + fmt("%.3f", f.time) + " s";
  if (f.width > 0 && f.height > 0) s += fmt(" &middot; %d&times;%d", f.width, f.height);
  s += "</span>" + badge(f.status) + "</div>";

  if (f.status == "new")
    s += "<p class=\"note\">No golden image existed: this frame was written as the new golden.</p>";
  if (f.status == "missing")
    s += "<p class=\"note\">No golden image, and none was written: run the accept command to create it.</p>";
  if (f.status == "updated") s += "<p class=\"note\">The golden image was replaced by this frame.</p>";
  s += attribution(f);
  if (!std::isnan(f.diff_ratio) || !std::isnan(f.psnr) || !std::isnan(f.ssim)) s += metrics(f);
  if (exp.present() || act.present() || dif.present()) {
    s += viewer(f, exp, act, dif, in);
  } else {
    s += "<p class=\"note\">No images for this frame.</p>";
  }
  return s + "</article>";
}

// The golden and actual fingerprints side by side; differing: the keys whose values differ.
std::string fingerprints(const ReportInput& in, std::vector<std::string>& differing) {
  const auto& g = in.golden_fingerprint;
  const auto& a = in.actual_fingerprint;
  if (g.empty() && a.empty()) return "<p class=\"empty\">No fingerprint recorded.</p>";
  auto find = [](const std::vector<std::pair<std::string, std::string>>& v, const std::string& k) {
    return std::find_if(v.begin(), v.end(), [&](const auto& p) { return p.first == k; });
  };
  std::vector<std::string> keys;  // the golden's order, then keys only the actual run has
  for (const auto& [k, v] : g) keys.push_back(k);
  for (const auto& [k, v] : a)
    if (find(g, k) == g.end()) keys.push_back(k);
  std::string rows;
  for (const std::string& k : keys) {
    const auto gi = find(g, k), ai = find(a, k);
    const bool same = gi != g.end() && ai != a.end() && gi->second == ai->second;
    if (!same) differing.push_back(k);
    auto cell = [](auto it, auto end) {
      return it == end ? std::string("<td class=\"absent\">absent</td>")
                       : "<td>" + html_escape(it->second) + "</td>";
    };
    rows += std::string(same ? "<tr>" : "<tr class=\"differ\">") + "<th>" + html_escape(k) + "</th>" +
            cell(gi, g.end()) + cell(ai, a.end()) + "</tr>";
  }
  return fmt("<div class=\"fp\" data-differ=\"%zu\"><table><thead><tr><th>Key</th><th>Golden</th>"
             "<th>Actual</th></tr></thead><tbody>",
             differing.size()) +
         rows + "</tbody></table></div>";
}

}  // namespace

std::string report_html(const ReportInput& in) {
  std::vector<size_t> order(in.frames.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return rank(in.frames[a].status) < rank(in.frames[b].status); });
  int count[4] = {0, 0, 0, 0};
  for (const ReportFrame& f : in.frames) ++count[rank(f.status)];

  const std::string title = in.title.empty() ? "simreel report" : in.title;
  std::string s;
  s += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n";
  // Nothing may be fetched: the page is opened from a CI artifact, possibly offline.
  s += "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; img-src data:; "
       "style-src 'unsafe-inline'; script-src 'unsafe-inline'\">\n";
  s += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  s += "<meta name=\"color-scheme\" content=\"light\">\n";
  s += "<title>" + html_escape(title) + (in.summary.empty() ? "" : " &mdash; " + html_escape(in.summary)) +
       "</title>\n";
  s += "<style>" + std::string(report_page::kCss) + "</style>\n</head>\n<body>\n";
  s += "<div id=\"selftest-result\" class=\"selftest\" hidden>SELFTEST NOT RUN</div>\n";

  // Header: what ran, what it found, how to accept it.
  s += "<header class=\"top\"><div class=\"page\">";
  s += "<h1>" + html_escape(title) + "</h1>";
  s += "<p class=\"summary\">" + html_escape(in.summary.empty() ? "No summary" : in.summary) + "</p>";
  s += "<div class=\"counts\">";
  const char* labels[4][2] = {
      {"fail", "failed"}, {"missing", "missing"}, {"new", "new / updated"}, {"pass", "passed"}};
  for (int r = 0; r < 4; ++r)
    if (count[r]) s += fmt("<span class=\"badge st-%s\">%d %s</span>", labels[r][0], count[r], labels[r][1]);
  s += "</div><div class=\"cmd\">";
  if (!in.command.empty())
    s += "<span class=\"label\">Command</span><code id=\"cmd-run\">" + html_escape(in.command) +
         "</code><button data-copy=\"cmd-run\">Copy</button>";
  if (!in.accept_command.empty())
    s += "<span class=\"label\">Accept the change</span><code id=\"cmd-accept\">" +
         html_escape(in.accept_command) + "</code><button data-copy=\"cmd-accept\">Copy</button>";
  s += "</div>";
  std::vector<std::string> fp_differ;
  const std::string fp_table = fingerprints(in, fp_differ);
  if (!fp_differ.empty()) {  // often the explanation of a rendering change: say so up front
    s +=
        "<p class=\"fp-note\"><a href=\"#fingerprint\">Fingerprint</a>: " + std::to_string(fp_differ.size()) +
        (fp_differ.size() == 1 ? " key differs" : " keys differ") + " between the golden and this run (";
    for (size_t i = 0; i < fp_differ.size(); ++i) s += (i ? ", " : "") + html_escape(fp_differ[i]);
    s += ")</p>";
  }
  if (count[0] + count[1] > 0) {
    s += "<div class=\"jump\">Jump to: ";
    for (size_t i : order) {
      const ReportFrame& f = in.frames[i];
      if (rank(f.status) > 1) break;
      s += "<a href=\"#f" + std::to_string(i) + "\">" + html_escape(f.scene) + " " +
           (!f.label.empty() ? html_escape(f.label)
            : f.frame >= 0   ? "#" + std::to_string(f.frame)
                             : "t=" + fmt("%g", f.time) + "s") +
           "</a> ";
    }
    s += "</div>";
  }
  s += "</div></header>\n";

  // Toolbar: the same controls as the keys 1-4, the zoom.
  s += "<nav class=\"toolbar\"><div class=\"page\">";
  s += "<div class=\"group\"><span class=\"name\">All frames</span><span class=\"seg\">"
       "<button data-allview=\"side\"><kbd>1</kbd> Side by side</button>"
       "<button data-allview=\"slider\"><kbd>2</kbd> Slider</button>"
       "<button data-allview=\"blink\"><kbd>3</kbd> Blink</button>"
       "<button data-allview=\"heat\"><kbd>4</kbd> Heat map</button></span></div>";
  s += "<div class=\"group\"><span class=\"name\">Zoom</span><span class=\"seg\">"
       "<button data-zoom=\"fit\">Fit</button><button data-zoom=\"1\">1&times;</button>"
       "<button data-zoom=\"2\">2&times;</button><button data-zoom=\"4\">4&times;</button></span>"
       "<label><input id=\"pixelated\" type=\"checkbox\"> Pixelated</label></div>";
  s += "</div></nav>\n<main class=\"page\">\n";

  // Frames: failures, missing, new/updated, then the passes collapsed.
  const char* headings[4] = {"Failures", "Missing goldens", "New and updated goldens", "Passing"};
  size_t k = 0;
  for (int r = 0; r < 4; ++r) {
    if (count[r] == 0) continue;
    if (r == 3) {
      s += fmt("<details class=\"group\"><summary>%s <span class=\"n\">(%d)</span></summary>\n", headings[r],
               count[r]);
    } else {
      s += fmt("<h2>%s <span class=\"n\">(%d)</span></h2>\n", headings[r], count[r]);
    }
    for (; k < order.size() && rank(in.frames[order[k]].status) == r; ++k)
      s += card(in.frames[order[k]], order[k], in) + "\n";
    if (r == 3) s += "</details>\n";
  }
  if (in.frames.empty()) s += "<p class=\"empty\">No frames were compared.</p>\n";

  s += "<h2 id=\"fingerprint\">Fingerprint <span class=\"n\">(golden vs actual)</span></h2>\n";
  s += "<section class=\"panel\">" + fp_table + "</section>\n";
  s += "</main>\n<script>" + std::string(report_page::kJs) + "</script>\n</body></html>\n";
  return s;
}

std::string write_report(const std::string& dir, const ReportInput& in) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create the report folder " + dir + ": " + ec.message());
  const fs::path page = fs::path(dir) / "index.html";
  const fs::path tmp = fs::path(dir) / (".index.html." + std::to_string(getpid()) + ".tmp");
  const std::string html = report_html(in);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (out) out.write(html.data(), std::streamsize(html.size()));
    if (out) out.close();
    if (!out) {
      const std::string why = std::strerror(errno);
      fs::remove(tmp, ec);
      throw std::runtime_error("cannot write " + page.string() + ": " + why);
    }
  }
  fs::rename(tmp, page, ec);
  if (ec) {
    const std::string why = ec.message();
    fs::remove(tmp, ec);
    throw std::runtime_error("cannot write " + page.string() + ": " + why);
  }
  return page.string();
}

}  // namespace simreel
