#include "sim/dynamics/integrators.hpp"

#include <algorithm>
#include <cmath>
#include "sim/base/enum_names.hpp"

namespace simreel {

namespace {
constexpr EnumNames<Integrator, 5> kIntegrators{{"auto", "seed", "euler_gyro", "rk4", "splitting"}};
static_assert(kIntegrators.complete());
}  // namespace

const char* to_string(Integrator i) {
  return kIntegrators(i);
}

std::optional<Integrator> integrator_from_name(std::string_view n) {
  return kIntegrators.parse(n);
}

const char* integrator_names() {
  return "auto, seed, euler_gyro, rk4, splitting";
}

Quat rotation_increment(const Vec3& w, double h) {
  const double wn = w.norm();
  const double half = 0.5 * wn * h;
  double c, k;  // exp(h w / 2) = (cos(half), k w) with k = sin(half) / |w|
  if (half < 1e-4) {
    // Taylor series: relative truncation error below half^6/5040 < 2e-28.
    const double h2 = half * half;
    c = 1.0 - h2 / 2.0 + h2 * h2 / 24.0;
    k = 0.5 * h * (1.0 - h2 / 6.0 + h2 * h2 / 120.0);
  } else {
    c = std::cos(half);
    k = std::sin(half) / wn;
  }
  return Quat(c, k * w.x(), k * w.y(), k * w.z());
}

namespace {

// Exact for a constant acceleration: x(h) = x + h v + h^2/2 a, v(h) = v + h a.
inline void linear_exact(MotionState& s, const Vec3& a, double h) {
  s.x_W += h * s.v_W + (0.5 * h * h) * a;
  s.v_W += h * a;
}
// Semi-implicit (symplectic) Euler, the article's: v += h a; x += h v.
inline void linear_semi_implicit(MotionState& s, const Vec3& a, double h) {
  s.v_W += h * a;
  s.x_W += h * s.v_W;
}

inline Vec3 acceleration(const BodyModel& m, const Wrench* w, const Vec3& g) {
  return w ? Vec3(g + m.inv_mass * w->f_W) : g;
}

// The RK4 rotation kernel is written once over a lane type T: `double` for one body, `Lanes` for
// four bodies at once (a GCC/Clang vector: one AVX2 register where the CPU has it, two SSE2
// halves otherwise). Each lane runs the same IEEE operations in the same order as the scalar code
// (no FMA: -ffp-contract=off, and the AVX2 clone does not enable FMA), so a body's result is
// bit-identical whether it was stepped alone or in a block, whatever the thread split.
using Lanes = double __attribute__((vector_size(32)));
constexpr int kLanes = 4;

// Scales the quaternion s[0..4) to unit length (out-parameter: returning a 32-byte vector by
// value would change the calling convention between the AVX2 and default clones).
inline void normalize_quat(double* s) {
  const double n = 1.0 / std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + s[3] * s[3]);
  for (int i = 0; i < 4; ++i) s[i] *= n;
}
[[gnu::always_inline]] inline void normalize_quat(Lanes* s) {
  const Lanes sq = s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + s[3] * s[3];
  Lanes n;
  for (int l = 0; l < kLanes; ++l) n[l] = 1.0 / std::sqrt(sq[l]);
  for (int i = 0; i < 4; ++i) s[i] *= n;
}

// Right-hand side of the rotational equations in the principal frame, on (q, w):
//   q' = 1/2 q (x) (0, w)                                  (quaternion kinematics)
//   w' = I^-1 (tau_P - w x I w),  tau_P = R(q)^T tau_W     (Euler's equations)
// Gyro = false drops w x I w (exact for isotropic bodies); Torque = false drops tau.
// s = (qw, qx, qy, qz, wx, wy, wz); tau_P = conj(q) tau_W q as Eigen computes a rotation:
// t = 2 u x v, v' = v + w t + u x t with u = -q.vec().
template <bool Gyro, bool Torque, typename T>
[[gnu::always_inline]] inline void rhs(const T* s, const T* I, const T* invI, const T* tau_W, T* d) {
  const T qw = s[0], qx = s[1], qy = s[2], qz = s[3], wx = s[4], wy = s[5], wz = s[6];
  d[0] = 0.5 * (-qx * wx - qy * wy - qz * wz);
  d[1] = 0.5 * (qw * wx + qy * wz - qz * wy);
  d[2] = 0.5 * (qw * wy + qz * wx - qx * wz);
  d[3] = 0.5 * (qw * wz + qx * wy - qy * wx);
  T tx{}, ty{}, tz{};
  if constexpr (Torque) {
    const T ux = -qx, uy = -qy, uz = -qz, vx = tau_W[0], vy = tau_W[1], vz = tau_W[2];
    const T cx = 2.0 * (uy * vz - uz * vy), cy = 2.0 * (uz * vx - ux * vz), cz = 2.0 * (ux * vy - uy * vx);
    tx = vx + qw * cx + (uy * cz - uz * cy);
    ty = vy + qw * cy + (uz * cx - ux * cz);
    tz = vz + qw * cz + (ux * cy - uy * cx);
  }
  if constexpr (Gyro) {
    const T Lx = I[0] * wx, Ly = I[1] * wy, Lz = I[2] * wz;
    tx -= wy * Lz - wz * Ly;
    ty -= wz * Lx - wx * Lz;
    tz -= wx * Ly - wy * Lx;
  }
  d[4] = invI[0] * tx;
  d[5] = invI[1] * ty;
  d[6] = invI[2] * tz;
}

// Classical fourth-order Runge-Kutta on s = (q, w_P) in place, quaternion renormalised after.
template <bool Gyro, bool Torque, typename T>
[[gnu::always_inline]] inline void rk4_rotation(T* s, const T* I, const T* invI, const T* tau_W, double h) {
  T k1[7], k2[7], k3[7], k4[7], t[7];
  rhs<Gyro, Torque>(s, I, invI, tau_W, k1);
  for (int i = 0; i < 7; ++i) t[i] = s[i] + 0.5 * h * k1[i];
  rhs<Gyro, Torque>(t, I, invI, tau_W, k2);
  for (int i = 0; i < 7; ++i) t[i] = s[i] + 0.5 * h * k2[i];
  rhs<Gyro, Torque>(t, I, invI, tau_W, k3);
  for (int i = 0; i < 7; ++i) t[i] = s[i] + h * k3[i];
  rhs<Gyro, Torque>(t, I, invI, tau_W, k4);
  const double h6 = h / 6.0;
  for (int i = 0; i < 7; ++i) s[i] += h6 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
  normalize_quat(s);
}

template <bool Gyro, bool Torque>
inline void rk4_rotation(MotionState& st, const BodyModel& m, const Vec3& tau_W, double h) {
  double s[7] = {st.q_WP.w(), st.q_WP.x(), st.q_WP.y(), st.q_WP.z(), st.w_P.x(), st.w_P.y(), st.w_P.z()};
  rk4_rotation<Gyro, Torque>(s, m.I_P.data(), m.inv_I_P.data(), tau_W.data(), h);
  st.q_WP = Quat(s[0], s[1], s[2], s[3]);
  st.w_P = Vec3(s[4], s[5], s[6]);
}

// Four torque-free gyroscopic bodies, one per lane: gather, step, scatter. A separate function so
// that it can be cloned for AVX2 (chosen at load time; both clones give identical results). Not in
// a ThreadSanitizer build: the clones' resolver runs before the sanitizer's runtime is up.
#if defined(__SANITIZE_THREAD__)
#define SIMREEL_RK4_TARGETS
#else
#define SIMREEL_RK4_TARGETS __attribute__((target_clones("avx2", "default")))
#endif
SIMREEL_RK4_TARGETS void rk4_rotation_block(MotionState* st, const BodyModel* mo, const int* idx, double h) {
  MotionState* b[kLanes];
  const BodyModel* m[kLanes];
  for (int l = 0; l < kLanes; ++l) b[l] = &st[idx[l]], m[l] = &mo[idx[l]];
  Lanes s[7], I[3], invI[3];
  for (int l = 0; l < kLanes; ++l) {
    s[0][l] = b[l]->q_WP.w(), s[1][l] = b[l]->q_WP.x(), s[2][l] = b[l]->q_WP.y(), s[3][l] = b[l]->q_WP.z();
    for (int k = 0; k < 3; ++k)
      s[4 + k][l] = b[l]->w_P[k], I[k][l] = m[l]->I_P[k], invI[k][l] = m[l]->inv_I_P[k];
  }
  rk4_rotation<true, false, Lanes>(s, I, invI, nullptr, h);
  for (int l = 0; l < kLanes; ++l) {
    b[l]->q_WP = Quat(s[0][l], s[1][l], s[2][l], s[3][l]);
    b[l]->w_P = Vec3(s[4][l], s[5][l], s[6][l]);
  }
}

inline void rk4_body(MotionState& s, const BodyModel& m, const Wrench* w, const Vec3& g, double h,
                     bool gyro) {
  linear_exact(s, acceleration(m, w, g), h);
  const bool torque = w && !w->tau_W.isZero(0.0);
  if (gyro) {
    if (torque)
      rk4_rotation<true, true>(s, m, w->tau_W, h);
    else
      rk4_rotation<true, false>(s, m, Vec3::Zero(), h);
  } else {
    if (torque)
      rk4_rotation<false, true>(s, m, w->tau_W, h);
    else
      rk4_rotation<false, false>(s, m, Vec3::Zero(), h);
  }
}

// The article's step: w_W += I_W^-1 tau h (with the corrected world inverse inertia
// R I^-1 R^T), no gyroscopic term, R <- Rot(w_W/|w_W|, |w_W| h) R, then UpdateOrientation
// (matrix -> quaternion -> normalise -> matrix). A zero w skips the rotation instead of
// normalising a zero vector.
inline void seed_body(MotionState& s, const BodyModel& m, const Wrench* w, const Vec3& g, double h) {
  Mat3 R = s.q_WP.toRotationMatrix();
  Vec3 w_W = R * s.w_P;
  if (w) w_W += R * m.inv_I_P.cwiseProduct(R.transpose() * w->tau_W) * h;
  linear_semi_implicit(s, acceleration(m, w, g), h);
  const double wn = w_W.norm();
  if (wn > 0) R = Eigen::AngleAxisd(wn * h, w_W / wn).toRotationMatrix() * R;
  s.q_WP = Quat(R).normalized();
  R = s.q_WP.toRotationMatrix();
  s.w_P = R.transpose() * w_W;
}

// Semi-implicit Euler with the implicit gyroscopic term (Catto, "Numerical methods", GDC 2015;
// Bullet's btRigidBody::computeGyroscopicImpulseImplicit_Body): one Newton step on
// f(w) = I (w - w0) + h w x I w = 0, Jacobian J = I + h (skew(w0) I - skew(I w0)).
inline void euler_gyro_body(MotionState& s, const BodyModel& m, const Wrench* w, const Vec3& g, double h) {
  const Vec3 w0 = s.w_P;
  const Vec3 Iw = m.I_P.cwiseProduct(w0);
  const Vec3 f = h * w0.cross(Iw);
  const Mat3 J = Mat3(m.I_P.asDiagonal()) + h * (skew(w0) * m.I_P.asDiagonal() - skew(Iw));
  Vec3 w1 = w0 - J.inverse() * f;
  if (w) w1 += h * m.inv_I_P.cwiseProduct(s.q_WP.conjugate() * w->tau_W);
  linear_semi_implicit(s, acceleration(m, w, g), h);
  s.w_P = w1;
  s.q_WP = (s.q_WP * rotation_increment(w1, h)).normalized();
}

// Free-rotor flow about principal axis i for time t: L_P turns by -theta about axis i and the
// orientation by +theta, theta = t L_i / I_i (both exact).
inline void free_rotor(Quat& q, Vec3& L, const Vec3& invI, int i, double t) {
  const double half = 0.5 * t * L[i] * invI[i];
  const double ch = std::cos(half), sh = std::sin(half);
  const double c = 1.0 - 2.0 * sh * sh, sn = 2.0 * sh * ch;
  const int j = (i + 1) % 3, k = (i + 2) % 3;
  const double Lj = L[j], Lk = L[k];
  L[j] = c * Lj + sn * Lk;
  L[k] = -sn * Lj + c * Lk;
  Quat r(ch, 0, 0, 0);
  r.vec()[i] = sh;
  q = q * r;
}

// Symmetric splitting of the free rigid body (Dullweber, Leimkuhler, McLachlan, "Symplectic
// splitting methods for rigid body molecular dynamics", J. Chem. Phys. 107, 1997): kinetic energy
// T = sum L_i^2 / 2 I_i split into three exactly solvable free rotors, composed as
// X(h/2) Y(h/2) Z(h) Y(h/2) X(h/2); torques enter as half kicks on L before and after (Strang).
// Second order, symplectic, each sub-step an exact rotation: world L and |L| are conserved to
// rounding and the energy error stays bounded over any run length.
inline void splitting_body(MotionState& s, const BodyModel& m, const Wrench* w, const Vec3& g, double h) {
  linear_exact(s, acceleration(m, w, g), h);
  Vec3 L = m.I_P.cwiseProduct(s.w_P);
  const bool torque = w && !w->tau_W.isZero(0.0);
  if (torque) L += 0.5 * h * (s.q_WP.conjugate() * w->tau_W);
  free_rotor(s.q_WP, L, m.inv_I_P, 0, 0.5 * h);
  free_rotor(s.q_WP, L, m.inv_I_P, 1, 0.5 * h);
  free_rotor(s.q_WP, L, m.inv_I_P, 2, h);
  free_rotor(s.q_WP, L, m.inv_I_P, 1, 0.5 * h);
  free_rotor(s.q_WP, L, m.inv_I_P, 0, 0.5 * h);
  s.q_WP.normalize();
  if (torque) L += 0.5 * h * (s.q_WP.conjugate() * w->tau_W);
  s.w_P = m.inv_I_P.cwiseProduct(L);
}

// Per body, what it needs: an isotropic body without torque keeps w (L = I w is conserved and
// w x I w = 0), so its rotation over the step is exactly exp(h w / 2); with torque it needs no
// gyroscopic work; everything else gets RK4 with the gyroscopic term. Fast spinners are
// substepped so that RK4 stays accurate and stable (World::check_spin warns); everything at
// ordinary rates takes exactly one step. Returns false for the common case, a torque-free
// gyroscopic body at an ordinary rate, which the caller steps in blocks.
inline bool auto_body_special(MotionState& s, const BodyModel& m, const Wrench* w, bool torque, const Vec3& g,
                              double h) {
  if (m.isotropic && !torque) {
    linear_exact(s, acceleration(m, w, g), h);
    s.q_WP = (s.q_WP * rotation_increment(s.w_P, h)).normalized();
    return true;
  }
  const double r = m.gyro_rate * h;
  const double w2 = s.w_P.squaredNorm();
  if (w2 * r * r > kAutoMaxStepAngle * kAutoMaxStepAngle) {
    const int n = (int)std::min<double>(kAutoMaxSubsteps, std::ceil(std::sqrt(w2) * r / kAutoMaxStepAngle));
    const double hs = h / n;
    for (int k = 0; k < n; ++k) rk4_body(s, m, w, g, hs, !m.isotropic);
    return true;
  }
  if (torque || m.isotropic) {
    rk4_body(s, m, w, g, h, !m.isotropic);
    return true;
  }
  return false;
}

// RK4 (Auto = false) or auto over a group: the torque-free gyroscopic bodies go through the
// four-lane kernel in blocks, the rest (and a last partial block) one by one; the results are the
// same either way (see Lanes).
template <bool Auto>
void rk4_group(const int* idx, int n, MotionState* st, const BodyModel* mo, const Wrench* wr, const Vec3& g,
               double h) {
  int block[kLanes];
  int nb = 0;
  for (int j = 0; j < n; ++j) {
    const int i = idx[j];
    MotionState& s = st[i];
    const BodyModel& m = mo[i];
    const Wrench* w = wr ? &wr[i] : nullptr;
    const bool torque = w && !w->tau_W.isZero(0.0);
    if constexpr (Auto) {
      if (auto_body_special(s, m, w, torque, g, h)) continue;
    } else if (torque) {
      rk4_body(s, m, w, g, h, true);
      continue;
    }
    linear_exact(s, acceleration(m, w, g), h);
    block[nb++] = i;
    if (nb == kLanes) {
      rk4_rotation_block(st, mo, block, h);
      nb = 0;
    }
  }
  for (int k = 0; k < nb; ++k) rk4_rotation<true, false>(st[block[k]], mo[block[k]], Vec3::Zero(), h);
}

template <typename Kernel>
inline void loop(Kernel k, const int* idx, int n, MotionState* st, const BodyModel* mo, const Wrench* wr,
                 const Vec3& g, double h) {
  if (wr) {
    for (int j = 0; j < n; ++j) k(st[idx[j]], mo[idx[j]], &wr[idx[j]], g, h);
  } else {
    for (int j = 0; j < n; ++j) k(st[idx[j]], mo[idx[j]], nullptr, g, h);
  }
}

}  // namespace

void state_derivative(const double* y, const BodyModel& m, const Wrench& w, const Vec3& g, double* dy) {
  for (int k = 0; k < 3; ++k) {
    dy[k] = y[3 + k];
    dy[3 + k] = g[k] + m.inv_mass * w.f_W[k];
  }
  if (m.isotropic)
    rhs<false, false>(y + 6, m.I_P.data(), m.inv_I_P.data(), (const double*)nullptr, dy + 6);
  else
    rhs<true, false>(y + 6, m.I_P.data(), m.inv_I_P.data(), (const double*)nullptr, dy + 6);
  // The torque into the principal frame by the stage's quaternion scaled to unit length, the
  // rotation the forces were evaluated with (World's forced RK4): a body-frame torque comes back
  // exactly (rotating by the raw stage quaternion, off the unit sphere by O(h^5), mixes its axes:
  // a spin-up about a principal axis drifted off it by 6e-9 rad/s in 1 s, measured).
  if (!w.tau_W.isZero(0.0)) {
    const Vec3 tau_P = Quat(y[6], y[7], y[8], y[9]).normalized().conjugate() * w.tau_W;
    for (int k = 0; k < 3; ++k) dy[10 + k] += m.inv_I_P[k] * tau_P[k];
  }
}

void integrate(Integrator method, const int* idx, int n, MotionState* st, const BodyModel* mo,
               const Wrench* wr, const Vec3& g, double h) {
  switch (method) {
    case Integrator::automatic:
      rk4_group<true>(idx, n, st, mo, wr, g, h);
      break;
    case Integrator::seed:
      loop(seed_body, idx, n, st, mo, wr, g, h);
      break;
    case Integrator::euler_gyro:
      loop(euler_gyro_body, idx, n, st, mo, wr, g, h);
      break;
    case Integrator::splitting:
      loop(splitting_body, idx, n, st, mo, wr, g, h);
      break;
    case Integrator::rk4:
      rk4_group<false>(idx, n, st, mo, wr, g, h);
      break;
  }
}

}  // namespace simreel
