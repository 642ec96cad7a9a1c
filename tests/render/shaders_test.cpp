// The lit shader's gamma encoding is a fitted sum of roots, not pow(): check it against
// x^(1/2.2) itself over the whole input range.
#include <gtest/gtest.h>

#include <cmath>

#include "render/shaders.hpp"

namespace simreel {
namespace {

// Within 1e-3 (a quarter of an 8-bit level, so the stored level is pow()'s or its neighbour)
// everywhere in [0, 1], sampled finely near 0 where x^(1/2.2) is steepest; never decreasing
// (a brighter surface never comes out darker); exact at 0 and within 1e-3 at 1.
TEST(Shaders, GammaEncodeFollowsThePowerLaw) {
  float worst = 0, prev = -1;
  const int n = 200000;
  for (int i = 0; i <= n; ++i) {
    const double u = (double)i / n;
    const float x = (float)(u * u * u);  // dense near 0
    const float g = gamma_encode(x);
    worst = std::max(worst, std::fabs(g - (float)std::pow((double)x, 1 / 2.2)));
    EXPECT_GE(g, prev) << "x = " << x;
    prev = g;
  }
  EXPECT_LT(worst, 1e-3f);
  EXPECT_EQ(gamma_encode(0.0f), 0.0f);
  EXPECT_NEAR(gamma_encode(1.0f), 1.0f, 1e-3f);
  EXPECT_EQ(gamma_encode(-0.5f), 0.0f);  // clamped, as in the shader
  EXPECT_EQ(gamma_encode(2.0f), gamma_encode(1.0f));
}

// The source the GPU compiles carries the same coefficients, written to read back exactly.
TEST(Shaders, FragmentShaderCarriesTheFittedCoefficients) {
  for (LitKind kind : {LitKind::body, LitKind::ground}) {
    const std::string src = lit_fragment_shader(kind);
    const size_t at = src.find("const vec4 kGamma = vec4(");
    ASSERT_NE(at, std::string::npos);
    float c[4];
    ASSERT_EQ(
        std::sscanf(src.c_str() + at, "const vec4 kGamma = vec4(%f, %f, %f, %f)", &c[0], &c[1], &c[2], &c[3]),
        4);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(c[k], kGammaFit[k]);
    EXPECT_NE(src.find(kind == LitKind::ground ? "#define GROUND 1" : "#define GROUND 0"), std::string::npos);
  }
}

}  // namespace
}  // namespace simreel
