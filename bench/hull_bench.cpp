// Convex hull speed and memory (sim/geometry/convex_hull.hpp): prints CSV "case,points,seconds,peak_rss_mb".
// Cases: a CAD-like gear point set of about 43k points (the size of the real meshes' tm_cycloidal.ply)
// and 500k random points in a ball. Peak RSS is the process's (getrusage), so run one case per
// process for a clean figure: bench_hull_bench gear | ball (default: both).
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>

#include "sim/geometry/convex_hull.hpp"

using namespace simreel;

static double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

static void run(const char* name, const std::vector<Vec3>& pts) {
  const auto t0 = std::chrono::steady_clock::now();
  const TriangleMesh h = convex_hull(pts);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%s,%zu,%.4f,%.1f\n", name, pts.size(), s, peak_rss_mb());
  (void)h;
}

int main(int argc, char** argv) {
  const std::string which = argc > 1 ? argv[1] : "both";
  std::printf("case,points,seconds,peak_rss_mb\n");
  uint64_t st = 1;
  auto rnd = [&] {
    st = st * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(st >> 11) * 0x1p-53;
  };
  if (which != "ball") {
    // 14300 profile samples x 3 layers, turned by a generic rotation (caps coplanar to rounding).
    std::vector<Vec3> pts;
    const Mat3 r = Eigen::AngleAxisd(0.7, Vec3(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 14300; ++i) {
        const double t = 2 * std::numbers::pi * i / 14300;
        pts.push_back(
            r * Vec3(std::cos(t) - 0.04 * std::cos(12 * t), std::sin(t) - 0.04 * std::sin(12 * t), 0.15 * k) +
            Vec3(1.2, 0.58, 1.31));
      }
    run("gear", pts);
  }
  if (which != "gear") {
    std::vector<Vec3> pts;
    while (pts.size() < 500000) {
      const Vec3 p(2 * rnd() - 1, 2 * rnd() - 1, 2 * rnd() - 1);
      if (p.squaredNorm() <= 1) pts.push_back(p);
    }
    run("ball", pts);
  }
}
