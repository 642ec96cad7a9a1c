// Cylinder-cylinder and capsule-cylinder manifolds (design note, ids and tolerances: collide.cpp).
//
// GJK/EPA (gjk.cpp) gives the normal and the witness points; the normal decides which features
// touch (a cap when the axis is within ~2.6 degrees of it, the side when the axis is within ~2.6
// degrees of perpendicular, else the rim), and the points come from exact geometry of those
// features: the lens where two caps overlap, a side's line clipped to a cap's disc, the overlap of
// two parallel sides, or one exact point (rim against a cap's plane, crossed sides, a rim against a
// side or another rim by Newton's method from EPA's witnesses), so nothing shows EPA's facets.
// Each multi-point manifold must keep GJK/EPA's depth (its deepest point at least as deep, to
// 1e-7 x size); otherwise, and wherever no exact feature pair applies, GJK/EPA's single point.
#include "sim/collision/narrow/internal.hpp"

namespace simreel::collide_detail {

namespace {

// A cylinder in the world: centre, unit axis, radius, half height, and its pose's x and y axes.
struct Cyl {
  Vec3 c, u, ex, ey;
  double r, h;
};
Cyl world_cylinder(const CollideShape& s, const Pose& x) {
  return {x.p, x.R.col(2), x.R.col(0), x.R.col(1), s.radius, s.half_length};
}

enum class Feature { cap, side, rim };
// The feature of a cylinder with axis u facing direction d (unit).
Feature facing(const Vec3& u, const Vec3& d) {
  const double a = std::fabs(u.dot(d));
  return a >= kCosTol ? Feature::cap : (a <= kSinTol ? Feature::side : Feature::rim);
}

// v without its component along unit m.
inline Vec3 flat(const Vec3& v, const Vec3& m) {
  return v - m.dot(v) * m;
}

// A point of a rim circle (centre o, radius r, in-plane basis e1, e2) and its derivatives.
struct Rim {
  Vec3 o, e1, e2;
  double r;
  Vec3 at(double phi) const { return o + r * (std::cos(phi) * e1 + std::sin(phi) * e2); }
  Vec3 d1(double phi) const { return r * (-std::sin(phi) * e1 + std::cos(phi) * e2); }
  double param(const Vec3& x) const { return std::atan2((x - o).dot(e2), (x - o).dot(e1)); }
};
// The rim of cylinder k on the side of direction d (the disc whose outward normal has d . n > 0).
Rim rim_towards(const Cyl& k, const Vec3& d) {
  const double z = k.u.dot(d) >= 0 ? k.h : -k.h;
  return {k.c + z * k.u, k.ex, k.ey, k.r};
}

// ---------------------------------------------------------------- cap on cap

// The lens where the cap of reference cylinder R (outward normal m, towards I) and the cap of the
// incident cylinder I overlap, projected along m onto R's cap plane.
struct Lens {
  Vec3 m, capR, capI, mI, uI;  // mI: I's cap's outward normal (about -m); uI: I's axis
  double rR, rI;
  Rim rimI;
  double size;
  // Separation along m of I's cap plane above R's cap plane at a point x of R's plane.
  double gap_above(const Vec3& x) const { return mI.dot(capI - x) / mI.dot(m); }
  bool in_R(const Vec3& x) const { return flat(x - capR, m).squaredNorm() <= rR * rR * (1 + 1e-9); }
  bool in_I(const Vec3& x) const { return (x - capI).squaredNorm() <= rI * rI * (1 + 1e-9); }
};

// The lens's support point in direction w (unit, perpendicular to m): R's rim point when it lies
// under I's disc, I's rim point when it lies over R's disc, else the crossing of the two rims
// (circle-circle in the plane, then Newton on I's rim parameter so that its projection lies on R's
// circle exactly: I's disc projects to an ellipse when it is tilted). Writes the midpoint and the
// separation; false when the discs' projections do not overlap.
bool lens_support(const Lens& L, const Vec3& w, Vec3& mid, double& s) {
  const Vec3& m = L.m;
  const Vec3 wI = w - w.dot(L.uI) * L.uI;
  const double wn = wI.norm();
  if (wn > 1e-12) {
    const Vec3 xI = L.capI + (L.rI / wn) * wI;
    if (L.in_R(xI)) {
      s = m.dot(xI - L.capR);
      mid = xI - 0.5 * s * m;
      return true;
    }
  }
  const Vec3 xR = L.capR + L.rR * w;
  const double t = L.gap_above(xR);
  if (L.in_I(xR + t * m)) {
    s = t;
    mid = xR + 0.5 * s * m;
    return true;
  }
  // The crossing of the two circles on the side of w.
  const Vec3 D = flat(L.capI - L.capR, m);
  const double d = D.norm();
  if (!(d > 1e-12 * L.size) || d >= L.rR + L.rI) return false;
  const Vec3 dh = D / d, dp = m.cross(dh);
  const double a = (d * d + L.rR * L.rR - L.rI * L.rI) / (2 * d);
  const double h = std::sqrt(std::max(L.rR * L.rR - a * a, 0.0));
  const Vec3 guess = L.capR + a * dh + (w.dot(dp) >= 0 ? h : -h) * dp;
  double phi = L.rimI.param(guess);
  for (int it = 0; it < 8; ++it) {
    const Vec3 q = flat(L.rimI.at(phi) - L.capR, m);
    const double g = q.squaredNorm() - L.rR * L.rR;
    const double dg = 2 * q.dot(flat(L.rimI.d1(phi), m));
    if (std::fabs(g) <= 1e-15 * L.rR * L.rR || std::fabs(dg) < 1e-12 * L.rR * L.rR) break;
    phi -= g / dg;
  }
  const Vec3 xI = L.rimI.at(phi);
  s = m.dot(xI - L.capR);
  mid = xI - 0.5 * s * m;
  return true;
}

// Cap of R on cap of I: the lens's support points in four directions (along the line between
// the discs' centres and across it, or I's own x and y axes when the centres nearly coincide, so
// the points stay put), plus the lens's deepest point (its support point down the slope of I's
// cap plane) when it is deeper than all four by more than kDeepGain x size: below that the four
// keep their ids under tilts up to ~1e-4 rad (a fifth point would make the reduction drop one of
// them) and the depth reported falls short by at most that much. Writes the lens's deepest
// separation to `deepest`. Returns the candidate count (0: no lens).
constexpr double kDeepGain = 1e-5;
int cap_cap(const Cyl& R, const Cyl& I, const Vec3& m, double size, double spec, Candidate* c,
            double& deepest) {
  Lens L;
  L.m = m;
  L.capR = R.c + (R.u.dot(m) >= 0 ? R.h : -R.h) * R.u;
  L.rimI = rim_towards(I, -m);
  L.capI = L.rimI.o;
  L.mI = I.u.dot(m) < 0 ? I.u : Vec3(-I.u);
  L.uI = I.u;
  L.rR = R.r, L.rI = I.r, L.size = size;
  const Vec3 D = flat(L.capI - L.capR, m);
  Vec3 e = D.norm() > 1e-3 * std::min(R.r, I.r) ? D : flat(I.ex, m);
  if (e.squaredNorm() < 1e-12) e = flat(I.ey, m);
  e.normalize();
  const Vec3 e2 = m.cross(e);
  const Vec3 dirs[4] = {e, e2, -e, -e2};
  int n = 0;
  double smin = INFINITY;
  for (int k = 0; k < 4; ++k) {
    Vec3 mid;
    double s;
    if (!lens_support(L, dirs[k], mid, s)) return 0;
    smin = std::min(smin, s);
    bool dup = false;
    for (int j = 0; j < n; ++j) dup = dup || (c[j].p_W - mid).squaredNorm() < 1e-18 * size * size;
    if (!dup && s <= spec) c[n++] = {mid, s, kIdLens + (uint32_t)k};
  }
  deepest = smin;
  const Vec3 slope = flat(L.mI, m);
  if (slope.norm() > 1e-12) {
    Vec3 mid;
    double s;
    if (lens_support(L, Vec3(-slope.normalized()), mid, s)) {
      deepest = std::min(deepest, s);
      if (s < smin - kDeepGain * size && s <= spec) c[n++] = {mid, s, kIdLensDeep};
    }
  }
  return n;
}

// ---------------------------------------------------------------- lines on caps

// The parameter range [t0, t1] of the line p + t d, t in [lo, hi], whose projection along m lies
// in the disc (centre o, radius r) of the plane normal to m. False when empty.
bool clip_line_to_disc(const Vec3& p, const Vec3& d, double lo, double hi, const Vec3& o, double r,
                       const Vec3& m, double& t0, double& t1) {
  const Vec3 a = flat(p - o, m), b = flat(d, m);
  const double A = b.squaredNorm(), B = a.dot(b), C = a.squaredNorm() - r * r;
  if (A < 1e-300) {
    if (C > 0) return false;
    t0 = lo, t1 = hi;
    return true;
  }
  const double disc = B * B - A * C;
  if (disc < 0) return false;
  const double q = std::sqrt(disc);
  t0 = std::max(lo, (-B - q) / A), t1 = std::min(hi, (-B + q) / A);
  return t1 >= t0;
}

// The side of S (its generator nearest the cap) on the cap of C (outward normal m, towards S).
int cap_side(const Cyl& C, const Cyl& S, const Vec3& m, double size, double spec, Candidate* c) {
  const Vec3 cap = C.c + (C.u.dot(m) >= 0 ? C.h : -C.h) * C.u;
  Vec3 w = flat(-m, S.u);
  if (w.squaredNorm() < 1e-24) return 0;
  w.normalize();
  const Vec3 p = S.c + S.r * w;
  double t0, t1;
  if (!clip_line_to_disc(p, S.u, -S.h, S.h, cap, C.r, m, t0, t1)) return 0;
  const int np = t1 - t0 > 1e-9 * size ? 2 : 1;
  const double ts[2] = {t0, t1};
  int n = 0;
  for (int i = 0; i < np; ++i) {
    const Vec3 x = p + ts[i] * S.u;
    const double s = m.dot(x - cap);
    if (s <= spec) c[n++] = {Vec3(x - 0.5 * s * m), s, kIdCapSide + (uint32_t)i};
  }
  return n;
}

// ---------------------------------------------------------------- parallel sides

// A's axis segment pa-qa (unit direction ua, radius ra: a cylinder's side or a capsule) along
// the side of cylinder B, the axes parallel within ~2.6 degrees: the normal (from A's axis to B's,
// perpendicular to ua) and up to two points at the ends of the axes' overlap. Each starts on A's
// surface (its axis point + ra n) and goes along n to B's side (the ray's entry into B's infinite
// cylinder, moved back along the axis if it lands past B's end), so both surface points are exact
// and the separation is measured along n. Returns the count, -1 when the axes do not overlap.
int parallel_sides(const Vec3& pa, const Vec3& qa, double ra, const Cyl& B, const Vec3& ua,
                   const Vec3& n_fallback, double size, double spec, Vec3& n, Candidate* c, uint32_t id) {
  const Vec3 pb = B.c - B.h * B.u, qb = B.c + B.h * B.u;
  const double L = (qa - pa).norm();
  double t0 = (pb - pa).dot(ua), t1 = (qb - pa).dot(ua);
  if (t0 > t1) std::swap(t0, t1);
  t0 = std::max(t0, 0.0), t1 = std::min(t1, L);
  if (!(t1 - t0 > 1e-9 * size)) return -1;
  double s0, s1;
  Vec3 c1, c2;
  closest_segments(pa, qa, pb, qb, s0, s1, c1, c2);
  n = flat(c2 - c1, ua);
  n = n.norm() > 1e-9 * size ? Vec3(n.normalized()) : Vec3(flat(n_fallback, ua).normalized());
  const double cosab = std::fabs(ua.dot(B.u));
  int k = 0;
  const double ts[2] = {t0, t1};
  for (int i = 0; i < 2; ++i) {
    double t = ts[i], lam = 0;
    bool hit = false;
    for (int pass = 0; pass < 2 && !hit; ++pass) {
      const Vec3 x = pa + t * ua + ra * n;
      // |flat(x + lam n - B.c, B.u)| = B.r: the smaller root (entering B along n).
      const Vec3 e = flat(x - B.c, B.u), f = flat(n, B.u);
      const double A2 = f.squaredNorm(), B1 = e.dot(f), C0 = e.squaredNorm() - B.r * B.r;
      const double disc = B1 * B1 - A2 * C0;
      if (!(A2 > 1e-12) || disc < 0) break;
      lam = (-B1 - std::sqrt(disc)) / A2;
      const double z = B.u.dot(x + lam * n - B.c);
      if (std::fabs(z) <= B.h * (1 + 1e-12)) {
        hit = true;
      } else {
        const double over = (z > 0 ? z - B.h : z + B.h) * (ua.dot(B.u) >= 0 ? 1 : -1);
        t = std::clamp(t - over / cosab, 0.0, L);
      }
    }
    if (!hit || lam > spec) continue;
    const Vec3 x = pa + t * ua + ra * n;
    c[k++] = {Vec3(x + 0.5 * lam * n), lam, id + (uint32_t)i};
  }
  return k;
}

// ---------------------------------------------------------------- single exact points

// Rim of K against the side of S (the infinite cylinder about S's axis), from EPA's witness x0 on
// K: Newton on the rim parameter for the rim point nearest S's axis. Writes K's point q, the
// outward normal of S there (towards K) and the separation. False when the point falls beyond
// S's ends or Newton fails.
bool rim_side(const Rim& rim, const Cyl& S, const Vec3& x0, Vec3& q, Vec3& nS, double& s) {
  double phi = rim.param(x0);
  for (int it = 0; it < 12; ++it) {
    const Vec3 x = rim.at(phi), dx = rim.d1(phi), ddx = rim.o - x;
    const Vec3 a = flat(x - S.c, S.u), b = flat(dx, S.u);
    const double f1 = a.dot(b), f2 = b.squaredNorm() + a.dot(flat(ddx, S.u));
    const double step = f2 > 1e-12 * rim.r * rim.r ? f1 / f2 : f1 / (rim.r * rim.r);
    phi -= step;
    if (std::fabs(step) < 1e-14) break;
  }
  q = rim.at(phi);
  if (std::fabs(S.u.dot(q - S.c)) > S.h) return false;
  const Vec3 a = flat(q - S.c, S.u);
  const double dist = a.norm();
  if (!(dist > 1e-12 * S.r)) return false;
  nS = a / dist;
  s = dist - S.r;
  return true;
}

// Rim against rim: Newton on both rim parameters for a stationary pair (the joining vector
// perpendicular to both rims), from EPA's witnesses. False when it does not converge.
bool rim_rim(const Rim& A, const Rim& B, const Vec3& a0, const Vec3& b0, Vec3& xa, Vec3& xb) {
  double pa = A.param(a0), pb = B.param(b0);
  for (int it = 0; it < 16; ++it) {
    xa = A.at(pa), xb = B.at(pb);
    const Vec3 da = A.d1(pa), db = B.d1(pb), dda = A.o - xa, ddb = B.o - xb;
    const Vec3 d = xb - xa;
    const double g1 = -d.dot(da), g2 = d.dot(db);
    const double h11 = da.squaredNorm() - d.dot(dda), h22 = db.squaredNorm() + d.dot(ddb), h12 = -da.dot(db);
    const double det = h11 * h22 - h12 * h12;
    if (!(det > 1e-12 * A.r * A.r * B.r * B.r)) return false;
    const double s1 = (h22 * g1 - h12 * g2) / det, s2 = (h11 * g2 - h12 * g1) / det;
    pa -= s1, pb -= s2;
    if (std::fabs(s1) + std::fabs(s2) < 1e-14) {
      xa = A.at(pa), xb = B.at(pb);
      return true;
    }
  }
  return false;
}

// Least separation of n candidates (+inf when none).
double min_s(const Candidate* c, int n) {
  double s = INFINITY;
  for (int i = 0; i < n; ++i) s = std::min(s, c[i].s);
  return s;
}

}  // namespace

int cylinder_cylinder(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb,
                      double spec, PairCache& cache, Manifold& out) {
  const Support SA(a, xa), SB(b, xb);
  const CoreDistance g = core_distance(SA, SB);
  const Vec3 n0 = g.normal;
  const double s0 = g.separation;
  out.normal_W = n0;
  out.count = 0;
  if (s0 > spec) return 0;
  const double size = std::max(a.bounding_radius + b.bounding_radius, 1e-300);
  const double keep = s0 + 1e-7 * size;  // a manifold must be at least this deep
  const Cyl A = world_cylinder(a, xa), B = world_cylinder(b, xb);
  const Feature fa = facing(A.u, n0), fb = facing(B.u, -n0);
  Candidate c[5];
  int nc = 0;
  if (fa == Feature::cap && fb == Feature::cap) {
    // Reference cap: the cached one while it still faces the normal, else the better aligned.
    bool refA = std::fabs(A.u.dot(n0)) >= std::fabs(B.u.dot(n0));
    if (cache.type == kCacheFaceA || cache.type == kCacheFaceB) refA = cache.type == kCacheFaceA;
    cache = {refA ? kCacheFaceA : kCacheFaceB, -1, -1};
    // mR: the reference cap's outward normal, towards the other cylinder; A -> B is +-mR.
    const Vec3 mR = refA ? (A.u.dot(n0) >= 0 ? A.u : Vec3(-A.u)) : (B.u.dot(n0) <= 0 ? B.u : Vec3(-B.u));
    double deepest;
    nc = refA ? cap_cap(A, B, mR, size, spec, c, deepest) : cap_cap(B, A, mR, size, spec, c, deepest);
    if (nc > 0 && deepest <= keep) {
      reduce_to_manifold(c, nc, refA ? mR : Vec3(-mR), out);
      return out.count;
    }
  } else {
    cache = {};
  }
  if ((fa == Feature::cap && fb == Feature::side) || (fa == Feature::side && fb == Feature::cap)) {
    const bool capA = fa == Feature::cap;
    const Cyl& C = capA ? A : B;
    const Vec3 toward = capA ? n0 : Vec3(-n0);
    const Vec3 m = C.u.dot(toward) >= 0 ? C.u : Vec3(-C.u);
    nc = cap_side(C, capA ? B : A, m, size, spec, c);
    if (nc > 0 && min_s(c, nc) <= keep) {
      out.normal_W = capA ? m : Vec3(-m);
      reduce_to_manifold(c, nc, out.normal_W, out);
      return out.count;
    }
  }
  if (fa == Feature::side && fb == Feature::side && A.u.cross(B.u).norm() <= kSinTol) {
    Vec3 n;
    nc = parallel_sides(A.c - A.h * A.u, A.c + A.h * A.u, A.r, B, A.u, n0, size, spec, n, c, kIdSides);
    if (nc > 0 && min_s(c, nc) <= keep) {
      out.normal_W = n;
      reduce_to_manifold(c, nc, n, out);
      return out.count;
    }
  }
  // One exact point.
  Vec3 n = n0, pa = g.pA;
  double s = s0;
  uint32_t id = kIdGeneric;
  if ((fa == Feature::cap) != (fb == Feature::cap) && (fa == Feature::rim || fb == Feature::rim)) {
    // A rim on a cap: the rim's deepest point against the cap's plane, inside the cap's disc.
    const bool capA = fa == Feature::cap;
    const Cyl& C = capA ? A : B;
    const Vec3 toward = capA ? n0 : Vec3(-n0);
    const Vec3 m = C.u.dot(toward) >= 0 ? C.u : Vec3(-C.u);
    const Vec3 cap = C.c + (C.u.dot(m) >= 0 ? C.h : -C.h) * C.u;
    Vec3 q[5];
    cylinder_rim_points(capA ? b : a, capA ? xb : xa, m, q);
    const double sq = m.dot(q[0] - cap);
    if (flat(q[0] - cap, m).norm() <= C.r && sq <= keep) {
      n = capA ? m : Vec3(-m);
      s = sq;
      pa = capA ? Vec3(q[0] - sq * m) : q[0];
      id = kIdCapRim;
    }
  } else if (fa == Feature::side && fb == Feature::side) {
    // Crossed sides: the closest points of the axes, both inside their segments.
    double ta, tb;
    Vec3 c1, c2;
    closest_segments(A.c - A.h * A.u, A.c + A.h * A.u, B.c - B.h * B.u, B.c + B.h * B.u, ta, tb, c1, c2);
    Vec3 x = A.u.cross(B.u);
    if (ta > 0 && ta < 1 && tb > 0 && tb < 1 && x.norm() > kSinTol) {
      x.normalize();
      if (x.dot(n0) < 0) x = -x;
      n = x;
      s = n.dot(c2 - c1) - A.r - B.r;
      pa = c1 + A.r * n;
      id = kIdCrossed;
    }
  } else if ((fa == Feature::rim && fb == Feature::side) || (fa == Feature::side && fb == Feature::rim)) {
    const bool rimA = fa == Feature::rim;
    Vec3 q, nS;
    double sr;
    if (rim_side(rim_towards(rimA ? A : B, rimA ? n0 : Vec3(-n0)), rimA ? B : A, rimA ? g.pA : g.pB, q, nS,
                 sr) &&
        sr <= keep) {
      n = rimA ? Vec3(-nS) : nS;  // A -> B
      if (n.dot(n0) > 0.9) {
        s = sr;
        pa = rimA ? q : Vec3(q - sr * nS);
        id = kIdRimSide;
      } else {
        n = n0;
      }
    }
  } else if (fa == Feature::rim && fb == Feature::rim) {
    Vec3 qa, qb;
    if (rim_rim(rim_towards(A, n0), rim_towards(B, -n0), g.pA, g.pB, qa, qb) &&
        (qa - g.pA).norm() < 0.1 * std::min(A.r, B.r)) {
      const Vec3 d = qb - qa;
      const double dl = d.norm();
      Vec3 nn = dl > 1e-9 * size ? Vec3(d / dl) : n0;
      double sr = dl;
      if (nn.dot(n0) < 0) nn = -nn, sr = -dl;
      if (nn.dot(n0) > 0.9 && sr <= keep) n = nn, s = sr, pa = qa, id = kIdRimRim;
    }
  }
  out.normal_W = n;
  if (s <= spec) push_point(out, pa, n, s, id);
  return out.count;
}

int capsule_cylinder(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb,
                     double spec, PairCache& cache, Manifold& out) {
  const Support SA(a, xa), SB(b, xb);
  const CoreDistance g = core_distance(SA, SB);
  const Vec3 n0 = g.normal;
  const double r = a.radius, s0 = g.separation - r;
  out.normal_W = n0;
  out.count = 0;
  cache = {};
  if (s0 > spec) return 0;
  const double size = std::max(a.bounding_radius + b.bounding_radius, 1e-300);
  const double keep = s0 + 1e-7 * size;
  const Vec3 ua = xa.R.col(2);
  const Vec3 p0 = xa.p - a.half_length * ua, p1 = xa.p + a.half_length * ua;
  const Cyl C = world_cylinder(b, xb);
  const Feature fc = facing(C.u, -n0);
  Candidate c[2];
  int nc = 0;
  if (fc == Feature::cap) {
    // m: the cap's outward normal (towards the capsule); A -> B is -m.
    const Vec3 m = C.u.dot(n0) <= 0 ? C.u : Vec3(-C.u);
    const Vec3 cap = C.c + (C.u.dot(m) >= 0 ? C.h : -C.h) * C.u;
    if (std::fabs(ua.dot(m)) <= kSinTol) {
      // Lying on the cap: the segment clipped to the disc, both ends.
      double t0, t1;
      if (clip_line_to_disc(p0, p1 - p0, 0, 1, cap, C.r, m, t0, t1)) {
        const int np = (t1 - t0) * 2 * a.half_length > 1e-9 * size ? 2 : 1;
        const double ts[2] = {t0, t1};
        for (int i = 0; i < np; ++i) {
          const Vec3 x = p0 + ts[i] * (p1 - p0);
          const double s = m.dot(x - cap) - r;
          if (s <= spec) c[nc++] = {Vec3(x - (r + 0.5 * s) * m), s, kIdCapsuleCap + (uint32_t)i};
        }
      }
    } else {
      // An end on the cap: its sphere against the cap's plane, over the disc.
      const Vec3 x = m.dot(p0) <= m.dot(p1) ? p0 : p1;
      const double s = m.dot(x - cap) - r;
      if (flat(x - cap, m).norm() <= C.r && s <= spec)
        c[nc++] = {Vec3(x - (r + 0.5 * s) * m), s, kIdCapsuleEnd};
    }
    if (nc > 0 && min_s(c, nc) <= keep) {
      out.normal_W = -m;
      reduce_to_manifold(c, nc, out.normal_W, out);
      return out.count;
    }
    nc = 0;
  } else if (fc == Feature::side && ua.cross(C.u).norm() <= kSinTol) {
    Vec3 n;
    nc = parallel_sides(p0, p1, r, C, ua, n0, size, spec, n, c, kIdCapsuleSide);
    if (nc > 0 && min_s(c, nc) <= keep) {
      out.normal_W = n;
      reduce_to_manifold(c, nc, n, out);
      return out.count;
    }
  }
  push_point(out, g.pA + r * n0, n0, s0, kIdGeneric);
  return out.count;
}

}  // namespace simreel::collide_detail
