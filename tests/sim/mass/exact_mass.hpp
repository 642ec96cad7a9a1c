// Exact mass properties of a triangle mesh, for tests: the same divergence-theorem sums simreel
// uses (signed tetrahedra from the origin), done in exact integer arithmetic (GMP) on the mesh's
// double coordinates, so the only rounding is the final conversion to double.
//
// Every double is an integer times a power of two; all coordinates are scaled by one power 2^k that
// makes them integers, the sums run over integers, and the scale comes out at the end:
//   V6 = sum d, F = sum d s, S = sum d (a a^T + b b^T + c c^T + s s^T),  d = a.(b x c), s = a+b+c,
//   volume = V6 / 6, centroid = F / (4 V6), covariance about the centroid
//   C = S / 120 - F F^T / (96 V6), inertia (density 1) = tr(C) 1 - C.
#pragma once
#include <gmpxx.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <vector>

#include <simreel/mesh.hpp>

namespace simreel::test {

struct ExactMass {
  bool zero_volume = false;  ///< the signed volume is exactly zero
  double volume = 0;
  Vec3 centroid = Vec3::Zero();
  Mat3 inertia = Mat3::Zero();  ///< about the centroid, density 1
};

inline ExactMass exact_mass(const TriangleMesh& m) {
  // The smallest binary exponent of any mantissa bit: x = M 2^(e - 53) with M an integer.
  int lowest = INT_MAX;
  for (const Vec3& v : m.vertices)
    for (int k = 0; k < 3; ++k)
      if (v[k] != 0) {
        int e;
        std::frexp(v[k], &e);
        lowest = std::min(lowest, e - 53);
      }
  if (lowest == INT_MAX) lowest = 0;
  std::vector<std::array<mpz_class, 3>> X(m.vertices.size());
  for (size_t i = 0; i < m.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      int e;
      const double f = std::frexp(m.vertices[i][k], &e);
      mpz_class M((long)std::ldexp(f, 53));  // exact: f has 53 bits
      mpz_mul_2exp(M.get_mpz_t(), M.get_mpz_t(), (unsigned long)(e - 53 - lowest));
      X[i][k] = M;
    }
  const int k = -lowest;  // X = x 2^k
  mpz_class V6 = 0, d, t;
  std::array<mpz_class, 3> F{0, 0, 0}, s;
  std::array<mpz_class, 6> S{0, 0, 0, 0, 0, 0};  // xx, yy, zz, xy, xz, yz
  static const int I0[6] = {0, 1, 2, 0, 0, 1}, I1[6] = {0, 1, 2, 1, 2, 2};
  for (const auto& tri : m.triangles) {
    const auto &a = X[tri[0]], &b = X[tri[1]], &c = X[tri[2]];
    d = a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
        a[2] * (b[0] * c[1] - b[1] * c[0]);
    if (d == 0) continue;
    V6 += d;
    for (int j = 0; j < 3; ++j) {
      s[j] = a[j] + b[j] + c[j];
      F[j] += d * s[j];
    }
    for (int j = 0; j < 6; ++j) {
      const int p = I0[j], q = I1[j];
      t = a[p] * a[q] + b[p] * b[q] + c[p] * c[q] + s[p] * s[q];
      S[j] += d * t;
    }
  }
  ExactMass out;
  if (V6 == 0) {
    out.zero_volume = true;
    return out;
  }
  const mpq_class v6(V6);
  out.volume = std::ldexp(mpq_class(v6 / 6).get_d(), -3 * k);
  for (int j = 0; j < 3; ++j) out.centroid[j] = std::ldexp(mpq_class(mpq_class(F[j]) / (4 * v6)).get_d(), -k);
  Mat3 C;
  for (int j = 0; j < 6; ++j) {
    const int p = I0[j], q = I1[j];
    const mpq_class c = mpq_class(S[j]) / 120 - mpq_class(F[p] * F[q]) / (96 * v6);
    C(p, q) = C(q, p) = std::ldexp(c.get_d(), -5 * k);
  }
  out.inertia = C.trace() * Mat3::Identity() - C;
  return out;
}

}  // namespace simreel::test
