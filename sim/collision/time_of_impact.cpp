// Time of impact by conservative advancement (design note and citations: time_of_impact.hpp).
#include "sim/collision/time_of_impact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/collision/narrow/internal.hpp"
#include "sim/geometry/trimesh.hpp"

namespace simreel {

namespace {

const Sweep kStill{};  // a body that does not move (a static mesh's triangle)

// The distance of the pair at poses xa, xb: a shape or a still triangle as B.
double pair_distance(const ToiInput& in, const Pose& xa, const Pose& xb, Vec3& n) {
  return in.tri_b ? triangle_distance(*in.a, xa, in.tri_b, n) : shape_distance(*in.a, xa, *in.b, xb, n);
}

}  // namespace

Quat Sweep::q_at(double t) const {
  if (angle == 0) return q0;
  return q0.slerp(t, q1).normalized();
}

Sweep make_sweep(const Vec3& x0, const Quat& q0, const Vec3& x1, const Quat& q1) {
  Sweep s;
  s.x0 = x0;
  s.dx = x1 - x0;
  s.q0 = q0;
  s.q1 = q1;
  // The angle of q1 q0^-1, the shorter way (q and -q are the same rotation).
  const double c = std::min(1.0, std::fabs(q0.dot(q1)));
  s.angle = 2.0 * std::acos(c);
  s.moves = s.angle > 0 || !s.dx.isZero(0);
  return s;
}

Pose shape_pose(const ShapeRecord& r, const Vec3& x, const Quat& q) {
  Pose p;
  const Mat3 R = q.toRotationMatrix();
  p.R = R * r.R_PC;
  p.p = x + R * r.p_PC;
  return p;
}

double min_width(const CollideShape& g) {
  switch (g.kind) {
    case CollideKind::sphere:
    case CollideKind::capsule:
      return 2.0 * g.radius;
    case CollideKind::cylinder:
      return 2.0 * std::min(g.radius, g.half_length);
    case CollideKind::ellipsoid:
      return 2.0 * g.radii.minCoeff();
    case CollideKind::box:
      return 2.0 * g.half_extents.minCoeff();
    case CollideKind::hull: {
      if (!g.hull || g.hull->faces.empty()) return 2.0 * g.bounding_radius;
      double w = std::numeric_limits<double>::infinity();
      for (const ConvexPolyhedron::Face& f : g.hull->faces)
        w = std::min(w, f.offset - f.normal.dot(g.hull->vertices[g.hull->support(-f.normal)]));
      return w;
    }
    default:
      return 0;
  }
}

double shape_distance(const CollideShape& a, const Pose& xa, const CollideShape& b, const Pose& xb, Vec3& n) {
  using collide_detail::Support;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const bool plane_a = a.kind == CollideKind::plane, plane_b = b.kind == CollideKind::plane;
  if ((plane_a && plane_b) || a.kind > CollideKind::hull || b.kind > CollideKind::hull) return kInf;
  if (plane_a) {
    // The plane z = 0 of A's frame, solid below: B's lowest point along the normal.
    const Vec3 np = xa.R.col(2);
    const Support B(b, xb);
    n = np;
    return np.dot(B.support_W(-np) - xa.p) - B.margin;
  }
  if (plane_b) {
    const Vec3 np = xb.R.col(2);
    const Support A(a, xa);
    n = -np;
    return np.dot(A.support_W(-np) - xb.p) - A.margin;
  }
  // A sphere and a box in closed form (the common bullet case; GJK reported a point 0.2 mm off a
  // thin box's face as touching, measured).
  if ((a.kind == CollideKind::sphere && b.kind == CollideKind::box) ||
      (a.kind == CollideKind::box && b.kind == CollideKind::sphere)) {
    const bool sa = a.kind == CollideKind::sphere;
    const CollideShape& sph = sa ? a : b;
    const CollideShape& bx = sa ? b : a;
    const Pose& xs = sa ? xa : xb;
    const Pose& xbx = sa ? xb : xa;
    const Vec3 c = xbx.apply_inverse(xs.p);
    const Vec3 q = c.cwiseMax(-bx.half_extents).cwiseMin(bx.half_extents);
    const Vec3 d = c - q;  // box frame, from the box's closest point to the centre
    const double L = d.norm();
    if (!(L > 0)) {
      n = Vec3::UnitZ();
      return -sph.radius;  // the centre is inside: touching (callers stop here)
    }
    const Vec3 u = xbx.R * (d / L);  // world, box to sphere
    n = sa ? Vec3(-u) : u;
    return L - sph.radius;
  }
  const Support A(a, xa), B(b, xb);
  bool overlap = false;
  const collide_detail::CoreDistance d = collide_detail::gjk_distance(A, B, overlap);
  if (overlap || !(d.separation > 0)) {
    // The cores overlap: the shapes touch at least as deep as the margins (the direction is only
    // a hint; callers stop here).
    const Vec3 c = xb.p - xa.p;
    n = c.squaredNorm() > 0 ? Vec3(c.normalized()) : Vec3(Vec3::UnitZ());
    return -(A.margin + B.margin);
  }
  n = d.normal;
  return d.separation - A.margin - B.margin;
}

ToiOutput time_of_impact(const ToiInput& in) {
  ToiOutput out;
  const Sweep& sa = *in.sa;
  const Sweep& sb = in.tri_b || !in.sb ? kStill : *in.sb;
  const Vec3 dx = sa.dx - sb.dx;  // A's displacement relative to B over the step
  const double spin = sa.angle * in.reach_a + (in.tri_b ? 0.0 : sb.angle * in.reach_b);
  double t = 0;
  for (int it = 0; it < kToiMaxIterations; ++it) {
    const Quat qa = sa.q_at(t), qb = sb.q_at(t);
    const Mat3 Ra = qa.toRotationMatrix(), Rb = qb.toRotationMatrix();
    Pose xa, xb;
    xa.R = Ra * in.R_PA;
    xa.p = sa.x_at(t) + Ra * in.p_PA;
    xb.R = Rb * in.R_PB;
    xb.p = sb.x_at(t) + Rb * in.p_PB;
    Vec3 n;
    const double d = pair_distance(in, xa, xb, n);
    out.iterations = it + 1;
    if (!std::isfinite(d)) {
      out.state = ToiOutput::separated;
      return out;
    }
    if (d <= in.target + in.tolerance) {
      out.state = t == 0 ? ToiOutput::touching : ToiOutput::hit;
      out.t = t;
      out.normal = n;
      return out;
    }
    // How fast the gap can close, per unit fraction of the step (time_of_impact.hpp).
    const double rate = n.dot(dx) + spin;
    const double gap = d - in.target;
    if (!(rate > 0) || gap >= rate * (1.0 - t)) {
      out.state = ToiOutput::separated;
      return out;
    }
    t += gap / rate;
  }
  // Not converged (a grazing rotation): the last t is still before contact.
  out.state = ToiOutput::hit;
  out.t = t;
  return out;
}

double triangle_distance(const CollideShape& a, const Pose& xa, const Vec3 tri[3], Vec3& n) {
  using collide_detail::Support;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (a.kind == CollideKind::plane || a.kind > CollideKind::hull) return kInf;
  const Vec3 front = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
  if (a.kind == CollideKind::sphere) {
    int f;
    const Vec3 v = collide_detail::closest_on_triangle(xa.p, tri[0], tri[1], tri[2], f) - xa.p;
    const double L = v.norm();
    if (!(L > 0)) {
      n = -front.normalized();
      return -a.radius;  // the centre is on the triangle: touching (callers stop here)
    }
    n = v / L;
    return L - a.radius;
  }
  // GJK against the triangle as a three-vertex hull about its centroid.
  Pose tp;
  const CollideShape ts = collide_detail::triangle_hull(tri, tp);
  const Support A(a, xa), B(ts, tp);
  bool overlap = false;
  const collide_detail::CoreDistance d = collide_detail::gjk_distance(A, B, overlap);
  if (overlap || !(d.separation > 0)) {
    n = -front.normalized();  // only a hint: callers stop here
    return -A.margin;
  }
  n = d.normal;
  return d.separation - A.margin;
}

ToiOutput time_of_impact_guarded(const ToiInput& in, int core) {
  ToiOutput out = time_of_impact(in);
  if (out.state != ToiOutput::touching) return out;
  out.state = ToiOutput::separated;
  const Sweep& still = kStill;
  for (int side = 0; side < 2; ++side) {
    if (!((core >> side) & 1) || (side == 1 && in.tri_b)) continue;
    const CollideShape& C = side == 0 ? *in.a : *in.b;
    if (C.kind == CollideKind::plane) continue;
    CollideShape cs;
    cs.kind = CollideKind::sphere;
    cs.radius = 0.25 * min_width(C);
    cs.bounding_radius = cs.radius;
    const Vec3 centre_C = C.kind == CollideKind::hull && C.hull ? C.hull->centroid : Vec3::Zero();
    const Vec3 p = side == 0 ? Vec3(in.p_PA + in.R_PA * centre_C) : Vec3(in.p_PB + in.R_PB * centre_C);
    const Sweep& sc = side == 0 ? *in.sa : *in.sb;
    const Sweep& so = side == 0 ? (in.tri_b || !in.sb ? still : *in.sb) : *in.sa;
    Pose pc;
    pc.R = Mat3::Identity();
    pc.p = sc.x0 + sc.q0.toRotationMatrix() * p;
    // One-sided against a triangle: a centre behind its plane is not held in front of it.
    if (in.tri_b &&
        !(((in.tri_b[1] - in.tri_b[0]).cross(in.tri_b[2] - in.tri_b[0])).dot(pc.p - in.tri_b[0]) > 0))
      continue;
    ToiInput ci = in;
    if (side == 0) {
      ci.a = &cs;
      ci.R_PA = Mat3::Identity();
      ci.p_PA = p;
      ci.reach_a = p.norm() + cs.radius;
    } else {
      ci.b = &cs;
      ci.R_PB = Mat3::Identity();
      ci.p_PB = p;
      ci.reach_b = p.norm() + cs.radius;
    }
    ToiOutput co = time_of_impact(ci);
    if (co.state == ToiOutput::touching) {
      // The core touches too (a body already sunk a quarter of its width into the other, as a
      // ball sliding fast across a spinning plate does; the solver's anchors are fixed within a
      // step): the last defence is the centre itself, which may approach the surface by half
      // its distance per step but never cross it.
      cs.radius = 0;
      const Mat3 Ro = so.q0.toRotationMatrix();
      Pose po;
      po.R = Ro * (side == 0 ? in.R_PB : in.R_PA);
      po.p = so.x0 + Ro * (side == 0 ? in.p_PB : in.p_PA);
      Vec3 n0;
      const double d0 = in.tri_b ? triangle_distance(cs, pc, in.tri_b, n0)
                                 : shape_distance(cs, pc, side == 0 ? *in.b : *in.a, po, n0);
      if (d0 > 0) {
        ci.target = std::min(ci.target, 0.5 * d0);
        ci.tolerance = std::min(ci.tolerance, 0.25 * ci.target);
        co = time_of_impact(ci);
      }
    }
    if (co.state == ToiOutput::hit && (out.state != ToiOutput::hit || co.t < out.t)) out = co;
  }
  return out;
}

ToiOutput mesh_time_of_impact(const ToiInput& in, const CollideShape& mesh, const Pose& xm, const Vec3& lo_W,
                              const Vec3& hi_W, bool guarded, int* triangle) {
  const TriMeshShape& M = *mesh.mesh;
  // The query box in the mesh frame: the box of the world box turned into it.
  const Vec3 c_W = 0.5 * (lo_W + hi_W), e_W = 0.5 * (hi_W - lo_W);
  const Vec3 c = xm.R.transpose() * (c_W - xm.p);
  const Vec3 e = xm.R.transpose().cwiseAbs() * e_W;
  const Sweep& sa = *in.sa;
  const Mat3 R0 = sa.q0.toRotationMatrix();
  Pose x0;
  x0.R = R0 * in.R_PA;
  x0.p = sa.x0 + R0 * in.p_PA;
  const collide_detail::Support A(*in.a, x0);
  // The shape's centre at the start and the end of the sweep, and its core distance.
  const Vec3 centre1 = sa.x_at(1.0) + sa.q1.toRotationMatrix() * in.p_PA;
  const double core = 0.25 * min_width(*in.a);
  ToiInput ti = in;
  ti.b = nullptr;
  ti.sb = nullptr;
  Vec3 p[3];
  ti.tri_b = p;
  ToiOutput best;
  best.state = ToiOutput::separated;
  int hit = -1;
  M.bvh.query(c - e, c + e, [&](int k) {
    if (best.state == ToiOutput::touching) return;
    const MeshTriangle& T = M.triangles[k];
    for (int j = 0; j < 3; ++j) p[j] = xm.apply(M.vertices[T.v[j]]);
    const Vec3 n = xm.R * T.normal;
    // One-sided: a shape wholly behind the triangle's plane at the start passes through it.
    if (n.dot(A.support_W(n) - p[0]) + A.margin < 0) return;
    // Box2D v3's rule for its chain segments (b2ContinuousQueryCallback), after the step only: a
    // centre that starts behind the plane, or that closes on it by less than the core distance and
    // ends more than that in front, does not pass through the triangle this step; sweeping it
    // would stop a body sliding fast across a flat mesh at every coplanar neighbour of the triangle
    // it rests on (measured: ten moves back per shot, each a loss of time, for a ball sliding along
    // a mesh wall's face). Not for the prediction: there a spinning box whose centre barely moves
    // would get no speculative manifold at all, and its corners went through a mesh wall.
    const double s1 = n.dot(x0.p - p[0]), s2 = n.dot(centre1 - p[0]);
    if (guarded && (s1 < 0 || (s1 - s2 < core && s2 > core))) return;
    const ToiOutput o = guarded ? time_of_impact_guarded(ti, 1) : time_of_impact(ti);
    best.iterations += o.iterations;
    if (o.state == ToiOutput::touching ||
        (o.state == ToiOutput::hit && (best.state != ToiOutput::hit || o.t < best.t))) {
      const int it = best.iterations;
      best = o;
      best.iterations = it;
      hit = k;
    }
  });
  if (triangle) *triangle = hit;
  return best;
}

}  // namespace simreel
