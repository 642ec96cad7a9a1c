// A 64-bit fingerprint of a world's motion state: FNV-1a over every body's q_WP (w x y z), x_W,
// v_W and w_P, value by value (no padding bytes). Two runs agree bit for bit exactly when their
// hashes do (to FNV's collision odds): what the determinism tests and the benches compare across
// thread counts, resumes and settings.
#pragma once
#include <cstdint>
#include <cstring>

#include "sim/world.hpp"

namespace simreel {

inline uint64_t state_hash(const World& w) {
  uint64_t h = 1469598103934665603ull;
  auto mix = [&h](double x) {
    unsigned char b[sizeof(double)];
    std::memcpy(b, &x, sizeof x);
    for (unsigned char c : b) {
      h ^= c;
      h *= 1099511628211ull;
    }
  };
  for (int i = 0; i < w.body_count(); ++i) {
    const MotionState& s = w.state(i);
    for (double x : {s.q_WP.w(), s.q_WP.x(), s.q_WP.y(), s.q_WP.z()}) mix(x);
    for (int k = 0; k < 3; ++k) mix(s.x_W[k]);
    for (int k = 0; k < 3; ++k) mix(s.v_W[k]);
    for (int k = 0; k < 3; ++k) mix(s.w_P[k]);
  }
  return h;
}

}  // namespace simreel
