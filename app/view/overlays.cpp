#include "app/view/overlays.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/runner/frame_loop.hpp"
#include "app/view/ghost_view.hpp"
#include "render/camera.hpp"

namespace simreel {

namespace {

float srgb_to_linear(int c) {
  const double x = c / 255.0;
  return (float)(x <= 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4));
}

Rgba with_alpha(const ShowRgb& c, double a) {
  return {c[0], c[1], c[2], (float)a};
}

// The default colour of each kind (Okabe-Ito indices, okabe_ito()).
int default_color(ShowKind k) {
  switch (k) {
    case ShowKind::angular_velocity:
      return 7;  // reddish purple
    case ShowKind::angular_momentum:
      return 5;  // blue
    case ShowKind::velocity:
      return 3;  // bluish green
    case ShowKind::inertia_box:
    case ShowKind::inertia_ellipsoid:
      return 2;  // sky blue
    case ShowKind::trail:
    case ShowKind::center_of_mass:
    case ShowKind::axes:
      return 0;  // black
    case ShowKind::cones:
      return 1;  // orange (the body cone; the space cone is blue, as L)
    case ShowKind::poinsot:
      return 2;  // sky blue (the ellipsoid)
    case ShowKind::forces:
      return 6;  // vermillion
    case ShowKind::contacts:
      return 1;  // orange
    case ShowKind::joints:
      return 0;  // black: reads on the sky and on light and dark bodies alike
    case ShowKind::joint_forces:
      return 6;  // vermillion, as `forces`
    case ShowKind::momentum:
      return 8;  // dark yellow (okabe_ito(8)): p and v share a direction but not a colour
    case ShowKind::angular_momentum_about:
      return 5;  // blue, as L (another colour where L is shown too: resolve_colors)
    case ShowKind::snapshot:
      return 0;  // (its own: the body's colour, lightened)
  }
  return 0;
}

// Arrows of different meanings in different colours, so that a legend never shows one colour
// twice: axes keep e1 e2 e3 = vermillion, green, blue; each arrow kind in turn keeps its own colour
// unless an earlier meaning took it, and then takes the first free one of kFallback (Okabe-Ito's
// yellow, index 4, is too light on a light ground; black is the markers'). Kinds of bodies first,
// then of systems. Only items without a `color` take part; a colour is set only where it changes.
// `others`: the other panes' items, so that one quantity has one colour across a split screen.
constexpr ShowKind kArrowOrder[] = {
    ShowKind::angular_velocity,       ShowKind::angular_momentum, ShowKind::velocity, ShowKind::momentum,
    ShowKind::angular_momentum_about, ShowKind::forces,           ShowKind::contacts, ShowKind::joint_forces};
constexpr int kFallback[] = {2, 1, 8, 7, 5, 3, 6};

void resolve_colors(std::vector<std::vector<ShowItem>>& show, std::vector<SystemSpec>& systems,
                    const std::vector<const std::vector<ShowItem>*>& others) {
  bool taken[9] = {};
  auto uncoloured = [](const std::vector<ShowItem>& items, ShowKind k) {
    for (const ShowItem& s : items)
      if (s.kind == k && !s.color) return true;
    return false;
  };
  auto pick = [&](ShowKind k) {
    int c = default_color(k);
    for (int f : kFallback)
      if (taken[c]) c = f;
    taken[c] = true;
    return c;
  };
  auto apply = [](std::vector<ShowItem>& items, ShowKind k, int c) {
    if (c == default_color(k)) return;
    const Rgba rgb = okabe_ito(c);
    for (ShowItem& s : items)
      if (s.kind == k && !s.color) s.color = ShowRgb{rgb[0], rgb[1], rgb[2]};
  };
  auto has_axes = [](const std::vector<ShowItem>& items) {
    for (const ShowItem& s : items)
      if (s.kind == ShowKind::axes) return true;
    return false;
  };
  for (const auto& items : show)
    if (has_axes(items)) taken[6] = taken[3] = taken[5] = true;
  for (const auto* items : others)
    if (has_axes(*items)) taken[6] = taken[3] = taken[5] = true;
  for (ShowKind k : kArrowOrder) {
    bool present = false;
    for (const auto& items : show) present = present || uncoloured(items, k);
    for (const auto* items : others) present = present || uncoloured(*items, k);
    if (!present) continue;
    const int c = pick(k);
    for (auto& items : show) apply(items, k, c);
  }
  for (ShowKind k : {ShowKind::momentum, ShowKind::velocity, ShowKind::angular_momentum}) {
    bool present = false;
    for (const SystemSpec& y : systems) present = present || uncoloured(y.show, k);
    if (!present) continue;
    const int c = pick(k);
    for (SystemSpec& y : systems) apply(y.show, k, c);
  }
}

// A group of bodies taken together: mass M, centre of mass C, momentum P, angular momentum about C.
struct SystemState {
  double M = 0;
  Vec3 C = Vec3::Zero(), P = Vec3::Zero(), L = Vec3::Zero();
};
SystemState system_state(const World& w, const std::vector<int>& bodies) {
  SystemState y;
  for (int i : bodies) {
    const double m = w.mass(i);
    y.M += m;
    y.C += m * w.centroid(i);
    y.P += m * w.linear_velocity(i);
  }
  y.C /= y.M;
  for (int i : bodies)
    y.L += w.angular_momentum(i) + (w.centroid(i) - y.C).cross(w.mass(i) * w.linear_velocity(i));
  return y;
}

// L_O = L + (c - O) x m v: body i's angular momentum about the fixed world point O.
Vec3 momentum_about(const World& w, int i, const Vec3& O) {
  return w.angular_momentum(i) + (w.centroid(i) - O).cross(w.mass(i) * w.linear_velocity(i));
}

// A system item's quantity (the vector its arrow draws).
Vec3 system_quantity(const SystemState& y, ShowKind k) {
  return k == ShowKind::momentum ? y.P : k == ShowKind::velocity ? Vec3(y.P / y.M) : y.L;
}

void accumulate_system(const SystemState& y, Magnitudes& m) {
  m.p = std::max(m.p, y.P.norm());
  m.v = std::max(m.v, y.P.norm() / y.M);
  m.L = std::max(m.L, y.L.norm());
}

// A distance or pulley joint: never a tree edge (docs/joints.md); `joints` draws it as a rope.
bool is_rope(const JointDef& j) {
  return j.type == JointType::distance || j.type == JointType::pulley;
}

bool is_arrow(ShowKind k) {
  return k == ShowKind::angular_velocity || k == ShowKind::angular_momentum || k == ShowKind::velocity ||
         k == ShowKind::momentum || k == ShowKind::angular_momentum_about;
}

Vec3 quantity(const World& w, int i, ShowKind k) {
  switch (k) {
    case ShowKind::angular_velocity:
      return w.angular_velocity(i);
    case ShowKind::angular_momentum:
      return w.angular_momentum(i);
    case ShowKind::velocity:
      return w.linear_velocity(i);
    case ShowKind::momentum:
      return w.mass(i) * w.linear_velocity(i);
    default:
      return Vec3::Zero();
  }
}

// The largest component of each magnitude, per body.
double largest(const Magnitudes& m, ShowKind k) {
  return k == ShowKind::angular_velocity         ? m.omega
         : k == ShowKind::angular_momentum       ? m.L
         : k == ShowKind::momentum               ? m.p
         : k == ShowKind::angular_momentum_about ? m.L_about
                                                 : m.v;
}

}  // namespace

Rgba okabe_ito(int index, float alpha) {
  // Index 8: Okabe-Ito's yellow darkened to 75% (#B4AB32), which its own yellow (#F0E442) is too
  // light to read as on a light ground.
  static const int hex[9] = {0x000000, 0xE69F00, 0x56B4E9, 0x009E73, 0xF0E442,
                             0x0072B2, 0xD55E00, 0xCC79A7, 0xB4AB32};
  const int h = hex[((index % 9) + 9) % 9];
  return {srgb_to_linear(h >> 16), srgb_to_linear((h >> 8) & 255), srgb_to_linear(h & 255), alpha};
}

namespace {

// The largest magnitudes of the world's present state into m (dynamic bodies).
void accumulate(const World& w, std::vector<Magnitudes>& m) {
  for (int i = 0; i < w.body_count(); ++i) {
    if (w.type(i) != BodyType::dynamic) continue;
    m[i].omega = std::max(m[i].omega, w.angular_velocity(i).norm());
    m[i].L = std::max(m[i].L, w.angular_momentum(i).norm());
    m[i].v = std::max(m[i].v, w.linear_velocity(i).norm());
    m[i].p = std::max(m[i].p, w.mass(i) * w.linear_velocity(i).norm());
  }
  if (!w.has_forces()) return;
  struct Max : ForceVisitor {
    std::vector<Magnitudes>& m;
    explicit Max(std::vector<Magnitudes>& m) : m(m) {}
    void force(int i, const Vec3& F, const Vec3&, ForceKind) override {
      m[i].force = std::max(m[i].force, F.norm());
    }
    void torque(int i, const Vec3& t) override { m[i].torque = std::max(m[i].torque, t.norm()); }
  } v(m);
  visit_forces(w, v);
}

}  // namespace

Rgba variant_color(const ViewsSpec& views, size_t k) {
  const VariantSpec& v = views.variants[k];
  const float a = (float)v.overlay_opacity;
  if (v.overlay_color) return with_alpha(*v.overlay_color, a);
  static const int kOrder[6] = {2, 1, 7, 3, 6, 5};
  int before = 0;
  for (size_t j = 0; j < k; ++j) before += views.variants[j].overlay ? 1 : 0;
  return okabe_ito(kOrder[before % 6], a);
}

Rgba item_color(const ShowItem& s) {
  return s.color ? with_alpha(*s.color, s.opacity) : okabe_ito(default_color(s.kind), (float)s.opacity);
}

Rgba rope_color(const ShowItem& s, bool rod) {
  if (s.color) return item_color(s);
  // Dark tan (sRGB 150, 112, 64) for a rope, grey (120, 120, 125) for a rod.
  const float a = (float)s.opacity;
  return rod ? Rgba{srgb_to_linear(120), srgb_to_linear(120), srgb_to_linear(125), a}
             : Rgba{srgb_to_linear(150), srgb_to_linear(112), srgb_to_linear(64), a};
}

std::vector<Magnitudes> measure_magnitudes(const Scene& scene, int threads) {
  FrameLoop loop(scene, threads);
  std::vector<Magnitudes> m((size_t)loop.world().body_count());
  FrameLoop::Hooks h;
  h.step = [&](const World& w) { accumulate(w, m); };
  loop.run({}, h, true);
  return m;
}

void SceneOverlays::prepass(const Scene& scene, int threads, bool magnitudes, std::vector<Magnitudes>& mags,
                            std::vector<Magnitudes>& system_mags, std::vector<double>& contact_forces) {
  FrameLoop loop(scene, threads);
  const World& w0 = loop.world();
  mags.assign((size_t)w0.body_count(), Magnitudes{});
  const double E0 = w0.kinetic_energy() + w0.potential_energy();
  const Vec3 L0 = w0.total_angular_momentum();
  std::vector<int> contact_bodies;
  for (const Item& it : items_)
    if (it.spec.kind == ShowKind::contacts && !it.spec.scale) contact_bodies.push_back(it.body);
  // The reactions through the joints of the `joint_forces` items that scale themselves.
  std::vector<std::pair<int, int>> reactions;  // (body, joint)
  for (const Item& it : items_)
    if (it.spec.kind == ShowKind::joint_forces && (!it.spec.scale || !it.spec.torque_scale))
      reactions.push_back({it.body, joints_[it.joint].index});
  // Contact forces sampled about 60 times a simulated second (a landing lasts a few steps).
  const long contact_every = std::max(1L, std::lround(1.0 / (60.0 * dt_)));
  // The bodies' paths for the HUD's corner: about 100 samples over the run.
  const long hud_every = std::max(1L, std::lround(duration_ / dt_ / 100.0));
  hud_samples_.clear();
  StepMeters meters;  // the plots' measured values, over the pre-pass's own steps
  meters.set_reference(E0, L0);
  for (const Plot& p : plots_)
    for (const HudField& f : p.spec.quantities) meters.track(f, dt_);
  FrameLoop::Hooks h;
  h.step = [&](const World& w) {
    if (!meters.empty()) meters.record(w);
    if (magnitudes) {
      accumulate(w, mags);
      for (const Item& it : items_)
        if (it.spec.kind == ShowKind::angular_momentum_about)
          mags[it.body].L_about =
              std::max(mags[it.body].L_about, momentum_about(w, it.body, it.spec.point).norm());
      for (size_t k = 0; k < systems_.size(); ++k)
        accumulate_system(system_state(w, systems_[k].spec.bodies), system_mags[k]);
      for (const auto& [b, j] : reactions) {
        Vec3 F, tau;
        w.joint_reaction(j, F, tau);
        mags[b].joint_force = std::max(mags[b].joint_force, F.norm());
        mags[b].joint_torque = std::max(mags[b].joint_torque, tau.norm());
      }
    }
    const long s = w.steps();
    if (!contact_bodies.empty() && s % contact_every == 0)
      for (int b : contact_bodies)
        visit_contacts(w, b, [&](const Vec3&, const Vec3&, const Vec3& F) {
          if (F.norm() > 0) contact_forces.push_back(F.norm());
        });
    if (hud_camera_ && s % hud_every == 0)
      for (int b : hud_bodies_) hud_samples_.push_back(w.centroid(b));
    for (Plot& p : plots_) {
      if (s % p.every != 0) continue;
      p.t.push_back(w.time());
      for (size_t q = 0; q < p.spec.quantities.size(); ++q)
        p.values[q].push_back((float)quantity_value(p.spec.quantities[q], w, -1, E0, L0, 0, &meters));
    }
  };
  loop.run({}, h, true);
}

void SceneOverlays::save_prepass(std::ostream& os, const std::vector<Magnitudes>& mags,
                                 const std::vector<Magnitudes>& system_mags, double contact_kth) const {
  put_vec(os, mags);
  put_vec(os, system_mags);
  put_vec(os, hud_samples_);
  put(os, contact_kth);
  put(os, (uint64_t)plots_.size());
  for (const Plot& p : plots_) {
    put_vec(os, p.t);
    put(os, (uint64_t)p.values.size());
    for (const std::vector<float>& v : p.values) put_vec(os, v);
  }
}

void SceneOverlays::load_prepass(std::istream& is, std::vector<Magnitudes>& mags,
                                 std::vector<Magnitudes>& system_mags, double& contact_kth) {
  const size_t bodies = mags.size(), systems = system_mags.size();
  get_vec(is, mags);
  get_vec(is, system_mags);
  get_vec(is, hud_samples_);
  if (system_mags.size() != systems)
    throw InputError("a checkpoint's pre-pass is of other systems than the scene's");
  get(is, contact_kth);
  uint64_t n = 0;
  get(is, n);
  if (mags.size() != bodies || n != plots_.size())
    throw InputError("a checkpoint's pre-pass is of another scene (bodies or plots differ)");
  for (Plot& p : plots_) {
    get_vec(is, p.t);
    uint64_t q = 0;
    get(is, q);
    if (q != p.values.size()) throw InputError("a checkpoint's plot has other quantities than the scene's");
    for (std::vector<float>& v : p.values) get_vec(is, v);
  }
}

void SceneOverlays::save_history(std::ostream& os) const {
  put(os, (uint64_t)trails_.size());
  for (const Trail& t : trails_) {
    put_vec(os, t.points);
    put_vec(os, t.steps);
    put(os, (uint64_t)t.head);
    put(os, (uint64_t)t.count);
    put(os, t.last);
  }
  meters_.save(os);
  put(os, (uint64_t)snapshots_.size());
  for (const Snapshot& s : snapshots_) {
    put(os, (uint8_t)s.taken);
    const double pose[7] = {s.x[0], s.x[1], s.x[2], s.q.w(), s.q.x(), s.q.y(), s.q.z()};
    put(os, pose);
  }
}

void SceneOverlays::restore_history(std::istream& is) {
  uint64_t n = 0;
  get(is, n);
  if (n != trails_.size()) throw InputError("a checkpoint's trails are not the scene's");
  for (Trail& t : trails_) {
    const size_t cap = t.points.size();
    get_vec(is, t.points);
    get_vec(is, t.steps);
    if (t.points.size() != cap || t.steps.size() != cap)
      throw InputError("a checkpoint's trail is of another length than the scene's");
    uint64_t head = 0, count = 0;
    get(is, head);
    get(is, count);
    t.head = (size_t)head, t.count = (size_t)count;
    get(is, t.last);
  }
  meters_.restore(is);
  get(is, n);
  if (n != snapshots_.size()) throw InputError("a checkpoint's snapshots are not the scene's");
  for (Snapshot& s : snapshots_) {
    uint8_t taken = 0;
    double pose[7];
    get(is, taken);
    get(is, pose);
    s.taken = taken != 0;
    s.x = Vec3(pose[0], pose[1], pose[2]);
    s.q = Quat(pose[3], pose[4], pose[5], pose[6]);
  }
}

SceneOverlays::SceneOverlays(const Scene& scene, const World& world, const std::vector<double>& body_radius,
                             int width, int height, int threads, PrepassStore* store,
                             const CameraView* fixed_camera)
    : width_(width),
      height_(height),
      dt_(scene.timestep),
      duration_(scene.duration),
      fps_(scene.video.fps),
      body_radius_(body_radius),
      hud_(scene.overlays.hud),
      hud_corner_(scene.overlays.hud_corner),
      title_(scene.overlays.title),
      captions_(scene.overlays.captions),
      labels_(scene.overlays.labels),
      legend_(scene.overlays.legend) {
  const OverlaySpec& o = scene.overlays;
  bool need_scales = false;
  show_ = o.show;
  std::vector<SystemSpec> systems = o.systems;
  std::vector<const std::vector<ShowItem>*> panes;
  for (const PaneSpec& p : scene.views.panes)
    for (const auto& [body, items] : p.show) panes.push_back(&items);
  resolve_colors(show_, systems, panes);
  for (SystemSpec& y : systems) {
    SystemLook look;
    look.spec = std::move(y);
    look.scale.assign(look.spec.show.size(), 0.0);
    for (int i : look.spec.bodies) look.size = std::max(look.size, body_radius_[i]);
    for (const ShowItem& s : look.spec.show) need_scales = need_scales || (is_arrow(s.kind) && !s.scale);
    systems_.push_back(std::move(look));
  }
  shows_forces_.assign(show_.size(), 0);
  for (size_t i = 0; i < show_.size(); ++i)
    for (const ShowItem& s : show_[i]) {
      if (s.kind == ShowKind::trail) {
        add_trail(
            (int)i, s, Source::point,
            s.color ? with_alpha(*s.color, s.opacity) : okabe_ito(default_color(s.kind), (float)s.opacity),
            height);
        trails_.back().p_B = s.point_in_world ? world.world_to_local((int)i, s.point) : s.point;
        continue;
      }
      if (s.kind == ShowKind::snapshot) {
        // Default: the body's colour, lightened halfway to white (as a ghost's).
        const ShowRgb c = s.color
                              ? *s.color
                              : lightened(i < scene.looks.size() ? scene.looks[i].color
                                                                 : std::array<float, 3>{0.7f, 0.7f, 0.7f});
        for (double t : s.at) {
          Snapshot snap;
          snap.body = (int)i, snap.at = t, snap.color = with_alpha(c, s.opacity);
          snapshots_.push_back(snap);
        }
        continue;
      }
      if (s.kind == ShowKind::poinsot) {
        Item it{(int)i, s, 0, 0, {-1, -1}};
        ShowItem line = s;
        line.opacity = 1;
        it.trails[0] = (int)trails_.size();
        add_trail((int)i, line, Source::polhode, okabe_ito(1), height);  // orange, on the body
        it.trails[1] = (int)trails_.size();
        add_trail((int)i, line, Source::herpolhode, okabe_ito(0), height);  // black, on the plane
        need_scales = need_scales || !s.scale;
        items_.push_back(it);
        continue;
      }
      if (s.kind == ShowKind::forces) {
        shows_forces_[i] = 1;
        need_scales = need_scales || !s.scale || !s.torque_scale;
      }
      need_scales = need_scales || (is_arrow(s.kind) && !s.scale);
      Item it{(int)i, s, 0, 0, {-1, -1}};
      if (s.kind == ShowKind::joints || s.kind == ShowKind::joint_forces) {
        // The joint holding body i to its parent and, `joints`, the ropes the body hangs on at
        // either end (the scene's check: there is one or the other; `joint_forces`: the joint).
        it.joint = add_joint_look(scene, world, (int)i);
        const int ropes = s.kind == ShowKind::joints ? add_rope_looks(scene, (int)i) : 0;
        if (it.joint < 0 && ropes == 0) continue;
        need_scales = need_scales || (s.kind == ShowKind::joint_forces && (!s.scale || !s.torque_scale));
      }
      items_.push_back(it);
    }
  for (const HudLine& l : o.hud)
    for (const HudField& f : l.fields) meters_.track(f, dt_);
  for (const PlotSpec& ps : o.plots)
    for (const HudField& f : ps.quantities) meters_.track(f, dt_);
  bool contacts_auto = false;
  for (const Item& it : items_)
    contacts_auto = contacts_auto || (it.spec.kind == ShowKind::contacts && !it.spec.scale);
  // Plots: their samples come from the pre-pass, about 1.5 per pixel of the plot's width.
  for (const PlotSpec& ps : o.plots) {
    Plot p;
    p.spec = ps;
    const double wpx = std::max(8.0, ps.rect[2] * width);
    const long steps = std::max(1L, std::lround(duration_ / dt_));
    p.every = std::max(1L, std::lround(steps / (1.5 * wpx)));
    p.t.reserve((size_t)(steps / p.every + 2));
    p.values.assign(ps.quantities.size(), {});
    for (auto& v : p.values) v.reserve(p.t.capacity());
    plots_.push_back(std::move(p));
  }
  // The HUD's `auto` corner is chosen against the bodies' paths when the camera stands still.
  if (!hud_.empty() && hud_corner_ == "auto") {
    if (fixed_camera) {
      hud_camera_ = *fixed_camera;
      for (int i = 0; i < world.body_count(); ++i)
        if (world.type(i) == BodyType::dynamic) hud_bodies_.push_back(i);
      if (hud_bodies_.empty()) hud_camera_.reset();
    }
    if (!hud_camera_) hud_corner_ = "top_left";
  }
  std::vector<Magnitudes> mags((size_t)world.body_count()), system_mags(systems_.size());
  double contact_kth = 0;  // N, the contact forces' kContactQuantile quantile; 0: none seen
  if (store && store->mode() == PrepassStore::Mode::replay) {
    std::istringstream in = store->next();
    load_prepass(in, mags, system_mags, contact_kth);
  } else {
    std::vector<double> contact_forces;
    if (need_scales || contacts_auto || !plots_.empty()) {
      prepass(scene, threads, need_scales, mags, system_mags, contact_forces);
    } else if (hud_camera_) {
      // The HUD alone does not pay for a pre-pass: its corner is chosen against where the bodies
      // start (a pre-pass that runs anyway gives their paths over the whole clip).
      hud_samples_.clear();
      for (int b : hud_bodies_) hud_samples_.push_back(world.centroid(b));
    }
    if (contacts_auto && !contact_forces.empty()) {
      const size_t k =
          std::min(contact_forces.size() - 1, (size_t)(kContactQuantile * contact_forces.size()));
      std::nth_element(contact_forces.begin(), contact_forces.begin() + (long)k, contact_forces.end());
      contact_kth = contact_forces[k];
    }
    if (store) {
      std::ostringstream out;
      save_prepass(out, mags, system_mags, contact_kth);
      store->add(out.str());
    }
  }
  // Contacts: one scale for every body showing them, so that forces compare across the pile.
  double contact_scale = 0;
  if (contacts_auto && contact_kth > 0) {
    double R = 0;
    int n = 0;
    for (const Item& it : items_)
      if (it.spec.kind == ShowKind::contacts && !it.spec.scale) R += body_radius_[it.body], ++n;
    contact_scale = kContactReach * (R / n) / contact_kth;
  }
  const Vec3 g = world.config().gravity;
  for (Item& it : items_) {
    const double R = it.body < (int)body_radius_.size() ? body_radius_[it.body] : 0.5;
    if (is_arrow(it.spec.kind)) {
      const double big = it.spec.scale ? 0 : largest(mags[it.body], it.spec.kind);
      it.scale = it.spec.scale ? *it.spec.scale : big > 0 ? kArrowReach * R / big : 0;
      it.radius = 0.028 * R * it.spec.width;
    } else if (it.spec.kind == ShowKind::forces) {
      double big = mags[it.body].force;
      if (it.spec.gravity) big = std::max(big, world.mass(it.body) * g.norm());
      it.scale = it.spec.scale ? *it.spec.scale : big > 0 ? kForceReach * R / big : 0;
      const double tb = mags[it.body].torque;
      it.torque_scale = it.spec.torque_scale ? *it.spec.torque_scale : tb > 0 ? kForceReach * R / tb : 0;
      it.radius = 0.028 * R * it.spec.width;
    } else if (it.spec.kind == ShowKind::contacts) {
      it.scale = it.spec.scale ? *it.spec.scale : contact_scale;
      it.radius = 0.02 * R * it.spec.width;
    } else if (it.spec.kind == ShowKind::axes) {
      it.scale = it.spec.scale ? *it.spec.scale : 1.25 * R;
      it.radius = 0.018 * R * it.spec.width;
    } else if (it.spec.kind == ShowKind::center_of_mass) {
      it.scale = it.spec.scale ? *it.spec.scale : 0.07 * R;
    } else if (it.spec.kind == ShowKind::poinsot) {
      // m per rad/s: as an auto-scaled omega arrow, whose tip is then the contact point.
      const double big = it.spec.scale ? 0 : mags[it.body].omega;
      it.scale = it.spec.scale ? *it.spec.scale : big > 0 ? kArrowReach * R / big : 0;
      for (int k : it.trails) trails_[k].k = it.scale;
    } else if (it.spec.kind == ShowKind::joints) {
      it.scale = it.spec.scale ? *it.spec.scale : 0.8 * R;  // the axis's drawn length
      it.radius = 0.015 * R * it.spec.width;                // its shaft
    } else if (it.spec.kind == ShowKind::joint_forces) {
      // As `forces`: the largest over the run is kForceReach body radii long. A reaction is
      // computed, so a component that is zero in exact arithmetic (a planar pendulum's hinge
      // torque) comes out as round-off: a largest force under kReactionFloor of the body's force
      // scale m (|g| + v^2 / R + omega^2 R), or a largest torque under kReactionFloor of that
      // force's (or the largest force's) moment at R, counts as none rather than being magnified
      // to kForceReach radii.
      const Magnitudes& m = mags[it.body];
      const double fref = world.mass(it.body) * (g.norm() + m.v * m.v / R + m.omega * m.omega * R);
      const double tref = std::max(fref, m.joint_force) * R;
      it.scale = it.spec.scale ? *it.spec.scale
                 : m.joint_force > kReactionFloor * fref && m.joint_force > 0
                     ? kForceReach * R / m.joint_force
                     : 0;
      it.torque_scale = it.spec.torque_scale ? *it.spec.torque_scale
                        : m.joint_torque > kReactionFloor * tref && m.joint_torque > 0
                            ? kForceReach * R / m.joint_torque
                            : 0;
      it.radius = 0.028 * R * it.spec.width;
    } else if (it.spec.kind == ShowKind::cones) {
      it.scale = it.spec.scale ? *it.spec.scale : kArrowReach * R;  // slant: an auto-scaled omega's length
    }
  }
  // A system's arrow takes the scale of its members' arrows of the same kind where they show one,
  // so that the drawn p_a + p_b adds up to the drawn P; else its own largest is kArrowReach times
  // its largest member's radius.
  for (size_t k = 0; k < systems_.size(); ++k) {
    SystemLook& y = systems_[k];
    y.radius = 0.028 * y.size;
    for (size_t j = 0; j < y.spec.show.size(); ++j) {
      const ShowItem& s = y.spec.show[j];
      if (s.kind == ShowKind::center_of_mass) {
        y.scale[j] = s.scale ? *s.scale : 0.1 * y.size;
        continue;
      }
      double member = 0;
      for (const Item& it : items_)
        if (it.spec.kind == s.kind && member == 0 &&
            std::find(y.spec.bodies.begin(), y.spec.bodies.end(), it.body) != y.spec.bodies.end())
          member = it.scale;
      const double big = largest(system_mags[k], s.kind);
      y.scale[j] = s.scale ? *s.scale : member > 0 ? member : big > 0 ? kArrowReach * y.size / big : 0;
    }
  }
  E0_ = world.kinetic_energy() + world.potential_energy();
  L0_ = world.total_angular_momentum();
  meters_.set_reference(E0_, L0_);
  make_screen(scene, world);
}

SceneOverlays::~SceneOverlays() = default;

void SceneOverlays::add_trail(int body, const ShowItem& s, Source src, const Rgba& color, int height) {
  Trail t;
  t.body = body;
  t.source = src;
  t.p_B = Vec3::Zero();
  t.color = color;
  t.width_px = std::max(1.5, s.width * height / 720.0);  // px, at least 1.5 on small frames
  // About 120 samples a second of simulated time, on whole steps; sparser when the trail is long, so
  // that no trail holds more than kMaxTrailPoints (a Poinsot trail over a 1e7-step run held 150 MB
  // and drew every one of its points each frame).
  t.span = std::lround(std::min(s.length, duration_ + dt_) / dt_);  // the ring holds no more than the run
  t.every =
      std::max({1L, std::lround(1.0 / (120.0 * dt_)), (t.span + kMaxTrailPoints - 1) / kMaxTrailPoints});
  const size_t cap = (size_t)(t.span / t.every + 3);
  t.points.resize(cap);
  t.steps.resize(cap);
  t.scratch.reserve(cap + 1);
  t.colors.reserve(cap + 1);
  trails_.push_back(std::move(t));
}

Vec3 SceneOverlays::sample(const Trail& t, const World& w) const {
  switch (t.source) {
    case Source::polhode:
      return t.k * w.angular_velocity_principal(t.body);
    case Source::herpolhode:
      return t.k * w.angular_velocity(t.body);
    case Source::point:
      break;
  }
  return w.local_to_world(t.body, t.p_B);
}

Vec3 SceneOverlays::to_world(const Trail& t, const World& w, const Vec3& v) const {
  switch (t.source) {
    case Source::polhode:  // on the principal axes, drawn a hair outside the ellipsoid it lies on
      return w.centroid(t.body) + w.principal_orientation(t.body) * (v * 1.006);
    case Source::herpolhode:
      return w.centroid(t.body) + v;
    case Source::point:
      break;
  }
  return v;
}

int SceneOverlays::add_joint_look(const Scene& scene, const World& world, int body) {
  for (size_t k = 0; k < joints_.size(); ++k)
    if (joints_[k].child == body) return (int)k;  // `joints` and `joint_forces` on one body
  // The joint holding `body` to its parent. Where the bodies are at t = 0 (their start poses) maps
  // the joint's world anchor and axes into the frames they move with.
  for (size_t jx = 0; jx < scene.joints.size(); ++jx) {
    const JointDef& j = scene.joints[jx];
    JointLook L;
    if (is_rope(j)) continue;  // add_rope_looks
    if (!joint_sides(j, scene.bodies, L.parent, L.child) || L.child != body) continue;
    L.index = (int)jx;
    L.type = j.type;
    const BodyDef& c = scene.bodies[L.child];
    L.anchor_C = c.q_WB.conjugate() * (j.anchor_W - c.p_WB);
    L.axis2_C = c.q_WB.conjugate() * j.axis2_W.normalized();
    // The parent's start pose (the world's frame for the world).
    Quat q_P = Quat::Identity();
    Vec3 p_P = Vec3::Zero();
    if (L.parent >= 0) q_P = scene.bodies[L.parent].q_WB, p_P = scene.bodies[L.parent].p_WB;
    const Vec3 axis_W = j.axis_W.normalized(), axis2_W = j.axis2_W.normalized();
    L.axis_P = q_P.conjugate() * axis_W;
    L.axis2_P = q_P.conjugate() * axis2_W;
    L.anchor_P = q_P.conjugate() * (j.anchor_W - p_P);
    // A hinge or slider written [child, world] is turned round with its axis reversed, so that
    // its coordinate keeps its meaning (sim/joints): the child turns (slides) about -axis.
    if (L.child != j.child && (j.type == JointType::revolute || j.type == JointType::prismatic)) L.sign = -1;
    L.limits = j.limits;
    L.ball = j.ball_limits;
    if (L.ball && L.child != j.child) {  // written [child, world]: the twist the other way (sim/joints)
      const double lower = L.ball->twist_lower;
      L.ball->twist_lower = -L.ball->twist_upper;
      L.ball->twist_upper = -lower;
    }
    L.q_P0 = q_P;
    L.q_C0 = c.q_WB;
    // The child's start direction: from the anchor to its centre of mass at t = 0, in the plane
    // perpendicular to the axis; where that is degenerate (the centre of mass on the axis), a
    // perpendicular of the axis.
    const Vec3 com_W = c.p_WB + c.q_WB * world.world_to_local(L.child, world.centroid(L.child));
    const Vec3 d = com_W - j.anchor_W;
    auto across = [&](const Vec3& a) {
      Vec3 u = d - d.dot(a) * a;
      if (!(u.norm() > 1e-9 * std::max(1.0, d.norm()))) {
        Vec3 e2;
        orthonormal_basis(a, u, e2);
      }
      return Vec3(q_P.conjugate() * u.normalized());
    };
    L.start_P = across(axis_W);
    L.start2_P = across(axis2_W);
    joints_.push_back(L);
    return (int)joints_.size() - 1;
  }
  return -1;
}

int SceneOverlays::add_rope_looks(const Scene& scene, int body) {
  int n = 0;
  for (size_t jx = 0; jx < scene.joints.size(); ++jx) {
    const JointDef& j = scene.joints[jx];
    if (!is_rope(j) || (j.parent != body && j.child != body)) continue;
    ++n;
    bool seen = false;  // shown from its other end already: drawn there
    for (const RopeLook& r : ropes_) seen = seen || r.index == (int)jx;
    if (seen) continue;
    RopeLook r;
    r.index = (int)jx;
    r.body = body;
    r.type = j.type;
    // Each end's point where its body carries it: from the body's start pose (as the anchors of
    // add_joint_look); the world's and a static body's stay world points.
    const int ends[2] = {j.parent, j.child};
    const Vec3 points[2] = {j.anchor_W, j.anchor2_W};
    for (int k : {0, 1}) {
      const int b = ends[k];
      if (b >= 0 && b < (int)scene.bodies.size() && scene.bodies[b].type != BodyType::static_body) {
        const BodyDef& d = scene.bodies[b];
        r.end[k] = b;
        r.point[k] = d.q_WB.conjugate() * (points[k] - d.p_WB);
      } else {
        r.point[k] = points[k];
      }
      r.pulley_W[k] = j.pulley_anchor_W[k];
    }
    r.wheel = j.type == JointType::pulley && j.wheel >= 0;
    r.rod = j.type == JointType::distance && !j.min_length && !j.max_length && !j.spring;
    ropes_.push_back(r);
  }
  return n;
}

// Ropes: each straight run as a thin rod between its ends, which move with their bodies; a rigid
// rod (a distance joint without bounds or spring) thicker and grey. A slack rope (joint_force 0,
// its length under its max) is drawn straight all the same: the physics has no sag to draw.
void SceneOverlays::build_ropes(const Item& it, const World& w, const CameraView& cam, OverlayList& out) {
  const ShowItem& s = it.spec;
  const float xray = (float)s.xray;
  const double lines = height_ / 720.0, R = body_radius_[it.body];
  const Rgba ink = item_color(s);  // the dots, as the pivot's ball
  auto px_at = [&](const Vec3& p) {
    return pixel_size_at(cam, height_, std::max((p - cam.eye).norm(), 1e-3));
  };
  for (const RopeLook& r : ropes_) {
    if (r.body != it.body) continue;
    const Rgba color = rope_color(s, r.rod);
    // At least 2 px thick at 720 lines (1.2 px), times `width`; a rod 1.8 times that.
    auto run = [&](const Vec3& a, const Vec3& b) {
      const double radius = std::max(1.0 * lines, 0.6) * px_at(0.5 * (a + b)) * s.width * (r.rod ? 1.8 : 1.0);
      out.rod(a, b, radius, color, xray);
    };
    // Dots half the pivot's ball: at least 3 px in radius at 720 lines (1.5 px), times `width`.
    auto dot = [&](const Vec3& p) {
      const double ball = std::max(0.03 * R, std::max(3.0 * lines, 1.5) * px_at(p)) * s.width;
      out.ellipsoid(p, Mat3::Identity(), Vec3::Constant(ball), ink, xray);
    };
    const Vec3 a = r.end[0] >= 0 ? w.local_to_world(r.end[0], r.point[0]) : r.point[0];
    const Vec3 b = r.end[1] >= 0 ? w.local_to_world(r.end[1], r.point[1]) : r.point[1];
    if (r.type == JointType::distance) {
      run(a, b);
    } else {
      // A pulley: the parent's run down from pulley_anchors[0], the child's from [1]; over a wheel
      // the rope lies on its rim (the wheel is a body, drawn), over a massless pulley a straight
      // span between the two fixed points.
      run(r.pulley_W[0], a);
      run(r.pulley_W[1], b);
      if (!r.wheel) {
        run(r.pulley_W[0], r.pulley_W[1]);
        dot(r.pulley_W[0]);
        dot(r.pulley_W[1]);
      }
    }
    dot(a);
    dot(b);
  }
}

namespace {

// The unit vector at angle t (rad) from u, turning right-handed about a (a, u unit, perpendicular).
Vec3 at_angle(const Vec3& a, const Vec3& u, double t) {
  return std::cos(t) * u + std::sin(t) * a.cross(u);
}

// A coordinate's range about axis a at c: an arc of radius r from `lower` to `upper` (from u;
// 5 degrees a segment, a range over a turn drawn once round), a tick across each end, and the
// present value q as a needle to a dot of radius `dot`.
void range_arc(OverlayList& out, const Vec3& c, const Vec3& a, const Vec3& u, double r, double lower,
               double upper, double q, double shaft, double dot, const Rgba& color, float xray) {
  const double t1 = std::min(upper, lower + 2 * M_PI);
  const int n = std::max(2, (int)std::ceil((t1 - lower) / (M_PI / 36)));
  Vec3 prev = c + r * at_angle(a, u, lower);
  for (int k = 1; k <= n; ++k) {
    const Vec3 next = c + r * at_angle(a, u, lower + (t1 - lower) * k / n);
    out.rod(prev, next, shaft, color, xray);
    prev = next;
  }
  for (double t : {lower, upper}) {
    const Vec3 e = at_angle(a, u, t);
    out.rod(c + 0.7 * r * e, c + 1.3 * r * e, shaft, color, xray);
  }
  const Vec3 e = at_angle(a, u, q);
  out.rod(c, c + r * e, 0.6 * shaft, color, xray);
  out.ellipsoid(c + r * e, Mat3::Identity(), Vec3::Constant(dot), color, xray);
}

}  // namespace

void SceneOverlays::build_joint(const Item& it, const World& w, const CameraView& cam, OverlayList& out) {
  const JointLook& L = joints_[it.joint];
  const ShowItem& s = it.spec;
  const Rgba color = item_color(s);
  const float xray = (float)s.xray;
  // The pivot: the anchor, carried by the child. Sizes have floors in px so that a joint reads on
  // a thin bar and in a small frame: the ball's radius at least 6 px at 720 lines (and 3 px), the
  // shaft's 1.5 px at 720 lines (and 0.75 px), both times `width`.
  const Vec3 p = w.local_to_world(L.child, L.anchor_C);
  const double px = pixel_size_at(cam, height_, std::max((p - cam.eye).norm(), 1e-3));
  const double R = body_radius_[L.child], lines = height_ / 720.0;
  const double ball = std::max(0.06 * R, std::max(6.0 * lines, 3.0) * px) * s.width;
  const double shaft = std::max(it.radius, std::max(1.5 * lines, 0.75) * px * s.width);
  out.ellipsoid(p, Mat3::Identity(), Vec3::Constant(ball), color, xray);
  // The axis: an arrow through the pivot, `scale` long, pointing along +axis (the coordinate grows
  // turning right-handed about it, or sliding along it). A hinge's and a slider's axis are fixed in
  // the parent; a universal joint's second axis is fixed in the child.
  const double len = std::max(it.scale, 4 * ball);
  auto axis = [&](const Vec3& a) { out.arrow(p - 0.5 * len * a, len * a, shaft, color, xray); };
  const Quat q_P = L.parent >= 0 ? w.orientation(L.parent) : Quat::Identity();
  const Vec3 a = q_P * L.axis_P;
  switch (L.type) {
    case JointType::revolute:
    case JointType::prismatic:
      axis(a);
      break;
    case JointType::universal:
    case JointType::wheel:  // the suspension (and steering) axis, and the axle turning with the wheel
      axis(a);
      axis(w.local_to_world_vec(L.child, L.axis2_C));
      break;
    case JointType::spherical:
      if (L.ball && (std::isfinite(L.ball->cone) || std::isfinite(L.ball->twist_lower) ||
                     std::isfinite(L.ball->twist_upper)))
        axis(a);
      break;
    case JointType::fixed:
    case JointType::distance:  // ropes and rods are drawn by build_ropes
    case JointType::pulley:
      break;
  }
  if (L.type == JointType::spherical && L.ball) {
    ball_limits(L, w, p, a, len, shaft, ball, color, xray, out);
    return;
  }
  if (!L.limits) return;
  // Limits. A hinge's range: an arc about the axis at the pivot, half the axis's length in radius,
  // fixed in the parent, from `lower` to `upper` measured from the child's start direction (a tick
  // across each end), and the present angle as a needle from the pivot to a dot on the arc. A
  // universal joint draws both: the first about `axis`, the second about `axis2` as it turns with
  // the first angle.
  const double lower = L.limits->lower, upper = L.limits->upper, r = 0.5 * len;
  auto range = [&](const Vec3& c, const Vec3& ax, const Vec3& u, double q) {
    range_arc(out, c, ax, u, r, lower, upper, q, shaft, 0.55 * ball, color, xray);
  };
  switch (L.type) {
    case JointType::revolute:
      range(p, L.sign * a, q_P * L.start_P, w.joint_position(L.index, 0));
      break;
    case JointType::universal: {
      const double q0 = w.joint_position(L.index, 0);
      range(p, a, q_P * L.start_P, q0);
      // The second angle turns about axis2 where the first has carried it: the parent's frame
      // turned by q0 about axis.
      const Quat q_I = q_P * Quat(Eigen::AngleAxisd(q0, L.axis_P));
      range(p, q_I * L.axis2_P, q_I * L.start2_P, w.joint_position(L.index, 1));
      break;
    }
    case JointType::distance:
    case JointType::pulley:
      break;
    case JointType::prismatic:
    case JointType::wheel: {  // a wheel's stops are on its suspension travel
      // A slider's range: a bar along the axis, fixed in the parent, from `lower` to `upper` from
      // where the child carried the anchor at t = 0, a tick across each end (facing the camera);
      // the pivot (the ball) slides along it.
      const Vec3 o = L.parent >= 0 ? w.local_to_world(L.parent, L.anchor_P) : L.anchor_P;
      const Vec3 e = L.sign * a, lo = o + lower * e, hi = o + upper * e;
      out.rod(lo, hi, 1.8 * shaft, color, xray);
      for (const Vec3& end : {lo, hi}) {
        Vec3 side = e.cross(cam.eye - end);
        if (!(side.norm() > 1e-12)) continue;
        side.normalize();
        out.rod(end - 2.5 * ball * side, end + 2.5 * ball * side, shaft, color, xray);
      }
      break;
    }
    case JointType::spherical:
    case JointType::fixed:
      break;
  }
}

void SceneOverlays::ball_limits(const JointLook& L, const World& w, const Vec3& p, const Vec3& a, double len,
                                double shaft, double ball, const Rgba& color, float xray,
                                OverlayList& out) const {
  // A ball joint's stops: the cone about the parent's axis a (a ring at its rim and four of its
  // lines, fixed in the parent), the child's axis as a needle from the pivot to a dot, and the
  // twist's range as an arc about the child's axis, from the swing-only pose (the child's axis
  // carried to where it points by the shortest turn), with a needle at the present twist.
  const BallLimits& B = *L.ball;
  const Quat q_P = L.parent >= 0 ? w.orientation(L.parent) : Quat::Identity();
  const Quat turn_P = q_P * L.q_P0.conjugate();  // the parent's turn since t = 0
  const Quat rel =
      turn_P.conjugate() * (w.orientation(L.child) * L.q_C0.conjugate());  // the joint's, world axes at t = 0
  const Vec3 a0 = L.q_P0 * L.axis_P;                                       // the axis at t = 0 (world)
  const Vec3 c = turn_P * (rel * a0);                                      // the child's axis now
  const double r = len;
  Vec3 u, v;
  orthonormal_basis(a, u, v);
  if (std::isfinite(B.cone)) {
    const double s = std::sin(B.cone), k = std::cos(B.cone);
    const int n = 48;
    Vec3 prev = p + r * (k * a + s * u);
    for (int i = 1; i <= n; ++i) {
      const double t = 2 * M_PI * i / n;
      const Vec3 next = p + r * (k * a + s * (std::cos(t) * u + std::sin(t) * v));
      out.rod(prev, next, shaft, color, xray);
      if (i % 12 == 0) out.rod(p, next, 0.5 * shaft, color, xray);
      prev = next;
    }
  }
  out.rod(p, p + r * c, 0.6 * shaft, color, xray);
  out.ellipsoid(p + r * c, Mat3::Identity(), Vec3::Constant(0.55 * ball), color, xray);
  if (!std::isfinite(B.twist_lower) && !std::isfinite(B.twist_upper)) return;
  // The twist: R = R_swing R_twist about a0; the reference direction u0 (perpendicular to a0) is
  // carried by the swing alone to the twist's zero, by the whole turn to its present value.
  Vec3 u0, v0;
  orthonormal_basis(a0, u0, v0);
  const Quat swing = Quat::FromTwoVectors(a0, rel * a0);
  const Vec3 zero = turn_P * (swing * u0), now = turn_P * (rel * u0);
  const double lo = std::isfinite(B.twist_lower) ? B.twist_lower : -M_PI;
  const double hi = std::isfinite(B.twist_upper) ? B.twist_upper : M_PI;
  // The present twist: now's angle from zero about the child's axis c.
  const double twist = std::atan2(c.dot(zero.cross(now)), zero.dot(now));
  range_arc(out, p + 0.6 * r * c, c, zero, 0.4 * r, lo, hi, twist, shaft, 0.45 * ball, color, xray);
}

void SceneOverlays::arrow_of(const Item& it, const World& w, Vec3& from, Vec3& vec) const {
  if (it.spec.kind == ShowKind::angular_momentum_about) {
    from = it.spec.point;
    vec = momentum_about(w, it.body, it.spec.point) * it.scale;
  } else {
    from = w.centroid(it.body);
    vec = quantity(w, it.body, it.spec.kind) * it.scale;
  }
}

bool SceneOverlays::item_arrow(int body, ShowKind kind, const World& w, Vec3& from, Vec3& vec) const {
  for (const Item& it : items_)
    if (it.body == body && it.spec.kind == kind && is_arrow(kind)) {
      arrow_of(it, w, from, vec);
      return true;
    }
  return false;
}

void SceneOverlays::system_arrow(int k, int j, const World& w, Vec3& from, Vec3& vec) const {
  const SystemLook& y = systems_[k];
  const SystemState st = system_state(w, y.spec.bodies);
  const ShowKind kind = y.spec.show[j].kind;
  from = st.C;
  vec = kind == ShowKind::center_of_mass ? Vec3::Zero() : Vec3(system_quantity(st, kind) * y.scale[j]);
}

Rgba SceneOverlays::color_of(int body, ShowKind kind) const {
  for (const ShowItem& s : show_[body])
    if (s.kind == kind) return item_color(s);
  return okabe_ito(default_color(kind));
}

void SceneOverlays::build_systems(const World& w, const CameraView& cam, OverlayList& out) {
  for (size_t k = 0; k < systems_.size(); ++k) {
    const SystemLook& y = systems_[k];
    for (size_t j = 0; j < y.spec.show.size(); ++j) {
      const ShowItem& s = y.spec.show[j];
      const Rgba color = item_color(s);
      Vec3 from, vec;
      system_arrow((int)k, (int)j, w, from, vec);
      if (s.kind == ShowKind::center_of_mass) {
        out.ellipsoid(from, Mat3::Identity(), Vec3::Constant(y.scale[j]), color, (float)s.xray);
        continue;
      }
      // Thicker than the members' arrows (1.5 times, and twice the least): the sum reads as the sum.
      const double px = pixel_size_at(cam, height_, std::max((from - cam.eye).norm(), 1e-3));
      const double radius = std::max(1.5 * y.radius * s.width, 2 * min_arrow_radius(px) * s.width);
      out.arrow(from, vec, radius, color, (float)s.xray);
    }
  }
}

void SceneOverlays::build_snapshots(const World& w, const SceneMeshes& meshes, DrawList& dl) const {
  for (const Snapshot& s : snapshots_)
    if (s.taken) draw_body_copy(w, meshes, s.body, s.x, s.q, s.color, kGhostInflate, dl);
}

double SceneOverlays::arrow_scale(int body, ShowKind kind, bool torque) const {
  for (const Item& it : items_)
    if (it.body == body && it.spec.kind == kind) return torque ? it.torque_scale : it.scale;
  return 0;
}

void SceneOverlays::record(const World& w) {
  if (!meters_.empty()) meters_.record(w);
  for (Snapshot& s : snapshots_)
    if (!s.taken && w.time() >= s.at - 0.5 * dt_)
      s.taken = true, s.x = w.centroid(s.body), s.q = w.orientation(s.body);
  const long s = w.steps();
  for (Trail& t : trails_) {
    if (s <= t.last) continue;
    t.last = s;
    if (s % t.every) continue;
    t.points[t.head] = sample(t, w);
    t.steps[t.head] = s;
    t.head = (t.head + 1) % t.points.size();
    t.count = std::min(t.count + 1, t.points.size());
  }
}

void SceneOverlays::build(const World& w, long frame, DrawList& dl) {
  dl.overlay.clear();
  dl.screen.clear();
  const Vec3 eye = dl.camera.eye;
  for (const Item& it : items_) {
    const int i = it.body;
    const Vec3 c = w.centroid(i);
    const ShowItem& s = it.spec;
    const Rgba color =
        s.color ? with_alpha(*s.color, s.opacity) : okabe_ito(default_color(s.kind), (float)s.opacity);
    const float xray = (float)s.xray;
    const double px = pixel_size_at(dl.camera, height_, std::max((c - eye).norm(), 1e-3));
    const double radius = std::max(it.radius, min_arrow_radius(px) * s.width);
    switch (s.kind) {
      case ShowKind::angular_velocity:
      case ShowKind::angular_momentum:
      case ShowKind::velocity:
      case ShowKind::momentum:
      case ShowKind::angular_momentum_about: {
        Vec3 from, vec;
        arrow_of(it, w, from, vec);
        dl.overlay.arrow(from, vec, radius, color, xray);
        break;
      }
      case ShowKind::axes: {
        const Mat3 R = w.principal_orientation(i).toRotationMatrix();
        // e1 e2 e3 red, green, blue: Okabe-Ito's vermillion, bluish green and blue.
        const int axis_color[3] = {6, 3, 5};
        for (int k = 0; k < 3; ++k)
          dl.overlay.arrow(c, R.col(k) * it.scale, radius, okabe_ito(axis_color[k], (float)s.opacity), xray);
        break;
      }
      case ShowKind::center_of_mass:
        dl.overlay.ellipsoid(c, Mat3::Identity(), Vec3::Constant(it.scale), color, xray);
        break;
      case ShowKind::inertia_box:
      case ShowKind::inertia_ellipsoid: {
        // The uniform box (I_1 = m (b^2 + c^2) / 12 ...) or solid ellipsoid (m (b^2 + c^2) / 5)
        // with the body's mass and principal moments: half-sides / semi-axes from the moments.
        const Vec3 I = w.principal_moments(i);
        const double mass = w.mass(i);
        const double k = s.kind == ShowKind::inertia_box ? 6.0 : 2.5;
        Vec3 half;
        for (int a = 0; a < 3; ++a)
          half[a] = std::sqrt(std::max(0.0, k * (I[(a + 1) % 3] + I[(a + 2) % 3] - I[a]) / mass)) *
                    (s.kind == ShowKind::inertia_box ? 0.5 : 1.0);
        const Mat3 R = w.principal_orientation(i).toRotationMatrix();
        if (s.kind == ShowKind::inertia_ellipsoid) {
          dl.overlay.ellipsoid(c, R, half, color, xray);
        } else {
          // A box as a cylinder would not do: draw its 12 edges as rods.
          const double r = 0.012 * body_radius_[i];
          for (int a = 0; a < 3; ++a)
            for (int sb : {-1, 1})
              for (int sc : {-1, 1}) {
                Vec3 p = Vec3::Zero();
                p[(a + 1) % 3] = sb * half[(a + 1) % 3];
                p[(a + 2) % 3] = sc * half[(a + 2) % 3];
                Vec3 q = p;
                p[a] = -half[a], q[a] = half[a];
                dl.overlay.rod(c + R * p, c + R * q, r, {color[0], color[1], color[2], 1.0f}, xray);
              }
        }
        break;
      }
      case ShowKind::forces:
        build_forces(it, w, dl.camera, dl.overlay);
        break;
      case ShowKind::contacts:
        build_contacts(it, w, dl.camera, dl.overlay);
        break;
      case ShowKind::joints:
        if (it.joint >= 0) build_joint(it, w, dl.camera, dl.overlay);
        build_ropes(it, w, dl.camera, dl.overlay);
        break;
      case ShowKind::joint_forces:
        build_joint_forces(it, w, dl.camera, dl.overlay);
        break;
      case ShowKind::trail:
      case ShowKind::poinsot:  // below, after every other item: translucent
      case ShowKind::cones:
      case ShowKind::snapshot:  // build_snapshots
        break;
    }
  }
  build_systems(w, dl.camera, dl.overlay);
  for (const Item& it : items_) {
    if (it.spec.kind != ShowKind::poinsot || !(it.scale > 0)) continue;
    // Poinsot: in omega-space scaled by k (m per rad/s), the energy ellipsoid omega.I.omega = 2T
    // (semi-axes sqrt(2T / I_i) on the principal axes, moving with the body) touches the
    // invariable plane omega.L / |L| = 2T / |L| (fixed in space) at omega itself, and rolls on it
    // without slipping: the contact point traces the polhode on the ellipsoid and the herpolhode on
    // the plane.
    const int i = it.body;
    const Vec3 c = w.centroid(i), L = w.angular_momentum(i), wP = w.angular_velocity_principal(i);
    const Vec3 I = w.principal_moments(i);
    if (!(L.norm() > 0)) continue;
    const double twoT = wP.dot(I.cwiseProduct(wP)), k = it.scale;
    const Vec3 semi(k * std::sqrt(twoT / I[0]), k * std::sqrt(twoT / I[1]), k * std::sqrt(twoT / I[2]));
    const Mat3 R = w.principal_orientation(i).toRotationMatrix();
    const float a = (float)it.spec.opacity;
    dl.overlay.ellipsoid(c, R, semi, okabe_ito(2, a));
    const Vec3 n = L.normalized();
    Vec3 u = n.cross(std::fabs(n.z()) < 0.9 ? Vec3::UnitZ() : Vec3::UnitX()).normalized(), v = n.cross(u);
    const double half = 1.05 * semi.maxCoeff();
    dl.overlay.quad(c + n * (k * twoT / L.norm()), u * half, v * half, {0.35f, 0.35f, 0.4f, 0.6f * a});
    dl.overlay.ellipsoid(c + k * w.angular_velocity(i), Mat3::Identity(),
                         Vec3::Constant(0.03 * semi.minCoeff()),
                         okabe_ito(6));  // the contact point, vermillion
  }
  for (const Item& it : items_) {
    if (it.spec.kind != ShowKind::cones) continue;
    // The body cone (swept by omega about the symmetry axis, fixed in the body) and the space
    // cone (swept about L, fixed in space): the body cone rolls on the space cone along omega.
    // The symmetry axis is the principal axis whose moment stands apart from the other two.
    const int i = it.body;
    const Vec3 c = w.centroid(i), om = w.angular_velocity(i), L = w.angular_momentum(i);
    if (!(om.norm() > 0) || !(L.norm() > 0)) continue;
    const Vec3 u = om.normalized();
    const Vec3 I = w.principal_moments(i);
    const Mat3 R = w.principal_orientation(i).toRotationMatrix();
    Vec3 s = R.col(std::fabs(I[0] - I[1]) < std::fabs(I[1] - I[2]) ? 2 : 0);
    if (s.dot(u) < 0) s = -s;
    const float a = (float)it.spec.opacity, xray = (float)it.spec.xray;
    for (const auto& [axis, color] :
         {std::pair<Vec3, Rgba>{s, okabe_ito(1, a)}, {L.normalized(), okabe_ito(5, a)}}) {
      const double cosb = std::clamp(u.dot(axis), -1.0, 1.0), sinb = std::sqrt(1 - cosb * cosb);
      dl.overlay.cone(c, axis * (it.scale * cosb), it.scale * sinb, color, xray);
    }
  }
  const long now = w.steps();
  for (Trail& t : trails_) {
    t.scratch.clear();
    t.colors.clear();
    const size_t n = t.points.size();
    for (size_t k = 0; k < t.count; ++k) {
      const size_t idx = (t.head + n - t.count + k) % n;  // oldest first
      const long age = now - t.steps[idx];
      if (age < 0 || age > t.span) continue;
      t.scratch.push_back(to_world(t, w, t.points[idx]));
    }
    // The newest sample may lag the frame by a few steps: end at the point's present position.
    const Vec3 p_now = to_world(t, w, sample(t, w));
    if (t.count == 0 || t.steps[(t.head + n - 1) % n] != now) t.scratch.push_back(p_now);
    // Fade: opacity falls linearly with age, from the item's at present to 0 `length` ago.
    const size_t m = t.scratch.size();
    for (size_t k = 0; k < m; ++k) {
      Rgba c = t.color;
      c[3] *= m > 1 ? (float)(k + 1) / (float)m : 1.0f;
      t.colors.push_back(c);
    }
    double d = (p_now - eye).norm();
    const double width = t.width_px * pixel_size_at(dl.camera, height_, std::max(d, 1e-3));
    dl.overlay.ribbon(t.scratch.data(), t.colors.data(), (int)m, eye, width);
  }
  if (has_screen_) build_screen(w, frame, dl.camera, dl.screen);
}

}  // namespace simreel
