#include "sim/joints/contact_rows.hpp"

#include <algorithm>
#include <cmath>

#include "sim/joints/articulation.hpp"

namespace simreel {

// ------------------------------------------------------------------ the mechanism's side
void Mechanism::contact_begin(const Vec3& g) {
  time_ = frame_time;  // loads are held at the frame's start while in contact (first order, as the contacts)
  std::copy(q.begin(), q.end(), y0_.begin());
  std::copy(v.begin(), v.end(), y0_.begin() + nq);
  if (events_on() && !started) {
    start_modes(y0_.data(), g, nullptr);
    started = true;
  }
  kinematics(q.data());
  const int n = (int)links.size();
  if (Jl_.rows() != 6 * n || Jl_.cols() != nv) Jl_.setZero(6 * n, nv);
  if (V_.size() != links.size()) V_.assign(links.size(), Vec6::Zero());
  for (int k = 0; k < nv; ++k) {
    unit_velocities(k, V_);
    for (int i = 0; i < n; ++i) {
      Jl_.block<3, 1>(6 * i, k) = work_[i].R_W * V_[i].head<3>();
      Jl_.block<3, 1>(6 * i + 3, k) = work_[i].R_W * V_[i].tail<3>();
    }
  }
  held_.assign(dofs.size() + tethers.size(), 0);
  held_rows_changed();
  contact_inverse_inertia();
  if ((int)dq_.size() != nv) dq_.assign(nv, 0);
}

bool Mechanism::held_rows_changed() {
  bool changed = false;
  for (size_t i = 0; i < dofs.size() + tethers.size(); ++i) {
    const char h = i < dofs.size() ? dofs[i].active() : tethers[i - dofs.size()].active();
    changed = changed || h != held_[i];
    held_[i] = h;
  }
  return changed;
}

void Mechanism::contact_inverse_inertia() {
  if (P_.rows() != nv) P_.setZero(nv, nv);
  ropes_free_ = true;
  bool rows = !loops.empty();
  for (const Dof& d : dofs) rows = rows || d.active();
  for (const Tether& t : tethers) rows = rows || t.rod;
  if (rows) {
    loop_jacobian();  // M_, its factor, Y_ = M^-1 G^T and the rows' factor
    P_.setIdentity();
    llt_.solveInPlace(P_);
    // P = M^-1 - Y (G M^-1 G^T)^-1 Y^T: the response that keeps every row.
    // Scratch kept per thread (mechanisms step on the calling thread; sized once per shape).
    static thread_local Eigen::MatrixXd Z;
    Z = Y_.transpose();
    llt_rows_.solveInPlace(Z);
    P_.noalias() -= Y_ * Z;
  } else {
    mass_matrix();
    llt_.compute(M_);
    P_.setIdentity();
    llt_.solveInPlace(P_);
  }
  ropes_free_ = false;
}

void Mechanism::contact_row(int link, const Vec3& r, const Vec3& n, double* J) const {
  const Vec3 rn = r.cross(n);
  for (int k = 0; k < nv; ++k)
    J[k] = n.dot(Jl_.block<3, 1>(6 * link + 3, k)) + rn.dot(Jl_.block<3, 1>(6 * link, k));
}

void Mechanism::contact_response(const double* J, double* W) const {
  Eigen::Map<Eigen::VectorXd>(W, nv).noalias() = P_ * Eigen::Map<const Eigen::VectorXd>(J, nv);
}

void Mechanism::contact_velocities(double hs, const Vec3& g) {
  derivative(y0_.data(), kd_.data(), g, nullptr, nullptr);
  if (events_on()) event_values(y0_.data(), g0_.data());
  for (int k = 0; k < nv; ++k) y0_[nq + k] += hs * kd_[nq + k];
}

bool Mechanism::contact_positions(double hs, const Vec3& g) {
  // A taut rope the contacts made slacken (its ends now approach) lets go; one they stretched is
  // put back on its bound with the projections below.
  if (!tethers.empty()) {
    link_velocities(y0_.data(), y0_.data() + nq, V_);
    for (Tether& t : tethers)
      if (!t.rod && t.taut != 0 &&
          t.taut * tether_rate(t, V_, t.wheel_iv >= 0 ? y0_[nq + t.wheel_iv] : 0.0) < -1e-12)
        t.taut = 0;
  }
  for (int k = 0; k < nv; ++k) dq_[k] = hs * y0_[nq + k];
  displace(y0_.data(), dq_.data());
  if (projected()) {
    project_positions(y0_.data());
    project_velocities(y0_.data(), y0_.data() + nq);
  } else if (any_active()) {
    project_dofs(y0_.data());
  }
  if (events_on()) {
    derivative(y0_.data(), kd_.data(), g, nullptr, nullptr);
    event_values(y0_.data(), g1_.data());
    bool crossed = false;
    for (size_t i = 0; i < g0_.size(); ++i) crossed = crossed || (g0_[i] >= 0 && g1_[i] < 0);
    if (crossed) {
      apply_events(y0_.data(), g0_.data(), g1_.data(), g, nullptr);
      if (projected()) project_velocities(y0_.data(), y0_.data() + nq);
    }
    if (!tethers.empty() && catch_stretched(y0_.data(), g, nullptr) && projected())
      project_velocities(y0_.data(), y0_.data() + nq);
    if (!dofs.empty() && catch_past_stops(y0_.data(), g, nullptr) && projected())
      project_velocities(y0_.data(), y0_.data() + nq);
  }
  kinematics(y0_.data());
  if (loop_tracked_on) track_loop_angles();
  if (!held_rows_changed()) return false;
  contact_inverse_inertia();  // at the poses just computed, which the contact rows read too
  return true;
}

void Mechanism::contact_end() {
  std::copy(y0_.begin(), y0_.begin() + nq, q.begin());
  std::copy(y0_.begin() + nq, y0_.end(), v.begin());
}

void Mechanism::apply_impulse(int link, const Vec3& r, const Vec3& P, const Vec3& L) {
  kinematics(q.data());
  // The generalised impulse J^T (P; L + r x P), column by column of the link's world Jacobian.
  if (V_.size() != links.size()) V_.assign(links.size(), Vec6::Zero());
  Eigen::VectorXd tau(nv);
  const Mat3& R = work_[link].R_W;
  const Vec3 Lr = L + r.cross(P);
  for (int k = 0; k < nv; ++k) {
    unit_velocities(k, V_);
    tau(k) = (R * V_[link].tail<3>()).dot(P) + (R * V_[link].head<3>()).dot(Lr);
  }
  // dv = P_c tau = M^-1 tau - Y (G M^-1 G^T)^-1 Y^T tau over the held rows (ropes left out).
  ropes_free_ = true;
  bool rows = !loops.empty();
  for (const Dof& d : dofs) rows = rows || d.active();
  for (const Tether& t : tethers) rows = rows || t.rod;
  if (rows) {
    loop_jacobian();
  } else {
    mass_matrix();
    llt_.compute(M_);
  }
  ropes_free_ = false;
  Eigen::VectorXd dv = llt_.solve(tau);
  if (rows) {
    Eigen::VectorXd z = Y_.transpose() * tau;
    llt_rows_.solveInPlace(z);
    dv.noalias() -= Y_ * z;
  }
  for (int k = 0; k < nv; ++k) v[k] += dv(k);
  refresh_rate_modes(q.data(), v.data());
  // A taut rope the impulse slackened lets go (one it stretched is caught by the next step).
  if (!tethers.empty()) {
    link_velocities(q.data(), v.data(), V_);
    for (Tether& t : tethers)
      if (!t.rod && t.taut != 0 &&
          t.taut * tether_rate(t, V_, t.wheel_iv >= 0 ? v[t.wheel_iv] : 0.0) < -1e-12)
        t.taut = 0;
  }
}

void Mechanism::loop_load(const Loop& L, const double* lambda, Vec3& F, Vec3& T) const {
  using K = Loop::Kind;
  const Mat3 Ra = L.la < 0 ? Mat3::Identity() : work_[L.la].R_W;
  int r = 0;
  if (L.kind == K::prismatic) {
    F = lambda[0] * (Ra * L.t1) + lambda[1] * (Ra * L.t2);
    r = 2;
  } else {
    F = Vec3(lambda[0], lambda[1], lambda[2]);
    r = 3;
  }
  T.setZero();
  switch (L.kind) {
    case K::spherical:
      break;
    case K::hinge:
      T = lambda[r] * (Ra * L.t1) + lambda[r + 1] * (Ra * L.t2);
      break;
    case K::prismatic:
    case K::fixed:
      T = Ra * Vec3(lambda[r], lambda[r + 1], lambda[r + 2]);
      break;
    case K::universal: {
      const Vec3 A = Ra * L.aa, B = work_[L.lb].R_W * L.ab;
      T = lambda[r] * B.cross(A);
      break;
    }
  }
}

void Mechanism::joint_wrench(int link, const Vec3& g, Vec3& force_W, Vec3& torque_W) {
  std::copy(q.begin(), q.end(), ys_.begin());
  std::copy(v.begin(), v.end(), ys_.begin() + nq);
  derivative(ys_.data(), kd_.data(), g, nullptr, nullptr);  // kinematics, velocities, loop multipliers
  const int n = (int)links.size();
  const double* qdd = kd_.data() + nq;
  if (link < 0) {  // a loop: its rows' multipliers as the force and torque on b at its anchor
    const int k = -1 - link;
    int r = 0;
    for (int i = 0; i < k; ++i) r += loops[i].rows();
    loop_load(loops[k], lambda_.data() + r, force_W, torque_W);
    return;
  }
  // True-with-gravity accelerations (the base accelerates at -g) from the final q'' (the rows'
  // corrections included), then f_i = I a_i + v x* I v_i - (loop forces on i) + sum of children.
  if ((int)rf_.size() != n) rf_.assign(n, Vec6::Zero());
  if (V_.size() != links.size()) V_.assign(links.size(), Vec6::Zero());
  if (Acc_.size() != links.size()) Acc_.assign(links.size(), Vec6::Zero());
  Vec6 a_world;
  a_world << 0, 0, 0, -g.x(), -g.y(), -g.z();
  for (int i = 0; i < n; ++i) {
    const Link& l = links[i];
    const Work& w = work_[i];
    Vec6 a = transform_motion(w.E, w.r, l.parent < 0 ? a_world : Acc_[l.parent]) + w.c;
    if (l.nv > 0) a += l.S * Eigen::Map<const VecX6>(qdd + l.iv, l.nv);
    Acc_[i] = a;
    const Mat6 I = spatial_inertia(l.mass, l.I_P);
    rf_[i] = I * a + cross_force(w.vel, I * w.vel);
  }
  int r = 0;
  for (const Loop& L : loops) {
    // The loop's force and torque on b at b's anchor (and the opposite on a, at the same point),
    // into each link's frame about its origin.
    Vec3 F, T;
    loop_load(L, lambda_.data() + r, F, T);
    r += L.rows();
    const Vec3 at = work_[L.lb].x_W + work_[L.lb].R_W * L.pb;
    auto add = [&](int li, double sign) {
      if (li < 0) return;
      const Mat3& R = work_[li].R_W;
      const Vec3 p = at - work_[li].x_W;  // from the link's origin, world
      Vec6 f;
      f << R.transpose() * (sign * (T + p.cross(F))), R.transpose() * (sign * F);
      rf_[li] -= f;  // external: the joint carries what the loop does not
    };
    add(L.lb, 1);
    add(L.la, -1);
  }
  for (const Tether& t : tethers) tether_loads(t, t.lambda + tether_spring_force(t), rf_);
  if (loop_springs_on) loop_springs(&rf_);
  if (!loads.empty()) apply_loads(&rf_);  // the force list's forces on the links
  for (int i = n; i-- > 0;)
    if (links[i].parent >= 0) rf_[links[i].parent] += transform_force_back(work_[i].E, work_[i].r, rf_[i]);
  const Mat3& R = work_[link].R_W;
  force_W = R * rf_[link].tail<3>();
  torque_W = R * rf_[link].head<3>();
}

// ------------------------------------------------------------------ the rows
void ArticulatedContacts::prepare(Articulations* articulations, const SolverInput& in,
                                  const std::vector<Contact>& contacts, const std::vector<int>& candidates,
                                  const std::vector<int>& solver_index, const std::vector<SolverBody>& sb,
                                  const Softness& soft, const Softness& static_soft) {
  rows_.clear();
  jw_.clear();
  mechs_.clear();
  if (!articulations || candidates.empty()) return;
  Articulations& art = *articulations;
  art_ = articulations;
  in_ = in;
  pushed_.assign(art.mechanism_count(), 0);
  for (int ci : candidates) {
    const Contact& c = contacts[ci];
    if (c.count == 0) continue;
    auto side_of = [&](int body, Side& s) {
      const auto [m, l] = art.link_of(body);
      s.mech = m;
      s.link = l;
      s.body = m >= 0 ? 0 : solver_index[body];
      if (m >= 0 && std::find(mechs_.begin(), mechs_.end(), m) == mechs_.end()) mechs_.push_back(m);
    };
    Row base;
    side_of(c.body_a, base.a);
    side_of(c.body_b, base.b);
    base.contact = ci;
    base.friction = c.friction;
    base.restitution = c.restitution;
    const bool fixed_a = base.a.mech < 0 && base.a.body == 0, fixed_b = base.b.mech < 0 && base.b.body == 0;
    base.soft = fixed_a || fixed_b ? static_soft : soft;
    // The tangents as the free bodies' solver makes them (from n alone: deterministic).
    const Vec3 n = c.normal_W;
    base.d[0] = n;
    base.d[1] = contact_tangent(n);
    base.d[2] = n.cross(base.d[1]);
    for (int j = 0; j < c.count; ++j) {
      const ContactPoint& cp = c.points[j];
      Row r = base;
      r.point = j;
      // Each body's anchor on its own surface (as the free bodies' solver: prepare's make_constraint).
      r.a.p0 = cp.p_W - (0.5 * cp.separation) * n - 0.5 * cp.offset_W;
      r.b.p0 = cp.p_W + (0.5 * cp.separation) * n + 0.5 * cp.offset_W;
      r.a.r = r.a.p0 - in.state[c.body_a].x_W;
      r.b.r = r.b.p0 - in.state[c.body_b].x_W;
      r.s0 = r.s = cp.separation;
      // Warm start: the point's last normal impulse, the manifold's friction shared by its points.
      r.lambda[0] = cp.normal_impulse;
      r.lambda[1] = r.d[1].dot(c.friction_impulse_W) / c.count;
      r.lambda[2] = r.d[2].dot(c.friction_impulse_W) / c.count;
      rows_.push_back(r);
    }
  }
  std::sort(mechs_.begin(), mechs_.end());
  std::vector<Mechanism>& ms = art.mechanisms();
  for (int m : mechs_) ms[m].contact_begin(in.gravity);
  changed_.assign(art.mechanism_count(), 0);
  // Each row's J per direction and side, then its W and effective masses.
  for (Row& r : rows_) {
    for (Side* s : {&r.a, &r.b})
      if (s->mech >= 0) s->local = ms[s->mech].link_R(s->link).transpose() * s->r;
    const bool same = r.a.mech >= 0 && r.a.mech == r.b.mech;
    for (int k = 0; k < 3; ++k) {
      r.j[k][0] = r.j[k][1] = -1;
      for (int side = 0; side < 2; ++side) {
        const Side& s = side == 0 ? r.a : r.b;
        if (s.mech < 0) continue;
        if (side == 0 && same) continue;  // two links of one mechanism: one row, J_b - J_a, on B's side
        Mechanism& m = ms[s.mech];
        const int o = (int)jw_.size();
        jw_.resize(o + 3 * m.nv);
        double* J = jw_.data() + o;
        m.contact_row(s.link, s.r, r.d[k], J);
        if (side == 1 && same) {
          double* Ja = J + 2 * m.nv;  // scratch
          m.contact_row(r.a.link, r.a.r, r.d[k], Ja);
          for (int x = 0; x < m.nv; ++x) J[x] -= Ja[x];
        }
        // A direction the mechanism cannot move along (a vertical push on a hinge's axis) has a
        // zero row; round-off left in it (1e-17 m of lever) would give an effective mass of 1e66.
        double Jmax = 0;
        for (int x = 0; x < m.nv; ++x) Jmax = std::max(Jmax, std::abs(J[x]));
        if (Jmax < 1e-12) std::fill(J, J + m.nv, 0.0);
        r.j[k][side] = o;
      }
    }
    masses(r, sb);
  }
}

void ArticulatedContacts::masses(Row& r, const std::vector<SolverBody>& sb) {
  // W = P J^T per direction and mechanism side, and the effective masses 1 / (J W + free terms).
  const std::vector<Mechanism>& ms = art_->mechanisms();
  for (int k = 0; k < 3; ++k) {
    double K = 0;
    for (int side = 0; side < 2; ++side) {
      const Side& s = side == 0 ? r.a : r.b;
      if (r.j[k][side] >= 0) {
        const Mechanism& m = ms[s.mech];
        double* J = jw_.data() + r.j[k][side];
        m.contact_response(J, J + m.nv);
        for (int x = 0; x < m.nv; ++x) K += J[x] * J[m.nv + x];
      } else if (s.mech < 0 && s.body != 0) {
        const SolverBody& f = sb[s.body];
        const Vec3 rd = s.r.cross(r.d[k]);
        K += f.inv_mass + rd.dot(f.inv_I * rd);
      }
    }
    r.mass[k] = K > 0 ? 1.0 / K : 0.0;
  }
}

Vec3 ArticulatedContacts::anchor(const Side& s, const std::vector<SolverBody>& sb) const {
  if (s.mech >= 0) {
    const Mechanism& m = art_->mechanisms()[s.mech];
    return m.link_x(s.link) + m.link_R(s.link) * s.local;
  }
  if (s.body == 0) return s.p0;
  const SolverBody& f = sb[s.body];
  return s.p0 + f.dp + (f.dq * s.r - s.r);
}

double ArticulatedContacts::rate(const Row& r, int k, const std::vector<SolverBody>& sb) const {
  double v = 0;
  const std::vector<Mechanism>& ms = art_->mechanisms();
  for (int side = 0; side < 2; ++side) {
    const Side& s = side == 0 ? r.a : r.b;
    const double sign = side == 0 ? -1.0 : 1.0;
    if (r.j[k][side] >= 0) {
      const Mechanism& m = ms[s.mech];
      const double* J = jw_.data() + r.j[k][side];
      const double* qd = const_cast<Mechanism&>(m).contact_v();
      double x = 0;
      for (int i = 0; i < m.nv; ++i) x += J[i] * qd[i];
      v += sign * x;
    } else if (s.mech < 0 && s.body != 0) {
      const SolverBody& f = sb[s.body];
      v += sign * r.d[k].dot(f.v + f.w.cross(s.r));
    }
  }
  return v;
}

void ArticulatedContacts::apply(Row& r, int k, double P, std::vector<SolverBody>& sb) {
  std::vector<Mechanism>& ms = art_->mechanisms();
  for (int side = 0; side < 2; ++side) {
    const Side& s = side == 0 ? r.a : r.b;
    const double p = side == 0 ? -P : P;
    if (r.j[k][side] >= 0) {
      Mechanism& m = ms[s.mech];
      const double* W = jw_.data() + r.j[k][side] + m.nv;
      double* qd = m.contact_v();
      for (int i = 0; i < m.nv; ++i) qd[i] += W[i] * p;
    } else if (s.mech < 0 && s.body != 0) {
      SolverBody& f = sb[s.body];
      f.v += (f.inv_mass * p) * r.d[k];
      f.w += f.inv_I * (s.r.cross(r.d[k]) * p);
    }
  }
}

void ArticulatedContacts::integrate_velocities(double h) {
  std::vector<Mechanism>& ms = art_->mechanisms();
  for (int m : mechs_) ms[m].contact_velocities(h, in_.gravity);
}

void ArticulatedContacts::warm_start(std::vector<SolverBody>& sb) {
  // The approach speeds a bounce reverses, before any of the substep's impulses.
  for (Row& r : rows_) r.vn_prev = rate(r, 0, sb);
  for (Row& r : rows_)
    for (int k = 0; k < 3; ++k)
      if (r.lambda[k] != 0) apply(r, k, r.lambda[k], sb);
}

void ArticulatedContacts::normal(Row& r, std::vector<SolverBody>& sb, double h, bool use_bias) {
  const ContactSettings& cs = in_.settings;
  double bias = 0, mass_scale = 1, impulse_scale = 0;
  if (r.s > 0) {
    bias = r.s / h;  // speculative: allow closing the gap within this substep, no more
  } else if (use_bias) {
    bias = std::max(r.soft.bias_rate * std::min(0.0, r.s + cs.linear_slop), -cs.max_push_out);
    mass_scale = r.soft.mass_scale;
    impulse_scale = r.soft.impulse_scale;
  }
  const double vn = rate(r, 0, sb);
  double total =
      std::max(r.lambda[0] - r.mass[0] * mass_scale * (vn + bias) - impulse_scale * r.lambda[0], 0.0);
  // The relax may only release a point still apart after the move (as the free bodies' solver).
  if (!use_bias && r.s > 1e-3 * cs.linear_slop + 1e-12) total = std::min(total, r.lambda[0]);
  const double d = total - r.lambda[0];
  r.lambda[0] = total;
  r.max_normal = std::max(r.max_normal, total);
  if (d != 0) apply(r, 0, d, sb);
}

void ArticulatedContacts::tangents(Row& r, std::vector<SolverBody>& sb) {
  // Coulomb: the point's tangent impulse within the disk of radius mu times its normal impulse.
  const double limit = r.friction * r.lambda[0];
  double t[2];
  for (int k = 1; k <= 2; ++k) t[k - 1] = r.lambda[k] - r.mass[k] * rate(r, k, sb);
  const double len = std::hypot(t[0], t[1]);
  if (len > limit && len > 0) {
    t[0] *= limit / len;
    t[1] *= limit / len;
  }
  for (int k = 1; k <= 2; ++k) {
    const double d = t[k - 1] - r.lambda[k];
    r.lambda[k] = t[k - 1];
    if (d != 0) apply(r, k, d, sb);
  }
}

void ArticulatedContacts::solve(std::vector<SolverBody>& sb, double h, bool use_bias) {
  for (Row& r : rows_) normal(r, sb, h, use_bias);
  for (Row& r : rows_) tangents(r, sb);
}

void ArticulatedContacts::integrate_positions(double h, const std::vector<SolverBody>& sb) {
  std::vector<Mechanism>& ms = art_->mechanisms();
  bool changed = false;
  for (int m : mechs_) {
    const bool c = ms[m].contact_positions(h, in_.gravity);
    changed_[m] = c;
    changed = changed || c;
  }
  // A mechanism whose held rows changed (a stop reached or left) answers impulses differently:
  // its rows' W = P J^T and effective masses again, J kept from the step's start.
  if (changed)
    for (Row& r : rows_)
      if ((r.a.mech >= 0 && changed_[r.a.mech]) || (r.b.mech >= 0 && changed_[r.b.mech])) masses(r, sb);
  for (Row& r : rows_) {
    const Vec3 da = anchor(r.a, sb) - r.a.p0, db = anchor(r.b, sb) - r.b.p0;
    r.s = r.s0 + r.d[0].dot(db - da);
  }
}

void ArticulatedContacts::restitution(std::vector<SolverBody>& sb, double threshold) {
  const double slop = in_.settings.linear_slop + 1e-9;
  for (Row& r : rows_) {
    if (r.restitution == 0) continue;
    if (r.bounced && r.s > slop) r.bounced = false;  // apart again: it may bounce again
    if (r.bounced || r.vn_prev >= -threshold || r.lambda[0] <= 0 || r.s > slop) continue;
    // Newton's restitution on the point: its normal rate to -e times the approach rate, by an
    // extra push (the free bodies' solver does the same: restitution_one).
    const double vn = rate(r, 0, sb);
    const double P = std::max(-r.mass[0] * (vn + r.restitution * r.vn_prev), 0.0);
    if (P > 0) apply(r, 0, P, sb);
    r.max_normal = std::max(r.max_normal, r.lambda[0] + P);
    r.lambda[0] = 0;  // the bounce is this substep's; the next substep starts from no push
    r.bounced = true;
  }
}

void ArticulatedContacts::store(std::vector<Contact>& contacts) const {
  for (const Row& r : rows_) {
    Contact& c = contacts[r.contact];
    c.points[r.point].normal_impulse = r.lambda[0];
    if (r.point == 0) c.friction_impulse_W.setZero();
    c.friction_impulse_W += r.lambda[1] * r.d[1] + r.lambda[2] * r.d[2];
    c.twist_impulse = 0;
    c.rolling_impulse.setZero();
  }
}

void ArticulatedContacts::touched(std::vector<char>& touched_none) const {
  for (const Row& r : rows_) {
    if (r.max_normal <= 0) continue;
    if (r.a.mech < 0) touched_none[r.a.body] = 0;
    if (r.b.mech < 0) touched_none[r.b.body] = 0;
  }
  touched_none[0] = 0;
}

void ArticulatedContacts::finish(MotionState* state) {
  if (!art_ || mechs_.empty()) return;  // no mechanism had a contact this step
  for (const Row& r : rows_) {
    if (r.max_normal <= 0) continue;
    if (r.a.mech >= 0) pushed_[r.a.mech] = 1;
    if (r.b.mech >= 0) pushed_[r.b.mech] = 1;
  }
  std::vector<Mechanism>& ms = art_->mechanisms();
  for (int m : mechs_) {
    if (!pushed_[m]) continue;  // nothing touched it after all: the adaptive integrator takes the step
    ms[m].contact_end();
    ms[m].write_bodies(state);
    ms[m].contact_stepped = true;
  }
}

}  // namespace simreel
