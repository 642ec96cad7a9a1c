#include "app/scene/camera_motion.hpp"

#include <algorithm>
#include <cmath>

namespace simreel {

CameraPath::CameraPath(std::vector<CameraKey> keys) : keys_(std::move(keys)) {
  auto add = [](Track& tr, double t, const Vec3& v) {
    tr.t.push_back(t);
    tr.v.push_back(v);
  };
  for (const CameraKey& k : keys_) {
    if (k.position) add(position_, k.t, *k.position);
    if (k.look_at) add(look_at_, k.t, *k.look_at);
    if (k.up) add(up_, k.t, *k.up);
    if (k.fov) add(fov_, k.t, Vec3(*k.fov, 0, 0));
  }
  // Velocities at the keys: zero at the two ends (the holds join C1), the parabola's through the
  // neighbours inside: m_i = (h_i d_(i-1) + h_(i-1) d_i) / (h_(i-1) + h_i), h_i = t_(i+1) - t_i,
  // d_i = (v_(i+1) - v_i) / h_i.
  for (Track* tr : {&position_, &look_at_, &up_, &fov_}) {
    const size_t n = tr->t.size();
    tr->m.assign(n, Vec3::Zero());
    for (size_t i = 1; i + 1 < n; ++i) {
      const double h0 = tr->t[i] - tr->t[i - 1], h1 = tr->t[i + 1] - tr->t[i];
      const Vec3 d0 = (tr->v[i] - tr->v[i - 1]) / h0, d1 = (tr->v[i + 1] - tr->v[i]) / h1;
      tr->m[i] = (h1 * d0 + h0 * d1) / (h0 + h1);
    }
  }
}

Vec3 CameraPath::Track::at(double time) const {
  if (time <= t.front()) return v.front();
  if (time >= t.back()) return v.back();
  // The segment [t_i, t_(i+1)) holding `time`; at a key the value is the key's exactly (s = 0).
  const size_t i = (size_t)(std::upper_bound(t.begin(), t.end(), time) - t.begin()) - 1;
  const double h = t[i + 1] - t[i], s = (time - t[i]) / h;
  if (s == 0) return v[i];
  // Cubic Hermite basis.
  const double s2 = s * s, s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
  return h00 * v[i] + h10 * h * m[i] + h01 * v[i + 1] + h11 * h * m[i + 1];
}

void CameraPath::apply(double t, Vec3& position, Vec3& look_at, Vec3& up, double& fov_deg) const {
  if (!position_.t.empty()) position = position_.at(t);
  if (!look_at_.t.empty()) look_at = look_at_.at(t);
  if (!up_.t.empty()) up = up_.at(t);
  if (!fov_.t.empty()) fov_deg = fov_.at(t).x();
}

Vec3 CameraOrbit::eye(double t, const Vec3& centre) const {
  const double a = start_angle + rate * t;
  return centre + Vec3(radius * std::cos(a), radius * std::sin(a), height);
}

DampedFollow::State DampedFollow::state() const {
  State s;
  s.started = started_, s.step = step_, s.t = t_;
  for (int k = 0; k < 3; ++k) s.x[k] = x_[k], s.v[k] = v_[k], s.p[k] = p_[k];
  return s;
}

void DampedFollow::set_state(const State& s) {
  started_ = s.started, step_ = s.step, t_ = s.t;
  for (int k = 0; k < 3; ++k) x_[k] = s.x[k], v_[k] = s.v[k], p_[k] = s.p[k];
}

void DampedFollow::track(long step, double t, const Vec3& p) {
  if (!started_) {
    started_ = true;
    step_ = step, t_ = t;
    x_ = p_ = p;
    v_.setZero();
    return;
  }
  if (step <= step_) return;
  const double h = t - t_;
  step_ = step, t_ = t;
  // The target moved from p_ to p at u over the step: z = x - (p - 2u/w) decays as a critically
  // damped oscillator (see the header), solved exactly over h.
  const Vec3 u = (p - p_) / h;
  const Vec3 lag = 2 * u / w_;
  const Vec3 z0 = x_ - (p_ - lag), dz0 = v_ - u;
  const double e = std::exp(-w_ * h);
  const Vec3 c = dz0 + w_ * z0;
  const Vec3 z = (z0 + c * h) * e, dz = (dz0 - w_ * c * h) * e;
  x_ = p - lag + z;
  v_ = u + dz;
  p_ = p;
}

}  // namespace simreel
