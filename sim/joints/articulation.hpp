// Mechanisms in joint coordinates (docs/joints.md). The joints of a scene split its jointed bodies
// into mechanisms, each a tree rooted at the world (or, when no joint reaches the world, at a body
// that floats freely). A mechanism's state is its joint coordinates q and velocities q'; its
// bodies' poses and velocities follow from them (forward kinematics), so a joint cannot open.
//
// Accelerations come from Featherstone's articulated-body algorithm (ABA), O(n) in the links; the
// coordinates are advanced by a Dormand-Prince 5(4) pair with adaptive steps. Reduced coordinates
// were chosen over constraint rows on free bodies because rows are either soft (they stretch:
// 20 m over a 100-link chain with a 1000:1 end mass in Box2D/Box3D) or projected (Jolt and Bullet
// lose up to 1.85 m g L of a pendulum's energy in 60 s); a tree in joint coordinates has no
// constraint to drift and takes any integrator's order.
//
// Composite public joints expand into primitive links: a universal joint is two revolute joints
// with a massless link between them.
#pragma once
#include <string>
#include <vector>

#include <Eigen/Cholesky>

#include <simreel/body.hpp>
#include <simreel/joints.hpp>

#include "sim/dynamics/state.hpp"
#include "sim/joints/spatial.hpp"

namespace simreel {

// The primitive joints of links; `free` is the root of a floating mechanism.
enum class LinkJoint { revolute, prismatic, spherical, fixed, free };

struct Link {
  int body = -1;    ///< world body index; -1: a massless link inside a composite joint
  int parent = -1;  ///< link index in the mechanism (smaller than this one), -1: the world
  LinkJoint kind = LinkJoint::fixed;
  int nq = 0, nv = 0;           ///< its joint's coordinates and velocities
  int iq = 0, iv = 0;           ///< their offsets in the mechanism's q and q'
  int joint = -1;               ///< public joint index, -1 for a free root
  int dof = 0;                  ///< which coordinate of the public joint this link's is (universal: 0 or 1)
  Vec3 axis_F = Vec3::UnitZ();  ///< revolute, prismatic: unit axis in the joint frame
  // The joint frame F (origin at the anchor) in the parent's link frame (the world's for a root),
  // and in this link's frame at q = 0. A link frame is the body's principal frame P: origin at the
  // centre of mass, axes along the principal axes.
  Quat q_pF = Quat::Identity();
  Vec3 p_pF = Vec3::Zero();
  Quat q_cF = Quat::Identity();
  Vec3 p_cF = Vec3::Zero();
  Mat3 R_pF = Mat3::Identity(), R_cF = Mat3::Identity();  ///< the same rotations as matrices
  // Products of the above that kinematics would otherwise form at every evaluation: R0 = R_pF
  // R_cF^T (the link in its parent at q = 0), t0 = p_pF - R0 p_cF (its origin there), the axis in
  // the link's frame (a hinge turns the link by R0 Rot(a_c, q)) and in the parent's (a slider moves
  // its origin by a_p q).
  Mat3 R0 = Mat3::Identity();
  Vec3 t0 = Vec3::Zero(), a_c = Vec3::UnitZ(), a_p = Vec3::UnitZ();
  // A hinge's pose in its parent as a polynomial in (sin q, 1 - cos q): Rot(a, q) = 1 + sin q [a]x +
  // (1 - cos q) [a]x^2 (Rodrigues), so R = R0 + sin q Rs + (1 - cos q) Rk with Rs = R0 [a_c]x,
  // Rk = R0 [a_c]x^2, and its origin t0 - sin q Rs p_cF - (1 - cos q) Rk p_cF.
  Mat3 Rs = Mat3::Zero(), Rk = Mat3::Zero();
  Vec3 ts = Vec3::Zero(), tk = Vec3::Zero();
  // The same rotation for write_bodies, as a quaternion: q_pF (cos(q/2) + sin(q/2) axis_F) q_cF^-1 =
  // cos(q/2) qh0 + sin(q/2) qh1 (the origin is kinematics', from t0, ts and tk).
  Quat qh0 = Quat::Identity(), qh1 = Quat::Identity();
  Vec3 p_cF_F = Vec3::Zero();  ///< the centre of mass in the joint frame (q_cF^-1 p_cF): write_bodies
  double mass = 0;             ///< kg
  Vec3 I_P = Vec3::Zero();     ///< kg m^2, principal moments
  Mat6 M = Mat6::Zero();       ///< the spatial inertia diag(I_P, mass), in the link frame
  Mat6X S;                     ///< motion subspace in the link frame (6 x nv), constant
  Vec6 s1 = Vec6::Zero();      ///< S when nv = 1 (hinges and sliders: the common case)
  double stiffness = 0, damping = 0, rest = 0;  ///< a 1-coordinate joint's spring
  double armature = 0;                          ///< kg m^2 or kg: rotor inertia on a 1-coordinate joint
  int dof_index = -1;                           ///< its Mechanism::Dof (limits, motor, friction), or -1
};

// The rotation vector (axis times angle, rad; the angle in [0, pi]) of a rotation: a ball joint's
// spring stretch and its position motor's rotation still to go (sim/joints/ball_limits.cpp).
Vec3 rotation_vector(Quat r);

class Mechanism {
 public:
  std::vector<Link> links;  ///< parents before children
  int nq = 0, nv = 0;
  std::vector<double> q, v;  ///< joint coordinates and velocities (saved state)
  double h = 0;              ///< s, the next internal step the controller proposes (saved state)
  // A lean mechanism (nothing acts on it that changes at a frame: no contact, force, stop, motor,
  // loop or rope; no ball or free joint) does not cut its last internal step at the frame's end:
  // the step runs on, and the frame's state is read from the step's dense output (Dormand and
  // Prince's continuous extension, 4th order). The next frame reads the same step while it
  // reaches, then steps on from its end. (Saved state: a restored run takes the step again from
  // its start, to the same bits.)
  struct Span {
    bool valid = false;
    bool retake = false;     ///< restored: take the step again from y0 before reading it
    double t0 = 0, len = 0;  ///< s: the step's start (the world's time) and length
    double t_out = 0;        ///< s: the frame end at which its state was last read
    Vec3 g = Vec3::Zero();   ///< m/s^2: the gravity it was taken under
    std::vector<double> y0;  ///< the state at its start
  };
  Span span;

  // Velocity Verlet (JointIntegrator::verlet, docs/joints.md "Verlet"), for a mechanism
  // without rows or quaternion coordinates (verlet_ok). A step of length h:
  //   v+ = v + h/2 a,  q1 = q + h v+,  a1 = f(q1, v + h a),  v1 = v+ + h/2 a1.
  // a1 is evaluated at the Euler-predicted rate rather than at v1 (which would make the step
  // implicit): the rate-dependent forces (Coriolis, damping) then err by O(h^2), times h/2, so the
  // step stays second order with one evaluation, and it is exactly velocity Verlet where the
  // forces do not depend on rates. The step is stable while the fastest mode's rate (the largest
  // |eigenvalue| of the linearised first-order system) times h stays under 2: that rate is measured
  // by power iteration on finite differences of f, and the frame split into enough steps to keep
  // rate h under kVerletReach. The rate is measured again at intervals that double up to
  // kVerletEvery frames while it holds within 10% and halve to every frame while it changes
  // faster: a chain
  // released level tightens from slack to 180 1/s in under a second; a growth seen over the last
  // interval is assumed to go on over the next.
  struct Verlet {
    bool carry = false;           ///< a is a1 of the last frame's last step, which ended at (q, v)
    Vec3 g = Vec3::Zero();        ///< m/s^2: the gravity a was evaluated under
    std::vector<double> a;        ///< nv: rad/s^2 or m/s^2
    std::vector<double> y;        ///< nq + nv: the state a was carried to ([q; v] of the last frame's end)
    std::vector<double> x;        ///< nq + nv: the power iteration's vector (unit length once measured)
    double rate = 0;              ///< 1/s: the fastest mode's rate at the last measurement (0: none yet)
    double growth = 1;            ///< the rate's growth over the last interval (at least 1): foreseen
    long next = 0;                ///< the frame index of the next measurement
    int every = 1;                ///< frames between measurements: 1 to kVerletEvery
    std::vector<double> y_start;  ///< the frame's start (scratch: an unresolved frame restarts there)
    long unresolved = 0;          ///< frames handed to dopri5 over the run
  };
  Verlet verlet;
  static constexpr double kVerletReach = 1.4;  ///< rate h per step (stability ends at 2)
  // The first measurement iterates until a pair moves the rate by less than this share: a
  // percent is what the step count needs (rate h is kept at 1.4 against stability's 2), and the
  // later measurements, one pair each, go on converging from the vector kept.
  static constexpr double kVerletConverged = 1e-2;
  static constexpr int kVerletEvery = 32;  ///< the most frames between measurements of the rate
  // A step whose acceleration changes by more than this share of the rates (h |a1 - a| / 2 against
  // max |v+|, the Euler predictor's error against the motion) does not resolve the motion: a whip,
  // a stiff damper's transient, an impact of forces, or a mode past the stability limit (which
  // grows 2.4-fold a step). The frame is then taken by dopri5, to its tolerance, and Verlet goes
  // on from the next. A smooth motion at w stays near (w h)^2 / 2; a chain's swing, whose fastest
  // modes carry a little of it, measured 0.07 (0.25 at its release, where v+ is small).
  static constexpr double kVerletResolve = 0.3;
  // A step failing that test is still resolved when its predictor's error, as a velocity, has at
  // most this share of the motion's kinetic energy (the error's at most 1e-2 of the motion's as a
  // velocity in the mass metric). The 1000:1 chain's fast mode scored at most 2.6e-3 there (median
  // 4e-5: the light links' oscillation, a millionth of the energy), while the level chain's
  // whip, where the energy runs into the last links, scores a median 0.4; a largest-rate test
  // alone handed the heavy chain's frames to dopri5, 7 times the cost for the same energy error.
  static constexpr double kVerletEnergyShare = 1e-4;
  bool verlet_ok() const { return !has_rows() && !loop_springs_on && nq == nv; }
  // The integrators' evaluations on a mechanism without rows, loop springs or loads (every link
  // then has at most one coordinate, as nq == nv) take derivative_world: the same articulated-body
  // algorithm with every spatial quantity in world axes about one point of the mechanism
  // (Featherstone 2008, sec. 7.3, "ABA in world coordinates"). A link's articulated inertia then
  // passes to its parent as it is: the 6x6 congruence X^T I X per link (a quarter of a chain's
  // evaluation in link frames) becomes 21 additions, and the rotations move to one R I R^T per
  // body. derivative() stays for everything else (modes, loops, contact rows), which reads its
  // link-frame quantities afterwards.
  bool world_aba_ok() const { return verlet_ok() && loads.empty(); }
  void derivative_world(const double* y, double* dy, const Vec3& g, const Wrench* wr);
  // A step's evaluation (Verlet's and dopri5's): derivative_world where world_aba_ok(), else
  // derivative().
  void step_derivative(const double* y, double* dy, const Vec3& g, const Wrench* wr, const MotionState* st) {
    if (world_aba_ok())
      derivative_world(y, dy, g, wr);
    else
      derivative(y, dy, g, wr, st);
  }
  // Twice the kinetic energies (J) of joint velocities a and b, a^T M a and b^T M b, at the last
  // evaluation's configuration (its kinematics): each link's velocity carried out from the root.
  void kinetic_energies(const double* a, const double* b, double& Ea, double& Eb);
  // The frame step by velocity Verlet: done, failed (the state stopped being finite, or the
  // steps the rate needs exceed JointSettings::max_steps), or unresolved (y0_ back at the frame's
  // start, for dopri5 to take).
  enum class VerletFrame { done, failed, unresolved };
  VerletFrame advance_verlet(double dt, const Vec3& g, const Wrench* wr, const MotionState* st,
                             const JointSettings& js);
  // The fastest mode's rate at y0_, whose derivative k_[0] holds: iterations of x <- J x / |J x|
  // with J x = (f(y0 + eps x) - f(y0)) / eps, rate = sqrt(|J J x| / |x|) (a conjugate pair +-i w
  // gives J^2 x = -w^2 x).
  void measure_rate(int pairs, const Vec3& g, const Wrench* wr, const MotionState* st);

  // A joint that closes a loop (docs/joints.md, "Closed loops"): constraint rows on the tree's
  // coordinates holding two links' anchor points together (3 rows) and, for a hinge, the axes
  // parallel (2 more). Accelerations satisfy the rows exactly at every evaluation (Lagrange
  // multipliers through the joint-space mass matrix), and after every internal step positions and
  // velocities are projected back onto them, so the loop's residual stays at round-off.
  struct Loop {
    int joint = -1;
    int la = -1, lb = -1;  ///< links (la = -1: the fixed base)
    Vec3 pa, pb;           ///< the anchor in each link's frame (the base's: world)
    // What it holds: spherical, the anchors together (3 rows); hinge, also the axes parallel (2);
    // prismatic, the anchors on the axis (2) and no relative rotation (3); fixed, the anchors
    // together and no relative rotation (3 + 3); universal, the anchors together and its two axes
    // perpendicular (3 + 1).
    enum class Kind { spherical, hinge, prismatic, fixed, universal } kind = Kind::spherical;
    bool hinge = false;  ///< kind == hinge
    Vec3 t1, t2;         ///< hinge, prismatic: perpendiculars to the axis, fixed in a (world for the base)
    Vec3 ab;             ///< hinge: the axis in b's frame; universal: axis2 in b's frame
    Vec3 aa;             ///< hinge, prismatic, universal: the (first) axis in a's frame
    Mat3 R0;             ///< prismatic, fixed: b's start orientation relative to a's (R_a^T R_b at t = 0)
    Quat q_a0, q_b0;     ///< the links' start orientations (read-outs of the angle)
    Vec3 axis_W0;        ///< the hinge axis at t = 0
    // A spring on a hinge's angle or a slider's slide (both zero at the start, as loop_angle reads
    // them): N m/rad or N/m, N m s/rad or N s/m, rad or m.
    double stiffness = 0, damping = 0, rest = 0;
    // A hinge with a spring or stops (tracked) keeps its angle continuous past +-pi (saved
    // state): the angle at the start of the internal step (or contact substep) being taken. A
    // stage's angle is the value nearest it of the relative rotation's, only known modulo 2 pi.
    bool tracked = false;
    double angle = 0;
    int rows() const {
      switch (kind) {
        case Kind::spherical:
          return 3;
        case Kind::hinge:
          return 5;
        case Kind::prismatic:
          return 5;
        case Kind::fixed:
          return 6;
        case Kind::universal:
          return 4;
      }
      return 3;
    }
  };
  std::vector<Loop> loops;
  int loop_rows = 0;
  bool loop_springs_on = false;  ///< any loop carries a spring
  bool loop_tracked_on = false;  ///< any loop hinge keeps a continuous angle (Loop::tracked)

  // A distance joint's rod or rope, or a pulley's rope (docs/joints.md, "Rods, ropes and
  // pulleys"): one row on the tree's coordinates, on the length
  //   s(q) = sum_k w_k |x_b,k - x_a,k| + c theta,
  // the sum over the rope's straight segments (each between a point of link a and one of link b;
  // a pulley's run from a fixed point to a body) and theta the coordinate of a wheel the rope turns
  // without slipping. A rod holds s at its length always; a rope is a hybrid mode like a
  // coordinate's stops: slack, or taut at its max (min) length, where it only pulls (pushes), its
  // multiplier the force along it. A spring acts along s as a force on the segments' ends.
  //
  // The same rows keep a ball joint's stops (BallLimits): s is then the swing or the twist angle
  // (rad) of link `link`'s joint, measured from its coordinates about `axis` (its joint frame), or
  // its whole rotation's angle, a slack rope between the stops' bounds; and a mimic (JointMimic):
  // s = q_link - ratio q_link2, held at 0 as a rod.
  struct Tether {
    int joint = -1;
    enum class Measure { length, swing, twist, angle, coupling, hinge, slide } measure = Measure::length;
    int link = -1;     ///< swing, twist, angle: the ball joint's link; coupling: the follower's
    int link2 = -1;    ///< coupling: the leader's link (s = q_link - ratio q_link2, held at 0)
    double ratio = 1;  ///< coupling: the mimic's multiplier
    std::vector<std::pair<int, double>> more;  ///< coupling: further (link, ratio): s -= ratio q_link
    int loop = -1;              ///< hinge, slide: the loop whose angle or slide (loop_angle) it stops
    Vec3 axis = Vec3::UnitZ();  ///< swing, twist: unit, joint frame
    int nseg = 1;
    int la[2] = {-1, -1}, lb[2] = {-1, -1};     ///< links (-1: the fixed base)
    Vec3 pa[2] = {Vec3::Zero(), Vec3::Zero()};  ///< the points in the links' frames (the base's: world)
    Vec3 pb[2] = {Vec3::Zero(), Vec3::Zero()};
    double w[2] = {1, 1};
    int wheel_iq = -1, wheel_iv = -1;  ///< the wheel's coordinate, or -1
    double wheel_c = 0;                ///< m: its weight c in s (-(+-r): the rope's lever on the wheel)
    int wheel_link = -1;
    Vec3 wheel_point[2] = {Vec3::Zero(), Vec3::Zero()};  ///< where segment k leaves the wheel (world,
                                                         ///< fixed): the rope pulls it there
    bool rod = false, has_lo = false, has_hi = false;
    double lo = 0, hi = 0;  ///< m; a rod's length is hi
    double restitution = 0;
    double stiffness = 0, damping = 0, rest = 0;  ///< N/m, N s/m, m
    int taut = 0;       ///< a rope's mode (saved state): +1 held at hi, -1 held at lo, 0 slack
    double aim = NAN;   ///< m: where project_positions puts a taut rope, when not at its bound
    double lambda = 0;  ///< N: the row's multiplier (the force along the rope; < 0 pulls)
    bool active() const { return rod || taut != 0; }
  };
  std::vector<Tether> tethers;
  int tether_row(int t) const { return loop_rows + (int)dofs.size() + t; }
  double measure_tether(int t);  ///< its length at q (sets the kinematics: build time only)
  /// N along a distance joint's spring (> 0 pushes its ends apart), at the last evaluated kinematics.
  double tether_spring_force(const Tether& t) const;
  // A tether's length and rate at the last written poses (write_bodies): whole (seg = -1) or one
  // segment's; and its residual (m) against the row it keeps (0 when slack within its bounds).
  double tether_length(int t, int seg = -1, double* rate = nullptr) const;
  double tether_gap(int t) const;
  // A ball joint's swing, twist or whole angle (rad) and its rate at the last written poses.
  double ball_readout(const Tether& t, double* rate = nullptr) const;
  // A loop-closing ball joint's rotation of b relative to a in its joint frame (the world's axes at
  // the start), from the two links' world rotations.
  static Mat3 loop_ball_rotation(const Loop& L, const Mat3& Ra, const Mat3& Rb);
  // A ball joint's rotation vector (rad; |phi| <= pi) from its coordinates: its spring's stretch.
  static Vec3 ball_rotation_vector(const Link& l, const double* q);
  bool events_on() const { return !dofs.empty() || !tethers.empty(); }
  bool projected() const { return !loops.empty() || !tethers.empty(); }  ///< rows that need projection

  // A one-coordinate link's limits, motor and Coulomb friction (docs/joints.md, "Limits, motors
  // and friction"): a hybrid system. Each holds a mode fixed over an internal step (so the
  // integrator sees a smooth right-hand side); a mode changes only at an event, located in time by
  // re-taking the step to the crossing of an event function (a coordinate reaching a stop, a rate
  // reaching the motor's target or zero, a constraint force reaching its bound). In a mode where
  // the coordinate is held (on a stop, at the motor's rate, stuck by friction) it is one more
  // constraint row, q''_k = a*, whose multiplier is the force holding it.
  // A scalar velocity coordinate with stops, a motor or friction: a hinge's or slider's (iq its
  // coordinate), or one of a ball joint's three angular velocities in the child's axes (ball the
  // component, iq the joint's quaternion, iv - ball its first rate; no stops: those are tethers).
  struct Dof {
    int iq = 0, iv = 0, joint = -1;
    int ball = -1;
    bool has_lo = false, has_hi = false;
    double lo = 0, hi = 0, restitution = 0;
    int motor = 0;  ///< 0 none, 1 speed, 2 position
    double speed = 0, position = 0, time_constant = 0.1, max_force = 0;
    Quat target = Quat::Identity();  ///< a ball joint's position motor: the joint rotation to reach
    double friction = 0;
    // Mode (saved state).
    int at_stop = 0;     ///< -1 resting on the lower stop, +1 on the upper, 0 free
    int rebounded = 0;   ///< -1, +1: it left that stop at the last apply_events (not saved)
    bool hold = false;   ///< the motor holds the rate at its target
    int push = 0;        ///< a saturated motor pushes with push * max_force
    bool stick = false;  ///< friction holds the coordinate still
    int slide = 0;       ///< sliding: friction acts as -slide * friction
    double lambda = 0;   ///< the holding row's multiplier (last evaluation)
    double force = 0;    ///< N m or N: the generalised force of stop, motor and friction (last evaluation)
    double lower_bound() const;  ///< the holding row's multiplier bounds in the current mode
    double upper_bound() const;
    bool active() const { return at_stop != 0 || hold || stick; }
    double target_rate(const double* q) const;  ///< the motor's target rate at coordinates q
    // d/dt of the target rate at q, v while the coordinate is held (a position motor's target
    // moves with q; every other target is constant).
    double target_acceleration(const double* q, const double* v) const;
  };
  std::vector<Dof> dofs;
  bool started = false;  ///< the modes were settled at the first step (saved state)
  bool has_rows() const { return !loops.empty() || !dofs.empty() || !tethers.empty(); }
  bool any_active() const {
    for (const Dof& d : dofs)
      if (d.active()) return true;
    for (const Tether& t : tethers)
      if (t.active()) return true;
    return false;
  }
  long events = 0;  ///< mode changes over the run
  // Puts the modes in agreement with the state (a stop reached moving into it takes its impact;
  // a held coordinate whose holding force is out of bounds is released); at the start and after
  // every event.
  void settle_modes(double* y, const Vec3& g, const Wrench* wr);
  void start_modes(double* y, const Vec3& g, const Wrench* wr);  ///< modes from the state at the first step

  void allocate_loops();  ///< scratch of the constraint rows (loops, Dofs and tethers)
  // Positions (Newton on the rows, the correction in the mass metric) and velocities (the
  // kinetic-energy-closest motion that keeps the rows) back onto the loops.
  void project_positions(double* q);
  void project_velocities(const double* q, double* v);
  // A loop's hinge angle (rad, zero at the start) and rate, from the last written poses.
  double loop_angle(int k) const;
  double loop_speed(int k) const;

  void allocate();  ///< scratch for nq, nv and the links
  // y' = f(y) for y = [q; q'], the external wrenches (world, about each body's centre of mass)
  // held constant over the step.
  void derivative(const double* y, double* dy, const Vec3& g, const Wrench* wr, const MotionState* st);
  // Advances q, q' by dt; false when the state stopped being finite or max_steps was exceeded.
  bool advance(double dt, const Vec3& g, const Wrench* wr, const MotionState* st, const JointSettings& js);
  // Forward kinematics of q, q' into the bodies' motion states.
  void write_bodies(MotionState* st) const;
  // The same from derivative_world's last kinematics, when that was at q (a Verlet frame's end):
  // poses from the world rotations (not the quaternion products), velocities summed in world
  // axes (write_bodies' quaternion products and 6x6 transforms were a fifth of a chain's frame).
  void write_bodies_world(MotionState* st) const;
  // The velocities of every body, link frame ([w; v] at the centre of mass), at q and q'.
  void link_velocities(const double* q, const double* v, std::vector<Vec6>& out);
  // Contacts on the mechanism's bodies (sim/joints/contact_rows.hpp): while a frame step has
  // any, the mechanism is stepped inside the contact solver's substeps instead of by advance().
  // contact_begin: the working state from q, v, each link's world Jacobian at the step's start
  // (angular and centre-of-mass rows) and the joint-space inverse inertia that keeps the loops and
  // the held coordinates, P = M^-1 - M^-1 G^T (G M^-1 G^T)^-1 G M^-1.
  void contact_begin(const Vec3& g);
  // Generalised row of a contact on link `link`: the rate n . (v + w x r) of the body point at r
  // (world offset from its centre of mass) along n, into J (nv); W = P J^T.
  void contact_row(int link, const Vec3& r, const Vec3& n, double* J) const;
  void contact_response(const double* J, double* W) const;
  double* contact_v() { return y0_.data() + nq; }  ///< the working joint velocities
  // A substep: q' += h q'' (modes held), then q moved by h q' (exact rotations); the links' poses.
  // Modes: a stop reached, a rate captured or a holding force out of bounds over a substep
  // switches its mode at the substep's end (first order in the substep while in contact).
  void contact_velocities(double h, const Vec3& g);
  // True when the substep's events changed which rows are held (a stop reached or left, a rope
  // gone taut or slack): P was then made again at the working state, and the contact rows' W
  // and effective masses must be too, or the contacts would push held coordinates off their rows.
  bool contact_positions(double h, const Vec3& g);
  const Mat3& link_R(int i) const { return work_[i].R_W; }  ///< after contact_positions / contact_begin
  const Vec3& link_x(int i) const { return work_[i].x_W; }
  void contact_end();  ///< q, v from the working state

  // An impulse on link `link`: P (N s, world) at the point r (world offset from its centre of mass)
  // and an angular impulse L (N m s, world). The joint velocities jump by P_c J^T (P; L + r x P),
  // P_c the inverse inertia that keeps the loops, rods and held coordinates (ropes left out: a rope
  // cannot push; one the impulse stretches is caught by the next step's event).
  void apply_impulse(int link, const Vec3& r, const Vec3& P, const Vec3& L);
  // The spatial force (link frame of `link`, about its origin) that link's joint transmits from
  // its parent, at the current q, v (Newton-Euler from the ABA's accelerations, the loops' forces
  // taken as external); for loop k (link = -1 - k), its multipliers as the force on b at the anchor
  // and the torque about the hinge's perpendiculars, world. Scratch only: the state is unchanged.
  void joint_wrench(int link, const Vec3& g, Vec3& force_W, Vec3& torque_about_origin_W);
  // A loop's force and torque on b at its anchor (world) from its rows' multipliers (current
  // kinematics): the gap rows are force components, the angular rows torques about their axes.
  void loop_load(const Loop& L, const double* lambda, Vec3& F, Vec3& T) const;

  // Continuous forces from the scene's force list on this mechanism's bodies (force, torque,
  // drag, and springs whose other end is the world, a static body or a body of this mechanism),
  // evaluated at every evaluation of the derivative from the links' poses and velocities at its
  // time, so they are integrated to the integrator's order; internal steps end at their windows'
  // edges. Each copy's bodies are renumbered: 0 its body, 1 a spring's other end.
  struct Load {
    ForceDef f;
    int link = -1, link_b = -1;  ///< link_b: -1 the world anchor or a static body (state_b)
    BodyModel model[2];
    MotionState state_b;
  };
  std::vector<Load> loads;
  double frame_time = 0;  ///< s, the time at the start of the frame step (Articulations::set_time)

  long steps_taken = 0, steps_rejected = 0;  ///< internal steps over the run
  bool exceeded = false;         ///< a frame step needed more internal steps than JointSettings::max_steps
  bool contact_stepped = false;  ///< this frame step was taken by the contact solver (ArticulatedContacts)
  bool asleep = false;           ///< its bodies sleep (the World's islands): not stepped

 private:
  void contact_inverse_inertia();  ///< P_ at the current kinematics and held rows (contact_begin)
  bool held_rows_changed();        ///< the held rows differ from the last call's (held_ updated)
  std::vector<char> held_;         ///< per Dof and tether: held at the last held_rows_changed()
  // Every link's transform from its parent at q, and (world) its pose in the world.
  void kinematics(const double* q, bool world = true);
  // Loop rows at the current kinematics: positions C(q); velocities for link velocities V (link
  // frames); accelerations for V and true link accelerations A. out has loop_rows entries.
  void loop_position_rows(double* out) const;
  void loop_velocity_rows(const std::vector<Vec6>& V, double* out) const;
  void loop_acceleration_rows(const std::vector<Vec6>& V, const std::vector<Vec6>& A, double* out) const;
  // A tether at the current kinematics: its length; its rate for link velocities V and the wheel's
  // rate; its second derivative for V, true link accelerations A and the wheel's acceleration.
  double tether_position(const Tether& t, const double* q) const;
  double tether_rate(const Tether& t, const std::vector<Vec6>& V, double wheel_rate) const;
  double tether_acceleration(const Tether& t, const std::vector<Vec6>& V, const std::vector<Vec6>& A,
                             double wheel_acc) const;
  // A ball joint's swing, twist or whole angle (Tether::Measure) at the current kinematics: the angle, its
  // rate for link velocities V, its second derivative for V and true link accelerations A.
  double ball_angle(const Tether& t) const;
  double ball_rate(const Tether& t, const std::vector<Vec6>& V) const;
  double ball_acceleration(const Tether& t, const std::vector<Vec6>& V, const std::vector<Vec6>& A) const;
  // A one-coordinate link's rate and acceleration from link velocities V and true link
  // accelerations A: V_i - X_i V_p = s q', A_i - X_i A_p = s q'' + V_i x s q'.
  double coordinate_rate(int link, const std::vector<Vec6>& V) const;
  double coordinate_acceleration(int link, const std::vector<Vec6>& V, const std::vector<Vec6>& A) const;
  // Springs along tethers: their forces on the segments' ends into the links' bias forces (pass 1
  // of the ABA done: kinematics and velocities); f_out (per tether, N) when given.
  void tether_springs();
  // Springs on loop-closing hinges and sliders (Loop::stiffness): a torque about the hinge's axis
  // (a force along the slider's, both at b's anchor) on the two links, at the current kinematics
  // and link velocities; subtracted from f (joint_wrench) or the ABA's bias forces (after pass 1).
  void loop_springs(std::vector<Vec6>* f = nullptr);
  // A tracked hinge's angle at the current kinematics, the one nearest its saved Loop::angle;
  // track_loop_angles() saves it after a step (kinematics of the new state done). Its rate and
  // second derivative for link velocities V and true link accelerations A (a stop's row).
  double hinge_angle(const Loop& L) const;
  double hinge_rate(const Loop& L, const std::vector<Vec6>& V) const;
  double hinge_acceleration(const Loop& L, const std::vector<Vec6>& V, const std::vector<Vec6>& A) const;
  // A loop slider's slide n . (P_b - P_a) (m; n = R_a aa, the axis fixed in a; P the anchors) and
  // its first two time derivatives.
  double slide_position(const Loop& L) const;
  double slide_rate(const Loop& L, const std::vector<Vec6>& V) const;
  double slide_acceleration(const Loop& L, const std::vector<Vec6>& V, const std::vector<Vec6>& A) const;
  void track_loop_angles();
  // The forces a tether's row and spring put on the links (link frames, about their origins),
  // subtracted from f (joint_wrench: external to the tree).
  void tether_loads(const Tether& t, double force, std::vector<Vec6>& f) const;
  Vec3 point_W(int link, const Vec3& p) const {  ///< a link's point in the world (link -1: p is world)
    return link < 0 ? p : Vec3(work_[link].x_W + work_[link].R_W * p);
  }
  void mass_matrix();  ///< M_ at the current kinematics (composite-rigid-body algorithm)
  // G_ at the current kinematics (loop rows, then one row per Dof: e_k when it is a row, else
  // zero); then Y_ = M^-1 G^T and A_ = G Y_. A Dof is a row when it is held (active()), or for
  // impulses when vtarget_ names a target rate for it.
  void loop_jacobian(bool impulse_rows = false);
  void unit_velocities(int k, std::vector<Vec6>& V) const;  ///< link velocities for q' = e_k
  // After the ABA: add M^-1 G^T lambda for the loops' and the held coordinates' rows.
  void constrain_accelerations(const double* q, const double* v, double* qdd);
  void solve_rows();  ///< dv_ = M^-1 G^T lambda for (G M^-1 G^T) lambda = rhs_ (after loop_jacobian)
  void displace(double* q, const double* dv) const;  ///< q moved by the velocity-space step dv
  // One Dormand-Prince step of size hs from y0_ (k_[0] evaluated there): the 5th-order result in
  // ys_ (and y1_), the error norm returned.
  double rk_step(double hs, const Vec3& g, const Wrench* wr, const MotionState* st, double tol);
  // The step just taken (y0_, y1_, k_) kept as the span starting at t0 (the world's time); and its
  // state at t (within it) written to y. retake_span: a restored span's step taken again.
  void keep_span(double t0, double hs, const Vec3& g);
  void read_span(double t, double* y) const;
  void retake_span(const Vec3& g, const Wrench* wr, const MotionState* st);
  std::vector<double> span_y1_, span_k7_, span_out_;  ///< the span's end, its derivative, the state read
  std::vector<double> span_rc_[5];                    ///< its dense output's coefficients
  // Event functions of the modes at a state whose derivative was just evaluated (positive while
  // the mode holds), into out (one slot per function, fixed layout).
  void event_values(const double* y, double* out) const;
  // Applies the mode changes whose event functions went from >= 0 (g0) to < 0 (g1) at state y.
  void apply_events(double* y, const double* g0, const double* g1, const Vec3& g, const Wrench* wr);
  // After a velocity jump: a motor or friction that held a rate lets go of it (or takes it), a
  // saturated motor or sliding friction takes the direction of the new rate.
  void refresh_rate_modes(const double* q, const double* v);
  // Velocity jump at stop impacts: rows (the loops, the coordinates on a stop, the impacting ones)
  // reach their target rates by impulses through the mass matrix.
  void impulse(const double* q, double* v, const std::vector<double>& target);
  void project_dofs(double* y);  ///< held coordinates back exactly on their rows after a step
  // A rope reaching bound (+1 max, -1 min) at q, v: its rate after the impact (restitution), and
  // taut when that is under the rest threshold.
  double rope_impact(int t, int bound, const double* q, const double* v);
  void keep_held_rows();  ///< impulse targets of 0 for every row already held (stops, rods, taut ropes)
  void back_on_stops(
      double* q) const;  ///< coordinates that just rebounded, a round-off past the stop, put on it
  // Slack ropes found past their bounds (a projection of other rows, or a contact substep's
  // travel, moved them there unseen by the event functions) are caught there: an impact if they
  // were moving out, then put back on the bound. True when any was.
  bool catch_stretched(double* y, const Vec3& g, const Wrench* wr);
  std::vector<int> rebound_;  ///< catch_stretched's scratch (sized once, at the first catch)
  // The same for coordinates found past a stop and moving further out: a contact substep's first-
  // order travel can take a coordinate over its stop between two event checks, or start from a
  // hair past it (its release read the holding force without the contacts' push). Each is put on
  // its stop with the stop's impact. True when any was.
  bool catch_past_stops(double* y, const Vec3& g, const Wrench* wr);
  // Contacts' inverse inertia leaves taut ropes out (contact_begin): a rope cannot push, so an
  // impact may not be stopped by it; a rope an impulse stretches is caught at the substep's end.
  bool ropes_free_ = false;
  // The loads at time_ subtracted from each link's spatial force: the ABA's bias forces (after its
  // pass 1), or f (joint_wrench: external to the tree).
  void apply_loads(std::vector<Vec6>* f = nullptr);
  double time_ = 0;                        ///< s, the time derivative() evaluates at
  double t_step_ = 0;                      ///< s, the start of the internal step rk_step takes
  std::vector<double> tau_;                ///< generalised forces of saturated motors and sliding friction
  std::vector<double> g0_, g1_, ga_, gc_;  ///< event functions: step start and end, bracket, trial
  std::vector<double> vtarget_;            ///< impulse targets (NaN: not a row)
  std::vector<double> kd_;                 ///< scratch derivative for settle_modes
  Eigen::MatrixXd Jl_;      ///< 6 n x nv: each link's world [angular; centre-of-mass] Jacobian (contacts)
  Eigen::MatrixXd P_;       ///< nv x nv: constrained inverse inertia (contacts)
  std::vector<double> dq_;  ///< nv scratch
  std::vector<Vec6> rf_;    ///< joint_wrench scratch
  // What an evaluation touches first (960 bytes), then what only multi-coordinate joints and the
  // mass matrix use (960 more): a chain's evaluation streams every link's record, and 100 chains
  // of 20 links' records (3.8 MB) outgrow the 2 MB L2 of the machines measured on.
  struct Work {
    Mat3 E;    ///< motion transform parent link -> this link (Featherstone's X = (E, r)):
    Vec3 r;    ///< E rotates parent coordinates into this link's, r is this link's origin in the parent's
    Mat3 R_W;  ///< this link's frame to world
    Vec3 x_W;  ///< this link's origin in the world
    Vec6 vel, c, pA, acc;
    Mat6 IA;
    Vec6 U1;        ///< U, 1/D and u of a one-coordinate joint
    Vec6 sO;        ///< derivative_world: the joint's motion subspace in world axes about origin_
    double Iw[21];  ///< derivative_world: the articulated inertia there (packed symmetric)
    double Dinv1 = 0, u1 = 0;
    Mat6X U;
    MatXX6 Dinv;
    VecX6 u;
    Mat6 Ic;  ///< composite inertia (mass_matrix)
  };
  std::vector<Work> work_;
  // m: derivative_world's reference point, fixed in the world (the first root's anchor): spatial
  // inertias about it carry m |c|^2 terms, so it is kept near the mechanism rather than at the
  // world's origin (a chain 100 m out would lose 8 digits of a 1 cm link's inertia there).
  Vec3 origin_ = Vec3::Zero();
  // derivative_world's last kinematics were at world_q_ (cleared by any other kinematics):
  // write_bodies reads the poses from them when that is q.
  bool world_at_q_ = false;
  std::vector<double> world_q_;
  bool lean_ = false;  ///< inside advance(), when no evaluation needs the links' world poses
  // The last frame's end state and gravity, when k_[0] holds the derivative there (advance).
  bool carry_k1_ = false;
  std::vector<double> y_end_;
  Vec3 g_end_ = Vec3::Zero();
  std::vector<double> y0_, y1_, ys_;
  std::vector<double> k_[7];
  // Loop scratch, sized once (allocate_loops).
  Eigen::MatrixXd M_, G_, Y_, A_;
  Eigen::VectorXd rows_, rhs_, lambda_, dv_;
  Eigen::LLT<Eigen::MatrixXd> llt_, llt_rows_;
  std::vector<Vec6> V_, Acc_;
  mutable std::vector<Quat> out_q_;  ///< write_bodies' scratch: no allocation per step
  mutable std::vector<Vec3> out_x_;
  mutable std::vector<Vec6> out_v_;
  std::vector<Vec6> ke_a_, ke_b_;  ///< kinetic_energies' link velocities
};

class Articulations {
 public:
  // Validates the joints (InputError naming the joint) and builds the mechanisms from the bodies'
  // start states; jointed bodies' initial velocities are projected onto their joints' freedoms
  // (with a warning when that changed them).
  // `bonds`: pairs of dynamic bodies that must move in one mechanism without a joint between them
  // (a spring from a jointed body to a free one): joined into the same mechanism, a body held by
  // bonds alone floating freely in it.
  void build(const std::vector<JointDef>& joints, const JointSettings& settings,
             const std::vector<BodyDef>& defs, const std::vector<BodyModel>& model,
             std::vector<MotionState>& state, std::vector<std::string>& warnings,
             const std::vector<std::pair<int, int>>& bonds = {});
  bool empty() const { return mechanisms_.empty(); }
  int joint_count() const { return (int)joints_.size(); }
  const JointDef& joint(int j) const { return joints_[j]; }
  const std::vector<JointDef>& joints() const { return joints_; }
  bool jointed(int body) const { return body < (int)link_of_.size() && link_of_[body].first >= 0; }
  int find(std::string_view name) const;  ///< joint index, -1 if none
  /// (mechanism, link) of a jointed body, (-1, -1) otherwise.
  std::pair<int, int> link_of(int body) const {
    return body < (int)link_of_.size() ? link_of_[body] : std::pair<int, int>{-1, -1};
  }

  // Advances every mechanism by dt and writes its bodies' motion states; false if a state stopped
  // being finite (or a mechanism needed more internal steps than the settings allow).
  bool step(double dt, const Vec3& g, const Wrench* wr, MotionState* st) {
    return step_range(0, (int)mechanisms_.size(), dt, g, wr, st);
  }
  // Continuous forces on jointed bodies (AppliedForces::jointed, indices into `forces`) onto
  // their mechanisms (InputError naming the body when a spring joins two that move separately).
  void add_loads(const std::vector<ForceDef>& forces, const std::vector<int>& which,
                 const std::vector<BodyDef>& defs, const std::vector<BodyModel>& model,
                 const std::vector<MotionState>& state);
  void set_time(double t) {  ///< s, the frame step's start (forces' windows)
    for (Mechanism& m : mechanisms_) m.frame_time = t;
  }
  // Mechanisms [begin, end) only: each is independent of the others (its own bodies, state and
  // scratch), so threads may take disjoint ranges with the same results.
  bool step_range(int begin, int end, double dt, const Vec3& g, const Wrench* wr, MotionState* st);
  int mechanism_count() const { return (int)mechanisms_.size(); }

  // A joint's coordinate k (rad or m; a spherical joint: its rotation angle from the start pose)
  // and its rate (rad/s or m/s; spherical: |relative angular velocity|).
  double position(int j, int k = 0) const;
  double speed(int j, int k = 0) const;
  // The largest gap between the two anchor points of any joint (m), and the largest angle between
  // the two sides' axes (rad; hinge axes, slider directions, welds), read from the bodies' states;
  // a mimic's residual counts in its follower's unit, a ball joint's overshoot of a stop as an angle.
  double gap(const MotionState* st) const;
  double coupling_gap(int j) const;  ///< joint j's mimic residual |q - multiplier q_leader|
  /// J, what the joints' springs store now: k (q - rest)^2 / 2 per sprung coordinate, and
  /// k (L - rest)^2 / 2 per sprung distance joint (from the poses of the last frame).
  double spring_energy() const;
  /// J, the joints' rotor inertias' kinetic energy: armature q'^2 / 2 per coordinate that has one.
  double armature_energy() const;
  double angular_gap(const MotionState* st) const;
  // An impulse P (N s, world) at the world point at_W and an angular impulse L (N m s) on jointed
  // body `body`: its mechanism's velocities jump (Mechanism::apply_impulse) and its bodies' states
  // are written.
  void apply_impulse(int body, const Vec3& P, const Vec3& at_W, const Vec3& L, MotionState* st);
  // The generalised force of coordinate k of joint j's stops, motor and friction (N m or N).
  double force(int j, int k = 0) const;
  // The force and torque (world, at the anchor) that joint j's parent exerts on its child, from
  // the bodies' motion (Newton-Euler over the child's subtree; loops: their multipliers).
  void reaction(int j, const MotionState* st, const Vec3& g, Vec3& force_W, Vec3& torque_W) const;

  const std::vector<Mechanism>& mechanisms() const { return mechanisms_; }
  std::vector<Mechanism>& mechanisms() { return mechanisms_; }
  long internal_steps() const;
  /// The first joint of a mechanism that exceeded its internal step budget, or -1.
  int exceeded_joint() const;

 private:
  void validate_tether(JointDef& d, const std::vector<BodyDef>& defs,
                       const std::vector<BodyModel>& model) const;
  // The rows of distance or pulley joint j on its mechanism (after the mechanisms' links exist).
  void build_tether(int j, const std::vector<BodyModel>& model, const std::vector<MotionState>& state);
  // Per public joint: (mechanism, first tether) of a distance or pulley joint, or (-1, -1).
  std::vector<std::pair<int, int>> tether_of_;
  // The link that carries coordinate k of joint j (universal: k = 0, 1), and its mechanism.
  const Link& coordinate_link(int j, int k, const Mechanism*& m) const;
  std::vector<JointDef> joints_;
  JointSettings settings_;
  std::vector<Mechanism> mechanisms_;
  std::vector<std::pair<int, int>> link_of_;  ///< per body: (mechanism, link) or (-1, -1)
  // Per public joint: its mechanism and first link (universal: two consecutive links).
  std::vector<std::pair<int, int>> joint_link_;
  // Per public joint: the anchor in the parent's and the child's principal frames (world for -1),
  // and the axes there, for the gap read-out.
  struct Side {
    Vec3 p_p, p_c, a_p, a_c;
  };
  std::vector<Side> sides_;
};

}  // namespace simreel
