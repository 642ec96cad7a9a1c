// Issue 11: the noise floor of compare_images between renders that should look the same, and
// what it gives for small real changes. bench/regress_noise.sh renders the frames and calls this.
//
//   bench_regress_noise header
//   bench_regress_noise pairs LABEL KIND THRESHOLDS DIR_A DIR_B [DIR...]
//       compares the frames (*.png, the same names in each folder) of every pair of folders under
//       the default CompareOptions with each threshold of THRESHOLDS (comma-separated, or - for the
//       default), one CSV row per threshold, the worst over all pairs and frames
//   bench_regress_noise time A.png B.png [REPS]
//       best-of-REPS times of compare_images (with and without the heat map), pixel_hash and
//       read_png on the two frames
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "app/regress/image.hpp"
#include "app/regress/metrics.hpp"

using namespace simreel;
namespace fs = std::filesystem;

namespace {

const char* kHeader =
    "label,kind,threshold,frames,frames_identical,max_differing,max_diff_ratio,max_antialiased,"
    "max_cluster,min_psnr,min_ssim,max_channel_delta,frames_failing,first_failing_frame,"
    "f0_differing,f0_antialiased,f0_cluster,f0_psnr,f0_max_channel_delta";

std::vector<Image> load_frames(const fs::path& dir, const std::vector<std::string>& names) {
  std::vector<Image> out;
  for (const std::string& n : names) out.push_back(read_png((dir / n).string()));
  return out;
}

// Every pair of the folders, frame by frame; one row per threshold with the worst figure over all
// pairs and frames (frames = frame comparisons made; f0_* = the worst first-frame figures).
int pairs(const std::string& label, const std::string& kind, const std::string& thresholds,
          const std::vector<fs::path>& dirs) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dirs[0]))
    if (e.path().extension() == ".png") names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  if (names.empty()) {
    std::fprintf(stderr, "no frames in %s\n", dirs[0].c_str());
    return 1;
  }
  std::vector<std::vector<Image>> frames;
  for (const fs::path& d : dirs) frames.push_back(load_frames(d, names));
  std::vector<double> ts;
  if (thresholds != "-") {
    size_t pos = 0;
    while (pos <= thresholds.size()) {
      const size_t comma = std::min(thresholds.find(',', pos), thresholds.size());
      ts.push_back(std::stod(thresholds.substr(pos, comma - pos)));
      pos = comma + 1;
    }
  }
  if (ts.empty()) ts.push_back(CompareOptions{}.threshold);
  for (double t : ts) {
    CompareOptions o;
    o.threshold = t;
    int compared = 0, identical_frames = 0, failing = 0, first_fail = -1, max_cluster = 0, f0_cluster = 0;
    long max_diff = 0, max_aa = 0, f0_diff = 0, f0_aa = 0;
    double max_ratio = 0, min_psnr = INFINITY, min_ssim = 1, max_ch = 0, f0_psnr = INFINITY, f0_ch = 0;
    for (size_t p = 0; p < dirs.size(); ++p)
      for (size_t q = p + 1; q < dirs.size(); ++q)
        for (size_t i = 0; i < names.size(); ++i) {
          const Image &a = frames[p][i], &b = frames[q][i];
          const CompareResult r = compare_images(a, b, o);
          ++compared;
          identical_frames += identical(a, b);
          max_diff = std::max(max_diff, r.differing);
          max_ratio = std::max(max_ratio, r.diff_ratio);
          max_aa = std::max(max_aa, r.antialiased);
          max_cluster = std::max(max_cluster, r.largest_cluster);
          min_psnr = std::min(min_psnr, r.psnr);
          min_ssim = std::min(min_ssim, r.ssim);
          max_ch = std::max(max_ch, r.max_channel_delta);
          if (!r.pass) {
            ++failing;
            if (first_fail < 0 || (int)i < first_fail) first_fail = (int)i;
          }
          if (i == 0) {
            f0_diff = std::max(f0_diff, r.differing);
            f0_aa = std::max(f0_aa, r.antialiased);
            f0_cluster = std::max(f0_cluster, r.largest_cluster);
            f0_psnr = std::min(f0_psnr, r.psnr);
            f0_ch = std::max(f0_ch, r.max_channel_delta);
          }
        }
    std::printf("%s,%s,%g,%d,%d,%ld,%.6f,%ld,%d,%.2f,%.5f,%g,%d,%d,%ld,%ld,%d,%.2f,%g\n", label.c_str(),
                kind.c_str(), t, compared, identical_frames, max_diff, max_ratio, max_aa, max_cluster, min_psnr,
                min_ssim, max_ch, failing, first_fail, f0_diff, f0_aa, f0_cluster, f0_psnr, f0_ch);
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
  std::printf("%dx%d: %ld differing, %ld anti-aliasing, largest cluster %d, PSNR %.2f dB, SSIM %.5f\n", a.width,
              a.height, r.differing, r.antialiased, r.largest_cluster, r.psnr, r.ssim);
  std::printf("best of %d: compare_images %.2f ms, with heat map %.2f ms, identical frames %.2f ms, "
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
    if ((args.size() == 3 || args.size() == 4) && args[0] == "time")
      return time_it(args[1], args[2], args.size() == 4 ? std::stoi(args[3]) : 20);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_regress_noise: %s\n", e.what());
    return 1;
  }
  std::fprintf(stderr,
               "usage: bench_regress_noise header | pairs LABEL KIND THRESHOLDS DIR_A DIR_B [DIR...] | "
               "time A.png B.png [REPS]\n");
  return 2;
}
