// An inset plot in the screen layer: quantities against time in a rectangle of the frame, drawn
// as the clip advances (the curves up to the present, a cursor at the present), with axes, ticks,
// tick labels and a legend. The axes are fixed when the plot is made (the time axis spans the
// run, the value axis the given range), so everything but the curves and the cursor is laid out
// once; a frame then appends line segments only (no allocation once the layer has grown).
#pragma once
#include <string>
#include <vector>

#include "render/screen.hpp"
#include "render/text.hpp"

namespace simreel {

struct PlotLayout {
  int x = 0, y = 0, width = 0, height = 0;  ///< px, the whole plot (panel) in the frame, y down
  double t0 = 0, t1 = 1;                    ///< s, the time axis
  double v0 = 0, v1 = 1;                    ///< the value axis (bottom, top)
  std::vector<std::string> labels;          ///< per curve, TeX subset (render/tex.hpp)
  std::vector<Rgba8> colors;                ///< per curve, display RGB
  std::string title;                        ///< optional, at the top left
  float line_width = 2;                     ///< px, the curves
};

class InsetPlot {
 public:
  // `text`: tick labels and legend (kept by reference: it must outlive the plot, and the frames).
  InsetPlot(const PlotLayout& layout, Typeface& text);

  // The pixel (continuous coordinates, y down) where time t and value v are drawn.
  double px_x(double t) const { return ax0_ + (t - L_.t0) / (L_.t1 - L_.t0) * (ax1_ - ax0_); }
  double px_y(double v) const { return ay1_ - (v - L_.v0) / (L_.v1 - L_.v0) * (ay1_ - ay0_); }
  // The plotting area, px: [x0, x1] x [y0, y1] (y down).
  double area_x0() const { return ax0_; }
  double area_x1() const { return ax1_; }
  double area_y0() const { return ay0_; }
  double area_y1() const { return ay1_; }
  const std::vector<double>& ticks() const { return ticks_; }
  const PlotLayout& layout() const { return L_; }  ///< values of the value axis's ticks

  // Appends the plot to `out`: `n` samples at times t[k], curve c's values at series[c][k]
  // (curves of layout.colors.size()); samples after t_now are left out, and the cursor drawn there.
  // `now` (one value per curve, or null): the values at t_now, which the curves then end at.
  void draw(const double* t, const float* const* series, int n, double t_now, ScreenLayer& out,
            const float* now = nullptr) const;

  // "Nice" tick values (1, 2 or 5 times a power of ten apart) covering [lo, hi], about `count` of them.
  static std::vector<double> nice_ticks(double lo, double hi, int count);

 private:
  PlotLayout L_;
  double ax0_ = 0, ax1_ = 0, ay0_ = 0, ay1_ = 0;
  std::vector<double> ticks_;
  ScreenLayer fixed_;  // panel, grid, axes, tick labels, legend
};

}  // namespace simreel
