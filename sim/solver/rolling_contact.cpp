#include "sim/solver/rolling_contact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <Eigen/Cholesky>

#include "sim/base/dormand_prince.hpp"
#include "sim/collision/smooth_support.hpp"

namespace simreel {

namespace {

// Most internal steps in one frame step before the body is given back to the soft solver (a
// rolling body needs a few; thousands mean something the ODE does not model well).
constexpr int kMaxInternalSteps = 2000;
// Most landings of lifted feet in one frame step: the chattering stem of scenes/tippe_top.yaml
// lands up to some hundreds of times in a 1/240 s step; beyond this bound (a Zeno-like chatter) the
// step is the solver's, whose soft contact settles it.
constexpr int kMaxLandings = 1000;
// A face of a static box or hull (or a cylinder's cap) is the plane the body rolls on when the
// contact's normal is the face's to this cosine (the narrow phase gives the face normal to
// rounding; an edge or corner contact's normal turns as the body rolls).
constexpr double kFaceCosine = 1.0 - 1e-9;

Mat3 cross_matrix(const Vec3& v) {
  Mat3 m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// The fixed flat surface that static shape `o` (at pose po) shows a contact whose normal, toward
// the other body, is n: the plane, a face of a box or hull, a cylinder's cap. Its unit normal n
// (replaced by the face's exact one) and offset (n . x on it); false if there is none.
bool flat_surface(const ShapeRecord& o, const Pose& po, Vec3& n, double& offset) {
  switch (o.geom.kind) {
    case CollideKind::plane:
      n = po.R.col(2);
      offset = n.dot(po.p);
      return true;
    case CollideKind::box:
    case CollideKind::hull: {
      if (!o.geom.hull) return false;
      const Vec3 n_C = po.R.transpose() * n;
      for (const ConvexPolyhedron::Face& f : o.geom.hull->faces)
        if (f.normal.dot(n_C) >= kFaceCosine) {
          n = po.R * f.normal;
          offset = f.offset + n.dot(po.p);
          return true;
        }
      return false;
    }
    case CollideKind::cylinder: {
      const double c = (po.R.transpose() * n).z();
      if (std::fabs(c) < kFaceCosine) return false;
      n = (c > 0 ? 1.0 : -1.0) * po.R.col(2);
      offset = o.geom.half_length + n.dot(po.p);
      return true;
    }
    default:
      return false;
  }
}

// The feet's small systems (at most kMaxFeet unknowns): fixed capacity, no allocation.
using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, RollingContacts::kMaxFeet,
                            RollingContacts::kMaxFeet>;
using SmallVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, RollingContacts::kMaxFeet, 1>;

}  // namespace

RollingContacts::Y RollingContacts::state_vector(const MotionState& s) {
  Y y;
  y << s.q_WP.w(), s.q_WP.x(), s.q_WP.y(), s.q_WP.z(), s.q_WP * s.w_P, s.x_W, s.v_W;
  return y;
}

bool RollingContacts::contact_arm(const Foot& f, const Mat3& R, Vec3& r, Mat3* dP) {
  const ShapeRecord& sh = *f.shape;
  const Vec3 d_C = sh.R_PC.transpose() * (R.transpose() * -f.n);
  Vec3 s;
  Mat3 S;
  if (!smooth_support(sh.geom, d_C, f.end, s, S)) return false;
  r = -(R * (sh.p_PC + sh.R_PC * s));  // G - P
  if (dP) *dP = sh.R_PC * S * sh.R_PC.transpose();
  return true;
}

RollingContacts::Rate RollingContacts::rate(const Problem& p, const Y& y) {
  Rate out;
  out.dy.setZero();
  const Quat q_raw(y[0], y[1], y[2], y[3]);
  const Mat3 R = q_raw.normalized().toRotationMatrix();
  const Vec3 w = y.segment<3>(4);
  const Vec3 w_P = R.transpose() * w;
  // Each foot's arm r = G - P and its rate: the material point's turn plus the contact point's
  // run over the body, as the body turns under the fixed normal (u = R^T (-n) turns at -w_P x u,
  // the point by M u', in P).
  Vec3 r[kMaxFeet], r_dot[kMaxFeet];
  for (int k = 0; k < p.feet; ++k) {
    Mat3 M;
    if (!contact_arm(p.foot[k], R, r[k], &M)) {
      out.smooth = false;
      return out;
    }
    const Vec3 u = R.transpose() * -p.foot[k].n;
    r_dot[k] = w.cross(r[k]) - R * (M * (-w_P.cross(u)));
  }
  const Mat3 I_W = R * p.m->I_P.asDiagonal() * R.transpose();
  const double m = p.m->mass;
  const Vec3 gyro = -w.cross(I_W * w) + p.tau;
  Vec3 w_dot, a;
  if (!p.slide) {
    // No slip at the one foot: eliminate its whole force.
    const Vec3& r0 = r[0];
    const Mat3 K = I_W + m * (r0.squaredNorm() * Mat3::Identity() - r0 * r0.transpose());
    const Vec3 rhs = gyro + r0.cross(p.f) - m * r0.cross(w.cross(r_dot[0])) + m * r0.cross(p.g);
    w_dot = K.ldlt().solve(rhs);
    a = w_dot.cross(r0) + w.cross(r_dot[0]);
    out.force[0] = m * (a - p.g) - p.f;
    out.dy.segment<3>(7) = w.cross(r0);
  } else {
    // Regularised Coulomb friction at each foot, T = -mu N s / max(|s|, v_s) for the slip s of its
    // material point: the force per unit normal force is e = n - mu s / max(|s|, v_s), and the
    // normal forces N are what keeps every foot's material point from accelerating into or off its
    // surface: n_k . (a + w' x rho_k) = n_k . (w x r_k'), rho = P - G = -r.
    const Vec3 v = y.segment<3>(10);
    const Mat3 inv_I_W = R * p.m->inv_I_P.asDiagonal() * R.transpose();
    const Vec3 a_free = p.g + p.f / m, w_free = inv_I_W * gyro;
    Vec3 e[kMaxFeet], dw[kMaxFeet];
    for (int j = 0; j < p.feet; ++j) {
      const Vec3& n = p.foot[j].n;
      const Vec3 slip = v - w.cross(r[j]);
      const Vec3 st = slip - n.dot(slip) * n;
      e[j] = n - p.foot[j].mu / std::max(st.norm(), p.slip_speed) * st;
      dw[j] = inv_I_W * (-r[j]).cross(e[j]);
    }
    Small A(p.feet, p.feet);
    SmallVec b(p.feet);
    for (int k = 0; k < p.feet; ++k) {
      const Vec3& n = p.foot[k].n;
      for (int j = 0; j < p.feet; ++j) A(k, j) = n.dot(e[j] / m + dw[j].cross(-r[k]));
      b[k] = n.dot(w.cross(r_dot[k])) - n.dot(a_free + w_free.cross(-r[k]));
    }
    const SmallVec N = A.partialPivLu().solve(b);
    a = a_free;
    w_dot = w_free;
    for (int j = 0; j < p.feet; ++j) {
      a += N[j] / m * e[j];
      w_dot += N[j] * dw[j];
      out.force[j] = N[j] * e[j];
    }
    out.dy.segment<3>(7) = v;
  }
  // q' = (0, w) q / 2, w in the world.
  const Quat dq = Quat(0, w.x(), w.y(), w.z()) * q_raw;
  out.dy.segment<4>(0) << 0.5 * dq.w(), 0.5 * dq.x(), 0.5 * dq.y(), 0.5 * dq.z();
  out.dy.segment<3>(4) = w_dot;
  out.dy.segment<3>(10) = a;
  return out;
}

bool RollingContacts::holds(const Problem& p, const Rate& k) {
  if (!k.smooth || !k.dy.allFinite()) return false;
  for (int j = 0; j < p.feet; ++j) {
    const Vec3& n = p.foot[j].n;
    const double fn = k.force[j].dot(n);
    if (!(fn > 0)) return false;                                                     // it would pull
    if (!p.slide && (k.force[j] - fn * n).norm() > p.foot[j].mu * fn) return false;  // it would slip
  }
  return true;
}

// The normal-only corrections that put every foot back on its surface (positions) and stop its
// material point's normal motion (velocities): impulses lambda along the normals through
// B_kj = n_k . (n_j / m + (I_W^-1 (rho_j x n_j)) x rho_k), the feet's normal effective-mass matrix,
// one Newton step (the residuals are the integrator's, 1e-10).
void RollingContacts::project(const Problem& p, bool positions, Quat& q, Vec3& x, Vec3& v, Vec3& w) {
  const Mat3 R = q.toRotationMatrix();
  const Mat3 inv_I_W = R * p.m->inv_I_P.asDiagonal() * R.transpose();
  Vec3 rho[kMaxFeet];
  for (int k = 0; k < p.feet; ++k) {
    Vec3 r;
    contact_arm(p.foot[k], R, r, nullptr);
    rho[k] = -r;
  }
  Small B(p.feet, p.feet);
  SmallVec c(p.feet);
  for (int k = 0; k < p.feet; ++k) {
    const Vec3& n = p.foot[k].n;
    for (int j = 0; j < p.feet; ++j)
      B(k, j) = n.dot(p.foot[j].n / p.m->mass + (inv_I_W * rho[j].cross(p.foot[j].n)).cross(rho[k]));
    c[k] = positions ? n.dot(x + rho[k]) - p.foot[k].offset : n.dot(v + w.cross(rho[k]));
  }
  const SmallVec l = B.partialPivLu().solve(-c);
  Vec3 dx = Vec3::Zero(), dth = Vec3::Zero();
  for (int j = 0; j < p.feet; ++j) {
    dx += l[j] / p.m->mass * p.foot[j].n;
    dth += l[j] * (inv_I_W * rho[j].cross(p.foot[j].n));
  }
  if (positions) {
    x += dx;
    const double th = dth.norm();
    if (th > 0) q = (Quat(Eigen::AngleAxisd(th, dth / th)) * q).normalized();
  } else {
    v += dx;
    w += dth;
  }
}

// Feet whose contact would pull (N < 0 with the others standing) lift: taken out of the problem,
// the one pulling hardest first, while more than one is left. A lifted foot is watched
// (landing_gap) and lands as a plastic impact (land).
void RollingContacts::lift_pulling_feet(Problem& p, const Y& y) {
  while (p.feet > 1) {
    const Rate k = rate(p, y);
    int worst = -1;
    double least = 0;
    for (int j = 0; j < p.feet; ++j) {
      const double fn = k.force[j].dot(p.foot[j].n);
      if (fn < least) least = fn, worst = j;
    }
    if (worst < 0) return;
    // Past the standing feet, first of the lifted ones (the order of the rest is kept); it lifts
    // from where it stands.
    Foot f = p.foot[worst];
    Vec3 r;
    const Mat3 R = Quat(y[0], y[1], y[2], y[3]).normalized().toRotationMatrix();
    if (contact_arm(f, R, r, nullptr)) f.offset = f.n.dot(Vec3(y.segment<3>(7)) - r);
    for (int j = worst; j + 1 < p.feet; ++j) p.foot[j] = p.foot[j + 1];
    p.foot[p.feet - 1] = f;
    --p.feet;
    ++p.lifted;
  }
}

// The lowest lifted foot's height above where it stood (m; +inf with none lifted), and which.
double RollingContacts::landing_gap(const Problem& p, const Y& y, int* which) {
  double g = std::numeric_limits<double>::infinity();
  if (p.lifted == 0) return g;
  const Mat3 R = Quat(y[0], y[1], y[2], y[3]).normalized().toRotationMatrix();
  const Vec3 x = y.segment<3>(7);
  for (int k = p.feet; k < p.feet + p.lifted; ++k) {
    const Foot& f = p.foot[k];
    Vec3 r;
    if (!contact_arm(f, R, r, nullptr)) return -g;  // off its smooth part: the solver's
    const double gk = f.n.dot(x - r) - f.offset + kLandingSlack;
    if (gk < g) {
      g = gk;
      if (which) *which = k;
    }
  }
  return g;
}

// A lifted foot lands (land), or a body comes from the solver's hands (impact alone): a plastic
// impact at the standing feet, each impulse along its foot's e = n - mu s / max(|s|, v_s) (the
// friction law's impulsive limit, the slip held over the instant), sized so that no foot's
// material point keeps moving into or off its surface; a foot whose impulse would pull leaves the
// impact and lifts. False if no foot is left standing.
bool RollingContacts::land(Problem& p, Y& y, int landing) {
  std::swap(p.foot[landing], p.foot[p.feet]);
  ++p.feet;
  --p.lifted;
  return impact(p, y);
}

bool RollingContacts::impact(Problem& p, Y& y) {
  const Mat3 R = Quat(y[0], y[1], y[2], y[3]).normalized().toRotationMatrix();
  const Mat3 inv_I_W = R * p.m->inv_I_P.asDiagonal() * R.transpose();
  Vec3 w = y.segment<3>(4), v = y.segment<3>(10);
  while (p.feet > 0) {
    Vec3 rho[kMaxFeet], e[kMaxFeet], dw[kMaxFeet];
    for (int j = 0; j < p.feet; ++j) {
      Vec3 r;
      if (!contact_arm(p.foot[j], R, r, nullptr)) return false;
      rho[j] = -r;
      const Vec3& n = p.foot[j].n;
      const Vec3 slip = v + w.cross(rho[j]);
      const Vec3 st = slip - n.dot(slip) * n;
      e[j] = n - p.foot[j].mu / std::max(st.norm(), p.slip_speed) * st;
      dw[j] = inv_I_W * rho[j].cross(e[j]);
    }
    Small A(p.feet, p.feet);
    SmallVec d(p.feet);
    for (int k = 0; k < p.feet; ++k) {
      const Vec3& n = p.foot[k].n;
      for (int j = 0; j < p.feet; ++j) A(k, j) = n.dot(e[j] / p.m->mass + dw[j].cross(rho[k]));
      d[k] = -n.dot(v + w.cross(rho[k]));
    }
    const SmallVec L = A.partialPivLu().solve(d);
    int worst = -1;
    for (int j = 0; j < p.feet; ++j)  // (an impulse of rounding's size is none)
      if (L[j] < -1e-12 * p.m->mass && (worst < 0 || L[j] < L[worst])) worst = j;
    if (worst >= 0) {  // it would pull: it lifts from where it is, and the impact is made without it
      Foot f = p.foot[worst];
      f.offset = f.n.dot(Vec3(y.segment<3>(7)) + rho[worst]);
      for (int j = worst; j + 1 < p.feet; ++j) p.foot[j] = p.foot[j + 1];
      p.foot[p.feet - 1] = f;
      --p.feet;
      ++p.lifted;
      continue;
    }
    for (int j = 0; j < p.feet; ++j) {
      v += L[j] / p.m->mass * e[j];
      w += L[j] * dw[j];
      p.foot[j].impulse += L[j] * e[j];
    }
    y.segment<3>(4) = w;
    y.segment<3>(10) = v;
    return true;
  }
  return false;
}

// The six stages of a Dormand-Prince step of length hs from y0 (k[0] its rate there): k[1..6] and
// the 5th-order solution ys. False if a stage left a foot's smooth part.
bool RollingContacts::stages(const Problem& p, const Y& y0, Rate (&k)[7], double hs, Y& ys) {
  for (int st = 1; st < 7; ++st) {
    Y acc = Y::Zero();
    for (int j = 0; j < st; ++j) acc += dopri::kA[st][j] * k[j].dy;
    ys = y0 + hs * acc;
    k[st] = rate(p, ys);
    if (!k[st].smooth) return false;
  }
  return true;  // the 7th stage is at the 5th-order solution (its row of A is b): ys holds y1
}

bool RollingContacts::advance(Problem& p, MotionState& s, double dt, double tol, double& h) {
  Y y0 = state_vector(s);
  for (Foot& f : p.foot) f.impulse.setZero();
  if (p.slide) lift_pulling_feet(p, y0);
  // The contact holds (pushes; without slip, inside its friction cone) at every internal step's
  // ends (the first stage of each).
  Rate k[7];
  k[0] = rate(p, y0);
  if (!holds(p, k[0])) return false;
  Y ys;
  double t = 0;
  int steps = 0, landings = 0;
  while (t < dt) {
    if (++steps > kMaxInternalSteps) return false;
    const bool last = h >= dt - t;
    double hs = last ? dt - t : h;
    if (!stages(p, y0, k, hs, ys)) return false;
    double e2 = 0;
    for (int j = 0; j < kDim; ++j) {
      double e = 0;
      for (int st = 0; st < 7; ++st) e += (dopri::kB[st] - dopri::kBstar[st]) * k[st].dy[j];
      const double sc = tol * (1 + std::max(std::abs(y0[j]), std::abs(ys[j])));
      e2 += (hs * e / sc) * (hs * e / sc);
    }
    const double err = std::sqrt(e2 / kDim);
    if (!std::isfinite(err)) return false;
    const double fac = dopri::step_factor(err);
    if (err > 1) {
      h = hs * std::min(fac, 1.0);
      continue;
    }
    int landing = -1;
    bool landed = false;
    if (landing_gap(p, ys, &landing) < 0) {
      // A lifted foot comes down within the step: the step is cut at its landing, located on the
      // step's length by regula falsi (Illinois) to 1e-12 of it, and the landing made there.
      if (++landings > kMaxLandings) return false;
      const double g_start = landing_gap(p, y0, nullptr);
      if (!(g_start >= 0)) return false;
      double a = 0, b = hs, ga = g_start, gb = landing_gap(p, ys, nullptr);
      int side = 0;
      for (int it = 0; it < 100 && b - a > 1e-12 * hs; ++it) {
        double c = a + (b - a) * ga / (ga - gb);
        c = std::clamp(c, a + 1e-3 * (b - a), b - 1e-3 * (b - a));
        if (!stages(p, y0, k, c, ys)) return false;
        const double gc = landing_gap(p, ys, nullptr);
        if (gc < 0) {
          b = c, gb = gc;
          if (side == -1) ga *= 0.5;
          side = -1;
        } else {
          a = c, ga = gc;
          if (side == 1) gb *= 0.5;
          side = 1;
        }
      }
      hs = b;
      if (!stages(p, y0, k, hs, ys)) return false;
      landing_gap(p, ys, &landing);
      landed = true;
    }
    if (!holds(p, k[6])) return false;
    // The contact's impulse over the internal step, by the same quadrature as the state's.
    for (int j = 0; j < p.feet; ++j)
      for (int st = 0; st < 7; ++st) p.foot[j].impulse += hs * dopri::kB[st] * k[st].force[j];
    t = landed ? t + hs : last ? dt : t + hs;
    y0 = ys;
    if (landed) {
      if (!land(p, y0, landing)) return false;
      lift_pulling_feet(p, y0);
      k[0] = rate(p, y0);
      if (!holds(p, k[0])) return false;
      continue;  // the step-size proposal stands
    }
    k[0] = k[6];  // first same as last
    // A step cut short to land on the frame step's end does not set the next proposal.
    if (!last || hs >= h) h = hs * fac;
  }
  // The state the constraints give: a unit quaternion, G at the surface's height; without slip
  // v = w x r exactly, with slip the feet's material points at rest along their normals.
  Quat q = Quat(y0[0], y0[1], y0[2], y0[3]).normalized();
  Vec3 w = y0.segment<3>(4), x = y0.segment<3>(7), v = y0.segment<3>(10);
  if (!p.slide) {
    const Mat3 R = q.toRotationMatrix();
    Vec3 r;
    if (!contact_arm(p.foot[0], R, r, nullptr)) return false;
    const Vec3& n = p.foot[0].n;
    x += (p.foot[0].offset + n.dot(r) - n.dot(x)) * n;
    v = w.cross(r);
  } else {
    project(p, true, q, x, v, w);
    project(p, false, q, x, v, w);
  }
  if (!all_finite(x) || !all_finite(v) || !all_finite(w)) return false;
  s.q_WP = q;
  s.x_W = x;
  s.v_W = v;
  s.w_P = q.toRotationMatrix().transpose() * w;
  return true;
}

void RollingContacts::step(const Input& in, const std::vector<int>& bodies, std::vector<Contact>& contacts,
                           int substeps, std::vector<char>& rolled) {
  const ContactSettings& cs = in.settings;
  if (!cs.rolling || cs.rolling_resistance > 0) return;
  const bool slide = cs.slip_speed > 0;
  const int nb = (int)h_.size();
  head_.resize(nb, -1);
  link_.resize(2 * contacts.size());
  // Each body's touching contacts, as linked lists through link_ (2 ci + side).
  for (const Contact& c : contacts) head_[c.body_a] = head_[c.body_b] = -1;
  for (int ci = (int)contacts.size() - 1; ci >= 0; --ci) {
    const Contact& c = contacts[ci];
    if (c.count == 0) continue;
    link_[2 * ci] = head_[c.body_a];
    head_[c.body_a] = 2 * ci;
    link_[2 * ci + 1] = head_[c.body_b];
    head_[c.body_b] = 2 * ci + 1;
  }
  const double slop = cs.linear_slop;
  const double v_tol = slop / in.dt + 1e-9;  // a point at rest to the slop per step
  const int subs = std::max(1, substeps);
  const ShapeTable& shapes = *in.shapes;
  for (int i : bodies) {
    const BodyModel& m = in.model[i];
    if ((in.excluded && in.excluded[i]) || m.is_static || m.is_kinematic || !(m.inv_mass > 0)) continue;
    MotionState s = in.state[i];
    const Mat3 R = s.q_WP.toRotationMatrix();
    const Vec3 w = s.q_WP * s.w_P;
    Problem p;
    p.m = &m;
    p.slide = slide;
    p.slip_speed = cs.slip_speed;
    p.g = in.gravity;
    if (in.wrench) {
      p.f = in.wrench[i].f_W;
      p.tau = in.wrench[i].tau_W;
    }
    // Every manifold of the body: against a fixed flat surface, one point touching (a smooth
    // shape's support point: a foot), any other apart and not closing within the step; with slip,
    // a manifold apart but closing is a lifted foot, whose landing the step makes.
    bool ok = head_[i] >= 0;
    Foot lifted[kMaxFeet];
    int nl = 0;
    for (int l = head_[i]; ok && l >= 0; l = link_[l]) {
      const int ci = l / 2;
      const bool is_a = (l & 1) == 0;
      const Contact& c = contacts[ci];
      const int other_body = is_a ? c.body_b : c.body_a;
      const ShapeRecord& sh = shapes[is_a ? c.shape_a : c.shape_b];
      const ShapeRecord& other = shapes[is_a ? c.shape_b : c.shape_a];
      if (!in.model[other_body].is_static || !smooth_kind(sh.geom.kind) || p.feet + nl == kMaxFeet) {
        ok = false;
        break;
      }
      Foot f;
      f.shape = &sh;
      f.contact = ci;
      f.body_is_a = is_a;
      f.mu = c.friction;
      f.n = is_a ? Vec3(-c.normal_W) : c.normal_W;
      double plane = 0;
      if (!flat_surface(other, ShapeTable::world_pose(other, in.state[other_body]), f.n, plane)) {
        ok = false;
        break;
      }
      int touching = 0, closing = 0;
      for (int j = 0; j < c.count; ++j) {
        const ContactPoint& cp = c.points[j];
        if (cp.separation <= slop + 1e-6) {
          ++touching;
          f.point = j;
        } else if (cp.separation + f.n.dot(s.v_W + w.cross(cp.p_W - s.x_W)) * in.dt <= slop) {
          ++closing;
          if (touching == 0) f.point = j;
        }
      }
      if (touching > 1 || (touching == 1 && closing > 0) || (closing > 0 && !slide)) ok = false;
      if (!ok) break;
      if (touching == 0 && closing == 0) continue;  // near, not touching, and not closing within the step
      const Vec3 u_C = sh.R_PC.transpose() * (R.transpose() * -f.n);
      f.end = u_C.z() >= 0 ? 1 : -1;
      Vec3 r;
      if (!contact_arm(f, R, r, nullptr)) {
        ok = false;
        break;
      }
      const double gap = f.n.dot(s.x_W - r) - plane;
      if (touching == 0) {  // lifted: it lands on the surface itself
        f.offset = plane;
        ok = gap > 0;
        lifted[nl++] = f;
        continue;
      }
      if (gap < -(2 * slop + 1e-6) || gap > slop + 1e-6) {
        ok = false;
        break;
      }
      f.offset = f.n.dot(s.x_W - r);  // the gap it has is kept
      p.foot[p.feet++] = f;
    }
    for (int k = 0; k < nl; ++k) p.foot[p.feet + k] = lifted[k];
    p.lifted = nl;
    if (!ok || p.feet == 0 || (!slide && p.feet > 1)) continue;
    // Entering: the plastic impulse that stops each foot's material point (without slip) or its
    // normal motion (with slip); zero for a body that was rolling last step.
    const Mat3 inv_I_W = R * m.inv_I_P.asDiagonal() * R.transpose();
    if (!slide) {
      Vec3 r;
      contact_arm(p.foot[0], R, r, nullptr);
      const Vec3 v_P = s.v_W - w.cross(r);
      if (v_P.norm() > v_tol) continue;
      // K J = -v_P, K = 1/m - [rho]x I_W^-1 [rho]x with rho = P - G.
      const Mat3 rho_x = cross_matrix(-r);
      const Mat3 K = m.inv_mass * Mat3::Identity() - rho_x * inv_I_W * rho_x;
      const Vec3 J = K.ldlt().solve(-v_P);
      if (J.dot(p.foot[0].n) < -1e-12 * m.mass * v_tol) continue;  // it would pull: a body leaving
      s.v_W += m.inv_mass * J;
      s.w_P = R.transpose() * (w + inv_I_W * (-r).cross(J));
      p.foot[0].entry = J;
    } else {
      bool slow = true;
      for (int k = 0; k < p.feet; ++k) {
        Vec3 r;
        contact_arm(p.foot[k], R, r, nullptr);
        slow = slow && std::fabs(p.foot[k].n.dot(s.v_W - w.cross(r))) <= v_tol;
      }
      if (!slow) continue;
      Y y = state_vector(s);
      for (Foot& f : p.foot) f.impulse.setZero();
      if (!impact(p, y)) continue;  // every foot is leaving
      for (Foot& f : p.foot) f.entry = f.impulse;
      s.v_W = y.segment<3>(10);
      s.w_P = R.transpose() * Vec3(y.segment<3>(4));
    }
    double h = h_[i] > 0 ? h_[i] : in.dt / subs;
    if (!advance(p, s, in.dt, cs.rolling_tolerance, h)) continue;
    in.state[i] = s;
    h_[i] = h;
    rolled[i] = 1;
    now_.push_back(i);
    // Stored as the solver stores its own: the impulse on B, per substep.
    for (int k = 0; k < p.feet + p.lifted; ++k) {
      const Foot& f = p.foot[k];
      Contact& c = contacts[f.contact];
      const Vec3 P_B = (f.body_is_a ? -1.0 : 1.0) * (f.impulse + f.entry) / subs;
      for (int j = 0; j < c.count; ++j) c.points[j].normal_impulse = 0;
      c.points[f.point].normal_impulse = std::max(0.0, P_B.dot(c.normal_W));
      c.friction_impulse_W = P_B - P_B.dot(c.normal_W) * c.normal_W;
      c.twist_impulse = 0;
      c.rolling_impulse.setZero();
    }
  }
  // Last step's rolling bodies that do not roll now lose their step proposal.
  for (int i : last_)
    if (!rolled[i]) h_[i] = 0;
  last_.swap(now_);
  now_.clear();
}

}  // namespace simreel
