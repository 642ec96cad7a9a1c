// Rolling contact (docs/contacts.md, "Rolling contact"): a body that touches fixed flat surfaces
// only at points of smooth shapes (sphere, ellipsoid, a capsule's end, a cylinder's rim), its
// feet, is stepped by the contact's own equations of motion, not by the soft solver's substeps.
//
// A foot's contact point P is the shape's support point against the surface's normal n (a function
// of the orientation alone), kept at the gap it had when the body came, so G's height is the
// geometry's. Without slip (Coulomb friction holding, one foot) the material point at P is at
// rest, v_G = w x r with r = G - P, and eliminating the contact force F = m (a_G - g) - f_ext from
// Newton-Euler gives an explicit ODE for (q, w) (Kane & Levinson 1982; Neimark & Fufaev, "Dynamics
// of Nonholonomic Systems", ch. 1):
//   a_G = w' x r + w x r',   r' = w x r - R dp_P/dt (the contact point running over the surface)
//   (I_W + m (|r|^2 1 - r r^T)) w' = -w x I_W w + tau + r x f_ext - m r x (w x r') + m r x g.
// With regularised Coulomb friction (slip_speed > 0) the friction force is a function of each
// foot's slip and the unknowns are the feet's normal forces, from keeping each foot's material
// point from accelerating into or off its surface (a small linear system). Either way the ODE is
// integrated by Dormand-Prince 5(4) with adaptive internal steps (as mechanisms are) and the
// constraints are restored exactly at the step's end: rolling does no work and keeps the energy
// to the tolerance. The soft solver's velocity-level contact instead removes, each substep, the
// normal velocity the curving surface brings: the Kane-Levinson rattleback lost 21% of its motion
// energy in 22 s at the default step, 2.6% at 64 substeps and a 3840 Hz contact.
//
// A body is taken while every foot pushes (N > 0), without slip inside its friction cone, and
// stays on its shape's smooth part, and nothing else touches it or closes on it within the step;
// with slip, a foot that would pull lifts, and a lifted foot (or one closing on its surface) is
// watched: the internal step is cut where it lands and the landing made as a plastic impact. A
// step that breaks any of this is given back, untouched, to the soft solver. A body comes from the
// solver's hands when each foot is within twice linear_slop of overlap and its material point
// nearly at rest along the normal (without slip: entirely) to linear_slop per step; the leftover
// is removed by the plastic impulse that stops it, the only energy the change takes.
#pragma once
#include <vector>

#include <simreel/settings.hpp>

#include "sim/collision/contact.hpp"
#include "sim/collision/shape_table.hpp"
#include "sim/dynamics/state.hpp"

namespace simreel {

class RollingContacts {
 public:
  struct Input {
    const BodyModel* model = nullptr;
    MotionState* state = nullptr;
    const Wrench* wrench = nullptr;  ///< may be null
    const ShapeTable* shapes = nullptr;
    Vec3 gravity = Vec3::Zero();  ///< m/s^2
    double dt = 0;                ///< s
    ContactSettings settings;
    /// Bodies that may not be taken whatever their contacts (jointed ones: their mechanisms step
    /// them); one char per body, nonzero = excluded; may be null.
    const char* excluded = nullptr;
  };

  void resize(int bodies) { h_.assign(bodies, 0.0); }

  // Steps those of `bodies` (the step's bodies in contact) that roll this step and marks them in
  // `rolled` (one char per body, set to 1; the caller clears them). `contacts` are the step's
  // active contacts; the ones of rolling bodies get the step's contact impulse, as substep impulses
  // of length dt / substeps (what the solver stores). A body whose rolling step fails in any way (a
  // non-finite state included) is left as it was, for the solver.
  void step(const Input& in, const std::vector<int>& bodies, std::vector<Contact>& contacts, int substeps,
            std::vector<char>& rolled);

  // s, each body's next internal step (0: not rolling): part of the saved state, so that a resumed
  // run takes the same internal steps.
  const std::vector<double>& proposals() const { return h_; }
  void restore_proposals(std::vector<double> h) {
    h_ = std::move(h);
    last_.clear();
    for (int i = 0; i < (int)h_.size(); ++i)
      if (h_[i] > 0) last_.push_back(i);
  }

  static constexpr int kMaxFeet = 4;

 private:
  // A foot: where a smooth shape of the body touches a fixed flat surface (its support point
  // against the surface's normal n).
  struct Foot {
    const ShapeRecord* shape = nullptr;
    int end = 1;                  ///< capsule and cylinder: which end (+1 or -1 along z_C) touches
    Vec3 n = Vec3::UnitZ();       ///< the surface's normal, world, toward the body
    double offset = 0;            ///< m, n . P for the contact point P (the surface plus the kept gap)
    Vec3 impulse = Vec3::Zero();  ///< N s, on the body over the step (advance)
    Vec3 entry = Vec3::Zero();    ///< N s, the impulse that brought the body in
    double mu = 0;                ///< friction coefficient
    int contact = -1, point = 0;  ///< the manifold and its point
    bool body_is_a = true;
  };
  // The problem of one body: its feet, what acts on it, and the ODE's state
  // y = (q_WP (w, x, y, z), w_W, x_W, v_W).
  struct Problem {
    const BodyModel* m = nullptr;
    int feet = 0;    ///< standing feet, foot[0 .. feet)
    int lifted = 0;  ///< lifted ones after them (watched, no force)
    Foot foot[kMaxFeet];
    bool slide = false;       ///< regularised Coulomb friction (else no slip at one foot)
    double slip_speed = 0;    ///< m/s
    Vec3 f = Vec3::Zero();    ///< N, applied force (constant over the step)
    Vec3 tau = Vec3::Zero();  ///< N m, applied torque about G
    Vec3 g = Vec3::Zero();
  };
  static constexpr int kDim = 13;
  using Y = Eigen::Matrix<double, kDim, 1>;
  struct Rate {
    Y dy;
    Vec3 force[kMaxFeet];  ///< N, each foot's contact force on the body
    bool smooth = true;    ///< false: a foot left its shape's smooth part
  };
  static Y state_vector(const MotionState& s);  ///< y from a body's state
  // A foot's arm r = G - P, world, and the derivative of its support point (P frame).
  static bool contact_arm(const Foot& f, const Mat3& R, Vec3& r, Mat3* dP);
  static Rate rate(const Problem& p, const Y& y);
  static bool holds(const Problem& p, const Rate& k);
  static void lift_pulling_feet(Problem& p, const Y& y);
  static double landing_gap(const Problem& p, const Y& y, int* which);
  static bool land(Problem& p, Y& y, int landing);
  static bool impact(Problem& p, Y& y);
  static bool stages(const Problem& p, const Y& y0, Rate (&k)[7], double hs, Y& ys);
  static void project(const Problem& p, bool positions, Quat& q, Vec3& x, Vec3& v, Vec3& w);
  // One body's step: false if it may not roll (the state is left as it was).
  bool advance(Problem& p, MotionState& s, double dt, double tol, double& h);
  // m, a lifted foot lands this far below where it stood (the integrator's rounding is not a landing).
  static constexpr double kLandingSlack = 1e-9;

  std::vector<double> h_;
  std::vector<int> head_, link_;  ///< each body's touching contacts: a list through 2 ci + side
  std::vector<int> last_, now_;   ///< the bodies that rolled last step, and this step
};

}  // namespace simreel
