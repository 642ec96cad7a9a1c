// The contact solver: Box2D v3's "soft step" (Catto, "Solver2D", 2024; Box3D src/solver.c and
// contact_solver.c), written here in double precision for 3D. Per step:
//   prepare           solver bodies in the world frame (v, w, 1/m, R I^-1 R^T fresh from this
//                     step's orientation) and one constraint per touching manifold (anchors,
//                     effective masses, tangent basis, warm-start impulses);
//   per substep h = dt / substeps:
//     integrate velocities  v += h (g + f/m); w += h I_W^-1 tau, then the implicit gyroscopic
//                           term (one Newton step of I (w' - w) + h w' x I w' = 0, Catto 2015);
//     warm start            apply the accumulated impulses (an impulse per substep; after the
//                           step's first substep per body where it may be: warm_start);
//     solve                 normal (soft, with bias) then friction, Gauss-Seidel in a fixed order
//                           (a manifold's resting points solved together: ManifoldSolve::block);
//     integrate positions   dp += h v; dq <- exp(h w / 2) dq (exact rotation for constant w);
//     relax                 solve again without bias, so push-out does not become velocity;
//     restitution           points that hit faster than the threshold this substep bounce;
//   store impulses    back into the contact cache for the next step's warm start.
// The soft constraint (a stiff damped spring solved implicitly, Catto GDC 2011 "Soft
// constraints"): with w = 2 pi f, a1 = 2 zeta + h w, a2 = h w a1, a3 = 1 / (1 + a2):
//   bias = (w / a1) s (capped at max_push_out), impulse = -m_eff (a2 a3) (vn + bias) - a3 lambda.
// Friction acts once per manifold at the centre of its points (Box3D): a 2D tangent impulse
// clamped to the disk of radius mu sum(lambda_n), and a twist impulse about the normal clamped to
// mu sum(lever_i lambda_n,i): the Coulomb limit of the pressure over the contact patch.
#pragma once
#include <array>
#include <cstddef>
#include <memory>
#include <vector>

#include "sim/collision/contact.hpp"
#include "sim/collision/shape_table.hpp"
#include "sim/collision/tracked_contacts.hpp"
#include "sim/dynamics/state.hpp"
#include "sim/solver/constraint_graph.hpp"
#include "sim/solver/contact_settings.hpp"
#include "sim/solver/contact_wide.hpp"
#include "sim/solver/worker_schedule.hpp"

namespace simreel {

class WorkerPool;
class Articulations;
class ArticulatedContacts;
class StageClock;
struct Profile;

// The wide sweeps (sim/solver/contact_wide.cpp) read only the first two cache lines, v to dq: a bundle's
// eight bodies are read at random, and each line a body adds waits on memory (the large pyramid's
// sweeps went 7% faster from five lines to two); the inverse inertia they read is copied into the
// bundle, and the rotation so far is read as the quaternion dq.
struct alignas(64) SolverBody {  // whole cache lines: two threads write neighbouring bodies
  Vec3 v = Vec3::Zero();         ///< m/s, centre-of-mass velocity, world
  Vec3 w = Vec3::Zero();         ///< rad/s, world
  Vec3 dp = Vec3::Zero();        ///< m, centre-of-mass displacement so far this step
  double inv_mass = 0;           ///< 1/kg (0: static or kinematic)
  Quat dq = Quat::Identity();    ///< rotation so far this step (world)
  Mat3 dR = Mat3::Identity();    ///< dq as a matrix (made only where read: need_dR_)
  Mat3 inv_I = Mat3::Zero();     ///< 1/(kg m^2), world, R I^-1 R^T at the step's start
};
static_assert(offsetof(SolverBody, dq) + sizeof(Quat) <= 128, "what the wide sweeps read: two lines");

// Per solver body, made by ContactSolver::warm_start: its velocities before the substep's contact
// impulses (the approach speeds an impact is judged by, kImpactSpeed) and, for the warm start per
// body, the change the last substep's impulses made to them.
struct BodyImpulse {
  Vec3 v0 = Vec3::Zero(), w0 = Vec3::Zero();  ///< m/s, rad/s
  Vec3 dv = Vec3::Zero(), dw = Vec3::Zero();  ///< m/s, rad/s
};

struct Softness {
  double bias_rate = 0;      ///< 1/s
  double mass_scale = 1;     ///< dimensionless
  double impulse_scale = 0;  ///< dimensionless
};
Softness make_softness(double hertz, double damping_ratio, double h);
// A contact's first tangent: a unit vector perpendicular to n, chosen from n alone (deterministic):
// n x e, with e the world axis least aligned with n.
Vec3 contact_tangent(const Vec3& n);

struct ConstraintPoint {
  Vec3 rA = Vec3::Zero(), rB = Vec3::Zero();      ///< m, anchors from each centre of mass, world
  Vec3 rnA = Vec3::Zero(), rnB = Vec3::Zero();    ///< m, rA x n and rB x n
  Vec3 IrnA = Vec3::Zero(), IrnB = Vec3::Zero();  ///< 1/(kg m), I_A^-1 (rA x n), I_B^-1 (rB x n)
  // Pivots for the separation within the step: each surface's centre of curvature (the contact
  // point moved into the body by the shape's rounding radius). A rolling sphere's contact point
  // is not a material point; its centre is, and the gap follows the centre exactly.
  Vec3 cA = Vec3::Zero(), cB = Vec3::Zero();  ///< m, from each centre of mass
  double adjusted_separation = 0;             ///< m, separation - n.(cB - cA)
  double normal_mass = 0;                     ///< kg
  double normal_impulse = 0;                  ///< N s, accumulated (per substep)
  double max_normal_impulse = 0;              ///< N s
  double impact_velocity = 0;                 ///< m/s, predicted normal velocity at impact (restitution)
  double vn_prev = 0;                         ///< m/s, normal velocity at the substep's start
  double lever = 0;                           ///< m, distance from the friction centre (twist limit)
  bool bounced = false;                       ///< restitution applied this step
};

struct ContactConstraint {
  int a = 0, b = 0;  ///< solver body indices (0 is the shared static body)
  int contact = -1;  ///< index into the contact list
  Vec3 n = Vec3::UnitZ(), t[2] = {Vec3::UnitX(), Vec3::UnitY()};
  Vec3 nA = Vec3::Zero(), nB = Vec3::Zero();  ///< 1/kg, n / m_A and n / m_B
  double friction = 0, restitution = 0, rolling = 0;
  // Friction at the manifold's centre.
  Vec3 fA = Vec3::Zero(), fB = Vec3::Zero();               ///< m, centre from each centre of mass
  Eigen::Matrix2d tangent_mass = Eigen::Matrix2d::Zero();  ///< kg, inverse of the 2x2 tangent K
  // Made once in prepare (an impulse's angular effect is linear in it): fA x t_j and fB x t_j
  // (the tangent velocity's angular terms), I_A^-1 (fA x t_j), I_B^-1 (fB x t_j), I_A^-1 n, I_B^-1 n.
  Vec3 fAt[2], fBt[2], IfAt[2], IfBt[2];
  Vec3 InA = Vec3::Zero(), InB = Vec3::Zero();
  double tangent_impulse[2] = {0, 0};        ///< N s
  double twist_mass = 0, twist_impulse = 0;  ///< kg m^2, N m s
  double rolling_lever = 0;                  ///< m
  Vec3 rolling_impulse = Vec3::Zero();       ///< N m s
  Mat3 rolling_mass = Mat3::Zero();          ///< kg m^2
  int count = 0;
  Softness soft;
  ConstraintPoint p[4];
  // A contact whose point runs over a smooth surface (a rim, an ellipsoid, ...:
  // sim/collision/tracked_contacts.hpp): its index in the solver's tracked list, or -1.
  int track = -1;
};

// What the three sweeps (warm start, solve, relax) read and write of a constraint, packed from its
// ContactConstraint in prepare (and again for a tracked point after it moves): the same values, less
// the anchors, the friction centre, rolling resistance and the restitution records (about 1.4 KB
// instead of 1.8). In large scenes the sweeps wait on memory (the large pyramid streams its 17,000
// constraints three times a substep; sampled, a sixth of its time sits on the prefetches of the
// next constraints), so what they do not read stays in the full record.
struct SweepPoint {
  Vec3 rnA, rnB, IrnA, IrnB;  ///< as ConstraintPoint
  Vec3 cA, cB;                ///< as ConstraintPoint
  double adjusted_separation, normal_mass, lever;
  double normal_impulse, max_normal_impulse;  ///< N s (the live values: the full record's are not kept)
};

struct SweepConstraint {
  int a, b, count, track;
  Vec3 n, t[2], nA, nB;
  double friction, restitution, rolling;
  Eigen::Matrix2d tangent_mass;
  Vec3 fAt[2], fBt[2], IfAt[2], IfBt[2], InA, InB;
  double twist_mass;
  Softness soft;
  double tangent_impulse[2], twist_impulse;  ///< N s, N m s (the live values)
  SweepPoint p[4];
  // The block solve of the normal points (count >= 2; docs/contacts.md "Block solve"): (K + D)^-1 for
  // the solve (D = diag(K_ii) impulse_scale / mass_scale, the softness) and (K + eps diag(K))^-1
  // for the relax, K the points' coupling J M^-1 J^T; symmetric, the lower triangle row by row.
  double block_soft[10], block_rigid[10];
  bool block;  ///< both made (count >= 2, both matrices positive definite)
};

// What the solver needs of the world for one step (arrays owned by World, indexed by body).
struct SolverInput {
  const BodyModel* model = nullptr;
  const MotionState* state = nullptr;
  const Wrench* wrench = nullptr;  ///< may be null
  const ShapeTable* shapes = nullptr;
  Vec3 gravity = Vec3::Zero();
  double dt = 0;
  int substeps = 1;
  ContactSettings settings;
  WorkerPool* pool = nullptr;  ///< threads for the stages (null: the calling thread alone)
  /// The scene's mechanisms (null: no joints): contacts with a jointed body are solved in joint
  /// coordinates (sim/joints/contact_rows.hpp).
  Articulations* articulations = nullptr;
};

// Threads: each stage is split among the pool's workers. Per-body stages (integrate velocities
// and positions, the write-back) and per-constraint stages that write nothing shared (prepare,
// store) take fixed shares; the stages that apply impulses (warm start, solve, relax,
// restitution) go colour by colour through the constraint graph (sim/solver/constraint_graph.hpp), each
// worker taking a part of every colour (spans of bodies, or fractions of each colour), and
// waiting before a colour only for the others' items of the colour before that touch bodies its
// own items touch (sim/solver/worker_schedule.cpp). (Blocks of 16 constraints claimed from a shared
// counter balanced the load but moved each constraint and its bodies between the cores' caches:
// the large pyramid's solve ran 1.55x one thread with them, 1.64x with fixed shares.) Within a
// colour no two constraints share a moving body, so every body receives the same impulses in the
// same order whatever the thread count: results are bit for bit those of one thread.
class ContactSolver {
 public:
  ContactSolver();
  ~ContactSolver();
  // Solver body index of each body this step: 0 for static bodies and bodies not in contact.
  // `bodies` lists the dynamic and kinematic bodies in contact, ascending. Reuses storage.
  void prepare(const SolverInput& in, const std::vector<int>& bodies, const std::vector<Contact>& contacts,
               std::vector<int>& solver_index);
  // The step's substeps after prepare (Box2D's solver stages): per substep h = dt / substeps,
  // integrate velocities, warm start, solve, integrate positions, relax, restitution, each timed
  // into `clock`; sweeps, impact substeps and per-body warm starts counted into `profile`.
  // `settle`: substeps left with one more sweep after an impact (saved state, carried by World).
  void run_substeps(int& settle, StageClock& clock, Profile& profile);
  void store_impulses(std::vector<Contact>& contacts) const;
  // Writes the solved motion of the dynamic bodies that received an impulse back to the state and
  // clears their flag in `touched_none`; the others (set to 1) touched nothing after all this
  // step and are left for the free-flight integrators. Kinematic bodies are advanced by World.
  // Mechanisms with contacts that pushed them take the substeps' result too
  // (Mechanism::contact_stepped).
  void finish(const BodyModel* model, MotionState* state, std::vector<char>& touched_none);

  const ConstraintGraph& graph() const { return graph_; }  ///< this step's colouring
  int workers() const { return workers_; }                 ///< this step's (1: no split)
  /// The split chosen last (sim/solver/worker_schedule.cpp): fractions of each colour, else spans of bodies.
  bool split_in_fractions() const { return schedule_.by_fractions(); }
  // Checks the workers' split of the colours (sim/solver/worker_schedule.cpp) as by_colour uses it: each
  // colour's items shared out whole, and no item solved after the worker's count went on touches
  // a body another worker's items touch. Returns the number of faults; if given, *deferred the
  // number of items solved after the count (the ones no other worker waits for) and *items all
  // of them (bundles and scalar constraints, over the colours). For tests.
  int split_faults(long* deferred = nullptr, long* items = nullptr) const;
  int constraint_count() const { return (int)cons_.size(); }

 private:
  // The stages run_substeps runs, in order.
  void integrate_velocities(double h);
  bool warm_start();  ///< true: made per body (the step's later substeps, when it may be)
  // One Gauss-Seidel sweep over the manifolds; returns whether one was struck (kImpactSpeed).
  bool solve(double h, bool use_bias, bool first_iteration);
  void integrate_positions(double h);
  void restitution(double threshold);  ///< call after each substep's relax
  SolverInput in_;
  std::vector<int> bodies_;      ///< body index of solver body k + 1
  std::vector<SolverBody> sb_;   ///< [0] is the static body: never written (zero mass and inertia)
  std::vector<Mat3> I_W_;        ///< world inertia of each solver body (gyroscopic term)
  std::vector<char> gyro_;       ///< needs the gyroscopic term (2: a tracked body's, after the warm start)
  std::vector<Vec3> gyro_w0_;    ///< rad/s, a tracked body's w before the warm start (gyro_ 2)
  double h_ = 0;                 ///< s, this substep's
  std::vector<Vec3> accel_;      ///< m/s^2, g + f/m
  std::vector<Vec3> ang_accel_;  ///< rad/s^2, I^-1 tau
  // In solve order: colour by colour (graph_.slot); a wide lane's is made on prepare's stack.
  std::vector<ContactConstraint> cons_;
  std::vector<SweepConstraint> sweep_;  ///< the same, what the scalar path's sweeps read (pack_sweep)
  // Each colour's plain manifolds go four at a time to the wide path (sim/solver/contact_wide.hpp), the
  // others (and the overflow set) to the scalar path; both per colour in slot order.
  std::vector<wide::Bundle> bundles_;  ///< colour by colour
  std::vector<int> bundle_start_;      ///< kColours + 2 entries: colour c's bundles
  std::vector<int> bundle_split_;      ///< per colour: its first bundle of manifolds apart
  std::vector<int> scalar_;            ///< slots on the scalar path, colour by colour
  std::vector<int> scalar_start_;      ///< kColours + 2 entries: colour c's in scalar_
  std::vector<int> lane_of_;           ///< per slot: 4 bundle + lane, or -1 (scalar)
  std::vector<char> plain_;            ///< per constraint (contact order): may take the wide path
  std::vector<char> apart_;            ///< per constraint: every point apart at the step's start
  std::vector<char> slot_plain_;       ///< per slot: 0 scalar, 1 wide, 2 wide and apart
  std::vector<TrackedContact>
      tracked_;  ///< contacts whose point runs over a surface (ContactConstraint::track), in contact order
  std::vector<int> tracked_bodies_;  ///< their tracked bodies' solver bodies, ascending
  bool track_due_ = false;           ///< moved since the tracked points were last found
  // Constraints that may be tracked (one point, a round shape on either side), in contact order:
  // make_constraint makes their records here (con -1: not tracked after all).
  std::vector<TrackedContact> track_scratch_;
  std::vector<int> track_candidate_of_;  ///< per constraint (contact order): its index there, or -1
  Softness soft_, static_soft_;
  bool inertia_due_ =
      false;  ///< the gyroscopic bodies' world inertia follows their turn (substeps after the first)
  bool any_restitution_ = false;  ///< some constraint has restitution > 0 (else the stage is empty)
  bool need_dR_ = true;           ///< SolverBody::dR is read this step (the scalar path, tracked points)
  // The warm start per body (warm_start): every constraint is on the wide path; warm starts done
  // this step.
  bool body_warm_ = false;
  int warm_starts_ = 0;
  std::vector<BodyImpulse> impulse_change_;  ///< per solver body ([0], the static body: zeros)
  // Contacts with a jointed body (contact order), solved in joint coordinates.
  std::vector<int> articulated_;
  std::unique_ptr<ArticulatedContacts> art_;

  // Threads.
  WorkerPool* pool_ = nullptr;  ///< null, or not used this step (too little work to split)
  int workers_ = 1;
  ConstraintGraph graph_;
  std::vector<int> wanted_;           ///< contact index of each constraint, in contact order
  std::vector<int> edge_a_, edge_b_;  ///< their solver bodies (the graph's edges)
  struct alignas(64) Flag {           // one cache line per worker
    bool value = false;
  };
  std::vector<Flag> struck_;
  std::vector<int> lane_slot_;  ///< per lane (4 bundle + lane): its slot, or -1 (padding)
  // Two or more workers: which part of each colour each takes, and which of it first
  // (sim/solver/worker_schedule.hpp), made in prepare from this step's layout.
  WorkerSchedule schedule_;
  WorkerSchedule::Layout schedule_layout() const;  ///< the colouring, lanes and scalar entries

  template <typename F>
  void on_workers(F&& f) const;  ///< f(worker, workers) on every worker, or f(0, 1)
  // Inside on_workers: per colour, scalar(begin, end) over this worker's share of the colour's
  // scalar_ entries and wide(begin, end) over its share of the colour's bundles (schedule_), waiting
  // before each colour until the other workers have solved the last colour's items they share
  // bodies with; then, after a barrier, the overflow set (scalar) on worker 0.
  template <typename FS, typename FW>
  void by_colour(int w, int nw, FS&& scalar, FW&& wide);
  void assign_lanes();                                  ///< bundles and scalar_ from the colouring (prepare)
  void set_lane(int slot, const ContactConstraint& f);  ///< f: the slot's record (make_constraint)
  void make_constraint(ContactConstraint& k, int slot, int cand, int ci, const Contact& c,
                       const std::vector<int>& solver_index);
  void integrate_velocity(int k, double h);
  static void normal_terms(ConstraintPoint& p, const Vec3& n, const SolverBody& A, const SolverBody& B);
  static void friction_terms(ContactConstraint& k, const SolverBody& A, const SolverBody& B);
  static void block_terms(SweepConstraint& k, const SolverBody& A, const SolverBody& B);
  // sweep_[slot] from cons_[slot]; with `impulses`, the accumulated impulses too (prepare).
  void pack_sweep(int slot, bool impulses);
  void refresh_tracked(int w, int nw);  ///< the tracked points and their bodies' inertia (inside on_workers)
  void restitution_one(SweepConstraint& k, ContactConstraint& f, double threshold);
  // Fewer constraints than this are solved on the calling thread alone.
  static constexpr int kMinParallelConstraints = 128;
};

}  // namespace simreel
