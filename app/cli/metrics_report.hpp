// A comparison's figures as the review page shows them (check and diff fill frames alike).
#pragma once
#include "app/regress/metrics.hpp"
#include "app/report/report.hpp"

namespace simreel {

inline void put_metrics(const CompareResult& r, ReportFrame& f) {
  // Images of another size were not compared: no metrics (they would read as a perfect match).
  if (!r.same_size) return;
  f.differing = r.differing;
  f.antialiased = r.antialiased;
  f.diff_ratio = r.diff_ratio;
  f.largest_cluster = r.largest_cluster;
  f.psnr = r.psnr;
  f.ssim = r.ssim;
  for (const Cluster& k : r.clusters) f.clusters.push_back({k.x0, k.y0, k.x1, k.y1, k.pixels});
}

}  // namespace simreel
