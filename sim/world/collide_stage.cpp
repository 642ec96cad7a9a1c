// World's contact stages (the pipeline is in world.cpp): broad phase, what the collide stage reads
// (the stage itself is the contact set's, contact_set.cpp), the solver's substeps, and kinematic
// bodies.
#include <algorithm>
#include <cmath>
#include <sstream>

#include <simreel/error.hpp>
#include "sim/base/worker_pool.hpp"
#include "sim/collision/smooth_support.hpp"
#include "sim/world/world_impl.hpp"

namespace simreel {

void WorldImpl::init_contacts() {
  const int n = (int)defs_.size();
  const ContactSettings& cs = cfg_.contacts;
  if (cs.substeps < 0 || cs.iterations < 1 || cs.passes < 1)
    throw InputError(
        "contacts: substeps must be at least 1 (or 0: automatic), iterations and passes at least 1");
  // Automatic: substeps of at most 1/960 s.
  base_substeps_ =
      cs.substeps > 0 ? cs.substeps : std::max(1, (int)std::ceil(cfg_.dt * kContactSubstepRate - 1e-9));
  substeps_ = base_substeps_;
  if (!(cs.contact_hertz >= 0) || !(cs.damping_ratio >= 0) || !(cs.max_push_out >= 0) ||
      !(cs.restitution_threshold >= 0) || !(cs.speculative_distance >= 0) || !(cs.linear_slop >= 0) ||
      !(cs.rolling_resistance >= 0) || !(cs.slip_speed >= 0))
    throw InputError("contacts: settings must be non-negative numbers");
  if (!(cs.rolling_tolerance > 0 && cs.rolling_tolerance < 1e-2))
    throw InputError("contacts: rolling_tolerance must be a number in (0, 0.01)");
  std::vector<std::string> notes;
  shapes_ = std::make_unique<ShapeTable>(defs_, model_, notes);
  extents_.build(*shapes_, n);
  for (std::string& s : notes) warnings_.push_back(std::move(s));
  for (const auto& [a, b] : cfg_.ignore_pairs) {
    if (a < 0 || b < 0 || a >= n || b >= n) throw InputError("ignore_pairs: body index out of range");
    ignore_.emplace_back(std::min(a, b), std::max(a, b));
  }
  std::sort(ignore_.begin(), ignore_.end());
  const ShapeTable& st = *shapes_;
  profile_.shapes = st.size();
  shape_moving_.assign(st.size(), 0);
  boxes_.assign(st.size(), Aabb{});
  margins_.assign(st.size(), cs.speculative_distance);
  drift_.assign(st.size(), Vec3::Zero());
  broad_.set_drift(&drift_);
  poses_.assign(st.size(), Pose{});
  pose_step_.assign(st.size(), -1);
  bool any_moving = false;
  for (int i = 0; i < st.size(); ++i) {
    const ShapeRecord& r = st[i];
    // A shape that belongs to no group or collides with no group never touches anything.
    if (r.group == 0 || r.mask == 0) continue;
    shape_moving_[i] = !model_[r.body].is_static;
    if (r.geom.kind == CollideKind::plane) {
      plane_shapes_.push_back(i);
      plane_poses_.push_back(ShapeTable::world_pose(r, state_[r.body]));
    } else {
      sweep_shapes_.push_back(i);
      any_moving = any_moving || shape_moving_[i];
      if (!shape_moving_[i]) {
        Aabb b = ShapeTable::bounds(r.geom, ShapeTable::world_pose(r, state_[r.body]));
        const Vec3 m = Vec3::Constant(cs.speculative_distance);
        boxes_[i] = Aabb{b.lo - m, b.hi + m};
      }
    }
  }
  // The broad phase's entries: shapes not in a compound, then the compounds.
  compounds_.build(st, extents_, sweep_shapes_, cs.compound_shapes, n);
  const int ns = st.size(), nc = compounds_.count();
  proxy_moving_ = shape_moving_;
  proxy_moving_.resize(ns + nc, 0);
  boxes_.resize(ns + nc, Aabb{});
  drift_.resize(ns + nc, Vec3::Zero());
  box_step_.assign(ns, -1);
  placed_step_.assign(nc, -1);
  for (int k : sweep_shapes_)
    if (compounds_.of_shape(k) < 0) sweep_proxies_.push_back(k);
  for (int c = 0; c < nc; ++c) {
    const int b = compounds_.body(c);
    proxy_moving_[ns + c] = !model_[b].is_static;
    sweep_proxies_.push_back(ns + c);
    if (!proxy_moving_[ns + c]) place_compound(c);
  }
  collide_enabled_ = any_moving && (sweep_shapes_.size() + plane_shapes_.size() >= 2);
  contacts_.init(n);
  solver_index_.assign(n, 0);
  rolling_.resize(n);
  rolled_.assign(n, 0);
  // Only bodies with a smooth colliding shape can roll; jointed ones move with their mechanisms.
  roll_excluded_.assign(n, 1);
  for (const ShapeRecord& sh : st.shapes())
    if (smooth_kind(sh.geom.kind)) roll_excluded_[sh.body] = 0;
  for (int i = 0; i < n; ++i)
    if (joints_.jointed(i)) roll_excluded_[i] = 1;
  free_.resize(groups_.size());
  if (!collide_enabled_) return;
  // Bodies overlapping at the start: a warning naming the pair and the depth.
  stage_broad_phase();
  contacts_.collide(collide_step(), islands_, profile_);
  for (const Contact& c : contacts_.active()) {
    double depth = 0;
    for (int j = 0; j < c.count; ++j) depth = std::max(depth, -c.points[j].separation);
    if (depth > cs.linear_slop) {
      std::ostringstream os;
      os << "bodies '" << defs_[c.body_a].name << "' and '" << defs_[c.body_b].name << "' overlap by "
         << depth << " m at the start; contacts will push them apart (at most " << cs.max_push_out << " m/s)";
      warnings_.push_back(os.str());
    }
  }
  contacts_.clear_stats();
  profile_.pairs = profile_.contact_points = 0;
}

bool WorldImpl::bodies_may_touch(int a, int b) const {
  if (a == b) return false;
  if (model_[a].inv_mass == 0 && model_[b].inv_mass == 0) return false;
  if (!ignore_.empty()) {
    const std::pair<int, int> p(std::min(a, b), std::max(a, b));
    if (std::binary_search(ignore_.begin(), ignore_.end(), p)) return false;
  }
  return true;
}

bool WorldImpl::shapes_may_touch(int a, int b) const {
  const ShapeRecord& A = (*shapes_)[a];
  const ShapeRecord& B = (*shapes_)[b];
  return bodies_may_touch(A.body, B.body) && filters_allow(A, B);
}

bool WorldImpl::proxies_may_touch(int a, int b) const {
  const int ns = shapes_->size();
  if (b < ns) return shapes_may_touch(a, b);
  // A compound: its body's checks here, each shape's filters when the pair is expanded.
  return bodies_may_touch(a < ns ? (*shapes_)[a].body : compounds_.body(a - ns), compounds_.body(b - ns));
}

// A compound's box from its body's state: the same speeds and margin formula as a shape's own.
void WorldImpl::place_compound(int c) {
  const int b = compounds_.body(c);
  const MotionState& s = state_[b];
  const int id = shapes_->size() + c;
  boxes_[id] = compounds_.place(c, s.q_WP.toRotationMatrix(), s.x_W, s.v_W.norm(), s.w_P.norm(),
                                cfg_.contacts.speculative_distance, cfg_.dt);
  drift_[id] = s.v_W * cfg_.dt;
  placed_step_[c] = broad_step_;
}

// Shape i's pose, margin and box from its body's state this step.
void WorldImpl::make_shape_box(int i) {
  const ShapeRecord& r = (*shapes_)[i];
  const MotionState& s = state_[r.body];
  const Aabb b = ShapeTable::bounds(r.geom, ShapeTable::world_pose(r, s));
  margins_[i] = box_margin(cfg_.contacts.speculative_distance, s.v_W.norm(), extents_.shape_reach[i],
                           s.w_P.norm(), cfg_.dt);
  const Vec3 m = Vec3::Constant(margins_[i]);
  boxes_[i] = Aabb{b.lo - m, b.hi + m};
}

const Aabb& WorldImpl::member_box(int k) {
  if (!shape_moving_[k] || box_step_[k] == broad_step_) return boxes_[k];  // static: made by init
  box_step_[k] = broad_step_;
  make_shape_box(k);
  return boxes_[k];
}

void WorldImpl::expand_compounds(std::vector<uint64_t>& pairs) {
  const int ns = shapes_->size();
  expanded_.clear();
  size_t kept = 0;
  auto add = [&](int p, int q) {
    const int lo = std::min(p, q), hi = std::max(p, q);
    if (shapes_may_touch(lo, hi)) expanded_.push_back(pair_key(lo, hi));
  };
  for (uint64_t key : pairs) {
    const int a = pair_first(key), b = pair_second(key);  // a < b: a compound is b
    if (b < ns) {
      pairs[kept++] = key;
      continue;
    }
    const int cb = b - ns;
    if (a >= ns) {  // two compounds: b's tree for each of a's shapes that reach b's box
      compounds_.query(a - ns, boxes_[b], [&](int ka) {
        const Aabb& KA = member_box(ka);
        if (!KA.overlaps(boxes_[b])) return;
        compounds_.query(cb, KA, [&](int kb) {
          if (KA.overlaps(member_box(kb))) add(ka, kb);
        });
      });
    } else if ((*shapes_)[a].geom.kind == CollideKind::plane) {
      const Vec3& n = broad_.plane_normal(a);
      const double d = broad_.plane_offset(a);
      compounds_.query_plane(cb, n, d, [&](int k) {
        if (box_reaches_plane(n, d, member_box(k))) add(a, k);
      });
    } else {
      const Aabb& A = boxes_[a];
      compounds_.query(cb, A, [&](int k) {
        if (A.overlaps(member_box(k))) add(a, k);
      });
    }
  }
  pairs.resize(kept);
  if (expanded_.empty()) return;
  std::sort(expanded_.begin(), expanded_.end());
  merged_pairs_.clear();
  std::merge(pairs.begin(), pairs.end(), expanded_.begin(), expanded_.end(),
             std::back_inserter(merged_pairs_));
  pairs.swap(merged_pairs_);
}

// World boxes of the moving shapes, grown by the speculative distance and by the farthest any
// point of the shape can travel this step (|v| + |w| r) dt, so a pair that can touch within the
// step is found before it does. Only the active shapes are looked at: those of awake bodies, and
// once those of a body that fell asleep (its box then has no motion margin: a function of its
// pose alone, as a resumed run computes it). Static and sleeping shapes cost nothing.
// (Flattened: GCC at -O2 calls Eigen's small products and the pose and bounds helpers here
// instead of inlining them.)
__attribute__((flatten)) void WorldImpl::stage_broad_phase() {
  const ShapeTable& st = *shapes_;
  const int ns = st.size();
  ++broad_step_;
  active_shapes_.clear();
  for (int b : islands_.awake_bodies()) {
    const int c = compounds_.of_body(b);
    if (c >= 0) {  // one box for the whole compound; its shapes' only where a pair needs them
      if (!proxy_moving_[ns + c]) continue;
      place_compound(c);
      active_shapes_.push_back(ns + c);
      continue;
    }
    for (int i = extents_.shape_begin[b]; i < extents_.shape_begin[b + 1]; ++i)
      if (shape_moving_[i]) active_shapes_.push_back(i);  // (planes are static)
  }
  // A body that fell asleep: its box at rest (v = w = 0 now), then nothing until it wakes. A
  // compound's shapes all get theirs now, once: a sleeping pair reads them without asking.
  std::vector<int>& freeze = islands_.pending_freeze();
  for (int i : freeze) {
    const int c = compounds_.of_shape(i);
    if (c < 0) {
      active_shapes_.push_back(i);
      continue;
    }
    member_box(i);
    if (placed_step_[c] != broad_step_) {
      place_compound(c);
      active_shapes_.push_back(ns + c);
    }
  }
  freeze.clear();
  for (int i : active_shapes_) {
    if (i >= ns) continue;  // a compound: placed above
    make_shape_box(i);
    drift_[i] = state_[st[i].body].v_W * cfg_.dt;
  }
  std::vector<uint64_t>& pairs = contacts_.pairs();
  broad_.update(
      boxes_, active_shapes_, sweep_proxies_, plane_shapes_, plane_poses_, proxy_moving_,
      [this](int a, int b) { return proxies_may_touch(a, b); }, pairs);
  profile_.fat_box_moves += broad_.moved_last_update();
  if (compounds_.count() > 0) {
    expand_compounds(pairs);
    if (broad_.dormant_changed()) {
      dormant_expanded_ = broad_.dormant_pairs();
      expand_compounds(dormant_expanded_);
    }
  }
  profile_.pairs += (long)pairs.size();
  // The narrow phase's poses of the moving shapes in live pairs (the state does not change
  // between here and the collide stage).
  for (uint64_t key : pairs)
    for (int k : {pair_first(key), pair_second(key)})
      if (shape_moving_[k] && pose_step_[k] != broad_step_) {
        pose_step_[k] = broad_step_;
        poses_[k] = ShapeTable::world_pose((*shapes_)[k], state_[(*shapes_)[k].body]);
      }
}

ContactSet::Step WorldImpl::collide_step() const {
  ContactSet::Step in;
  in.shapes = shapes_.get();
  in.extents = &extents_;
  in.model = model_.data();
  in.state = state_.data();
  in.ccd = &ccd_;
  in.shape_moving = shape_moving_.data();
  in.poses = poses_.data();
  in.pose_step = pose_step_.data();
  in.broad_step = broad_step_;
  in.boxes = boxes_.data();
  in.dt = cfg_.dt;
  in.gravity = cfg_.gravity;
  in.speculative_distance = cfg_.contacts.speculative_distance;
  in.linear_slop = cfg_.contacts.linear_slop;
  in.timing = clock_.timing();
  in.threads = cfg_.threads;
  in.pool = pool_.get();
  in.dormant = compounds_.count() > 0 ? &dormant_expanded_ : &broad_.dormant_pairs();
  in.dormant_changed = broad_.dormant_changed();
  return in;
}

// The soft step over the bodies in contact (sim/solver/contact_solver.hpp), then their new state.
bool WorldImpl::stage_solve_contacts() {
  const ContactSettings& cs = cfg_.contacts;
  const std::vector<int>* all = &contacts_.bodies();
  char* in_contact = contacts_.in_contact();
  // Automatic substeps: at least base_substeps_ (substeps of <= 1/240 s), more while a body in
  // contact turns fast, so that none turns more than kContactMaxSubstepAngle per substep (the
  // solver's rotation and lever arms are first order in that angle: a top spinning at 54 rad/s
  // precessed 3.4% slow with one 1/240 s substep, 0.35% with four, measured). A function of the
  // state only, so runs stay deterministic and a resumed run takes the same substeps.
  substeps_ = base_substeps_;
  if (cfg_.contacts.substeps == 0) {
    double w_max = 0;
    for (int i : contacts_.bodies()) w_max = std::max(w_max, state_[i].w_P.norm());
    const double need = std::ceil(w_max * cfg_.dt / kContactMaxSubstepAngle - 1e-9);
    substeps_ = std::max(substeps_, (int)std::min(need, (double)kContactMaxSubsteps));
  }
  // Bodies rolling on a fixed surface are stepped first, by their own equations
  // (sim/solver/rolling_contact.hpp); the solver takes the rest. Jointed bodies in contact are
  // stepped with their mechanisms (sim/joints/contact_rows.hpp).
  if (cs.rolling) {
    StageClock::Scope t(clock_, Stage::roll);
    for (int i : rolled_list_) rolled_[i] = 0;
    RollingContacts::Input in;
    in.model = model_.data();
    in.state = state_.data();
    in.wrench = wrench_dirty_ ? wrench_.data() : nullptr;
    in.shapes = shapes_.get();
    in.gravity = cfg_.gravity;
    in.dt = cfg_.dt;
    in.settings = cs;
    in.excluded = roll_excluded_.data();
    rolling_.step(in, *all, contacts_.active(), substeps_, rolled_);
    rolled_list_.clear();
    for (int i : *all)
      if (rolled_[i]) rolled_list_.push_back(i);
  }
  if (rolled_list_.empty())
    clock_.skipped(Stage::roll);
  else
    clock_.ran(Stage::roll);
  profile_.rolling_bodies += (long)rolled_list_.size();
  if (!joints_.empty() || !rolled_list_.empty()) {
    solver_bodies_.clear();
    for (int i : *all)
      if (!joints_.jointed(i) && !rolled_[i]) solver_bodies_.push_back(i);
    all = &solver_bodies_;
  }
  const std::vector<int>& contact_bodies = *all;
  if (contact_bodies.empty() && joints_.empty()) {  // every body in contact rolled
    for (Stage st : {Stage::prepare_contacts, Stage::integrate_velocities, Stage::warm_start, Stage::solve,
                     Stage::integrate_positions, Stage::relax, Stage::restitution, Stage::store_impulses})
      clock_.skipped(st);
    refresh_free_lists();
    return true;
  }
  {
    StageClock::Scope t(clock_, Stage::prepare_contacts);
    SolverInput in;
    in.model = model_.data();
    in.state = state_.data();
    in.wrench = wrench_dirty_ ? wrench_.data() : nullptr;
    in.gravity = cfg_.gravity;
    in.dt = cfg_.dt;
    in.substeps = substeps_;
    in.shapes = shapes_.get();
    in.settings = cs;
    in.pool = pool_.get();
    in.articulations = joints_.empty() ? nullptr : &joints_;
    solver_.prepare(in, contact_bodies, contacts_.active(), solver_index_);
  }
  clock_.ran(Stage::prepare_contacts);
  solver_.run_substeps(settle_substeps_, clock_, profile_);
  bool finite = true;
  {
    StageClock::Scope t(clock_, Stage::store_impulses);
    solver_.store_impulses(contacts_.active());
    touched_none_.resize(contact_bodies.size() + 1);
    solver_.finish(model_.data(), state_.data(), touched_none_);
    // Bodies that received no impulse after all (they only came within the speculative distance)
    // go back to the free-flight integrators, which are exact for them.
    double sum = 0;
    int solved = 0;
    for (size_t k = 0; k < contact_bodies.size(); ++k) {
      const int i = contact_bodies[k];
      solver_index_[i] = 0;
      if (touched_none_[k + 1]) {
        in_contact[i] = 0;
        continue;
      }
      ++solved;
      const MotionState& s = state_[i];
      sum += s.q_WP.w() + s.x_W.x() + s.x_W.y() + s.x_W.z() + s.v_W.x() + s.w_P.x();
    }
    finite = std::isfinite(sum);
    refresh_free_lists();
    profile_.solver_bodies += solved;
    if (pool_) profile_.pool_runs = pool_->runs(), profile_.pool_alone_runs = pool_->alone_runs();
  }
  clock_.ran(Stage::store_impulses);
  return finite;
}

// The bodies the free-flight integrators step: those touching nothing this step, awake.
void WorldImpl::refresh_free_lists() {
  const char* in_contact = contacts_.in_contact();
  for (size_t g = 0; g < groups_.size(); ++g) {
    free_[g].clear();
    for (int i : groups_[g].bodies)
      if (!in_contact[i] && !islands_.asleep(i)) free_[g].push_back(i);
  }
}

// Kinematic bodies move at their given velocity, exactly: x += h v, and a constant world angular
// velocity w turns the orientation by exp(h w / 2) (w_P is re-expressed so that w stays fixed).
void WorldImpl::stage_kinematic() {
  const double h = cfg_.dt;
  for (int i : kinematic_) {
    MotionState& s = state_[i];
    const Vec3 w_W = s.q_WP * s.w_P;
    s.x_W += h * s.v_W;
    s.q_WP = (rotation_increment(w_W, h) * s.q_WP).normalized();
    s.w_P = s.q_WP.conjugate() * w_W;
  }
}

}  // namespace simreel
