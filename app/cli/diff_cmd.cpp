// simreel diff: two PNGs, folders of PNGs or videos, frame by frame.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>

#include <simreel/error.hpp>
#include "app/cli/cli.hpp"
#include "app/cli/commands.hpp"
#include "app/cli/metrics_report.hpp"
#include "app/cli/video_frames.hpp"
#include "app/regress/image.hpp"
#include "app/regress/metrics.hpp"
#include "app/report/report.hpp"

namespace simreel {

namespace {

namespace fs = std::filesystem;

struct DiffOptions {
  std::vector<std::string> inputs;
  std::optional<std::string> out, tolerance;
  bool quiet = false;
};

// diff's option table.
void diff_table(CLI::App& app, DiffOptions& o) {
  cli::setup(app, "diff",
             "Compares A with B frame by frame. Each is a PNG, a folder of PNGs (matched by file name) or a "
             "video (.mp4, .webm, .gif, ...; decoded with the FFmpeg libraries and matched by timestamp). "
             "Prints per-frame metrics (differing pixels, largest cluster, PSNR, SSIM) and a summary; frame "
             "count, size and frame rate mismatches are reported as differences.",
             "Exit codes: 0 no difference, 1 a difference, 2 bad input (unreadable file).");
  cli::add_positionals(app, o.inputs);
  app.add_option("--out", o.out, "write diff images of the worst frames and DIR/index.html, the review page")
      ->type_name("DIR");
  app.add_option("--tolerance", o.tolerance,
                 "portable (default): a perceptual comparison that ignores anti-aliasing and noise but fails "
                 "on many differing pixels or one cluster of them; exact: any changed pixel fails")
      ->check(cli::choice({"portable", "exact"}));
  app.add_flag("--quiet", o.quiet, "print only differing frames and the summary");
}

// One side of the comparison, read a frame at a time.
class Source {
 public:
  virtual ~Source() = default;
  // The next frame: its image and its key (file name, or time for a video). False at the end.
  virtual bool next(Image& img, std::string& name, double& time) = 0;
  virtual bool timed() const { return false; }
  virtual double fps() const { return 0; }
  std::string path;
};

class PngFiles : public Source {
 public:
  explicit PngFiles(std::vector<fs::path> files) : files_(std::move(files)) {}
  bool next(Image& img, std::string& name, double& time) override {
    if (i_ >= files_.size()) return false;
    img = read_png(files_[i_].string());
    name = files_[i_].filename().string();
    time = (double)i_++;
    return true;
  }
  const std::vector<fs::path>& files() const { return files_; }

 private:
  std::vector<fs::path> files_;
  size_t i_ = 0;
};

class Video : public Source {
 public:
  explicit Video(const std::string& p) : v_(p) {}
  bool next(Image& img, std::string& name, double& time) override {
    if (!v_.next(img, time)) return false;
    char b[32];
    std::snprintf(b, sizeof b, "t=%.3fs", time);
    name = b;
    return true;
  }
  bool timed() const override { return true; }
  double fps() const override { return v_.fps(); }

 private:
  VideoFrames v_;
};

std::unique_ptr<Source> open_source(const std::string& p) {
  std::error_code ec;
  std::unique_ptr<Source> s;
  if (fs::is_directory(p, ec)) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(p, ec)) {
      std::string ext = e.path().extension().string();
      for (char& c : ext) c = (char)std::tolower((unsigned char)c);
      if (ext == ".png" && e.is_regular_file()) files.push_back(e.path());
    }
    if (files.empty()) throw InputError(p + ": a folder with no PNG files");
    std::sort(files.begin(), files.end());
    s = std::make_unique<PngFiles>(files);
  } else if (!fs::exists(p, ec)) {
    throw InputError(p + ": does not exist");
  } else {
    std::ifstream in(p, std::ios::binary);
    char sig[8] = {};
    in.read(sig, 8);
    if (in.gcount() == 8 && std::equal(sig, sig + 8, "\x89PNG\r\n\x1a\n"))
      s = std::make_unique<PngFiles>(std::vector<fs::path>{p});
    else
      s = std::make_unique<Video>(p);
  }
  s->path = p;
  return s;
}

struct Pair {
  std::string label;
  std::optional<Image> a, b;
  double time = 0;
};

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

}  // namespace

int cmd_diff(const std::vector<std::string>& args) {
  DiffOptions o;
  CLI::App app;
  diff_table(app, o);
  if (!cli::parse(app, args)) return kExitOk;
  if (o.inputs.size() != 2) throw UsageError("diff takes two inputs, A and B");
  CompareOptions opt;
  if (o.tolerance == "exact") opt = CompareOptions::exact();  // names checked by the table
  const bool quiet = o.quiet;
  std::unique_ptr<Source> A = open_source(o.inputs[0]), B = open_source(o.inputs[1]);
  std::vector<std::string> mismatches;
  if (A->timed() && B->timed() && A->fps() > 0 && B->fps() > 0 &&
      std::fabs(A->fps() - B->fps()) > 1e-6 * A->fps())
    mismatches.push_back("frame rate: A " + fmt("%g", A->fps()) + " fps, B " + fmt("%g", B->fps()) + " fps");

  // Pairing: videos by timestamp (within half a frame), folders by file name, otherwise in order.
  const bool by_time = A->timed() && B->timed();
  auto* fa = dynamic_cast<PngFiles*>(A.get());
  auto* fb = dynamic_cast<PngFiles*>(B.get());
  const bool by_name = fa && fb && fa->files().size() > 1 && fb->files().size() > 1;
  const double half = 0.5 / std::max({A->fps(), B->fps(), 1.0});

  ReportInput report;
  report.title = "simreel diff";
  report.expected_label = "A: " + o.inputs[0];
  report.actual_label = "B: " + o.inputs[1];
  report.command = "simreel diff";
  for (const std::string& s : args) report.command += " " + s;
  std::vector<ReportFrame> frames;  // every frame's metrics (images only for the worst)
  long compared = 0, differing = 0, only_a = 0, only_b = 0, size_mismatch = 0, measured = 0;
  double worst_psnr = INFINITY, worst_ssim = 1;
  std::map<double, size_t, std::greater<double>> worst;  // badness -> index into frames (kept <= 6)
  std::vector<std::optional<std::array<Image, 3>>> kept;

  // Frames found on one side only, collapsed into runs (a clip of 10 frames against the full
  // video of 151 prints two lines, not 141): printed and given one report card per run.
  struct Run {
    int side = 0;  // 1: A, 2: B
    std::string first, last;
    double time = 0;
    long n = 0, index = 0;
    int width = 0, height = 0;
  } run;
  auto flush = [&] {
    if (run.n == 0) return;
    const char* side = run.side == 1 ? "A" : "B";
    const std::string what = run.n == 1 ? run.first : run.first + " .. " + run.last;
    std::printf("%-24s only in %s%s\n", what.c_str(), side,
                run.n == 1 ? "" : (" (" + std::to_string(run.n) + " frames)").c_str());
    ReportFrame rf;
    rf.scene = what;
    rf.frame = (int)run.index;
    rf.time = run.time;
    rf.status = "fail";
    rf.kind = "count";
    rf.width = run.width;
    rf.height = run.height;
    rf.messages.push_back(std::string("only in ") + side + ": " + what +
                          (run.n == 1 ? "" : " (" + std::to_string(run.n) + " frames)"));
    frames.push_back(std::move(rf));
    run = Run{};
  };

  Image ia, ib;
  std::string na, nb;
  double ta = 0, tb = 0;
  bool ha = A->next(ia, na, ta), hb = B->next(ib, nb, tb);
  long index = 0;
  while (ha || hb) {
    // Which frames pair up now.
    int take = 3;  // 1: A alone, 2: B alone, 3: both
    if (!hb)
      take = 1;
    else if (!ha)
      take = 2;
    else if (by_time && std::fabs(ta - tb) > half)
      take = ta < tb ? 1 : 2;
    else if (by_name && na != nb)
      take = na < nb ? 1 : 2;
    if (take == 1 || take == 2) {
      (take == 1 ? only_a : only_b)++;
      if (run.side != take) flush();
      const Image& im = take == 1 ? ia : ib;
      const std::string& name = take == 1 ? na : nb;
      if (run.n++ == 0) {
        run.side = take;
        run.first = name;
        run.time = by_time ? (take == 1 ? ta : tb) : 0;
        run.index = index;
        run.width = im.width;
        run.height = im.height;
      }
      run.last = name;
      ++index;
      if (take == 1)
        ha = A->next(ia, na, ta);
      else
        hb = B->next(ib, nb, tb);
      continue;
    }
    flush();
    ++compared;
    ReportFrame rf;
    rf.scene = na;
    rf.frame = (int)index++;
    rf.time = by_time ? ta : 0;
    if (!by_time && !by_name && na != nb) rf.scene = na + " | " + nb;
    Image diff;
    const CompareResult r = compare_images(ia, ib, opt, &diff);
    rf.width = ib.width;
    rf.height = ib.height;
    rf.status = r.pass ? "pass" : "fail";
    if (!r.same_size) {
      ++size_mismatch;
      rf.kind = "size";
    } else if (!r.pass) {
      rf.kind = "pixels";
    }
    if (!r.pass) {
      ++differing;
      rf.messages.push_back(r.reason);
    }
    put_metrics(r, rf);
    if (r.same_size) {
      ++measured;
      worst_psnr = std::min(worst_psnr, r.psnr);
      worst_ssim = std::min(worst_ssim, r.ssim);
    }
    if (!r.same_size)  // nothing was measured: say why, not metrics of nothing
      std::printf("%-24s DIFF  %s\n", rf.scene.c_str(), r.reason.c_str());
    else if (!quiet || !r.pass)
      std::printf("%-24s %s  differing %ld (%.4f%%), largest cluster %d, PSNR %s dB, SSIM %.6f\n",
                  rf.scene.c_str(), r.pass ? "same" : "DIFF", r.differing, 100 * r.diff_ratio,
                  r.largest_cluster, std::isinf(r.psnr) ? "inf" : fmt("%.2f", r.psnr).c_str(), r.ssim);
    // Keep the images of the worst frames only: a long video never sits in memory.
    const double badness = r.same_size ? (r.pass ? 0.0 : 1.0) + r.diff_ratio + (1 - r.ssim) : 2.0;
    if (o.out && badness > 0 && (worst.size() < 6 || badness > worst.rbegin()->first)) {
      kept.resize(frames.size() + 1);
      kept[frames.size()] = std::array<Image, 3>{ia, ib, diff};
      worst.emplace(badness + 1e-12 * (double)frames.size(), frames.size());
      if (worst.size() > 6) {
        kept[worst.rbegin()->second].reset();
        worst.erase(std::prev(worst.end()));
      }
    }
    frames.push_back(std::move(rf));
    ha = A->next(ia, na, ta);
    hb = B->next(ib, nb, tb);
  }
  flush();
  if (only_a || only_b)
    mismatches.push_back("frame count: " + std::to_string(compared + only_a) + " in A, " +
                         std::to_string(compared + only_b) + " in B");
  if (size_mismatch) mismatches.push_back(std::to_string(size_mismatch) + " frames differ in size");

  std::string summary = std::to_string(differing) + " of " + std::to_string(compared) + " frames differ";
  if (measured) {
    summary += "; worst PSNR " + (std::isinf(worst_psnr) ? std::string("inf") : fmt("%.2f", worst_psnr)) +
               " dB, worst SSIM " + fmt("%.6f", worst_ssim);
  }
  for (const std::string& m : mismatches) summary += "; " + m;
  std::printf("%s\n", summary.c_str());

  if (o.out) {
    const std::string out = *o.out;
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec) throw std::runtime_error("cannot create '" + out + "': " + ec.message());
    for (const auto& [score, i] : worst) {
      if (!kept[i]) continue;
      const auto& [ea, eb, d] = *kept[i];
      ReportFrame& rf = frames[i];
      rf.expected_png = encode_png(ea);
      rf.actual_png = encode_png(eb);
      if (!d.rgba.empty() && ea.width == eb.width && ea.height == eb.height) {
        rf.diff_png = encode_png(d);
        std::string safe = rf.scene;
        for (char& c : safe)
          if (!std::isalnum((unsigned char)c) && c != '.' && c != '_' && c != '-' && c != '=') c = '_';
        write_png_file((fs::path(out) / ("diff_" + std::to_string(rf.frame) + "_" + safe + ".png")).string(),
                       d);
      }
    }
    // The page lists the differing frames first and shows the images of the worst.
    report.frames = frames;
    report.summary = summary;
    const std::string page = write_report(out, report);
    std::printf("report: %s\n", page.c_str());
  }
  return differing || !mismatches.empty() ? kExitFailure : kExitOk;
}

}  // namespace simreel
