#include "sim/world/snapshot.hpp"

#include <bit>
#include <cmath>
#include <cstring>
#include <istream>
#include <ostream>
#include <string>

#include <simreel/error.hpp>
#include "sim/base/hash.hpp"
#include "sim/world/world_impl.hpp"

namespace simreel {

namespace {

constexpr char kMagic[] = "SIMREEL-STATE\n";

class Out {
 public:
  explicit Out(std::ostream& os) : os_(os) {}
  void u64(uint64_t v) {
    unsigned char b[8];
    for (int i = 0; i < 8; ++i) b[i] = (unsigned char)(v >> (8 * i));
    os_.write(reinterpret_cast<const char*>(b), 8);
  }
  void u32(uint32_t v) {
    unsigned char b[4];
    for (int i = 0; i < 4; ++i) b[i] = (unsigned char)(v >> (8 * i));
    os_.write(reinterpret_cast<const char*>(b), 4);
  }
  void i32(int32_t v) { u32((uint32_t)v); }
  void i64(int64_t v) { u64((uint64_t)v); }
  void u8(uint8_t v) { os_.put((char)v); }
  void f64(double v) { u64(std::bit_cast<uint64_t>(v)); }
  void vec(const Vec3& v) {
    f64(v.x());
    f64(v.y());
    f64(v.z());
  }
  void quat(const Quat& q) {
    f64(q.w());
    f64(q.x());
    f64(q.y());
    f64(q.z());
  }

 private:
  std::ostream& os_;
};

class In {
 public:
  explicit In(std::istream& is) : is_(is) {}
  uint64_t u64() {
    unsigned char b[8];
    read(b, 8);
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= (uint64_t)b[i] << (8 * i);
    return v;
  }
  uint32_t u32() {
    unsigned char b[4];
    read(b, 4);
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= (uint32_t)b[i] << (8 * i);
    return v;
  }
  int32_t i32() { return (int32_t)u32(); }
  int64_t i64() { return (int64_t)u64(); }
  uint8_t u8() {
    unsigned char b;
    read(&b, 1);
    return b;
  }
  double f64() { return std::bit_cast<double>(u64()); }
  Vec3 vec() {
    const double x = f64(), y = f64(), z = f64();
    return Vec3(x, y, z);
  }
  Quat quat() {
    const double w = f64(), x = f64(), y = f64(), z = f64();
    return Quat(w, x, y, z);
  }

 private:
  void read(unsigned char* b, std::streamsize n) {
    is_.read(reinterpret_cast<char*>(b), n);
    if (is_.gcount() != n) throw InputError("saved state is truncated");
  }
  std::istream& is_;
};

void fnv(uint64_t& h, const void* p, size_t n) {
  h = fnv1a(h, p, n);
}

}  // namespace

uint64_t WorldImpl::fingerprint() const {
  uint64_t h = kFnvOffsetBasis;
  const uint64_t n = defs_.size();
  fnv(h, &n, sizeof n);
  for (const BodyDef& d : defs_) {
    fnv(h, d.name.data(), d.name.size());
    const int t = (int)d.type;
    fnv(h, &t, sizeof t);
  }
  const uint64_t ns = shapes_->size();
  fnv(h, &ns, sizeof ns);
  for (const ShapeRecord& r : shapes_->shapes()) {
    const int k = (int)r.geom.kind;
    fnv(h, &k, sizeof k);
  }
  const uint64_t dt = std::bit_cast<uint64_t>(cfg_.dt);
  fnv(h, &dt, sizeof dt);
  // The force list's kinds and bodies (only when there is one: a scene without forces keeps the
  // fingerprint it had before forces existed).
  if (!cfg_.forces.empty()) {
    const uint64_t nf = cfg_.forces.size();
    fnv(h, &nf, sizeof nf);
    for (const ForceDef& f : cfg_.forces) {
      const int v[3] = {(int)f.kind, f.body, f.body_b};
      fnv(h, v, sizeof v);
    }
  }
  // The joints' types and bodies, likewise only when there are some.
  if (!cfg_.joints.empty()) {
    const uint64_t nj = cfg_.joints.size();
    fnv(h, &nj, sizeof nj);
    for (const JointDef& j : cfg_.joints) {
      const int v[3] = {(int)j.type, j.parent, j.child};
      fnv(h, v, sizeof v);
      // Which coordinates carry limits, a motor or friction (their saved modes), when any do.
      if (j.limits || j.motor || j.friction != 0 || j.steering) {
        const int w[4] = {j.limits ? 1 : 0, j.motor ? 1 + (int)j.motor->mode : 0, j.friction != 0 ? 1 : 0,
                          j.steering ? 1 : 0};
        fnv(h, w, sizeof w);
      }
      // A pulley over a wheel saves one rope mode per run.
      if (j.type == JointType::pulley && j.wheel >= 0) fnv(h, &j.wheel, sizeof j.wheel);
    }
  }
  return h;
}

void WorldImpl::save_state(std::ostream& os) const {
  Out o(os);
  os.write(kMagic, sizeof kMagic - 1);
  o.u32(kStateVersion);
  o.u64(fingerprint());
  o.i64(steps_);
  for (size_t i = 0; i < state_.size(); ++i) {
    const MotionState& s = state_[i];
    o.quat(s.q_WP);
    o.vec(s.x_W);
    o.vec(s.v_W);
    o.vec(s.w_P);
    o.vec(wrench_[i].f_W);
    o.vec(wrench_[i].tau_W);
  }
  o.i32(contacts_.stats().contacts_max);
  o.f64(contacts_.stats().max_penetration);
  // The active and resting records merged in key order: the one list the contact set keeps.
  o.u32((uint32_t)contacts_.size());
  contacts_.for_each([&o](const Contact& c) {
    o.i32(c.shape_a);
    o.i32(c.shape_b);
    o.i32(c.body_a);
    o.i32(c.body_b);
    o.vec(c.normal_W);
    o.i32(c.count);
    for (int j = 0; j < c.count; ++j) {
      const ContactPoint& p = c.points[j];
      o.u32(p.id);
      o.vec(p.p_W);
      o.f64(p.separation);
      o.f64(p.normal_impulse);
    }
    o.vec(c.friction_impulse_W);
    o.f64(c.twist_impulse);
    o.vec(c.rolling_impulse);
    o.u8(c.cache.type);
    o.i32(c.cache.a);
    o.i32(c.cache.b);
    o.f64(c.friction);
    o.f64(c.restitution);
  });
  o.u32((uint32_t)forces_.fired_flags().size());
  for (char f : forces_.fired_flags()) o.u8((uint8_t)f);
  o.i32(settle_substeps_);
  for (size_t i = 0; i < state_.size(); ++i) {
    o.f64(islands_.still_time(i));
    o.i32(islands_.island(i));
  }
  // The mechanisms' coordinates, velocities and proposed next internal step: present only in a
  // scene with joints (its fingerprint says so), so older files keep their bytes.
  for (const Mechanism& m : joints_.mechanisms()) {
    for (double x : m.q) o.f64(x);
    for (double x : m.v) o.f64(x);
    o.f64(m.h);
    // Tracked loop hinges' continuous angles (only where a loop hinge carries a spring or stops).
    for (const Mechanism::Loop& L : m.loops)
      if (L.tracked) o.f64(L.angle);
    // The modes of limits, motors and friction (only when the mechanism has any).
    if (m.events_on()) {
      o.u8(m.started ? 1 : 0);
      for (const Mechanism::Dof& d : m.dofs) {
        o.i32(d.at_stop);
        o.i32(d.push);
        o.i32(d.slide);
        o.u8((uint8_t)((d.hold ? 1 : 0) | (d.stick ? 2 : 0)));
      }
      for (const Mechanism::Tether& t : m.tethers) o.i32(t.taut);  // slack or taut ropes
    }
  }
  // Version 4: the rolling bodies' proposed next internal step.
  const std::vector<double>& roll_h = rolling_.proposals();
  uint32_t rolling = 0;
  for (double h : roll_h) rolling += h > 0 ? 1 : 0;
  o.u32(rolling);
  for (size_t i = 0; i < roll_h.size(); ++i)
    if (roll_h[i] > 0) {
      o.i32((int32_t)i);
      o.f64(roll_h[i]);
    }
  // Version 5: the mechanisms' steps running past the frame (retaken from their start on restore).
  uint32_t spans = 0;
  for (const Mechanism& m : joints_.mechanisms()) spans += m.span.valid ? 1 : 0;
  o.u32(spans);
  for (size_t k = 0; k < joints_.mechanisms().size(); ++k) {
    const Mechanism::Span& sp = joints_.mechanisms()[k].span;
    if (!sp.valid) continue;
    o.i32((int32_t)k);
    for (double x : {sp.t0, sp.len, sp.t_out, sp.g.x(), sp.g.y(), sp.g.z()}) o.f64(x);
    for (double x : sp.y0) o.f64(x);
  }
  // Version 6: the Verlet mechanisms' carried accelerations and measured fastest modes.
  auto verlet_started = [](const Mechanism& m) { return m.verlet.carry || m.verlet.rate > 0; };
  uint32_t verlets = 0;
  for (const Mechanism& m : joints_.mechanisms()) verlets += verlet_started(m) ? 1 : 0;
  o.u32(verlets);
  for (size_t k = 0; k < joints_.mechanisms().size(); ++k) {
    const Mechanism::Verlet& vl = joints_.mechanisms()[k].verlet;
    if (!verlet_started(joints_.mechanisms()[k])) continue;
    o.i32((int32_t)k);
    o.u8(vl.carry ? 1 : 0);
    for (double x : {vl.rate, vl.growth, vl.g.x(), vl.g.y(), vl.g.z()}) o.f64(x);
    o.i64(vl.next);
    o.i32(vl.every);
    for (double x : vl.x) o.f64(x);
    for (double x : vl.a) o.f64(x);
  }
  if (!os) throw std::runtime_error("could not write the saved state");
}

void WorldImpl::restore_state(std::istream& is) {
  char magic[sizeof kMagic - 1];
  is.read(magic, sizeof magic);
  if (is.gcount() != (std::streamsize)sizeof magic || std::memcmp(magic, kMagic, sizeof magic) != 0)
    throw InputError("not a simreel saved state");
  In in(is);
  const uint32_t version = in.u32();
  if (version < 1 || version > kStateVersion)
    throw InputError("saved state has version " + std::to_string(version) + "; this simreel reads version " +
                     std::to_string(kStateVersion));
  if (in.u64() != fingerprint())
    throw InputError("saved state is from another scene (bodies, shapes or timestep differ)");
  const int64_t steps = in.i64();
  if (steps < 0) throw InputError("saved state is damaged (negative step count)");
  std::vector<MotionState> state(state_.size());
  std::vector<Wrench> wrench(state_.size());
  bool dirty = false;
  for (size_t i = 0; i < state.size(); ++i) {
    MotionState& s = state[i];
    s.q_WP = in.quat();
    s.x_W = in.vec();
    s.v_W = in.vec();
    s.w_P = in.vec();
    wrench[i].f_W = in.vec();
    wrench[i].tau_W = in.vec();
    dirty = dirty || !wrench[i].f_W.isZero(0) || !wrench[i].tau_W.isZero(0);
    if (!s.q_WP.coeffs().allFinite() || !all_finite(s.x_W) || !all_finite(s.v_W) || !all_finite(s.w_P))
      throw InputError("saved state is damaged (non-finite state of body '" + defs_[i].name + "')");
  }
  ContactStats stats;
  stats.contacts_max = in.i32();
  stats.max_penetration = in.f64();
  const uint32_t nc = in.u32();
  const int ns = shapes_->size();
  if (nc > (uint64_t)ns * (uint64_t)ns) throw InputError("saved state is damaged (contact count)");
  std::vector<Contact> contacts(nc);
  uint64_t last = 0;
  for (uint32_t k = 0; k < nc; ++k) {
    Contact& c = contacts[k];
    c.shape_a = in.i32();
    c.shape_b = in.i32();
    c.body_a = in.i32();
    c.body_b = in.i32();
    if (c.shape_a < 0 || c.shape_b <= c.shape_a || c.shape_b >= ns || (k > 0 && c.key() < last) ||
        c.body_a != (*shapes_)[c.shape_a].body || c.body_b != (*shapes_)[c.shape_b].body)
      throw InputError("saved state is damaged (contact " + std::to_string(k) + ")");
    last = c.key();
    c.normal_W = in.vec();
    c.count = in.i32();
    if (c.count < 0 || c.count > 4) throw InputError("saved state is damaged (contact point count)");
    for (int j = 0; j < c.count; ++j) {
      ContactPoint& p = c.points[j];
      p.id = in.u32();
      p.p_W = in.vec();
      p.separation = in.f64();
      p.normal_impulse = in.f64();
    }
    c.friction_impulse_W = in.vec();
    c.twist_impulse = in.f64();
    c.rolling_impulse = in.vec();
    c.cache.type = in.u8();
    c.cache.a = in.i32();
    c.cache.b = in.i32();
    c.friction = in.f64();
    c.restitution = in.f64();
  }
  // Version 2: which impulses were applied. Version 1 had no forces (its fingerprint matched a
  // world without any): none applied.
  std::vector<char> fired(forces_.fired_flags().size(), 0);
  if (version >= 2) {
    if (in.u32() != fired.size()) throw InputError("saved state is damaged (force count)");
    for (char& f : fired) {
      const uint8_t b = in.u8();
      if (b > 1) throw InputError("saved state is damaged (impulse flag)");
      f = (char)b;
    }
  }
  // Version 3: substeps left with an impact's extra sweep (none before).
  // and each body's still time and sleeping island (all awake before).
  int settle = 0;
  std::vector<double> still(state_.size(), 0.0);
  std::vector<int> asleep(state_.size(), -1);
  if (version >= 3) {
    settle = in.i32();
    if (settle < 0 || settle > 100000) throw InputError("saved state is damaged (impact settling)");
    for (size_t i = 0; i < state_.size(); ++i) {
      still[i] = in.f64();
      asleep[i] = in.i32();
      if (!(still[i] >= 0) || !std::isfinite(still[i]) || asleep[i] < -1 || asleep[i] >= (int)state_.size() ||
          (asleep[i] >= 0 && !islands_.may_sleep((int)i)))
        throw InputError("saved state is damaged (sleep state of body '" + defs_[i].name + "')");
    }
  }
  std::vector<std::vector<double>> mq, mv;
  std::vector<double> mh;
  std::vector<std::vector<double>> angles;
  std::vector<std::vector<int>> modes;
  for (const Mechanism& m : joints_.mechanisms()) {
    mq.emplace_back(m.q.size());
    mv.emplace_back(m.v.size());
    for (double& x : mq.back()) x = in.f64();
    for (double& x : mv.back()) x = in.f64();
    mh.push_back(in.f64());
    bool ok = std::isfinite(mh.back()) && mh.back() >= 0;
    angles.emplace_back();
    for (const Mechanism::Loop& L : m.loops)
      if (L.tracked) {
        angles.back().push_back(in.f64());
        ok = ok && std::isfinite(angles.back().back());
      }
    for (double x : mq.back()) ok = ok && std::isfinite(x);
    for (double x : mv.back()) ok = ok && std::isfinite(x);
    if (m.events_on()) {
      const uint8_t started = in.u8();
      ok = ok && started <= 1;
      modes.emplace_back();
      modes.back().push_back(started);
      for (size_t d = 0; d < m.dofs.size(); ++d) {
        const int at = in.i32(), push = in.i32(), slide = in.i32(), flags = in.u8();
        ok = ok && at >= -1 && at <= 1 && push >= -1 && push <= 1 && slide >= -1 && slide <= 1 && flags <= 3;
        for (int x : {at, push, slide, flags}) modes.back().push_back(x);
      }
      for (size_t t = 0; t < m.tethers.size(); ++t) {
        const int taut = in.i32();
        ok = ok && taut >= -1 && taut <= 1 && (taut == 0 || !m.tethers[t].rod);
        modes.back().push_back(taut);
      }
    } else {
      modes.emplace_back();
    }
    if (!ok) throw InputError("saved state is damaged (joint coordinates)");
  }
  for (size_t k = 0; k < mq.size(); ++k) {
    Mechanism& m = joints_.mechanisms()[k];
    m.q = std::move(mq[k]);
    m.v = std::move(mv[k]);
    m.h = mh[k];
    size_t a = 0;
    for (Mechanism::Loop& L : m.loops)
      if (L.tracked) L.angle = angles[k][a++];
    if (m.events_on()) {
      const std::vector<int>& md = modes[k];
      m.started = md[0] != 0;
      for (size_t d = 0; d < m.dofs.size(); ++d) {
        Mechanism::Dof& f = m.dofs[d];
        f.at_stop = md[1 + 4 * d];
        f.push = md[2 + 4 * d];
        f.slide = md[3 + 4 * d];
        f.hold = (md[4 + 4 * d] & 1) != 0;
        f.stick = (md[4 + 4 * d] & 2) != 0;
      }
      for (size_t t = 0; t < m.tethers.size(); ++t) m.tethers[t].taut = md[1 + 4 * m.dofs.size() + t];
    }
  }
  std::vector<double> roll_h(state_.size(), 0.0);
  if (version >= 4) {
    const uint32_t rolling = in.u32();
    if (rolling > state_.size()) throw InputError("saved state is damaged (rolling bodies)");
    int prev = -1;
    for (uint32_t k = 0; k < rolling; ++k) {
      const int i = in.i32();
      const double h = in.f64();
      if (i <= prev || i >= (int)state_.size() || !(h > 0) || !std::isfinite(h))
        throw InputError("saved state is damaged (rolling body " + std::to_string(k) + ")");
      roll_h[i] = h;
      prev = i;
    }
  }
  std::vector<Mechanism::Span> spans(joints_.mechanisms().size());
  if (version >= 5) {
    const uint32_t n = in.u32();
    if (n > spans.size()) throw InputError("saved state is damaged (joint steps)");
    int prev = -1;
    for (uint32_t k = 0; k < n; ++k) {
      const int i = in.i32();
      if (i <= prev || i >= (int)spans.size())
        throw InputError("saved state is damaged (joint step " + std::to_string(k) + ")");
      const Mechanism& m = joints_.mechanisms()[i];
      Mechanism::Span& sp = spans[i];
      sp.t0 = in.f64();
      sp.len = in.f64();
      sp.t_out = in.f64();
      for (int c = 0; c < 3; ++c) sp.g[c] = in.f64();
      sp.y0.resize((size_t)(m.nq + m.nv));
      bool ok = sp.len > 0 && std::isfinite(sp.len) && std::isfinite(sp.t0) && std::isfinite(sp.t_out) &&
                sp.g.allFinite() && m.nq == m.nv && sp.t0 <= sp.t_out &&
                sp.t_out <= sp.t0 + sp.len * (1 + 1e-9);
      for (double& x : sp.y0) ok = ok && std::isfinite(x = in.f64());
      if (!ok) throw InputError("saved state is damaged (joint step " + std::to_string(k) + ")");
      sp.valid = sp.retake = true;
      prev = i;
    }
  }
  std::vector<Mechanism::Verlet> verlets(joints_.mechanisms().size());
  for (size_t k = 0; k < verlets.size(); ++k) {
    const Mechanism& m = joints_.mechanisms()[k];
    Mechanism::Verlet& vl = verlets[k];
    vl.a.assign(m.nv, 0);
    vl.x.assign(m.nq + m.nv, 0);
    vl.y = m.q;  // restored above
    vl.y.insert(vl.y.end(), m.v.begin(), m.v.end());
  }
  if (version >= 6) {
    const uint32_t n = in.u32();
    if (n > verlets.size()) throw InputError("saved state is damaged (verlet mechanisms)");
    int prev = -1;
    for (uint32_t k = 0; k < n; ++k) {
      const int i = in.i32();
      if (i <= prev || i >= (int)verlets.size())
        throw InputError("saved state is damaged (verlet mechanism " + std::to_string(k) + ")");
      Mechanism::Verlet& vl = verlets[i];
      const uint8_t carry = in.u8();
      vl.carry = carry == 1;
      vl.rate = in.f64();
      vl.growth = in.f64();
      for (int c = 0; c < 3; ++c) vl.g[c] = in.f64();
      vl.next = in.i64();
      vl.every = in.i32();
      bool ok = carry <= 1 && std::isfinite(vl.rate) && vl.rate >= 0 && vl.g.allFinite() &&
                std::isfinite(vl.growth) && vl.growth >= 1 && vl.every >= 1 &&
                vl.every <= Mechanism::kVerletEvery;
      for (double& x : vl.x) ok = ok && std::isfinite(x = in.f64());
      for (double& x : vl.a) ok = ok && std::isfinite(x = in.f64());
      if (!ok) throw InputError("saved state is damaged (verlet mechanism " + std::to_string(k) + ")");
      prev = i;
    }
  }
  for (size_t k = 0; k < verlets.size(); ++k) {  // the saved fields; the scratch and counts stay
    Mechanism::Verlet& to = joints_.mechanisms()[k].verlet;
    Mechanism::Verlet& from = verlets[k];
    to.carry = from.carry;
    to.g = from.g;
    to.a = std::move(from.a);
    to.y = std::move(from.y);
    to.x = std::move(from.x);
    to.rate = from.rate;
    to.growth = from.growth;
    to.next = from.next;
    to.every = from.every;
  }
  for (size_t k = 0; k < spans.size(); ++k) {
    Mechanism::Span& sp = joints_.mechanisms()[k].span;
    if (spans[k].valid)
      sp = spans[k];  // retaken from its start at the next step
    else
      sp.valid = false;
  }
  forces_.restore_fired(std::move(fired));
  if (!roll_h.empty() && rolling_.proposals().size() == roll_h.size())
    rolling_.restore_proposals(std::move(roll_h));
  settle_substeps_ = settle;
  state_ = std::move(state);
  wrench_ = std::move(wrench);
  wrench_dirty_ = dirty;
  steps_ = steps;
  contacts_.restore(std::move(contacts), stats);
  after_restore(std::move(still), std::move(asleep));
}

}  // namespace simreel
