// The noise floor of compare_images between renders that should look the same, and
// what it gives for small real changes. bench/regress_noise.sh renders the frames and calls this.
//
//   bench_regress_noise header
//   bench_regress_noise pairs LABEL KIND THRESHOLDS DIR_A DIR_B [DIR...]
//       compares the frames (*.png, the same names in each folder) of every pair of folders under
//       the default CompareOptions with each threshold of THRESHOLDS (comma-separated, or - for the
//       default), one CSV row per threshold, the worst over all pairs and frames
//   bench_regress_noise jitter LABEL THRESHOLDS K DIR
//       DIR's frames against copies with every RGB byte moved by a pseudo-random -K..K
//   bench_regress_noise time A.png B.png [REPS]
//       best-of-REPS times of compare_images (with and without the heat map), pixel_hash and
//       read_png on the two frames
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/regress/image.hpp"
#include "app/regress/metrics.hpp"

using namespace simreel;
namespace fs = std::filesystem;

namespace {

const char* kHeader =
    "label,kind,threshold,frames,frames_identical,max_changed,max_differing,max_diff_ratio,max_antialiased,"
    "max_cluster,min_psnr,min_ssim,max_channel_delta,frames_failing,first_failing_frame,"
    "f0_differing,f0_antialiased,f0_cluster,f0_psnr,f0_max_channel_delta";

// Pixels whose bytes differ at all.
long changed_pixels(const Image& a, const Image& b) {
  long n = 0;
  for (size_t i = 0; i < a.rgba.size(); i += 4)
    n += a.rgba[i] != b.rgba[i] || a.rgba[i + 1] != b.rgba[i + 1] || a.rgba[i + 2] != b.rgba[i + 2] ||
         a.rgba[i + 3] != b.rgba[i + 3];
  return n;
}

std::vector<Image> load_frames(const fs::path& dir, const std::vector<std::string>& names) {
  std::vector<Image> out;
  for (const std::string& n : names) out.push_back(read_png((dir / n).string()));
  return out;
}

std::vector<std::string> frame_names(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".png") names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  if (names.empty()) throw std::runtime_error("no frames in " + dir.string());
  return names;
}

std::vector<double> parse_thresholds(const std::string& list) {
  std::vector<double> ts;
  if (list != "-") {
    size_t pos = 0;
    while (pos <= list.size()) {
      const size_t comma = std::min(list.find(',', pos), list.size());
      ts.push_back(std::stod(list.substr(pos, comma - pos)));
      pos = comma + 1;
    }
  }
  if (ts.empty()) ts.push_back(CompareOptions{}.threshold);
  return ts;
}

// The worst figures over a set of frame comparisons: one CSV row.
struct Row {
  int compared = 0, identical_frames = 0, failing = 0, first_fail = -1, max_cluster = 0, f0_cluster = 0;
  long max_changed = 0, max_diff = 0, max_aa = 0, f0_diff = 0, f0_aa = 0;
  double max_ratio = 0, min_psnr = INFINITY, min_ssim = 1, max_ch = 0, f0_psnr = INFINITY, f0_ch = 0;

  void add(const Image& a, const Image& b, const CompareOptions& o, int frame) {
    const CompareResult r = compare_images(a, b, o);
    ++compared;
    identical_frames += identical(a, b);
    max_changed = std::max(max_changed, changed_pixels(a, b));
    max_diff = std::max(max_diff, r.differing);
    max_ratio = std::max(max_ratio, r.diff_ratio);
    max_aa = std::max(max_aa, r.antialiased);
    max_cluster = std::max(max_cluster, r.largest_cluster);
    min_psnr = std::min(min_psnr, r.psnr);
    min_ssim = std::min(min_ssim, r.ssim);
    max_ch = std::max(max_ch, r.max_channel_delta);
    if (!r.pass) {
      ++failing;
      if (first_fail < 0 || frame < first_fail) first_fail = frame;
    }
    if (frame == 0) {
      f0_diff = std::max(f0_diff, r.differing);
      f0_aa = std::max(f0_aa, r.antialiased);
      f0_cluster = std::max(f0_cluster, r.largest_cluster);
      f0_psnr = std::min(f0_psnr, r.psnr);
      f0_ch = std::max(f0_ch, r.max_channel_delta);
    }
  }
  void print(const std::string& label, const std::string& kind, double t) const {
    std::printf("%s,%s,%g,%d,%d,%ld,%ld,%.6f,%ld,%d,%.2f,%.5f,%g,%d,%d,%ld,%ld,%d,%.2f,%g\n", label.c_str(),
                kind.c_str(), t, compared, identical_frames, max_changed, max_diff, max_ratio, max_aa,
                max_cluster, min_psnr, min_ssim, max_ch, failing, first_fail, f0_diff, f0_aa, f0_cluster,
                f0_psnr, f0_ch);
  }
};

// Every pair of the folders, frame by frame; one row per threshold with the worst figure over all
// pairs and frames (frames = frame comparisons made; max_changed = pixels with any byte changed;
// f0_* = the worst first-frame figures).
int pairs(const std::string& label, const std::string& kind, const std::string& thresholds,
          const std::vector<fs::path>& dirs) {
  const std::vector<std::string> names = frame_names(dirs[0]);
  std::vector<std::vector<Image>> frames;
  for (const fs::path& d : dirs) frames.push_back(load_frames(d, names));
  for (double t : parse_thresholds(thresholds)) {
    CompareOptions o;
    o.threshold = t;
    Row row;
    for (size_t p = 0; p < dirs.size(); ++p)
      for (size_t q = p + 1; q < dirs.size(); ++q)
        for (size_t i = 0; i < names.size(); ++i) row.add(frames[p][i], frames[q][i], o, (int)i);
    row.print(label, kind, t);
  }
  return 0;
}

// Synthetic drift: each frame of DIR against a copy with every R, G, B byte moved by an independent
// uniform whole number in [-k, k] (a fixed pseudo-random sequence), clamped to 0..255.
int jitter(const std::string& label, const std::string& thresholds, int k, const fs::path& dir) {
  const std::vector<std::string> names = frame_names(dir);
  const std::vector<Image> frames = load_frames(dir, names);
  std::vector<Image> moved = frames;
  uint64_t s = 0x9e3779b97f4a7c15ull;
  for (Image& img : moved)
    for (size_t i = 0; i < img.rgba.size(); ++i) {
      if (i % 4 == 3) continue;
      s = s * 6364136223846793005ull + 1442695040888963407ull;  // Knuth's MMIX LCG
      const int d = (int)((s >> 33) % (uint64_t)(2 * k + 1)) - k;
      img.rgba[i] = (uint8_t)std::clamp(img.rgba[i] + d, 0, 255);
    }
  for (double t : parse_thresholds(thresholds)) {
    CompareOptions o;
    o.threshold = t;
    Row row;
    for (size_t i = 0; i < names.size(); ++i) row.add(frames[i], moved[i], o, (int)i);
    row.print(label, "jitter", t);
  }
  return 0;
}

template <class F>
double best_ms(int reps, F f) {
  double best = INFINITY;
  for (int i = 0; i < reps; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    const auto t1 = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double, std::milli>(t1 - t0).count());
  }
  return best;
}

int time_it(const std::string& pa, const std::string& pb, int reps) {
  const Image a = read_png(pa), b = read_png(pb);
  CompareResult r;
  Image diff;
  const double plain = best_ms(reps, [&] { r = compare_images(a, b, CompareOptions{}); });
  const double with_map = best_ms(reps, [&] { r = compare_images(a, b, CompareOptions{}, &diff); });
  const double same = best_ms(reps, [&] { compare_images(a, a, CompareOptions{}); });
  std::string h;
  const double hash = best_ms(reps, [&] { h = pixel_hash(a); });
  const double read = best_ms(reps, [&] { read_png(pa); });
  std::printf("%dx%d: %ld differing, %ld anti-aliasing, largest cluster %d, PSNR %.2f dB, SSIM %.5f\n",
              a.width, a.height, r.differing, r.antialiased, r.largest_cluster, r.psnr, r.ssim);
  std::printf(
      "best of %d: compare_images %.2f ms, with heat map %.2f ms, identical frames %.2f ms, "
      "pixel_hash %.2f ms, read_png %.2f ms\n",
      reps, plain, with_map, same, hash, read);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  try {
    if (args.size() == 1 && args[0] == "header") {
      std::printf("%s\n", kHeader);
      return 0;
    }
    if (args.size() >= 6 && args[0] == "pairs")
      return pairs(args[1], args[2], args[3], std::vector<fs::path>(args.begin() + 4, args.end()));
    if (args.size() == 5 && args[0] == "jitter") return jitter(args[1], args[2], std::stoi(args[3]), args[4]);
    if ((args.size() == 3 || args.size() == 4) && args[0] == "time")
      return time_it(args[1], args[2], args.size() == 4 ? std::stoi(args[3]) : 20);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_regress_noise: %s\n", e.what());
    return 1;
  }
  std::fprintf(stderr,
               "usage: bench_regress_noise header | pairs LABEL KIND THRESHOLDS DIR_A DIR_B [DIR...] | "
               "jitter LABEL THRESHOLDS K DIR | "
               "time A.png B.png [REPS]\n");
  return 2;
}
