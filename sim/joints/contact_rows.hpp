// Contacts on jointed bodies (docs/joints.md, "Contacts"): rows of the contact solver written in
// joint coordinates. A contact point on a mechanism's body pushes the whole mechanism: its rate
// along a direction d is J q' with J = d^T J_v + (r x d)^T J_w (the link's world Jacobian), and
// an impulse P along it changes the joint velocities by W P, W = P_c J^T with P_c the joint-space
// inverse inertia that keeps the mechanism's loops and held coordinates (Featherstone ch. 11;
// Bullet's btMultiBody solves its contacts the same way). So a wrecking ball's chain, a pendulum's
// pivot or a car's suspension takes each impact through its true effective mass, and the joints
// stay exact: the impulse moves joint coordinates, never the bodies apart.
//
// A mechanism with contacts in a frame step is stepped inside the contact solver's substeps
// (semi-implicit Euler in joint coordinates, exact rotations) with the same soft contact, the
// same speculative gap, relax and restitution as free bodies; a mechanism whose contacts gave
// no impulse after all is handed back to its adaptive integrator for that step, which is exact
// for it. Rows are solved in a fixed order on the calling thread after each sweep of the free
// bodies' constraints (a mechanism couples all its bodies, so its rows cannot share a colour).
#pragma once
#include <vector>

#include "sim/collision/contact.hpp"
#include "sim/dynamics/state.hpp"
#include "sim/solver/contact_solver.hpp"

namespace simreel {

class Articulations;

class ArticulatedContacts {
 public:
  // The contacts with a jointed body on either side, from the step's list: rows made at the
  // step's start. `sb` are the contact solver's bodies (free bodies' velocities), `solver_index`
  // each body's solver body (0 for static bodies and jointed ones).
  void prepare(Articulations* art, const SolverInput& in, const std::vector<Contact>& contacts,
               const std::vector<int>& candidates, const std::vector<int>& solver_index,
               const std::vector<SolverBody>& sb, const Softness& soft, const Softness& static_soft);
  bool empty() const { return rows_.empty(); }
  void integrate_velocities(double h);
  void warm_start(std::vector<SolverBody>& sb);
  void solve(std::vector<SolverBody>& sb, double h, bool use_bias);
  void integrate_positions(double h, const std::vector<SolverBody>& sb);
  void restitution(std::vector<SolverBody>& sb, double threshold);
  void store(std::vector<Contact>& contacts) const;
  // Free bodies that an articulated row pushed: touched (their solved motion is kept).
  void touched(std::vector<char>& touched_none) const;
  // Mechanisms that an articulated row pushed take the substeps' result (q, q', the bodies'
  // states) and are marked Mechanism::contact_stepped, so that the joints stage leaves them; the
  // others keep their start state for the adaptive integrator.
  void finish(MotionState* state);

 private:
  struct Side {
    int mech = -1, link = -1;   ///< a mechanism's link, or
    int body = 0;               ///< a free body's solver body (0: static)
    Vec3 r = Vec3::Zero();      ///< m, anchor from the centre of mass, world, at the step's start
    Vec3 local = Vec3::Zero();  ///< m, anchor in the link frame (mechanism)
    Vec3 p0 = Vec3::Zero();     ///< m, anchor in the world at the step's start
  };
  struct Row {
    int contact = -1, point = 0;
    Side a, b;
    Vec3 d[3];    ///< normal, two tangents
    int j[3][2];  ///< offsets of J (and W) for each direction and side in jw_ (-1: none)
    double mass[3] = {0, 0, 0};
    double lambda[3] = {0, 0, 0};
    double s0 = 0, s = 0;  ///< m, separation at the step's start, and now
    double friction = 0, restitution = 0;
    double vn_prev = 0, max_normal = 0;
    bool bounced = false;
    Softness soft;
  };
  // Rate of the row's direction k (B's point minus A's), and an impulse P along it.
  double rate(const Row& r, int k, const std::vector<SolverBody>& sb) const;
  void apply(Row& r, int k, double P, std::vector<SolverBody>& sb);
  void normal(Row& r, std::vector<SolverBody>& sb, double h, bool use_bias);
  void tangents(Row& r, std::vector<SolverBody>& sb);
  Vec3 anchor(const Side& s, const std::vector<SolverBody>& sb) const;  ///< now, world
  void masses(Row& r, const std::vector<SolverBody>& sb);  ///< W = P J^T and the effective masses
  Articulations* art_ = nullptr;
  SolverInput in_;
  std::vector<Row> rows_;
  std::vector<double> jw_;     ///< J then W (nv each) per direction and mechanism side
  std::vector<int> mechs_;     ///< mechanisms with rows this step, ascending
  std::vector<char> pushed_;   ///< per mechanism: some row pushed it this step
  std::vector<char> changed_;  ///< per mechanism: its held rows changed in this substep
};

}  // namespace simreel
