// The shaders' sRGB encoding is a fitted sum of roots, not pow(): check it against the sRGB
// curve itself (IEC 61966-2-1) over the whole input range.
#include <gtest/gtest.h>

#include <cmath>

#include "render/shaders.hpp"

namespace simreel {
namespace {

double srgb(double l) {  // IEC 61966-2-1
  return l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055;
}

// Within 1e-4 (a fortieth of an 8-bit level, so the stored level is the curve's) everywhere in
// [0, 1], sampled finely near 0 where the curve is steepest; never decreasing by more than the fit's
// error (a brighter surface never comes out a level darker); exact at 0 and within 1e-4 at 1.
TEST(Shaders, SrgbEncodeFollowsTheStandardCurve) {
  float worst = 0, prev = -1;
  const int n = 200000;
  for (int i = 0; i <= n; ++i) {
    const double u = (double)i / n;
    const float x = (float)(u * u * u);  // dense near 0
    const float g = srgb_encode(x);
    worst = std::max(worst, std::fabs(g - (float)srgb(x)));
    EXPECT_GE(g, prev - 1e-4f) << "x = " << x;
    prev = g;
  }
  EXPECT_LT(worst, 1e-4f);
  EXPECT_EQ(srgb_encode(0.0f), 0.0f);
  EXPECT_NEAR(srgb_encode(1.0f), 1.0f, 1e-4f);
  EXPECT_EQ(srgb_encode(-0.5f), 0.0f);  // clamped, as in the shader
  EXPECT_EQ(srgb_encode(2.0f), srgb_encode(1.0f));
}

// The source the GPU compiles carries the same coefficients, written to read back exactly.
TEST(Shaders, FragmentShaderCarriesTheFittedCoefficients) {
  for (LitKind kind : {LitKind::body, LitKind::ground}) {
    const std::string src = lit_fragment_shader(kind);
    const size_t at = src.find("vec3 f = ");
    ASSERT_NE(at, std::string::npos);
    float c[5];
    ASSERT_EQ(std::sscanf(src.c_str() + at, "vec3 f = %f * s + %f * q + %f * e + c * (%f + %f * q)", &c[0],
                          &c[1], &c[4], &c[2], &c[3]),
              5);
    for (int k = 0; k < 5; ++k) EXPECT_EQ(c[k], kSrgbFit[k]);
    EXPECT_NE(src.find(kind == LitKind::ground ? "#define GROUND 1" : "#define GROUND 0"), std::string::npos);
  }
}

}  // namespace
}  // namespace simreel
