#include "sim/solver/contact_wide.hpp"

#include <cmath>

#include "sim/solver/contact_solver.hpp"

namespace simreel::wide {

namespace {

// Lane-wise arithmetic is the vector types' own (IEEE, per lane, no contraction: the build has
// -ffp-contract=off), so a lane computes what the same expression on doubles would. Every helper
// that takes or returns a vector type is always inlined: the solver's functions are cloned per
// target (AVX-512, AVX2, default), and a helper left out of line (a Debug build) returns its
// vector by the default target's convention to a caller expecting another's (a crash at -O0).
__attribute__((always_inline)) inline Real splat(double x) {
  Real r;
  for (int l = 0; l < kLanes; ++l) r[l] = x;
  return r;
}
__attribute__((always_inline)) inline Mask msplat(std::int64_t x) {
  Mask r;
  for (int l = 0; l < kLanes; ++l) r[l] = x;
  return r;
}
constexpr Mask kNone = {};     ///< every lane false
constexpr Mask kAll = ~kNone;  ///< every lane true
__attribute__((always_inline)) inline Real sel(Mask m, Real a, Real b) {
  return (Real)((m & (Mask)a) | (~m & (Mask)b));
}
__attribute__((always_inline)) inline Real vmax(Real a, Real b) {
  return sel(a < b, b, a);
}  // std::max's order
__attribute__((always_inline)) inline Real vmin(Real a, Real b) {
  return sel(b < a, b, a);
}  // std::min's order
__attribute__((always_inline)) inline Real vabs(Real a) {
  return sel(a < 0.0, -a, a);
}
// The lanes' square roots (IEEE: each lane's is std::sqrt's; one vector instruction where the
// file is built without errno for sqrt, CMakeLists.txt).
__attribute__((always_inline)) inline Real vsqrt(Real a) {
  Real r;
  for (int l = 0; l < kLanes; ++l) r[l] = __builtin_sqrt(a[l]);
  return r;
}
__attribute__((always_inline)) inline bool any(Mask m) {
  std::int64_t o = 0;
  for (int l = 0; l < kLanes; ++l) o |= m[l];
  return o != 0;
}

__attribute__((always_inline)) inline Vec operator+(const Vec& a, const Vec& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
__attribute__((always_inline)) inline Vec operator-(const Vec& a, const Vec& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
__attribute__((always_inline)) inline Vec operator*(Real s, const Vec& a) {
  return {s * a.x, s * a.y, s * a.z};
}
__attribute__((always_inline)) inline Real dot(const Vec& a, const Vec& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
__attribute__((always_inline)) inline Vec cross(const Vec& a, const Vec& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// A symmetric 3x3 (the world inverse inertia R I^-1 R^T).
struct Sym {
  Real xx, xy, xz, yy, yz, zz;
};
__attribute__((always_inline)) inline Vec operator*(const Sym& I, const Vec& v) {
  return {I.xx * v.x + I.xy * v.y + I.xz * v.z, I.xy * v.x + I.yy * v.y + I.yz * v.z,
          I.xz * v.x + I.yz * v.y + I.zz * v.z};
}

// One side's four bodies (the static body reads as zero velocity, mass and inertia).
struct Bodies {
  Vec v, w;
  Real inv_mass;
  Sym inv_I;
};

// Lane l's value of `expr` read off body b<l> (declared by SIMREEL_BODIES from sb and idx).
static_assert(kLanes == 4, "the gathers below spell out four lanes");
#define SIMREEL_BODIES const SolverBody &b0 = sb[idx[0]], &b1 = sb[idx[1]], &b2 = sb[idx[2]], &b3 = sb[idx[3]]
#define SIMREEL_LANES(expr)            \
  Real {                               \
    b0.expr, b1.expr, b2.expr, b3.expr \
  }

// Velocities and inverse mass from the bodies, inverse inertia from the bundle (inv_IA or inv_IB).
__attribute__((always_inline)) inline Bodies gather(const SolverBody* sb, const int* idx, const Real* inv_I) {
  SIMREEL_BODIES;
  Bodies o;
  o.v = {SIMREEL_LANES(v.x()), SIMREEL_LANES(v.y()), SIMREEL_LANES(v.z())};
  o.w = {SIMREEL_LANES(w.x()), SIMREEL_LANES(w.y()), SIMREEL_LANES(w.z())};
  o.inv_mass = SIMREEL_LANES(inv_mass);
  o.inv_I = {inv_I[0], inv_I[1], inv_I[2], inv_I[3], inv_I[4], inv_I[5]};
  return o;
}

// R^T n for each lane's body, R its rotation so far this step (the quaternion dq = (c, u)): n.(R c)
// = (R^T n).c, one rotation per body instead of one per point. R^T n = n - c t + u x t with t = 2 u
// x n (the conjugate's rotation).
__attribute__((always_inline)) inline Vec rotated_back(const SolverBody* sb, const int* idx, const Vec& n) {
  SIMREEL_BODIES;
  const Vec u{SIMREEL_LANES(dq.x()), SIMREEL_LANES(dq.y()), SIMREEL_LANES(dq.z())};
  const Real c = SIMREEL_LANES(dq.w());
  const Vec t = splat(2.0) * cross(u, n);
  return (n - c * t) + cross(u, t);
}

__attribute__((always_inline)) inline Vec displacement(const SolverBody* sb, const int* idx) {
  SIMREEL_BODIES;
  return {SIMREEL_LANES(dp.x()), SIMREEL_LANES(dp.y()), SIMREEL_LANES(dp.z())};
}

#undef SIMREEL_LANES
#undef SIMREEL_BODIES

// The moving bodies' velocities back (the static body, shared by every ground contact and read
// by other threads, is never written; neither is an empty lane's).
__attribute__((always_inline)) inline void scatter(SolverBody* sb, const int* idx, const Bodies& o) {
  for (int l = 0; l < kLanes; ++l) {
    if (idx[l] == 0) continue;
    SolverBody& b = sb[idx[l]];
    b.v = Vec3(o.v.x[l], o.v.y[l], o.v.z[l]);
    b.w = Vec3(o.w.x[l], o.w.y[l], o.w.z[l]);
  }
}

// Index of K_ij in a symmetric 4x4 stored as its lower triangle row by row.
constexpr int lower(int i, int j) {
  return i >= j ? i * (i + 1) / 2 + j : j * (j + 1) / 2 + i;
}

// Solves A x = r for a symmetric positive definite 4x4 A (lower triangle row by row) by LDL^T;
// returns the lanes whose pivots are positive (relatively: K + eps diag(K) of a face on a face is
// near singular by design).
__attribute__((always_inline)) inline Mask ldlt_solve(const Real* A, const Real* r, Real* x) {
  const Real D0 = A[0];
  const Real L10 = A[1] / D0, L20 = A[3] / D0, L30 = A[6] / D0;
  const Real D1 = A[2] - L10 * A[1];
  const Real M21 = A[4] - L20 * A[1], M31 = A[7] - L30 * A[1];
  const Real L21 = M21 / D1, L31 = M31 / D1;
  const Real D2 = (A[5] - L20 * A[3]) - L21 * M21;
  const Real M32 = (A[8] - L30 * A[3]) - L31 * M21;
  const Real L32 = M32 / D2;
  const Real D3 = ((A[9] - L30 * A[6]) - L31 * M31) - L32 * M32;
  const Real y0 = r[0], y1 = r[1] - L10 * y0, y2 = (r[2] - L20 * y0) - L21 * y1;
  const Real y3 = ((r[3] - L30 * y0) - L31 * y1) - L32 * y2;
  x[3] = y3 / D3;
  x[2] = y2 / D2 - L32 * x[3];
  x[1] = (y1 / D1 - L21 * x[2]) - L31 * x[3];
  x[0] = ((y0 / D0 - L10 * x[1]) - L20 * x[2]) - L30 * x[3];
  return (D0 > 1e-14 * A[0]) & (D1 > 1e-14 * A[2]) & (D2 > 1e-14 * A[5]) & (D3 > 1e-14 * A[9]);
}

// Point j's normal mass 1 / K_jj, as ContactSolver::normal_terms makes it (K_jj is the same sum,
// bit for bit; an absent point's K_jj is 1).
__attribute__((always_inline)) inline Real normal_mass(const Bundle& k, int j) {
  const Real Kjj = k.K[lower(j, j)];
  return sel(Kjj > 0.0, 1.0 / Kjj, splat(0));
}

// Point j's normal velocity from its bodies' velocities before the substep's contact impulses (an
// impact's approach speed; a velocity read within a sweep carries the impulses the sweep has
// applied so far), per lane: called only where a point may have been struck. (Out of line, called
// from the sweeps' clones: so no vector type crosses the call, whose convention differs between
// them.)
void start_normal_velocity(const Bundle& k, int j, const BodyImpulse* start, double* r) {
  for (int l = 0; l < kLanes; ++l) {
    const BodyImpulse &A = start[k.a[l]], &B = start[k.b[l]];
    const Vec3 n(k.n.x[l], k.n.y[l], k.n.z[l]);
    const Vec3 cA(k.p[j].cA.x[l], k.p[j].cA.y[l], k.p[j].cA.z[l]);
    const Vec3 cB(k.p[j].cB.x[l], k.p[j].cB.y[l], k.p[j].cB.z[l]);
    r[l] = (n.dot(B.v0) + B.w0.dot(cB.cross(n))) - (n.dot(A.v0) + A.w0.dot(cA.cross(n)));
  }
}

__attribute__((always_inline)) inline Mask lane_count(const Bundle& k) {
  Mask m;
  for (int l = 0; l < kLanes; ++l) m[l] = k.count[l];
  return m;
}

// An impulse on both sides: linear part L (along which the lanes push B and pull A), angular
// parts about each centre of mass aA, aB (already r x P).
__attribute__((always_inline)) inline void apply(Bodies& A, Bodies& B, const Vec& L, const Vec& aA,
                                                 const Vec& aB) {
  A.v = A.v - A.inv_mass * L;
  A.w = A.w - A.inv_I * aA;
  B.v = B.v + B.inv_mass * L;
  B.w = B.w + B.inv_I * aB;
}

}  // namespace

void clear_lane(Bundle& k, int l) {
  k.a[l] = k.b[l] = 0;
  k.count[l] = 0;
  k.contact[l] = -1;
  for (int e = 0; e < 6; ++e) k.inv_IA[e][l] = k.inv_IB[e][l] = 0;
  for (Vec* v : {&k.n, &k.t0, &k.fA, &k.fB}) v->x[l] = v->y[l] = v->z[l] = 0;
  k.friction[l] = k.twist_mass[l] = 0;
  k.tangent_mass[0][l] = k.tangent_mass[1][l] = k.tangent_mass[2][l] = 0;
  k.tangent_impulse0[l] = k.tangent_impulse1[l] = k.twist_impulse[l] = 0;
  for (Point& p : k.p) {
    p.cA.x[l] = p.cA.y[l] = p.cA.z[l] = p.cB.x[l] = p.cB.y[l] = p.cB.z[l] = 0;
    p.adjusted_separation[l] = 0;
    p.lever[l] = p.normal_impulse[l] = 0;
  }
  for (int i = 0, e = 0; i < 4; ++i)
    for (int j = 0; j <= i; ++j, ++e) k.K[e][l] = i == j ? 1.0 : 0.0;
  k.touched[l] = 0;
}

void set_lane(Bundle& k, int l, const ContactConstraint& f, const double* K, const Mat3& inv_IA,
              const Mat3& inv_IB) {
  clear_lane(k, l);
  k.a[l] = f.a;
  k.b[l] = f.b;
  const int row[6] = {0, 0, 0, 1, 1, 2}, col[6] = {0, 1, 2, 1, 2, 2};
  for (int e = 0; e < 6; ++e) {
    k.inv_IA[e][l] = inv_IA(row[e], col[e]);
    k.inv_IB[e][l] = inv_IB(row[e], col[e]);
  }
  k.count[l] = f.count;
  k.contact[l] = f.contact;
  auto put = [l](Vec& v, const Vec3& x) {
    v.x[l] = x.x();
    v.y[l] = x.y();
    v.z[l] = x.z();
  };
  put(k.n, f.n);
  put(k.t0, f.t[0]);
  put(k.fA, f.fA);
  put(k.fB, f.fB);
  k.friction[l] = f.friction;
  k.twist_mass[l] = f.twist_mass;
  k.tangent_mass[0][l] = f.tangent_mass(0, 0);
  k.tangent_mass[1][l] = f.tangent_mass(0, 1);
  k.tangent_mass[2][l] = f.tangent_mass(1, 1);
  k.tangent_impulse0[l] = f.tangent_impulse[0];
  k.tangent_impulse1[l] = f.tangent_impulse[1];
  k.twist_impulse[l] = f.twist_impulse;
  for (int j = 0; j < f.count; ++j) {
    const ConstraintPoint& fp = f.p[j];
    Point& p = k.p[j];
    put(p.cA, fp.cA);
    put(p.cB, fp.cB);
    p.adjusted_separation[l] = fp.adjusted_separation;
    p.lever[l] = fp.lever;
    p.normal_impulse[l] = fp.normal_impulse;
  }
  for (int i = 0, e = 0; i < 4; ++i)
    for (int j = 0; j <= i; ++j, ++e)
      if (i < f.count && j < f.count) k.K[e][l] = K[e];
}

// Both sweeps built twice, for AVX2 (four doubles an instruction) and for the baseline x86-64 (two),
// chosen at load time; the same operations on the same lanes, so the same results either way.
// Clang checks the vector calling convention at each call before inlining, so an AVX2 clone may not
// call the helpers above (built for the baseline): a clang build runs the baseline sweeps only. A
// ThreadSanitizer build too: the clones' resolver runs before the sanitizer's runtime is up.
#if defined(__clang__) || defined(__SANITIZE_THREAD__)
#define SIMREEL_WIDE_TARGETS
#else
#define SIMREEL_WIDE_TARGETS __attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#endif

SIMREEL_WIDE_TARGETS void warm_start(const Bundle& k, SolverBody* sb) {
  Mask held = (k.tangent_impulse0 != 0.0) | (k.tangent_impulse1 != 0.0) | (k.twist_impulse != 0.0);
  for (const Point& p : k.p) held |= p.normal_impulse != 0.0;
  if (!any(held)) return;  // nothing to apply (a bundle of manifolds apart)
  Bodies A = gather(sb, k.a, k.inv_IA), B = gather(sb, k.b, k.inv_IB);
  // The normal impulses' angular parts sum(l_j c_j x n) = (sum l_j c_j) x n.
  Real total = splat(0);
  Vec cA{total, total, total}, cB = cA;
  for (int j = 0; j < 4; ++j) {
    const Point& p = k.p[j];
    const Real l = p.normal_impulse;
    total = total + l;
    cA = cA + l * p.cA;
    cB = cB + l * p.cB;
  }
  const Vec P = k.tangent_impulse0 * k.t0 + k.tangent_impulse1 * cross(k.n, k.t0);
  const Vec L = total * k.n + P;
  const Vec twist = k.twist_impulse * k.n;
  apply(A, B, L, cross(cA, k.n) + cross(k.fA, P) + twist, cross(cB, k.n) + cross(k.fB, P) + twist);
  scatter(sb, k.a, A);
  scatter(sb, k.b, B);
}

SIMREEL_WIDE_TARGETS bool solve(Bundle& k, SolverBody* sb, const SolveParams& q) {
  Bodies A = gather(sb, k.a, k.inv_IA), B = gather(sb, k.b, k.inv_IB);
  const Mask count = lane_count(k);
  const Real zero = splat(0);
  // The lane's softness: against a static or kinematic body (no mass to move), or between two
  // moving bodies.
  const Mask fixed = (A.inv_mass == 0.0) | (B.inv_mass == 0.0);
  const Real bias_rate = sel(fixed, splat(q.bias_rate[1]), splat(q.bias_rate[0]));
  const Real mass_scale = sel(fixed, splat(q.mass_scale[1]), splat(q.mass_scale[0]));
  const Real impulse_scale = sel(fixed, splat(q.impulse_scale[1]), splat(q.impulse_scale[0]));

  // Separation now of each point: each surface's centre of curvature moved with its body since
  // the manifold was made (ManifoldSolve's constructor).
  const Vec nRA = rotated_back(sb, k.a, k.n), nRB = rotated_back(sb, k.b, k.n);
  const Real ndp = dot(k.n, displacement(sb, k.b) - displacement(sb, k.a));
  Real s[4];
  Mask in[4];  // the lane has point j
  for (int j = 0; j < 4; ++j) {
    const Point& p = k.p[j];
    s[j] = ((ndp + dot(nRB, p.cB)) - dot(nRA, p.cA)) + p.adjusted_separation;
    in[j] = count > j;
  }

  // Each point's row: its bias, whether it is speculative (apart at the substep's start: rigid,
  // closing at most the gap), whether the relax may only release it (apart by more than
  // `apart`), and the normal velocity now.
  Real bias[4], vn[4];
  Mask spec[4], release[4];
  // The lever arms are r x n = c x n (the anchor and the centre of curvature differ along n), and
  // w.(c x n) = c.(n x w): one cross product per body, not one per point.
  const Real nvA = dot(k.n, A.v), nvB = dot(k.n, B.v);
  const Vec nwA = cross(k.n, A.w), nwB = cross(k.n, B.w);
  for (int j = 0; j < 4; ++j) {
    spec[j] = s[j] > 0.0;
    const Real soft_bias =
        q.use_bias ? vmax(bias_rate * vmin(zero, s[j] + q.slop), splat(-q.max_push)) : zero;
    bias[j] = sel(spec[j], s[j] * q.inv_h, soft_bias);
    release[j] = q.use_bias ? kNone : (s[j] > q.apart);
    vn[j] = (nvB + dot(k.p[j].cB, nwB)) - (nvA + dot(k.p[j].cA, nwA));
  }
  // A lane whose points are all apart, hold no impulse and will not close their gaps this
  // substep (or may only release) is left as it is: a pass would give each point max(c (vn +
  // s / h), 0) = 0 (c < 0) and move nothing. (The sides of the large pyramid's rows, a gap
  // apart: a quarter of its manifolds.)
  Mask quiet = count > 0;
  for (int j = 0; j < 4; ++j)
    quiet &= ~in[j] | (spec[j] & (k.p[j].normal_impulse == 0.0) & (release[j] | (vn[j] + bias[j] >= 0.0)));
  // A bundle of such lanes with no friction or twist impulse either comes out as it went in.
  if (!any(~quiet & (count > 0)) &&
      !any((k.tangent_impulse0 != 0.0) | (k.tangent_impulse1 != 0.0) | (k.twist_impulse != 0.0)))
    return false;

  // The block solve: the fixed point the passes converge to, at once (docs/contacts.md "Block
  // solve"). In the solve every row is soft, D_ii = d K_ii (d = impulse_scale / mass_scale); in
  // the relax every row is rigid with bias s / h for a point a little apart, and D_ii = eps K_ii
  // (kBlockRegularisation):
  //   (K + D) x = -(vn + b) - D_soft l0,
  // solved by LDL^T (K + D is positive definite: K is J M^-1 J^T, positive semi-definite, and D
  // positive). Accepted where every accumulated impulse l0 + x stays >= 0 (the clamps inactive:
  // then it is the passes' limit exactly); the other lanes run the passes.
  const Real d = q.use_bias ? sel(fixed, splat(q.d[1]), splat(q.d[0])) : zero;
  Real dr[4], Kd[4];
  for (int j = 0; j < 4; ++j) {
    const Real Kjj = k.K[j * (j + 1) / 2 + j];
    const Mask soft = ~spec[j] & (q.use_bias ? kAll : kNone);
    dr[j] = sel(soft, d, zero) * Kjj;
    Kd[j] = Kjj + sel(soft, d, splat(kBlockRegularisation)) * Kjj;
  }
  Real r[4];
  for (int j = 0; j < 4; ++j) r[j] = sel(in[j], -(vn[j] + bias[j]) - dr[j] * k.p[j].normal_impulse, zero);
  // Where a point's impulse would come out negative (a corner lifting off), the most negative is
  // let go (impulse 0, x_i = -l0_i) and the others solved again: the exact solution of the
  // complementarity problem the passes converge to (K + D positive definite: it has one), when
  // the points let go do not then approach (vn_i + b_i >= 0 with everyone's change). Up to two
  // points let go, then the passes.
  // A point apart that holds no impulse and is not closing its gap (the quiet test above, per
  // point: a corner a little off its support) starts let go. Other speculative points in the
  // solve (an impact arriving) and release-only ones in the relax send the lane to the passes, as
  // ManifoldSolve::block does. (Solved in the block too, exactly, the R3 column's landing went
  // 0.97 -> 1.01 mm deep and the pile's 0.96 -> 1.27 mm; starts a few tenths of a millimetre
  // higher spread as widely either way, 0.8-1.8 mm, see the issue note: kept for the figures.)
  Mask act[4];
  Mask open = ~quiet & (count > 0), ok = kNone;
  for (int j = 0; j < 4; ++j) {
    const Mask idle =
        in[j] & spec[j] & (k.p[j].normal_impulse == 0.0) & (release[j] | (vn[j] + bias[j] >= 0.0));
    act[j] = in[j] & ~idle;
    open &= ~(act[j] & (q.use_bias ? spec[j] : release[j]));
  }
  Real x[4] = {zero, zero, zero, zero}, sum[4];
  for (int round = 0; round < 3 && any(open); ++round) {
    Real A[10], rr[4], xf[4], xr[4];
    for (int i = 0; i < 4; ++i) xf[i] = sel(act[i], zero, -k.p[i].normal_impulse);
    for (int i = 0, e = 0; i < 4; ++i)
      for (int j = 0; j <= i; ++j, ++e)
        A[e] = i == j ? sel(act[i], Kd[i], splat(1)) : sel(act[i] & act[j], k.K[e], zero);
    for (int i = 0; i < 4; ++i) {
      Real ri = r[i];
      for (int j = 0; j < 4; ++j)
        if (j != i) ri = ri - k.K[lower(i, j)] * xf[j];
      rr[i] = sel(act[i], ri, xf[i]);
    }
    Mask good = open & ldlt_solve(A, rr, xr);
    Mask drop = kNone;
    Real scale = splat(1e-300), least = zero;
    Mask worst = kAll;  // the point with the most negative impulse (-1: none)
    for (int i = 0; i < 4; ++i) {
      const Real si = k.p[i].normal_impulse + xr[i];
      scale = vmax(scale, si);
      const Mask lower_still = act[i] & (si < least);
      least = sel(lower_still, si, least);
      worst = (lower_still & msplat(i)) | (~lower_still & worst);
    }
    for (int i = 0; i < 4; ++i) {
      const Real si = k.p[i].normal_impulse + xr[i];
      const Mask neg = act[i] & (si < 0.0);
      drop |= neg;
      good &= ~neg;
      // A point let go must not approach, its velocity taken with everyone's change: not by
      // more than a pass would answer with an impulse of a 1e-4th of the largest (the passes'
      // own test of convergence, kRestingTolerance: rounding leaves a point on the edge of
      // contact a little either way).
      const Mask off = in[i] & ~act[i] & ~release[i];
      if (any(off)) {
        Real vf = vn[i];
        for (int j = 0; j < 4; ++j) vf = vf + k.K[lower(i, j)] * xr[j];
        good &= ~(off & (-(vf + bias[i]) * normal_mass(k, i) > 1e-4 * scale));
      }
      // Only the most negative is let go (a face on a face whose corners' gaps are not in one
      // plane: its singular K pushes the solution along (+1, -1, +1, -1), two corners negative,
      // and three corners hold it).
      act[i] &= ~(worst == i);
    }
    for (int i = 0; i < 4; ++i) x[i] = sel(good, xr[i], x[i]);
    ok |= good;
    open &= ~good & drop;  // a lane fails for good unless it has points to let go
  }
  for (int i = 0; i < 4; ++i) sum[i] = k.p[i].normal_impulse + x[i];
  Real total_normal = zero, twist_limit = zero;
  Mask struck = kNone;
  if (any(ok)) {
    // The impulses' angular parts sum(x_j c_j x n) = (sum x_j c_j) x n.
    Real X = zero;
    Vec cA{zero, zero, zero}, cB = cA;
    for (int j = 0; j < 4; ++j) {
      Point& p = k.p[j];
      const Mask m = ok & in[j];
      const Real xj = sel(m, x[j], zero);
      X = X + xj;
      cA = cA + xj * p.cA;
      cB = cB + xj * p.cB;
      p.normal_impulse = sel(m, sum[j], p.normal_impulse);
      k.touched |= m & (sum[j] > 0.0);
      total_normal = total_normal + sel(m, sum[j], zero);
      twist_limit = twist_limit + sel(m, p.lever * sum[j], zero);
    }
    apply(A, B, X * k.n, cross(cA, k.n), cross(cB, k.n));
  }

  // The passes (ManifoldSolve::point and end_pass) for the other lanes, masked: symmetric
  // Gauss-Seidel over the points (backwards on odd passes: j from 3 down, a lane's absent points
  // masked, is each lane's own count - 1 down to 0), until each lane's manifold has converged.
  Mask done = ok | quiet | (count == 0);
  if (any(~done)) {
    Vec rnA[4], rnB[4], IrnA[4], IrnB[4];
    Real c[4], is[4];
    for (int j = 0; j < 4; ++j) {
      rnA[j] = cross(k.p[j].cA, k.n);
      rnB[j] = cross(k.p[j].cB, k.n);
      IrnA[j] = A.inv_I * rnA[j];
      IrnB[j] = B.inv_I * rnB[j];
      // Speculative: close the gap within this substep, no more, rigid. Else soft with bias
      // (solve) or rigid without (relax).
      const Mask soft = ~spec[j] & (q.use_bias ? kAll : kNone);
      const Real ms = sel(soft, mass_scale, splat(1));
      is[j] = sel(soft, impulse_scale, zero);
      c[j] = -normal_mass(k, j) * ms;
    }
    const Vec nA = A.inv_mass * k.n, nB = B.inv_mass * k.n;
    Mask had_impact = kNone;
    for (int pass = 0; any(~done); ++pass) {
      Real total_pass = zero, twist_pass = zero, change = zero, scale = splat(1e-300);
      Mask impact = kNone;
      for (int jj = 0; jj < 4; ++jj) {
        const int j = (pass & 1) ? 3 - jj : jj;
        Point& p = k.p[j];
        const Mask m = ~done & in[j];
        const Real base = (p.normal_impulse - is[j] * p.normal_impulse) + c[j] * bias[j];
        const Real vn = (dot(k.n, B.v) + dot(B.w, rnB[j])) - (dot(k.n, A.v) + dot(A.w, rnA[j]));
        Real total = vmax(base + c[j] * vn, zero);
        total = sel(release[j], vmin(total, p.normal_impulse), total);
        const Real lambda = sel(m, total - p.normal_impulse, zero);
        p.normal_impulse = sel(m, total, p.normal_impulse);
        k.touched |= m & (total > 0.0);
        total_pass = total_pass + sel(m, total, zero);
        twist_pass = twist_pass + sel(m, p.lever * total, zero);
        const Mask hit = m & spec[j] & (total > 0.0);
        impact |= hit;
        const Mask fast = hit & (vn < -kImpactSpeed);
        if (q.use_bias && any(fast)) {  // (the relax's `struck` is not used)
          double v0[kLanes];
          start_normal_velocity(k, j, q.start, v0);
          Real v;
          for (int l = 0; l < kLanes; ++l) v[l] = v0[l];
          struck |= fast & (v < -kImpactSpeed);
        }
        change = vmax(change, vabs(lambda));
        scale = vmax(scale, sel(m, total, zero));
        A.v = A.v - lambda * nA;
        A.w = A.w - lambda * IrnA[j];
        B.v = B.v + lambda * nB;
        B.w = B.w + lambda * IrnB[j];
      }
      const Mask active = ~done;
      total_normal = sel(active, total_pass, total_normal);
      twist_limit = sel(active, twist_pass, twist_limit);
      had_impact |= impact;
      const Real tolerance = sel(had_impact, splat(1e-6), splat(1e-4));
      const Mask passes_done = (pass + 1 >= q.resting_passes) ? ~impact : kNone;
      done |= (count == 1) | passes_done | (change <= tolerance * scale);
      if (pass + 1 >= 32) done = kAll;
    }
  }

  // Friction at the centre (ManifoldSolve::finish): the accumulated 2D impulse clamped to the
  // disk of radius mu N. An empty lane, or one with no normal impulse and none accumulated,
  // comes out with zero impulses and moves nothing.
  {
    // The relative velocity of the two centres, (vB + wB x fB) - (vA + wA x fA), along each tangent.
    const Vec t1 = cross(k.n, k.t0);
    const Vec u = (B.v + cross(B.w, k.fB)) - (A.v + cross(A.w, k.fA));
    const Real vt0 = dot(k.t0, u), vt1 = dot(t1, u);
    const Real old0 = k.tangent_impulse0, old1 = k.tangent_impulse1;
    Real i0 = old0 - (k.tangent_mass[0] * vt0 + k.tangent_mass[1] * vt1);
    Real i1 = old1 - (k.tangent_mass[1] * vt0 + k.tangent_mass[2] * vt1);
    const Real limit = k.friction * total_normal;
    const Real mag2 = i0 * i0 + i1 * i1;
    const Mask clamp = mag2 > limit * limit;
    if (any(clamp)) {
      const Real f = sel(clamp, limit / vsqrt(sel(clamp, mag2, splat(1))), splat(1));
      i0 = i0 * f;
      i1 = i1 * f;
    }
    k.tangent_impulse0 = i0;
    k.tangent_impulse1 = i1;
    const Vec P = (i0 - old0) * k.t0 + (i1 - old1) * t1;
    apply(A, B, P, cross(k.fA, P), cross(k.fB, P));
  }
  // Twist friction about the normal, limited by the pressure's moment arm over the patch.
  {
    const Real tl = k.friction * twist_limit;
    const Real old = k.twist_impulse;
    const Real raw = old - k.twist_mass * dot(k.n, B.w - A.w);
    const Real total = sel(count > 1, vmin(vmax(raw, -tl), tl), old);
    k.twist_impulse = total;
    const Vec T = (total - old) * k.n;
    A.w = A.w - A.inv_I * T;
    B.w = B.w + B.inv_I * T;
  }
  scatter(sb, k.a, A);
  scatter(sb, k.b, B);
  return any(struck);
}

}  // namespace simreel::wide
