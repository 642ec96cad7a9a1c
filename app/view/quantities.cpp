// HUD fields' and plot quantities' values, and the values measured over the physics steps
// (app/view/quantities.hpp).
#include "app/view/quantities.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "app/view/view_state.hpp"

namespace simreel {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A per-body vector quantity of the HUD's names.
Vec3 body_vector(const HudField& f, const World& w) {
  const int i = f.body;
  if (f.name == "P") return w.total_momentum();  // the scene's, of every moving body
  if (f.name == "omega") return w.angular_velocity(i);
  if (f.name == "omega_body") return w.angular_velocity_principal(i);
  if (f.name == "L") return w.angular_momentum(i);
  if (f.name == "v") return w.linear_velocity(i);
  if (f.name == "p") return w.mass(i) * w.linear_velocity(i);
  if (f.name == "position") return w.centroid(i);
  return Vec3::Zero();
}

// A per-body number: `tilt`, the angle of the body's z axis from the world's vertical (deg; for a
// disk or coin with its axis along z, the angle between the disk and a level floor); `precession`,
// the rate at which that axis turns about the vertical (rad/s, counter-clockwise seen from above;
// the line of nodes' rate, Omega of Euler's disk); `m`, the mass (kg); `KE`, the kinetic energy of
// translation and rotation (J).
bool body_scalar(const HudField& f, const World& w, double& out) {
  if (f.name == "m") {
    out = w.mass(f.body);
    return true;
  }
  if (f.name == "KE") {
    const Vec3 v = w.linear_velocity(f.body);
    out = 0.5 * w.mass(f.body) * v.squaredNorm() +
          0.5 * w.angular_velocity(f.body).dot(w.angular_momentum(f.body));
    return true;
  }
  if (f.name != "tilt" && f.name != "precession") return false;
  const Vec3 a = w.local_to_world_vec(f.body, Vec3::UnitZ());
  if (f.name == "tilt") {
    out = std::acos(std::clamp(a.z(), -1.0, 1.0)) * 180.0 / std::numbers::pi;
  } else {
    const Vec3 da = w.angular_velocity(f.body).cross(a);
    const double h2 = a.x() * a.x() + a.y() * a.y();
    out = h2 > 1e-24 ? (a.x() * da.y() - a.y() * da.x()) / h2 : 0.0;
  }
  return true;
}

// Whether two fields read the same thing (a measured value's identity: the same text may mean
// another body under a plot's `body:`).
bool same(const HudField& a, const HudField& b) {
  if (a.name != b.name || a.body != b.body || a.component != b.component || a.norm != b.norm ||
      a.joint != b.joint || a.coord != b.coord || a.window != b.window || a.body2 != b.body2 ||
      a.code.size() != b.code.size() || a.terms.size() != b.terms.size())
    return false;
  for (size_t k = 0; k < a.code.size(); ++k) {
    const HudField::Op &x = a.code[k], &y = b.code[k];
    if (x.kind != y.kind || x.value != y.value || x.arg != y.arg || x.fn != y.fn) return false;
  }
  for (size_t k = 0; k < a.terms.size(); ++k)
    if (!same(a.terms[k], b.terms[k])) return false;
  return true;
}

// Whether the bodies touch at the end of the last step: a point overlapping or pushing.
bool touching(const std::vector<ContactData>& pairs, int other) {
  for (const ContactData& c : pairs) {
    if (other >= 0 && c.body_a != other) continue;
    for (int j = 0; j < c.count; ++j)
      if (c.points[j].separation <= 0 || c.points[j].normal_force > 0) return true;
  }
  return false;
}

}  // namespace

void StepMeters::track(const HudField& f, double dt) {
  for (const HudField& t : f.terms)
    if (!f.is_meter()) track(t, dt);  // a meter's argument is read by the meter, not measured itself
  if (f.joint >= 0 && f.name.starts_with("period")) {
    for (const JointMeter& m : joints_)
      if (m.joint == f.joint && m.coord == f.coord) return;
    JointMeter m;
    m.joint = f.joint, m.coord = f.coord;
    joints_.push_back(m);
    return;
  }
  if (!f.is_meter()) return;
  for (const Meter& m : meters_)
    if (same(m.spec, f)) return;
  Meter m;
  m.spec = f;
  if (f.name == "mean" && f.window > 0) {
    const size_t n = (size_t)std::ceil(f.window / dt - 1e-9) + 1;  // the window's steps and its start
    m.ring_t.assign(n, 0.0);
    m.ring_i.assign(n, 0.0);
  }
  if (f.name == "first_contact") scratch_.reserve(64);
  meters_.push_back(std::move(m));
}

void StepMeters::record(const World& w) {
  const long step = w.steps();
  const double t = w.time();
  for (JointMeter& m : joints_) {
    if (step <= m.last_step) continue;
    const double s = w.joint_speed(m.joint, m.coord);
    if (m.last_step >= 0) {
      // A turn between the previous step (rate m.s) and this one: + to - at a maximum, - to + at a
      // minimum; the rate's zero interpolated linearly between the two.
      const int dir = m.s >= 0 && s < 0 ? 1 : m.s <= 0 && s > 0 ? -1 : 0;
      if (dir) {
        const double tc = m.t + (t - m.t) * (m.s / (m.s - s));
        std::vector<double>& v = dir > 0 ? m.up : m.down;
        v.push_back(tc);
        if (v.size() >= 2) m.period = v.back() - v[v.size() - 2];
      }
    }
    m.last_step = step, m.t = t, m.s = s;
  }
  for (Meter& m : meters_) {
    if (step <= m.last_step) continue;
    record(m, w);
    m.last_step = step;
  }
}

void StepMeters::record(Meter& m, const World& w) {
  const double t = w.time();
  const std::string& kind = m.spec.name;
  if (kind == "first_contact") {
    if (std::isnan(m.value)) {
      scratch_.clear();
      bool hit = false;
      if (m.spec.body < 0) {
        w.contacts(scratch_);
        hit = touching(scratch_, -1);
      } else {
        w.body_contacts(m.spec.body, scratch_);
        hit = touching(scratch_, m.spec.body2);
      }
      // The contacts read now are the last step's: the bodies met during it, so its start is the
      // time (bodies touching from the start read 0).
      if (hit) m.value = m.samples > 0 ? m.t1 : t;
    }
    m.t1 = t;
    m.samples = std::min(m.samples + 1, 2);
    return;
  }
  const double q = quantity_value(m.spec.terms[0], w, -1, E0_, L0_);
  if (kind == "mean") {
    if (m.samples > 0) m.integral += 0.5 * (q + m.q1) * (t - m.t1);
    if (m.ring_t.empty()) {
      m.value = t > 0 ? m.integral / t : q;
    } else {
      // The ring holds the last n steps' (t, integral); the oldest is the window's start once full.
      const size_t n = m.ring_t.size();
      m.ring_t[m.head] = t, m.ring_i[m.head] = m.integral;
      m.head = (m.head + 1) % n;
      m.count = std::min(m.count + 1, n);
      const size_t oldest = m.count < n ? 0 : m.head;
      const double t0 = m.ring_t[oldest], i0 = m.ring_i[oldest];
      m.value = t > t0 ? (m.integral - i0) / (t - t0) : q;
    }
  } else if (kind == "last_zero") {
    if (m.samples == 0 && q == 0) m.value = t;
    if (m.samples > 0 && ((m.q1 > 0 && q <= 0) || (m.q1 < 0 && q >= 0)))
      m.value = m.t1 + (t - m.t1) * (m.q1 / (m.q1 - q));
  } else if (kind == "period_of" && m.samples > 0) {
    const double d = q - m.q1;
    const int dir = m.trend > 0 && d < 0 ? 1 : m.trend < 0 && d > 0 ? -1 : 0;
    if (dir && m.samples >= 2) {
      // The vertex of the parabola through the three samples around the turn (uniform steps).
      const double h = t - m.t1, den = m.q0 - 2 * m.q1 + q;
      double tc = m.t1 + (den != 0 ? 0.5 * h * (m.q0 - q) / den : 0.0);
      tc = std::clamp(tc, m.t0, t);
      double& last = dir > 0 ? m.last_up : m.last_down;
      if (!std::isnan(last)) m.value = tc - last;
      last = tc;
    }
    if (d != 0) m.trend = d > 0 ? 1 : -1;
  }
  m.t0 = m.t1, m.q0 = m.q1, m.t1 = t, m.q1 = q;
  m.samples = std::min(m.samples + 1, 2);
}

void StepMeters::save(std::ostream& os) const {
  put(os, (uint64_t)joints_.size());
  for (const JointMeter& m : joints_) {
    put(os, m.last_step);
    put(os, m.t);
    put(os, m.s);
    put(os, m.period);
    put_vec(os, m.up);
    put_vec(os, m.down);
  }
  put(os, (uint64_t)meters_.size());
  for (const Meter& m : meters_) {
    put(os, m.last_step);
    put(os, m.t1), put(os, m.q1), put(os, m.t0), put(os, m.q0);
    put(os, m.samples), put(os, m.trend);
    put(os, m.integral);
    put_vec(os, m.ring_t), put_vec(os, m.ring_i);
    put(os, (uint64_t)m.head), put(os, (uint64_t)m.count);
    put(os, m.last_up), put(os, m.last_down), put(os, m.value);
  }
}

void StepMeters::restore(std::istream& is) {
  uint64_t n = 0;
  get(is, n);
  if (n != joints_.size()) throw InputError("a checkpoint measures other joints' periods than the scene");
  for (JointMeter& m : joints_) {
    get(is, m.last_step);
    get(is, m.t);
    get(is, m.s);
    get(is, m.period);
    get_vec(is, m.up);
    get_vec(is, m.down);
  }
  get(is, n);
  if (n != meters_.size())
    throw InputError("a checkpoint measures other values than the scene's HUD and plots");
  for (Meter& m : meters_) {
    const size_t ring = m.ring_t.size();
    get(is, m.last_step);
    get(is, m.t1), get(is, m.q1), get(is, m.t0), get(is, m.q0);
    get(is, m.samples), get(is, m.trend);
    get(is, m.integral);
    get_vec(is, m.ring_t), get_vec(is, m.ring_i);
    if (m.ring_t.size() != ring || m.ring_i.size() != ring)
      throw InputError("a checkpoint's mean(q, T) has another window than the scene's");
    uint64_t head = 0, count = 0;
    get(is, head), get(is, count);
    m.head = (size_t)head, m.count = (size_t)count;
    get(is, m.last_up), get(is, m.last_down), get(is, m.value);
  }
}

double StepMeters::period(int joint, int coord) const {
  for (const JointMeter& m : joints_)
    if (m.joint == joint && m.coord == coord) return m.period;
  return kNaN;
}

double StepMeters::value(const HudField& f) const {
  for (const Meter& m : meters_)
    if (same(m.spec, f)) return m.value;
  return kNaN;
}

const std::vector<double>& StepMeters::turns(int joint, int coord, int direction) const {
  static const std::vector<double> none;
  for (const JointMeter& m : joints_)
    if (m.joint == joint && m.coord == coord) return direction > 0 ? m.up : m.down;
  return none;
}

double quantity_value(const HudField& f, const World& w, long frame, double E0, const Vec3& L0, double fps,
                      const StepMeters* meters) {
  if (f.is_expr()) {
    double st[HudField::kMaxDepth];  // the parser checked the depth
    int n = 0;
    for (const HudField::Op& op : f.code) {
      switch (op.kind) {
        case HudField::Op::number:
          st[n++] = op.value;
          break;
        case HudField::Op::term:
          st[n++] = quantity_value(f.terms[op.arg], w, frame, E0, L0, fps, meters);
          break;
        case HudField::Op::neg:
          st[n - 1] = -st[n - 1];
          break;
        case HudField::Op::fn1:
          st[n - 1] = op.fn(st[n - 1]);
          break;
        case HudField::Op::add:
          --n, st[n - 1] += st[n];
          break;
        case HudField::Op::sub:
          --n, st[n - 1] -= st[n];
          break;
        case HudField::Op::mul:
          --n, st[n - 1] *= st[n];
          break;
        case HudField::Op::div:
          --n, st[n - 1] /= st[n];
          break;
        case HudField::Op::pow:
          --n, st[n - 1] = std::pow(st[n - 1], st[n]);
          break;
        case HudField::Op::atan2:
          --n, st[n - 1] = std::atan2(st[n - 1], st[n]);
          break;
      }
    }
    return n == 1 ? st[0] : kNaN;
  }
  if (f.is_meter()) return meters ? meters->value(f) : kNaN;
  if (f.name == "frame") return (double)frame;
  if (f.joint >= 0) {
    if (f.name.starts_with("angle")) return w.joint_position(f.joint, f.coord);
    if (f.name.starts_with("speed")) return w.joint_speed(f.joint, f.coord);
    return meters ? meters->period(f.joint, f.coord) : kNaN;
  }
  if (f.body < 0 && f.name != "P") {
    const double E = w.kinetic_energy() + w.potential_energy();
    if (f.name == "t") return w.time();
    if (f.name == "video_t") return fps > 0 ? (double)frame / fps : w.time();
    if (f.name == "E") return E;
    if (f.name == "E_drift") return E0 != 0 ? (E - E0) / std::fabs(E0) : E - E0;
    if (f.name == "joint_gap") return w.joint_gap();
    if (f.name == "L_drift") {
      const double n0 = L0.norm();
      return n0 > 0 ? (w.total_angular_momentum() - L0).norm() / n0
                    : (w.total_angular_momentum() - L0).norm();
    }
    return 0;
  }
  double x;
  if (body_scalar(f, w, x)) return x;
  const Vec3 v = body_vector(f, w);
  return f.norm ? v.norm() : f.component >= 0 ? v[f.component] : 0.0;
}

void format_hud_line(const HudLine& line, const World& w, long frame, double E0, const Vec3& L0,
                     std::string& out, double fps, const StepMeters* meters) {
  out.clear();
  char buf[96];
  for (size_t k = 0; k < line.fields.size(); ++k) {
    out += line.text[k];
    const HudField& f = line.fields[k];
    const char* fmt = f.printf.c_str();
    if (f.name == "frame") {
      std::snprintf(buf, sizeof buf, fmt, frame);
      out += buf;
      continue;
    }
    if (f.scalar()) {
      const double v = quantity_value(f, w, frame, E0, L0, fps, meters);
      if (!std::isfinite(v)) {
        out += "\u2014";  // not known yet (a period before two turns), or no number (0 / 0)
        continue;
      }
      std::snprintf(buf, sizeof buf, fmt, v);
      out += buf;
      continue;
    }
    // A whole vector: (x, y, z), the format applied to each.
    const Vec3 v = body_vector(f, w);
    out += '(';
    for (int c = 0; c < 3; ++c) {
      std::snprintf(buf, sizeof buf, fmt, v[c]);
      out += buf;
      if (c < 2) out += ", ";
    }
    out += ')';
  }
  out += line.text.back();
}

}  // namespace simreel
