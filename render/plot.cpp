#include "render/plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace simreel {

namespace {

const Rgba8 kPanel{16, 20, 28, 170}, kAxis{235, 235, 235, 255}, kGrid{255, 255, 255, 40},
    kInk{235, 235, 235, 255}, kCursor{255, 255, 255, 150};

// A tick value as text: as many decimals as the step needs, and a true minus sign.
std::string tick_text(double v, double step) {
  const int decimals = std::max(0, (int)std::ceil(-std::log10(step) - 1e-9));
  char buf[48];
  if (std::fabs(v) < 0.5 * step) v = 0;  // no "-0"
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  std::string s = buf;
  if (!s.empty() && s[0] == '-') s = "−" + s.substr(1);
  return s;
}

}  // namespace

std::vector<double> InsetPlot::nice_ticks(double lo, double hi, int count) {
  std::vector<double> out;
  if (!(hi > lo) || count < 1) return out;
  const double raw = (hi - lo) / count, mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double r = raw / mag;
  const double step = (r < 1.5 ? 1 : r < 3.5 ? 2 : r < 7.5 ? 5 : 10) * mag;
  for (double k = std::ceil(lo / step - 1e-9); k * step <= hi + 1e-9 * step; k += 1) out.push_back(k * step);
  return out;
}

InsetPlot::InsetPlot(const PlotLayout& layout, Typeface& text) : L_(layout) {
  const int pad = std::max(2, text.pixel_size() / 2), lh = text.line_height();
  const int x0 = L_.x, y0 = L_.y, x1 = L_.x + L_.width, y1 = L_.y + L_.height;
  fixed_.rects.push_back({x0, y0, x1, y1, kPanel});

  ticks_ = nice_ticks(L_.v0, L_.v1, std::max(2, L_.height / (3 * lh)));
  const double vstep = ticks_.size() > 1 ? ticks_[1] - ticks_[0] : (L_.v1 - L_.v0);
  std::vector<std::string> vlabels;
  int label_w = 0;
  for (double v : ticks_) {
    vlabels.push_back(tick_text(v, vstep));
    label_w = std::max(label_w, text.width(vlabels.back()));
  }
  // The legend rows above the plotting area: the title, then a swatch and a label per curve,
  // wrapped onto more rows where the panel is too narrow.
  const int swatch = (int)(2.8 * pad), right = x1 - pad;
  int pen = x0 + pad, row = 0;
  std::vector<std::pair<int, int>> at;  // per item (the title first, if any): its pen and row
  auto place = [&](int w) {
    if (pen > x0 + pad && pen + w > right) pen = x0 + pad, ++row;
    at.push_back({pen, row});
    pen += w + 2 * pad;
  };
  if (!L_.title.empty()) place(text.width(L_.title));
  for (const std::string& l : L_.labels) place(swatch + pad / 2 + text.width(l));
  size_t item = 0;
  auto base_of = [&](int r) { return y0 + pad + text.ascent() + r * lh; };
  if (!L_.title.empty()) {
    text.draw(L_.title, at[0].first, base_of(at[0].second), kInk, &fixed_);
    ++item;
  }
  for (size_t c = 0; c < L_.labels.size(); ++c, ++item) {
    const int p = at[item].first, base = base_of(at[item].second);
    const float ym = base - 0.3f * text.ascent();
    fixed_.lines.push_back({(float)p, ym, (float)(p + swatch), ym, 3.0f, L_.colors[c]});
    text.draw(L_.labels[c], p + swatch + pad / 2, base, kInk, &fixed_);
  }

  // The plotting area: tick labels to its left and below it, the legend rows above it.
  ax0_ = x0 + pad + label_w + pad * 0.75;
  ax1_ = x1 - pad * 1.5;
  ay0_ = y0 + pad + (row + 1) * lh + pad * 0.5;
  ay1_ = y1 - pad * 0.5 - lh;

  // Value axis: grid lines and tick labels, right-aligned.
  for (size_t k = 0; k < ticks_.size(); ++k) {
    const float y = (float)px_y(ticks_[k]);
    fixed_.lines.push_back({(float)ax0_, y, (float)ax1_, y, 1.0f, kGrid});
    fixed_.lines.push_back({(float)ax0_ - pad * 0.5f, y, (float)ax0_, y, 1.0f, kAxis});
    const int w = text.width(vlabels[k]);
    text.draw(vlabels[k], (int)std::lround(ax0_ - pad * 0.75 - w), (int)std::lround(y + 0.35 * text.ascent()),
              kInk, &fixed_);
  }
  // Time axis: ticks and labels below the area, the unit after the last.
  const std::vector<double> tt = nice_ticks(L_.t0, L_.t1, std::max(2, L_.width / (5 * text.pixel_size())));
  const double tstep = tt.size() > 1 ? tt[1] - tt[0] : (L_.t1 - L_.t0);
  for (size_t k = 0; k < tt.size(); ++k) {
    const float x = (float)px_x(tt[k]);
    fixed_.lines.push_back({x, (float)ay1_, x, (float)ay1_ + pad * 0.5f, 1.0f, kAxis});
    std::string s = tick_text(tt[k], tstep);
    if (k + 1 == tt.size()) s += " s";
    const int w = text.width(tick_text(tt[k], tstep));
    // Centred on its tick, but inside the panel (the last label carries the unit).
    const int left = std::min((int)std::lround(x - 0.5 * w), x1 - pad / 2 - text.width(s));
    text.draw(s, left, (int)std::lround(ay1_ + pad * 0.5 + text.ascent()), kInk, &fixed_);
  }
  // The axes: left and bottom edges of the area, and the zero line if it is inside.
  fixed_.lines.push_back({(float)ax0_, (float)ay0_, (float)ax0_, (float)ay1_, 1.0f, kAxis});
  fixed_.lines.push_back({(float)ax0_, (float)ay1_, (float)ax1_, (float)ay1_, 1.0f, kAxis});
  if (L_.v0 < 0 && L_.v1 > 0)
    fixed_.lines.push_back(
        {(float)ax0_, (float)px_y(0), (float)ax1_, (float)px_y(0), 1.0f, {255, 255, 255, 110}});
}

void InsetPlot::draw(const double* t, const float* const* series, int n, double t_now, ScreenLayer& out,
                     const float* now) const {
  out.append(fixed_);
  int last = -1;
  for (int k = 0; k < n && t[k] <= t_now + 1e-12; ++k) last = k;
  const float ylo = (float)ay0_, yhi = (float)ay1_;
  auto y_of = [&](float v) { return std::clamp((float)px_y(v), ylo, yhi); };
  for (size_t c = 0; c < L_.colors.size(); ++c) {
    const float* v = series[c];
    // A value not known yet (NaN: a period before it is measured) leaves a gap.
    for (int k = 0; k < last; ++k)
      if (std::isfinite(v[k]) && std::isfinite(v[k + 1]))
        out.lines.push_back({(float)px_x(t[k]), y_of(v[k]), (float)px_x(t[k + 1]), y_of(v[k + 1]),
                             L_.line_width, L_.colors[c]});
    if (now && last >= 0 && t_now > t[last] && t_now <= L_.t1 && std::isfinite(v[last]) &&
        std::isfinite(now[c]))
      out.lines.push_back({(float)px_x(t[last]), y_of(v[last]), (float)px_x(t_now), y_of(now[c]),
                           L_.line_width, L_.colors[c]});
  }
  if (t_now >= L_.t0 && t_now <= L_.t1) {
    const float x = (float)px_x(t_now);
    out.lines.push_back({x, (float)ay0_, x, (float)ay1_, 1.0f, kCursor});
  }
}

}  // namespace simreel
