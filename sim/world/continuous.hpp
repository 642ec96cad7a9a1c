// Continuous collision as a subsystem (docs/continuous-collision.md): each body's pose at the
// step's start, and the `continuous` stage that sweeps the bodies that moved fast from there to
// where the step left them and moves each back to its earliest time of impact. Owns the start
// poses, the sweeps, the swept boxes and the candidate pairs (scratch: nothing here outlives a
// step but the start poses of sleeping bodies, which a restore makes again).
#pragma once
#include <cstdint>
#include <vector>

#include <simreel/body.hpp>
#include <simreel/profile.hpp>

#include "sim/collision/body_extents.hpp"
#include "sim/collision/broad_phase.hpp"
#include "sim/collision/compound.hpp"
#include "sim/collision/shape_table.hpp"
#include "sim/collision/time_of_impact.hpp"
#include "sim/dynamics/state.hpp"
#include "sim/world/islands.hpp"

namespace simreel {

class ContinuousCollision {
 public:
  // Off unless `enabled`; else the movers (dynamic and kinematic bodies), the bullets, the start
  // poses from `state`, and the static shapes' boxes (they never move).
  void init(bool enabled, const std::vector<BodyDef>& defs, const std::vector<int>& dynamic,
            const std::vector<int>& kinematic, const std::vector<MotionState>& state,
            const ShapeTable& shapes, const std::vector<int>& sweep_shapes,
            const std::vector<char>& shape_moving);
  bool enabled() const { return enabled_; }
  bool bullet(int i) const { return bullet_[i] != 0; }

  // The start poses of the awake bodies; a sleeping body's was saved when it fell asleep (or was
  // restored) and holds while it sleeps, since nothing moves it without waking it first (with
  // 50,000 bodies asleep, copying every pose was a quarter of the step).
  void save_start_poses(const std::vector<int>& awake, const MotionState* state) {
    for (int i : awake) save_start_pose(i, state[i]);
  }
  void save_start_pose(int i, const MotionState& s) {
    x0_[i] = s.x_W;
    q0_[i] = s.q_WP;
  }

  // What the stage reads of the world.
  struct Step {
    MotionState* state = nullptr;
    const ShapeTable* shapes = nullptr;
    const BodyExtents* extents = nullptr;
    const Islands* islands = nullptr;
    const std::vector<int>* dynamic = nullptr;  ///< dynamic bodies, ascending
    const std::vector<int>* awake = nullptr;    ///< the awake moving bodies, ascending
    // This step's broad phase: its pairs (allowed, boxes overlapping), box margins and tree.
    const std::vector<uint64_t>* broad_pairs = nullptr;
    const std::vector<double>* margins = nullptr;  ///< per shape: m, boxes' reach past the shape
    const BroadPhase* broad = nullptr;  ///< its entries: shapes, then compounds (shape count + index)
    const CompoundProxies* compounds = nullptr;      ///< margins of their shapes, trees of their boxes
    const std::vector<int>* sweep_shapes = nullptr;  ///< non-plane colliding shapes
    const std::vector<int>* plane_shapes = nullptr;
    const std::vector<char>* shape_moving = nullptr;
    double linear_slop = 0;  ///< m
    Profile* profile = nullptr;
  };
  // The stage; false when nothing moved fast. may_touch(a, b): whether shapes a < b may touch at
  // all (filters, ignored pairs). Defined in continuous.cpp, its one caller's file.
  template <class MayTouch>
  bool step(const Step& in, MayTouch&& may_touch);

  // The earliest time of impact (fraction of the step; 1: none) of convex shape c on sweep s with
  // the triangles of static mesh shape m whose boxes meet `box` (c's box over the sweep), grown by
  // the target gap. guarded: the stage's fallbacks for triangles touched at the start; else a
  // triangle touched at the start gives -1 (the mesh pair then collides as usual).
  static double mesh_toi(const ShapeTable& shapes, const BodyExtents& extents, const MotionState* state,
                         int c, int m, const Sweep& s, const Aabb& box, double target, double tolerance,
                         bool guarded, int* triangle = nullptr);

 private:
  bool enabled_ = false;
  std::vector<int> movers_;        ///< dynamic and kinematic bodies, ascending
  std::vector<Vec3> x0_;           ///< per body: centre of mass at the step's start
  std::vector<Quat> q0_;           ///< per body: orientation at the step's start
  std::vector<char> shape_swept_;  ///< per shape: swept this step
  std::vector<char> bullet_;       ///< per body: dynamic and flagged `bullet`
  std::vector<double> toi_;        ///< per body: earliest time of impact this step (fraction)
  std::vector<Sweep> sweeps_;      ///< per body, this step
  std::vector<int> fast_;          ///< swept bodies this step, ascending
  std::vector<Aabb> swept_boxes_;  ///< per shape: its box over the whole step
  std::vector<char> sweepable_;    ///< per body: in Step::dynamic (set on the first step)
  std::vector<char> covered_;      ///< per shape: its swept box lies in its broad-phase box
  std::vector<long> box_stamp_;    ///< per shape: the stage run its swept box is from
  std::vector<long> sweep_stamp_;  ///< per body: the stage run its sweep is from
  std::vector<double> moved_;      ///< per awake body: m, how far its centre moved this step
  std::vector<double> turned_;     ///< per awake body: rad, how far it turned this step
  std::vector<char> cover_kind_;   ///< per shape: 0 not tested for coverage, 1 mesh, 2 other
  long run_ = 0;                   ///< stage runs with a fast body
  std::vector<int> escaped_;       ///< moving shapes whose swept box left their broad-phase box
  std::vector<uint64_t> pairs_;    ///< shape pairs (pair_key) to sweep, this step
};

}  // namespace simreel
