// Joints: simreel's mechanisms in joint coordinates (Featherstone's articulated-body algorithm,
// adaptive Dormand-Prince 5(4)) against MuJoCo 2.2.2 (RK4, Euler) and Bullet 3.24 double precision
// (btHingeConstraint world, btMultiBody) in the same run, on identical planar scenes with identical
// mass properties, no damping, sleeping off. CSV on stdout; bench/README.md quotes it.
//
//   work_precision  double pendulum released horizontal (60 s) and the 100-link chain with a 1000:1
//                   end mass released from 30 degrees (10 s; MuJoCo 90 links, its XML parser's
//                   nesting limit): run time (median of 3; a run of 4 s or more is timed once)
//                   against the energy error, the state error at 2 s and the summed joint gaps.
//                   simreel sweeps its tolerance at dt = 1/60; the others sweep dt.
//   pendulum        one bob at 10 / 90 / 170 degrees: first-period error and energy over 60 s.
//   throughput      1000 double pendulums in one world, 100 chains of 20 links in one world:
//                   body-steps per second at dt = 1/60 (one thread everywhere).
//
// Every scene is a planar tree of links hinged about world y, gravity along -z. A link: mass m,
// isotropic inertia I about its centre of mass, pivot -> next pivot l, pivot -> centre c.
// Angles phi (rad) are absolute, from the downward vertical, positive about +y.
// `--quick`: fewer settings, shorter runs, one timed run (a smoke test, a few tens of seconds).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <simreel/simreel.hpp>

#include "bench/bench_util.hpp"
#include "tests/fixtures/joint_reference.hpp"

#ifdef SIMREEL_BENCH_MUJOCO
#include <mujoco/mujoco.h>
#endif
#ifdef SIMREEL_BENCH_BULLET
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyLink.h>
#include <btBulletDynamicsCommon.h>
#endif

using namespace simreel;

namespace {

constexpr double kG = 9.81;
constexpr double kPi = std::numbers::pi;

// ------------------------------------------------------------------------------------------------
// Scenes
// ------------------------------------------------------------------------------------------------
struct Link {
  double m;  ///< kg
  double I;  ///< kg m^2, isotropic, about the centre of mass
  double l;  ///< m, pivot -> next pivot
  double c;  ///< m, pivot -> centre of mass
};
struct Scene {
  std::vector<Link> links;
  std::vector<double> phi0;  ///< rad, absolute start angles; released at rest
  /// m, the pivot's offset along the hinge axis: scenes sharing a world are set apart so that no
  /// two bodies' bounding boxes overlap (Bullet's broad phase would otherwise find, and filter out,
  /// every pair of neighbours); it changes nothing in a planar motion.
  double y = 0;
};

// Unit direction of a link at absolute angle phi: R_y(phi) (0, 0, -1) = (-sin phi, 0, -cos phi).
Vec3 dir(double phi) {
  return Vec3(-std::sin(phi), 0, -std::cos(phi));
}

Scene pendulum(double theta0) {
  return {{{1, 1e-3, 1, 1}}, {theta0}};
}
Scene double_pendulum(double phi = kPi / 2) {
  return {{{1, 1e-3, 1, 1}, {1, 1e-3, 1, 1}}, {phi, phi}};
}
// n rods of length l and mass ml (inertia ml l^2 / 12 about the centre, taken isotropic as the
// anchors did; only the moment about the hinge axis enters a planar motion), the last carrying a
// point mass ratio * ml at its free end (merged into that link, as tests/sim/joints/ does),
// released straight at `tilt`.
Scene chain(int n, double ratio, double tilt, double l = 0.1, double ml = 0.01) {
  Scene s;
  for (int i = 0; i < n; ++i) {
    Link k{ml, ml * l * l / 12, l, 0.5 * l};
    if (i == n - 1 && ratio > 0) {
      const double M = ratio * ml;
      k.c = (ml * 0.5 * l + M * l) / (ml + M);
      k.I = ml * l * l / 12 + ml * std::pow(0.5 * l - k.c, 2) + M * std::pow(l - k.c, 2);
      k.m = ml + M;
    }
    s.links.push_back(k);
    s.phi0.push_back(tilt);
  }
  return s;
}
double total_mass(const Scene& s) {
  double M = 0;
  for (const Link& k : s.links) M += k.m;
  return M;
}
double chain_energy_scale(const Scene& s) {
  return total_mass(s) * kG * (double)s.links.size() * s.links[0].l;
}

// Energy (J) of a planar chain from its absolute angles and rates: the same formula for every
// engine that exposes joint coordinates.
[[maybe_unused]] double planar_energy(const Scene& s, const double* phi, const double* phid) {
  double pz = 0, vx = 0, vz = 0, E = 0;
  for (size_t k = 0; k < s.links.size(); ++k) {
    const Link& L = s.links[k];
    const double uz = -std::cos(phi[k]);
    const double dux = -std::cos(phi[k]) * phid[k], duz = std::sin(phi[k]) * phid[k];
    const double cvx = vx + L.c * dux, cvz = vz + L.c * duz, cz = pz + L.c * uz;
    E += 0.5 * L.m * (cvx * cvx + cvz * cvz) + 0.5 * L.I * phid[k] * phid[k] + L.m * kG * cz;
    pz += L.l * uz;
    vx += L.l * dux;
    vz += L.l * duz;
  }
  return E;
}

double wrap(double a) {
  return std::remainder(a, 2 * kPi);
}

// ------------------------------------------------------------------------------------------------
// One interface over the engines. A Sim holds `copies` independent scenes in one world.
// ------------------------------------------------------------------------------------------------
class Sim {
 public:
  virtual ~Sim() = default;
  virtual void step() = 0;
  virtual bool failed() = 0;  ///< the engine stopped (simreel), reset itself (MuJoCo) or went non-finite
  /// Absolute angles and rates of scene c's links (rad, rad/s).
  virtual void angles(int c, double* phi, double* phid) = 0;
  virtual double energy(int c) = 0;   ///< J
  virtual double gap_sum(int c) = 0;  ///< m, summed distances between each joint's two anchor points
  virtual double internal_steps() { return NAN; }

 protected:
  // The energy of a reduced-coordinate engine's scene c from its joint angles and rates.
  double energy_from_angles(int c, const Scene& s) {
    const size_t n = s.links.size();
    std::vector<double> phi(n), phid(n);
    angles(c, phi.data(), phid.data());
    return planar_energy(s, phi.data(), phid.data());
  }
};

// ---------------------------------------------------------------- simreel
class SimreelSim : public Sim {
 public:
  SimreelSim(const std::vector<Scene>& scenes, double dt, const JointSettings& js) : scenes_(scenes) {
    WorldConfig cfg;
    cfg.dt = dt;
    cfg.gravity = Vec3(0, 0, -kG);
    cfg.threads = 1;
    cfg.contacts.sleep = false;
    cfg.joint_settings = js;
    std::vector<BodyDef> bodies;
    for (size_t c = 0; c < scenes.size(); ++c) {
      const Scene& s = scenes[c];
      base_.push_back((int)bodies.size());
      Vec3 p(0, s.y, 0);
      for (size_t k = 0; k < s.links.size(); ++k) {
        const Link& L = s.links[k];
        const Vec3 u = dir(s.phi0[k]);
        BodyDef b;
        b.name = "s" + std::to_string(c) + "_" + std::to_string(k);
        b.p_WB = p + L.c * u;  // body origin at the centre of mass, body axes = world axes
        Collider col = sphere_collider(0.01, 1000);
        col.collide = false;  // mass properties are stated below; the shape never touches anything
        b.colliders.push_back(col);
        b.mass_override = MassProperties{L.m, Vec3::Zero(), L.I * Mat3::Identity()};
        JointDef j;
        j.name = "j" + b.name;
        j.type = JointType::revolute;
        j.parent = k == 0 ? -1 : (int)bodies.size() - 1;
        j.child = (int)bodies.size();
        j.anchor_W = p;
        j.axis_W = Vec3::UnitY();
        cfg.joints.push_back(j);
        pivot_B_.push_back(-L.c * u);       // this joint's anchor in the child's frame
        tip_B_.push_back((L.l - L.c) * u);  // the next joint's anchor in this body's frame
        bodies.push_back(std::move(b));
        p += L.l * u;
      }
    }
    w_ = std::make_unique<World>(cfg, std::move(bodies));
    frames_ = 0;
  }
  void step() override {
    if (failed_) return;
    try {
      w_->step();
      ++frames_;
    } catch (const std::exception&) {
      failed_ = true;
    }
  }
  bool failed() override { return failed_; }
  void angles(int c, double* phi, double* phid) override {
    const Scene& s = scenes_[c];
    double a = 0, ad = 0;
    for (size_t k = 0; k < s.links.size(); ++k) {
      a += w_->joint_position(base_[c] + (int)k);  // relative coordinates: the hinge axes are parallel
      ad += w_->joint_speed(base_[c] + (int)k);
      phi[k] = s.phi0[k] + a;
      phid[k] = ad;
    }
  }
  double energy(int c) override {  // from the bodies' states
    const Scene& s = scenes_[c];
    double E = 0;
    for (size_t k = 0; k < s.links.size(); ++k) {
      const int i = base_[c] + (int)k;
      E += 0.5 * s.links[k].m * w_->linear_velocity(i).squaredNorm() +
           0.5 * s.links[k].I * w_->angular_velocity(i).squaredNorm() +
           s.links[k].m * kG * w_->centroid(i).z();
    }
    return E;
  }
  double gap_sum(int c) override {
    const Scene& s = scenes_[c];
    double sum = 0;
    for (size_t k = 0; k < s.links.size(); ++k) {
      const int i = base_[c] + (int)k;
      const Vec3 a = w_->local_to_world(i, pivot_B_[i]);
      const Vec3 b = k == 0 ? Vec3(0, s.y, 0) : w_->local_to_world(i - 1, tip_B_[i - 1]);
      sum += (a - b).norm();
    }
    return sum;
  }
  double internal_steps() override { return frames_ ? (double)w_->profile().joint_steps / frames_ : NAN; }

 private:
  std::vector<Scene> scenes_;
  std::vector<int> base_;
  std::vector<Vec3> pivot_B_, tip_B_;
  std::unique_ptr<World> w_;
  long frames_ = 0;
  bool failed_ = false;
};

// ---------------------------------------------------------------- MuJoCo 2.2.2
#ifdef SIMREEL_BENCH_MUJOCO
// One model, every scene a tree of nested bodies from the world (all scenes overlap; contacts are
// disabled). Link k: a body at its pivot with a hinge about y there and an explicit inertial
// (mass, centre c below the pivot, diagonal inertia): no geoms, so nothing is inferred.
std::string mj_num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}
std::string mujoco_xml(const std::vector<Scene>& scenes, double dt, const std::string& integrator) {
  std::string x = "<mujoco><option timestep='" + mj_num(dt) + "' integrator='" + integrator +
                  "' gravity='0 0 " + mj_num(-kG) + "'><flag contact='disable'/></option><worldbody>";
  for (const Scene& s : scenes) {
    for (size_t k = 0; k < s.links.size(); ++k) {
      const Link& L = s.links[k];
      x += "<body pos='0 " + mj_num(k == 0 ? s.y : 0.0) + " " + mj_num(k == 0 ? 0.0 : -s.links[k - 1].l) +
           "'><joint type='hinge' axis='0 1 0' pos='0 0 0' damping='0' armature='0'/><inertial pos='0 0 " +
           mj_num(-L.c) + "' mass='" + mj_num(L.m) + "' diaginertia='" + mj_num(L.I) + " " + mj_num(L.I) +
           " " + mj_num(L.I) + "'/>";
    }
    for (size_t k = 0; k < s.links.size(); ++k) x += "</body>";
  }
  return x + "</worldbody></mujoco>";
}
class MujocoModel {
 public:
  explicit MujocoModel(const std::string& x) : xml(x) {
    auto vfs = std::make_unique<mjVFS>();
    mj_defaultVFS(vfs.get());
    mj_makeEmptyFileVFS(vfs.get(), "joints_bench.xml", (int)x.size());
    std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), "joints_bench.xml")], x.data(), x.size());
    char err[1000] = "";
    m_ = mj_loadXML("joints_bench.xml", vfs.get(), err, sizeof err);
    mj_deleteVFS(vfs.get());
    if (!m_) {
      std::fprintf(stderr, "MuJoCo: %s\n", err);
      std::exit(1);
    }
  }
  ~MujocoModel() { mj_deleteModel(m_); }
  MujocoModel(const MujocoModel&) = delete;
  MujocoModel& operator=(const MujocoModel&) = delete;
  std::string xml;
  mjModel* m_ = nullptr;
};

class MujocoSim : public Sim {
 public:
  MujocoSim(const std::vector<Scene>& scenes, const MujocoModel& model) : scenes_(scenes), m_(model.m_) {
    d_ = mj_makeData(m_);
    int i = 0;
    for (const Scene& s : scenes) {
      base_.push_back(i);
      for (size_t k = 0; k < s.links.size(); ++k, ++i) d_->qpos[i] = s.phi0[k] - (k ? s.phi0[k - 1] : 0.0);
    }
  }
  ~MujocoSim() override { mj_deleteData(d_); }
  void step() override { mj_step(m_, d_); }
  bool failed() override {
    // MuJoCo resets the state to qpos0 when an acceleration stops being finite: the warning
    // counters are the only trace of it.
    return d_->warning[mjWARN_BADQACC].number > 0 || d_->warning[mjWARN_BADQPOS].number > 0 ||
           d_->warning[mjWARN_BADQVEL].number > 0;
  }
  void angles(int c, double* phi, double* phid) override {
    double a = 0, ad = 0;
    for (size_t k = 0; k < scenes_[c].links.size(); ++k) {
      a += d_->qpos[base_[c] + k];
      ad += d_->qvel[base_[c] + k];
      phi[k] = a;
      phid[k] = ad;
    }
  }
  double energy(int c) override { return energy_from_angles(c, scenes_[c]); }
  double gap_sum(int c) override {  // from MuJoCo's own body frames (mj_kinematics)
    mj_kinematics(m_, d_);
    const Scene& s = scenes_[c];
    double sum = 0;
    for (size_t k = 0; k < s.links.size(); ++k) {
      const int b = 1 + base_[c] + (int)k;
      double e[3] = {0, s.y, 0};
      if (k > 0) {
        const mjtNum* p = d_->xpos + 3 * (b - 1);
        const mjtNum* R = d_->xmat + 9 * (b - 1);
        const double off = -s.links[k - 1].l;
        for (int r = 0; r < 3; ++r) e[r] = p[r] + R[3 * r + 2] * off;
      }
      const mjtNum* a = d_->xpos + 3 * b;
      sum += std::sqrt((a[0] - e[0]) * (a[0] - e[0]) + (a[1] - e[1]) * (a[1] - e[1]) +
                       (a[2] - e[2]) * (a[2] - e[2]));
    }
    return sum;
  }

 private:
  std::vector<Scene> scenes_;
  std::vector<int> base_;
  mjModel* m_;
  mjData* d_;
};
#endif

// ---------------------------------------------------------------- Bullet 3.24 double precision
#ifdef SIMREEL_BENCH_BULLET
// Maximal coordinates: a btRigidBody per link (centre of mass at its origin, isotropic inertia,
// a 1 cm sphere in collision group 0 with mask 0: never tested), a btHingeConstraint per joint
// (to the world for the first link), the sequential-impulse solver with `iterations`, default
// ERP; deactivation off, no damping (Bullet's default for rigid bodies).
class BulletHingeSim : public Sim {
 public:
  BulletHingeSim(const std::vector<Scene>& scenes, double dt, int iterations) : scenes_(scenes), dt_(dt) {
    w_.setGravity(btVector3(0, 0, -kG));
    w_.getSolverInfo().m_numIterations = iterations;
    for (const Scene& s : scenes) {
      base_.push_back((int)bodies_.size());
      Vec3 p(0, s.y, 0);
      for (size_t k = 0; k < s.links.size(); ++k) {
        const Link& L = s.links[k];
        const Vec3 u = dir(s.phi0[k]);
        const Vec3 com = p + L.c * u;
        btRigidBody::btRigidBodyConstructionInfo ci(L.m, nullptr, &shape_, btVector3(L.I, L.I, L.I));
        ci.m_startWorldTransform.setIdentity();
        ci.m_startWorldTransform.setOrigin(btVector3(com.x(), com.y(), com.z()));
        auto b = std::make_unique<btRigidBody>(ci);
        b->setActivationState(DISABLE_DEACTIVATION);
        w_.addRigidBody(b.get(), 0, 0);
        const btVector3 pivB(-L.c * u.x(), 0, -L.c * u.z());
        std::unique_ptr<btHingeConstraint> h;
        if (k == 0) {
          h = std::make_unique<btHingeConstraint>(*b, pivB, btVector3(0, 1, 0));
          pivA_.push_back(btVector3(p.x(), p.y(), p.z()));
        } else {
          const Link& P = s.links[k - 1];
          const Vec3 up = dir(s.phi0[k - 1]);
          const btVector3 pivA((P.l - P.c) * up.x(), 0, (P.l - P.c) * up.z());
          h = std::make_unique<btHingeConstraint>(*bodies_.back(), *b, pivA, pivB, btVector3(0, 1, 0),
                                                  btVector3(0, 1, 0));
          pivA_.push_back(pivA);
        }
        pivB_.push_back(pivB);
        w_.addConstraint(h.get(), true);
        u0_.push_back(btVector3(u.x(), u.y(), u.z()));
        bodies_.push_back(std::move(b));
        joints_.push_back(std::move(h));
        p += L.l * u;
      }
    }
  }
  ~BulletHingeSim() override {
    for (auto& j : joints_) w_.removeConstraint(j.get());
    for (auto& b : bodies_) w_.removeRigidBody(b.get());
  }
  void step() override { w_.stepSimulation(dt_, 0); }
  bool failed() override { return false; }  // judged from the energy
  void angles(int c, double* phi, double* phid) override {
    for (size_t k = 0; k < scenes_[c].links.size(); ++k) {
      const btRigidBody& b = *bodies_[base_[c] + k];
      const btVector3 d = b.getCenterOfMassTransform().getBasis() * u0_[base_[c] + k];
      phi[k] = std::atan2(-d.x(), -d.z());  // in (-pi, pi]
      phid[k] = b.getAngularVelocity().y();
    }
  }
  double energy(int c) override {
    double E = 0;
    for (size_t k = 0; k < scenes_[c].links.size(); ++k) {
      const Link& L = scenes_[c].links[k];
      const btRigidBody& b = *bodies_[base_[c] + k];
      E += 0.5 * L.m * b.getLinearVelocity().length2() + 0.5 * L.I * b.getAngularVelocity().length2() +
           L.m * kG * b.getCenterOfMassPosition().z();
    }
    return E;
  }
  double gap_sum(int c) override {
    double sum = 0;
    for (size_t k = 0; k < scenes_[c].links.size(); ++k) {
      const int i = base_[c] + (int)k;
      const btVector3 a = bodies_[i]->getCenterOfMassTransform() * pivB_[i];
      const btVector3 b = k == 0 ? pivA_[i] : bodies_[i - 1]->getCenterOfMassTransform() * pivA_[i];
      sum += (a - b).length();
    }
    return sum;
  }

 private:
  std::vector<Scene> scenes_;
  double dt_;
  btDefaultCollisionConfiguration cc_;
  btCollisionDispatcher disp_{&cc_};
  btDbvtBroadphase bp_;
  btSequentialImpulseConstraintSolver solver_;
  btDiscreteDynamicsWorld w_{&disp_, &bp_, &solver_, &cc_};
  btSphereShape shape_{0.01};
  std::vector<int> base_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
  std::vector<std::unique_ptr<btHingeConstraint>> joints_;
  std::vector<btVector3> pivA_, pivB_, u0_;
};

// Reduced coordinates: one btMultiBody per scene (Featherstone's ABA), fixed base at the origin,
// revolute links about y, no colliders; damping 0 (default 0.04), maxCoordinateVelocity off
// (default 100 rad/s), sleeping off.
class BulletMultiBodySim : public Sim {
 public:
  BulletMultiBodySim(const std::vector<Scene>& scenes, double dt) : scenes_(scenes), dt_(dt) {
    w_.setGravity(btVector3(0, 0, -kG));
    for (const Scene& s : scenes) {
      const int n = (int)s.links.size();
      auto mb = std::make_unique<btMultiBody>(n, 0, btVector3(0, 0, 0), true, false);
      mb->setBaseWorldTransform(btTransform(btQuaternion(0, 0, 0, 1), btVector3(0, s.y, 0)));
      mb->setLinearDamping(0);
      mb->setAngularDamping(0);
      mb->setMaxCoordinateVelocity(1e30);
      mb->setCanSleep(false);
      mb->setHasSelfCollision(false);
      for (int k = 0; k < n; ++k) {
        const Link& L = s.links[k];
        const btVector3 parentComToPivot =
            k == 0 ? btVector3(0, 0, 0) : btVector3(0, 0, -(s.links[k - 1].l - s.links[k - 1].c));
        mb->setupRevolute(k, L.m, btVector3(L.I, L.I, L.I), k - 1, btQuaternion(0, 0, 0, 1),
                          btVector3(0, 1, 0), parentComToPivot, btVector3(0, 0, -L.c), true);
      }
      mb->finalizeMultiDof();
      for (int k = 0; k < n; ++k) mb->setJointPos(k, s.phi0[k] - (k ? s.phi0[k - 1] : 0.0));
      w_.addMultiBody(mb.get());
      mbs_.push_back(std::move(mb));
    }
  }
  ~BulletMultiBodySim() override {
    for (auto& mb : mbs_) w_.removeMultiBody(mb.get());
  }
  void step() override { w_.stepSimulation(dt_, 0); }
  bool failed() override { return false; }
  void angles(int c, double* phi, double* phid) override {
    double a = 0, ad = 0;
    for (size_t k = 0; k < scenes_[c].links.size(); ++k) {
      a += mbs_[c]->getJointPos((int)k);
      ad += mbs_[c]->getJointVel((int)k);
      phi[k] = a;
      phid[k] = ad;
    }
  }
  double energy(int c) override { return energy_from_angles(c, scenes_[c]); }
  double gap_sum(int c) override {  // from Bullet's own link frames (forwardKinematics)
    btMultiBody& mb = *mbs_[c];
    btAlignedObjectArray<btQuaternion> w2l;
    btAlignedObjectArray<btVector3> org;
    mb.forwardKinematics(w2l, org);
    const Scene& s = scenes_[c];
    double sum = 0;
    for (int k = 0; k < (int)s.links.size(); ++k) {
      const btVector3 a = mb.getLink(k).m_cachedWorldTransform * btVector3(0, 0, s.links[k].c);
      const btVector3 b = k == 0 ? btVector3(0, s.y, 0)
                                 : mb.getLink(k - 1).m_cachedWorldTransform *
                                       btVector3(0, 0, -(s.links[k - 1].l - s.links[k - 1].c));
      sum += (a - b).length();
    }
    return sum;
  }

 private:
  std::vector<Scene> scenes_;
  double dt_;
  btDefaultCollisionConfiguration cc_;
  btCollisionDispatcher disp_{&cc_};
  btDbvtBroadphase bp_;
  btMultiBodyConstraintSolver solver_;
  btMultiBodyDynamicsWorld w_{&disp_, &bp_, &solver_, &cc_};
  std::vector<std::unique_ptr<btMultiBody>> mbs_;
};
#endif

// ------------------------------------------------------------------------------------------------
// Engines and settings
// ------------------------------------------------------------------------------------------------
struct Config {
  std::string engine, method, setting;
  double dt = 1.0 / 60;
  double tol = NAN;  ///< simreel only
  bool built = true;
  std::function<std::unique_ptr<Sim>(const std::vector<Scene>&)> make;
};

Config simreel_cfg(double tol, double dt = 1.0 / 60) {
  char s[64];
  std::snprintf(s, sizeof s, "tol=%.0e", tol);
  Config c{"simreel", "ABA+DOPRI5(4)", s, dt, tol, true, nullptr};
  JointSettings js;
  js.tolerance = tol;
  c.make = [dt, js](const std::vector<Scene>& sc) { return std::make_unique<SimreelSim>(sc, dt, js); };
  return c;
}
// Velocity Verlet, `substeps` steps a frame (0: chosen from the fastest mode).
Config simreel_verlet_cfg(int substeps, int per_second = 60) {
  const std::string s = substeps > 0
                            ? "dt=1/" + std::to_string(per_second) + " substeps=" + std::to_string(substeps)
                            : "dt=1/" + std::to_string(per_second) + " substeps=auto";
  const double dt = 1.0 / per_second;
  Config c{"simreel", "ABA+Verlet(2)", s, dt, NAN, true, nullptr};
  JointSettings js;
  js.integrator = JointIntegrator::verlet;
  js.substeps = substeps;
  c.make = [dt, js](const std::vector<Scene>& sc) { return std::make_unique<SimreelSim>(sc, dt, js); };
  return c;
}
std::string dt_setting(int dtinv) {
  return "dt=1/" + std::to_string(dtinv);
}

Config mujoco_cfg(const char* integ, int dtinv) {
  Config c{"mujoco", integ, dt_setting(dtinv), 1.0 / dtinv, NAN, false, nullptr};
#ifdef SIMREEL_BENCH_MUJOCO
  c.built = true;
  const double dt = 1.0 / dtinv;
  // The model is compiled once per scene list (its XML) and shared by the runs.
  auto cache = std::make_shared<std::unique_ptr<MujocoModel>>();
  std::string in = integ;
  c.make = [dt, in, cache](const std::vector<Scene>& sc) -> std::unique_ptr<Sim> {
    const std::string x = mujoco_xml(sc, dt, in);
    if (!*cache || (*cache)->xml != x) *cache = std::make_unique<MujocoModel>(x);
    return std::make_unique<MujocoSim>(sc, **cache);
  };
#endif
  return c;
}
Config bullet_hinge_cfg(int dtinv, int iterations = 10) {
  Config c{"bullet", "hinge", dt_setting(dtinv) + " iters=" + std::to_string(iterations), 1.0 / dtinv, NAN,
           false,    nullptr};
#ifdef SIMREEL_BENCH_BULLET
  c.built = true;
  const double dt = 1.0 / dtinv;
  c.make = [dt, iterations](const std::vector<Scene>& sc) {
    return std::make_unique<BulletHingeSim>(sc, dt, iterations);
  };
#endif
  return c;
}
Config bullet_mb_cfg(int dtinv) {
  Config c{"bullet", "multibody", dt_setting(dtinv), 1.0 / dtinv, NAN, false, nullptr};
#ifdef SIMREEL_BENCH_BULLET
  c.built = true;
  const double dt = 1.0 / dtinv;
  c.make = [dt](const std::vector<Scene>& sc) { return std::make_unique<BulletMultiBodySim>(sc, dt); };
#endif
  return c;
}

// ------------------------------------------------------------------------------------------------
// Output
// ------------------------------------------------------------------------------------------------
struct Row {
  std::string section, scene, engine, method, setting;
  double dt_inv = NAN;
  int links = 0, timed_runs = 0;
  double run_s = NAN, cpu_s = NAN, internal_steps = NAN, max_abs_dE = NAN, dE_end = NAN, state_err = NAN,
         gap_sum = NAN, period_relerr = NAN, body_steps_per_s = NAN;
  std::string status = "ok";
};
std::vector<Row> g_rows;

std::string fmt(double v, const char* f = "%.3e") {
  if (std::isnan(v)) return "";
  char b[40];
  std::snprintf(b, sizeof b, f, v);
  return b;
}
void print_header() {
  std::printf(
      "section,scene,engine,method,setting,dt_inv,links,run_s,cpu_s,timed_runs,internal_steps_per_frame,max_"
      "abs_dE,dE_end,"
      "state_err_rad,gap_sum_m,period_relerr,body_steps_per_s,status\n");
}
void emit(const Row& r) {
  std::printf("%s,%s,%s,%s,%s,%s,%d,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s\n", r.section.c_str(), r.scene.c_str(),
              r.engine.c_str(), r.method.c_str(), r.setting.c_str(), fmt(r.dt_inv, "%.0f").c_str(), r.links,
              fmt(r.run_s, "%.4e").c_str(), fmt(r.cpu_s, "%.4e").c_str(),
              r.timed_runs ? std::to_string(r.timed_runs).c_str() : "", fmt(r.internal_steps, "%.2f").c_str(),
              fmt(r.max_abs_dE).c_str(), fmt(r.dE_end, "%+.3e").c_str(), fmt(r.state_err).c_str(),
              fmt(r.gap_sum).c_str(), fmt(r.period_relerr, "%+.3e").c_str(), fmt(r.body_steps_per_s).c_str(),
              r.status.c_str());
  std::fflush(stdout);
  g_rows.push_back(r);
}
Row row_for(const std::string& section, const std::string& scene, const Config& c, int links) {
  Row r;
  r.section = section;
  r.scene = scene;
  r.engine = c.engine;
  r.method = c.method;
  r.setting = c.setting;
  r.dt_inv = std::round(1 / c.dt);
  r.links = links;
  if (!c.built) r.status = "not built";
  return r;
}

// A measured run (errors every frame) is timed too. When it took under 4 s, `reps` more runs that
// only step are timed and the row quotes their median (construction is never timed); a longer
// run is quoted alone (the chains and throughput: there the per-frame read-outs cost well under
// 1% of a step). Wall and thread-CPU seconds of the same runs.
struct Clock {
  double wall0 = bench::now_s(), cpu0 = bench::thread_cpu_s();
  double wall() const { return bench::now_s() - wall0; }
  double cpu() const { return bench::thread_cpu_s() - cpu0; }
};
void time_stepping(Row& r, const Config& c, const std::vector<Scene>& scenes, long frames, int reps,
                   double measured_wall, double measured_cpu) {
  if (measured_wall >= 4.0 || reps <= 0) {
    r.run_s = measured_wall;
    r.cpu_s = measured_cpu;
    r.timed_runs = 1;
    return;
  }
  std::vector<double> tw, tc;
  for (int k = 0; k < reps; ++k) {
    std::unique_ptr<Sim> sim = c.make(scenes);
    const Clock clk;
    for (long i = 0; i < frames; ++i) sim->step();
    tw.push_back(clk.wall());
    tc.push_back(clk.cpu());
  }
  std::sort(tw.begin(), tw.end());
  std::sort(tc.begin(), tc.end());
  r.run_s = tw[tw.size() / 2];
  r.cpu_s = tc[tc.size() / 2];
  r.timed_runs = reps;
}

struct Options {
  bool quick = false;
  int reps = 3;
};

// ------------------------------------------------------------------------------------------------
// 1. Work-precision
// ------------------------------------------------------------------------------------------------
void wp_double_pendulum(const std::vector<Config>& configs, const Options& o) {
  const double T = o.quick ? 10 : 60;
  const std::vector<Scene> sc{double_pendulum()};
  const ref::PendulumLink link{1, 1, 1e-3, 1};
  const ref::DoublePendulum dp(link, link, kG);
  ref::DoublePendulumTrajectory traj(dp, ref::DoublePendulumState{kPi / 2, kPi / 2, 0, 0});
  const ref::DoublePendulumState r2 = traj.sample(2.0);
  const double mgL = kG;
  for (const Config& c : configs) {
    Row r = row_for("work_precision", "double_pendulum", c, 2);
    if (!c.built) {
      emit(r);
      continue;
    }
    const long frames = std::lround(T / c.dt), at2 = std::lround(2.0 / c.dt);
    std::unique_ptr<Sim> sim = c.make(sc);
    const double E0 = sim->energy(0);
    double worst = 0;
    const Clock clk;
    for (long i = 1; i <= frames; ++i) {
      sim->step();
      const double dE = sim->energy(0) - E0;
      if (sim->failed() || !std::isfinite(dE)) {
        r.status = "diverged at t=" + fmt(i * c.dt, "%.2f");
        break;
      }
      worst = std::max(worst, std::abs(dE));
      r.dE_end = dE / mgL;
      if (i == at2) {
        double phi[2], phid[2];
        sim->angles(0, phi, phid);
        r.state_err = std::max(std::abs(wrap(phi[0] - r2.theta1)), std::abs(wrap(phi[1] - r2.theta2)));
      }
    }
    const double mw = clk.wall(), mc = clk.cpu();
    r.internal_steps = sim->internal_steps();
    sim.reset();
    if (r.status == "ok") {
      r.max_abs_dE = worst / mgL;
      time_stepping(r, c, sc, frames, o.reps, mw, mc);
    } else {
      r.dE_end = NAN;
    }
    emit(r);
  }
}

void wp_chain(const std::string& scene_name, int n, const std::vector<Config>& configs, const Options& o) {
  const double T = o.quick ? 2 : 10;
  const std::vector<Scene> sc{chain(n, 1000, kPi / 6)};
  const double scale = chain_energy_scale(sc[0]);
  for (const Config& c : configs) {
    Row r = row_for("work_precision", scene_name, c, n);
    if (!c.built) {
      emit(r);
      continue;
    }
    const long frames = std::lround(T / c.dt);
    std::unique_ptr<Sim> sim = c.make(sc);
    const double E0 = sim->energy(0);
    double worst = 0;
    const Clock clk;
    for (long i = 1; i <= frames; ++i) {
      sim->step();
      const double dE = sim->energy(0) - E0;
      // Diverged: the engine said so, or the state is not finite, or the energy moved by more than
      // the chain's whole potential energy scale (a conservative system cannot).
      if (sim->failed() || !std::isfinite(dE) || std::abs(dE) > scale) {
        r.status = "diverged at t=" + fmt(i * c.dt, "%.2f");
        break;
      }
      worst = std::max(worst, std::abs(dE));
      r.dE_end = dE / scale;
    }
    const double mw = clk.wall(), mc = clk.cpu();
    r.internal_steps = sim->internal_steps();
    if (r.status == "ok") {
      r.max_abs_dE = worst / scale;
      r.gap_sum = sim->gap_sum(0);
      // Torn: the joints have opened by more, summed, than the chain is long.
      if (r.gap_sum > n * sc[0].links[0].l) r.status = "torn";
      sim.reset();
      time_stepping(r, c, sc, frames, o.reps, mw, mc);
    } else {
      r.dE_end = NAN;
    }
    emit(r);
  }
}

// ------------------------------------------------------------------------------------------------
// 2. Pendulum: the first period between two upward zero crossings of theta (as the anchors), each
// crossing located on the cubic Hermite interpolant of (theta, theta') at the two frames around
// it (its error at a crossing, where theta'' = 0, is O(h^5): 1e-10 of the period at 1/60 s,
// below what linear interpolation gives, 1e-6 at 170 degrees); energy over 60 s.
// ------------------------------------------------------------------------------------------------
double hermite_root(double h, double y0, double d0, double y1, double d1) {
  auto p = [&](double s) {
    const double s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * y0 + (s3 - 2 * s2 + s) * h * d0 + (-2 * s3 + 3 * s2) * y1 +
           (s3 - s2) * h * d1;
  };
  double a = 0, b = 1;  // p(a) < 0 <= p(b)
  for (int i = 0; i < 80; ++i) {
    const double m = 0.5 * (a + b);
    (p(m) < 0 ? a : b) = m;
  }
  return 0.5 * (a + b) * h;
}

void pendulum_section(const std::vector<Config>& configs, const Options& o) {
  const double Tend = o.quick ? 10 : 60;
  for (double deg : {10.0, 90.0, 170.0}) {
    const double th0 = deg * kPi / 180;
    const std::vector<Scene> sc{pendulum(th0)};
    const double Tex = ref::pendulum_period(th0, 1e-3 + 1, 1, kG, 1);
    char name[32];
    std::snprintf(name, sizeof name, "pendulum_%g", deg);
    for (const Config& c : configs) {
      Row r = row_for("pendulum", name, c, 1);
      if (!c.built) {
        emit(r);
        continue;
      }
      const long frames = std::lround(Tend / c.dt);
      std::unique_ptr<Sim> sim = c.make(sc);
      const double E0 = sim->energy(0);
      double worst = 0, prev_th = 0, prev_w = 0;
      std::vector<double> ups;
      const Clock clk;
      for (long i = 1; i <= frames; ++i) {
        sim->step();
        const double dE = sim->energy(0) - E0;
        if (sim->failed() || !std::isfinite(dE)) {
          r.status = "diverged at t=" + fmt(i * c.dt, "%.2f");
          break;
        }
        worst = std::max(worst, std::abs(dE));
        r.dE_end = dE / kG;
        double th, w;
        sim->angles(0, &th, &w);
        if (i > 1 && prev_th < 0 && th >= 0 && std::abs(prev_th) < 1.5 && std::abs(th) < 1.5)
          ups.push_back((i - 1) * c.dt + hermite_root(c.dt, prev_th, prev_w, th, w));
        prev_th = th;
        prev_w = w;
      }
      const double mw = clk.wall(), mc = clk.cpu();
      r.internal_steps = sim->internal_steps();
      sim.reset();
      if (r.status == "ok") {
        r.max_abs_dE = worst / kG;
        if (ups.size() >= 2) r.period_relerr = (ups[1] - ups[0] - Tex) / Tex;
        time_stepping(r, c, sc, frames, o.reps, mw, mc);
      }
      emit(r);
    }
  }
}

// ------------------------------------------------------------------------------------------------
// 3. Throughput
// ------------------------------------------------------------------------------------------------
void throughput(const std::string& name, const std::vector<Scene>& sc, double energy_scale, double T,
                const std::vector<Config>& configs, const Options& o) {
  long bodies = 0;
  for (const Scene& s : sc) bodies += (long)s.links.size();
  for (const Config& c : configs) {
    Row r = row_for("throughput", name, c, (int)sc[0].links.size());
    if (!c.built) {
      emit(r);
      continue;
    }
    const long frames = std::lround(T / c.dt);
    // Accuracy beside the speed: the mean over the scenes of |E(T) - E0|, and summed gaps.
    std::unique_ptr<Sim> sim = c.make(sc);
    std::vector<double> E0(sc.size());
    for (size_t i = 0; i < sc.size(); ++i) E0[i] = sim->energy((int)i);
    const Clock clk;
    for (long i = 0; i < frames; ++i) sim->step();
    const double mw = clk.wall(), mc = clk.cpu();
    double dE = 0, gaps = 0;
    for (size_t i = 0; i < sc.size(); ++i) {
      dE += std::abs(sim->energy((int)i) - E0[i]);
      gaps += sim->gap_sum((int)i);
    }
    if (sim->failed() || !std::isfinite(dE)) r.status = "diverged";
    r.dE_end = dE / (double)sc.size() / energy_scale;
    r.gap_sum = gaps / (double)sc.size();
    r.internal_steps = sim->internal_steps() / (double)sc.size();  // per mechanism
    sim.reset();
    time_stepping(r, c, sc, frames, o.reps, mw, mc);
    r.body_steps_per_s = (double)bodies * (double)frames / r.run_s;
    emit(r);
  }
}

// ------------------------------------------------------------------------------------------------
// Identical scenes: every engine's start energy, and the angular accelerations it starts with
// (the rates after one 1e-6 s step, divided by the step), against simreel's.
// ------------------------------------------------------------------------------------------------
void scene_check(const std::string& name, const Scene& scene) {
  const double h = 1e-6;
  const std::vector<Scene> sc{scene};
  const size_t n = scene.links.size();
  std::vector<Config> cs{simreel_cfg(JointSettings{}.tolerance, h), mujoco_cfg("Euler", 1000000),
                         bullet_hinge_cfg(1000000), bullet_mb_cfg(1000000)};
  std::vector<double> E0, acc0;
  std::string out;
  for (const Config& c : cs) {
    if (!c.built) continue;
    std::unique_ptr<Sim> sim = c.make(sc);
    const double E = sim->energy(0);
    sim->step();
    std::vector<double> phi(n), phid(n);
    sim->angles(0, phi.data(), phid.data());
    for (double& v : phid) v /= h;
    if (E0.empty()) {
      E0.push_back(E);
      acc0 = phid;
      char b[200];
      std::snprintf(b, sizeof b, "E0 %.12g J (simreel)", E);
      out += b;
      continue;
    }
    double da = 0, amax = 0;
    for (size_t k = 0; k < n; ++k) {
      da = std::max(da, std::abs(phid[k] - acc0[k]));
      amax = std::max(amax, std::abs(acc0[k]));
    }
    char b[200];
    std::snprintf(b, sizeof b, "; %s %s: E0 %+.1e J, accelerations %.1e relative", c.engine.c_str(),
                  c.method.c_str(), E - E0[0], da / amax);
    out += b;
  }
  std::printf("# check %s: %s\n", name.c_str(), out.c_str());
}

// ------------------------------------------------------------------------------------------------
// The target: at every run time, simreel's error at least 100x smaller than the best
// anchor's. Both sides as frontiers: at each anchor row's run time t, the best anchor error among
// rows that ran in at most t against the best simreel error among settings that ran in at most t
// (the ratio can only dip where an anchor frontier steps down, so those times are enough).
// Diverged and torn rows have no error and are left out.
// ------------------------------------------------------------------------------------------------
void target_summary(const std::string& scene, double Row::*metric, const char* what, double Row::*time,
                    const char* clock) {
  auto usable = [&](const Row& r) {
    return r.section == "work_precision" && r.scene == scene && r.status == "ok" && !std::isnan(r.*metric) &&
           !std::isnan(r.*time);
  };
  const Row* fastest = nullptr;
  for (const Row& r : g_rows)
    if (usable(r) && r.engine == "simreel" && (!fastest || r.*time < fastest->*time)) fastest = &r;
  double worst = INFINITY, worst_t = NAN;
  std::string worst_at;
  int uncovered = 0;
  double uncovered_best = INFINITY;
  for (const Row& a : g_rows) {
    if (!usable(a) || a.engine == "simreel") continue;
    const double t = a.*time;
    double A = INFINITY, S = INFINITY;
    std::string who;
    for (const Row& r : g_rows) {
      if (!usable(r) || r.*time > t) continue;
      if (r.engine == "simreel") {
        S = std::min(S, r.*metric);
      } else if (r.*metric < A) {
        A = r.*metric;
        who = r.engine + " " + r.method + " " + r.setting;
      }
    }
    if (!std::isfinite(S)) {
      ++uncovered;
      uncovered_best = std::min(uncovered_best, A);
      continue;
    }
    const double ratio = A / std::max(S, 1e-300);
    if (ratio < worst) {
      worst = ratio;
      worst_t = t;
      worst_at = who;
    }
  }
  if (std::isfinite(worst))
    std::printf(
        "# target %s, %s, %s time: smallest (best anchor / best simreel) at equal run time %.3g, at %.3g s "
        "(anchor: %s): %s\n",
        scene.c_str(), what, clock, worst, worst_t, worst_at.c_str(),
        worst >= 100 ? "holds (>= 100)" : "does NOT hold (< 100)");
  if (uncovered && fastest)
    std::printf(
        "# target %s, %s, %s time: %d anchor rows ran faster than simreel's fastest setting (%s, %.3g s, "
        "error %.3g; the best of those rows %.3g): no simreel point at those run times, so the target does "
        "NOT "
        "hold there\n",
        scene.c_str(), what, clock, uncovered, fastest->setting.c_str(), fastest->*time, fastest->*metric,
        uncovered_best);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  bool want_wp = true, want_pend = true, want_tp = true;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      o.quick = true;
      o.reps = 1;
    } else if (a == "--only") {
      const std::string s = bench::option_value(i, argc, argv);
      want_wp = s == "work_precision";
      want_pend = s == "pendulum";
      want_tp = s == "throughput";
    } else {
      std::fprintf(stderr, "usage: %s [--quick] [--only work_precision|pendulum|throughput]\n", argv[0]);
      return 2;
    }
  }
  const double t_start = bench::now_s();
  std::printf(
      "# bench_joints%s: simreel vs MuJoCo 2.2.2 (%s) and Bullet 3.24 double precision (%s), same run\n",
      o.quick ? " --quick" : "",
#ifdef SIMREEL_BENCH_MUJOCO
      "built",
#else
      "not built",
#endif
#ifdef SIMREEL_BENCH_BULLET
      "built"
#else
      "not built"
#endif
  );
  std::printf(
      "# units: run_s (wall) and cpu_s (thread CPU) seconds of the stepping alone, median of timed_runs (%d, "
      "or the "
      "measured run alone when it took 4 s or more); max_abs_dE and dE_end in m g L (pendulums) or "
      "M g N l (chains; throughput: mean |E(end) - E0| per scene); state_err_rad max |dphi| at t = 2 s "
      "against the "
      "Gauss-Legendre reference; gap_sum_m summed joint gaps at the end; period_relerr first period, upward "
      "zero "
      "crossings; internal_steps_per_frame: simreel's adaptive steps\n",
      o.reps);
  scene_check("pendulum_170", pendulum(170 * kPi / 180));
  scene_check("double_pendulum", double_pendulum());
  scene_check("chain_R1000_N90", chain(90, 1000, kPi / 6));
  print_header();

  // simreel's tolerances. The chains are stiff (a 0.01 kg link between a 10 kg end and the rest):
  // the explicit step is held by stability, about 15 internal steps per frame whatever the
  // tolerance above 1e-5, and each tighter decade costs more steps without lowering an energy error
  // that is already at round-off, so the chain sweep stops at the default, 1e-10.
  const std::vector<double> tols = o.quick ? std::vector<double>{1e-6, 1e-8, 1e-10, 1e-12}
                                           : std::vector<double>{1e-3, 1e-4,  1e-5,  1e-6,  1e-7,  1e-8,
                                                                 1e-9, 1e-10, 1e-11, 1e-12, 1e-13, 1e-14};
  const std::vector<double> chain_tols = o.quick
                                             ? std::vector<double>{1e-5, 1e-8}
                                             : std::vector<double>{1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-10};
  const std::vector<double> chain90_tols =
      o.quick ? std::vector<double>{1e-5, 1e-8} : std::vector<double>{1e-3, 1e-4, 1e-5, 1e-6, 1e-8, 1e-10};
  const std::vector<int> dts =
      o.quick ? std::vector<int>{60, 240, 1000} : std::vector<int>{60, 120, 240, 500, 1000, 2000};

  if (want_wp) {
    std::vector<Config> dp;
    for (double t : tols) dp.push_back(simreel_cfg(t));
    for (int n : {0, 1, 2, 4, 8, 16}) dp.push_back(simreel_verlet_cfg(n));
    for (const char* in : {"RK4", "Euler"})
      for (int d : dts) dp.push_back(mujoco_cfg(in, d));
    for (int d : dts) dp.push_back(bullet_hinge_cfg(d));
    for (int d : dts) dp.push_back(bullet_mb_cfg(d));
    wp_double_pendulum(dp, o);

    // The chain: simreel and Bullet at 100 links; MuJoCo 2.2.2's XML parser rejects bodies nested
    // deeper than 96, so MuJoCo runs 90 links (as the anchors did) and simreel runs 90 too beside it.
    std::vector<Config> c100, c90;
    for (double t : chain_tols) c100.push_back(simreel_cfg(t));
    c100.push_back(simreel_verlet_cfg(0));
    for (int d : dts) c100.push_back(bullet_hinge_cfg(d));
    for (int d : dts) c100.push_back(bullet_mb_cfg(d));
    for (double t : chain90_tols) c90.push_back(simreel_cfg(t));
    c90.push_back(simreel_verlet_cfg(0));
    for (const char* in : {"RK4", "Euler"})
      for (int d : dts) c90.push_back(mujoco_cfg(in, d));
    wp_chain("chain_R1000_N100", 100, c100, o);
    wp_chain("chain_R1000_N90", 90, c90, o);
  }

  if (want_pend) {
    std::vector<Config> pc{simreel_cfg(JointSettings{}.tolerance)};
    for (const char* in : {"RK4", "Euler"})
      for (int d : {60, 240}) pc.push_back(mujoco_cfg(in, d));
    for (int d : {60, 240}) pc.push_back(bullet_hinge_cfg(d));
    for (int d : {60, 240}) pc.push_back(bullet_mb_cfg(d));
    pendulum_section(pc, o);
  }

  if (want_tp) {
    const int npend = o.quick ? 100 : 1000, nchain = o.quick ? 10 : 100;
    // Released at spread angles, so that the pendulums do not all take the same internal steps.
    std::vector<Scene> dps, chains;
    for (int i = 0; i < npend; ++i) {
      dps.push_back(double_pendulum(kPi / 4 + kPi / 4 * i / std::max(npend - 1, 1)));
      dps.back().y = 0.1 * i;
    }
    for (int i = 0; i < nchain; ++i) {
      chains.push_back(chain(20, 0, kPi / 18 + kPi / 9 * i / std::max(nchain - 1, 1)));
      chains.back().y = 0.1 * i;
    }
    const std::vector<Config> tc{simreel_cfg(JointSettings{}.tolerance),
                                 simreel_cfg(1e-6),
                                 simreel_cfg(1e-4),
                                 simreel_cfg(1e-3),
                                 simreel_verlet_cfg(0),
                                 bullet_hinge_cfg(60),
                                 bullet_mb_cfg(60),
                                 mujoco_cfg("RK4", 60),
                                 mujoco_cfg("Euler", 60)};
    throughput("double_pendulums_x" + std::to_string(npend), dps, kG, o.quick ? 1 : 2, tc, o);
    throughput("chains20_x" + std::to_string(nchain), chains, chain_energy_scale(chains[0]),
               o.quick ? 0.5 : 1, tc, o);
    // Against Bullet's hinge world: every simreel setting's ratio beside its error, and whether
    // some setting holds the target with an energy error below Bullet's.
    for (const std::string& scene :
         {"double_pendulums_x" + std::to_string(npend), "chains20_x" + std::to_string(nchain)}) {
      const Row* hinge = nullptr;
      for (const Row& r : g_rows)
        if (r.section == "throughput" && r.scene == scene && r.engine == "bullet" && r.method == "hinge")
          hinge = &r;
      if (!hinge || std::isnan(hinge->body_steps_per_s)) continue;
      std::string line, best;
      double best_ratio = 0;
      for (const Row& r : g_rows) {
        if (r.section != "throughput" || r.scene != scene || r.engine != "simreel") continue;
        const double ratio = r.body_steps_per_s / hinge->body_steps_per_s;
        line +=
            "; " + r.setting + " " + fmt(ratio, "%.3g") + "x (|dE| " + fmt(std::abs(r.dE_end), "%.1e") + ")";
        if (std::abs(r.dE_end) < std::abs(hinge->dE_end) && ratio > best_ratio)
          best_ratio = ratio, best = r.setting;
      }
      std::printf(
          "# target throughput %s: simreel / Bullet hinge (%.3g body-steps/s, |dE| %.1e)%s; target >= 3 "
          "at an error below Bullet's: %s\n",
          scene.c_str(), hinge->body_steps_per_s, std::abs(hinge->dE_end), line.c_str(),
          best_ratio >= 3 ? ("holds (" + best + ")").c_str() : "does NOT hold");
    }
  }

  if (want_wp) {
    for (auto [time, clock] : {std::pair{&Row::run_s, "wall"}, std::pair{&Row::cpu_s, "cpu"}}) {
      target_summary("double_pendulum", &Row::max_abs_dE, "max |dE|", time, clock);
      target_summary("double_pendulum", &Row::state_err, "state error at 2 s", time, clock);
      target_summary("chain_R1000_N100", &Row::max_abs_dE, "max |dE|", time, clock);
      target_summary("chain_R1000_N90", &Row::max_abs_dE, "max |dE|", time, clock);
    }
  }
  std::printf("# total wall time %.1f s\n", bench::now_s() - t_start);
  return 0;
}
