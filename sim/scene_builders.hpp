// Reference scenes shared by tests, benchmarks and the demo scenes (one definition each).
//   R1 tumble: solid box 3 x 2 x 1 m, 6 kg, I = (2.5, 5, 6.5) kg m^2, no gravity, body angular
//              velocity (0.01, 5, 0.01) rad/s about its intermediate axis: it flips three times
//              in 20 s (the Dzhanibekov effect). Same scene as ../shared/anchors R1.
//   R2 free boxes: N boxes, sides uniform in 0.2..1 m, density 1000, random orientation, |w| up
//              to 10 rad/s, g = -9.81 z, on a 3 m grid; the same splitmix64 sequence as the
//              anchors, so the bodies are identical to the ones Bullet and MuJoCo stepped.
#pragma once
#include <cstdint>
#include <vector>

#include "sim/body.hpp"
#include "sim/world.hpp"

namespace simreel {

// splitmix64 (Steele, Lea, Flood 2014): identical sequences on every platform.
struct SplitMix64 {
  uint64_t s;
  explicit SplitMix64(uint64_t seed) : s(seed) {}
  uint64_t next();
  double uniform();                    ///< [0, 1)
  double uniform(double a, double b);  ///< [a, b)
};

BodyDef box_body(const char* name, const Vec3& size, double mass);
BodyDef r1_tumble_body();  ///< identity orientation, w_W = (0.01, 5, 0.01) rad/s
constexpr double kR1Duration = 20.0;
std::vector<BodyDef> r2_free_boxes(int n, uint64_t seed = 12345);

}  // namespace simreel
