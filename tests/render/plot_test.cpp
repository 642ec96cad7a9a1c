// Inset plots (render/plot.hpp): a curve's pixels lie where its data puts them, within a pixel; the
// curve stops at the present; ticks are round numbers; line coverage is what the screen layer says.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "render/plot.hpp"
#include "render/screen.hpp"

namespace simreel {
namespace {

constexpr int W = 640, H = 360;

TEST(Plot, NiceTicks) {
  EXPECT_EQ(InsetPlot::nice_ticks(0, 12, 6), (std::vector<double>{0, 2, 4, 6, 8, 10, 12}));
  EXPECT_EQ(InsetPlot::nice_ticks(-6.5, 6.5, 6), (std::vector<double>{-6, -4, -2, 0, 2, 4, 6}));
  const auto t = InsetPlot::nice_ticks(0.013, 0.087, 4);
  ASSERT_EQ(t.size(), 4u);
  EXPECT_NEAR(t[0], 0.02, 1e-15);
  EXPECT_NEAR(t[3], 0.08, 1e-15);
}

TEST(Plot, ALineCoversThePixelsItCrosses) {
  ScreenLayer l;
  l.lines.push_back({10.5f, 20.5f, 50.5f, 20.5f, 1.0f, {255, 255, 255, 255}});    // along row 20
  l.lines.push_back({100.0f, 10.0f, 100.0f, 40.0f, 3.0f, {255, 255, 255, 255}});  // columns 98.5 .. 101.5
  std::vector<uint8_t> img((size_t)W * H * 4, 0);
  composite(l, img.data(), W, H);
  auto at = [&](int x, int y) { return (int)img[((size_t)y * W + x) * 4]; };
  EXPECT_EQ(at(30, 20), 255);
  EXPECT_EQ(at(30, 19), 0);
  EXPECT_EQ(at(30, 21), 0);
  EXPECT_EQ(at(99, 25), 255);
  EXPECT_EQ(at(100, 25), 255);
  EXPECT_EQ(at(98, 25), 128);  // centre 98.5 is 1.5 px from the line: half covered
  EXPECT_EQ(at(101, 25), 128);
  EXPECT_EQ(at(97, 25), 0);
}

TEST(Plot, TheCurveLiesWhereTheDataPutsItWithinAPixel) {
  Typeface text(default_font_path(), 12);
  PlotLayout L;
  L.x = 40, L.y = 30, L.width = 520, L.height = 300;
  L.t0 = 0, L.t1 = 10;
  L.v0 = -1.3, L.v1 = 1.4;
  L.labels = {"\\omega_2"};
  L.colors = {{0, 255, 0, 255}};
  L.line_width = 2;
  InsetPlot plot(L, text);
  // y = sin(t) + 0.2 cos(3 t), sampled 400 times.
  std::vector<double> t;
  std::vector<float> v;
  auto f = [](double s) { return std::sin(s) + 0.2 * std::cos(3 * s); };
  for (int k = 0; k <= 400; ++k) t.push_back(10.0 * k / 400), v.push_back((float)f(t.back()));
  const float* series[1] = {v.data()};
  const double now = 7.0;
  ScreenLayer layer;
  plot.draw(t.data(), series, (int)t.size(), now, layer);
  std::vector<uint8_t> img((size_t)W * H * 4, 0);
  composite(layer, img.data(), W, H);
  // Green is the curve alone: the panel, grid, axes and text are grey.
  auto green = [&](int x, int y) {
    const uint8_t* p = &img[((size_t)y * W + x) * 4];
    return std::max(0, (int)p[1] - std::max((int)p[0], (int)p[2]));
  };
  int checked = 0;
  for (int x = (int)std::ceil(plot.area_x0()) + 2; x < (int)plot.px_x(now) - 2; ++x) {
    // The ink-weighted centre of the curve in this column, against the data at the column's centre.
    double sum = 0, wy = 0;
    for (int y = (int)plot.area_y0(); y <= (int)plot.area_y1(); ++y)
      sum += green(x, y), wy += green(x, y) * (y + 0.5);
    ASSERT_GT(sum, 0) << "column " << x;
    const double tc = L.t0 + (x + 0.5 - plot.area_x0()) / (plot.area_x1() - plot.area_x0()) * (L.t1 - L.t0);
    EXPECT_NEAR(wy / sum, plot.px_y(f(tc)), 1.0) << "column " << x << ", t = " << tc;
    ++checked;
  }
  EXPECT_GT(checked, 300);
  // After the present, nothing: the curve stops at the cursor.
  for (int x = (int)plot.px_x(now) + 3; x < (int)plot.area_x1(); ++x)
    for (int y = (int)plot.area_y0(); y <= (int)plot.area_y1(); ++y)
      ASSERT_EQ(green(x, y), 0) << x << "," << y;
  // The value axis's ticks are round numbers inside the range, at their pixels.
  ASSERT_GE(plot.ticks().size(), 3u);
  const double step = plot.ticks()[1] - plot.ticks()[0];
  EXPECT_GE(plot.ticks().front(), L.v0);
  EXPECT_LE(plot.ticks().back(), L.v1);
  for (double v : plot.ticks()) EXPECT_NEAR(v / step, std::round(v / step), 1e-9);
  EXPECT_NEAR(plot.px_y(L.v0), plot.area_y1(), 1e-9);
  EXPECT_NEAR(plot.px_y(L.v1), plot.area_y0(), 1e-9);
}

}  // namespace
}  // namespace simreel
