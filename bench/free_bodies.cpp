// Free bodies with colliders: simreel against Bullet 3.24 f64 (Debian's libbullet-dev, -float64
// libraries) in the same run, one thread each, on the three scenes of
// ../shared/anchors/FREEBODIES.md. Each scene isolates a cost that the collider-free R2 figure
// (bench_r2_throughput, mask 0) hides:
//
//   (a) r2_colliders   The R2 boxes (r2_free_boxes: sides 0.2-1 m, 3 m grid, random pose and spin
//                      up to 10 rad/s, falling) with ordinary colliders. They never touch, so every
//                      second spent beyond integration is collision bookkeeping for pairs that
//                      never happen: the broad phase keeping its tree as the bodies fall out of
//                      their fat boxes, and the continuous stage once bodies are fast. Sleeping
//                      off in both engines (deactivation disabled in Bullet); N = 1000 to 100,000.
//   (b) sleeping_world 10,000 1 m cubes asleep on a ground plane plus 10 bouncing balls: what a
//                      step costs when almost nothing moves. An engine that only touches awake
//                      bodies pays for 10; one that walks every body or every resting pair pays
//                      for 10,000. Sleeping on in both (Bullet's default deactivation).
//   (c) compound_16k   One body made of 16,000 boxes in a row, falling with nothing to hit: the
//                      cost of many colliders on one rigid body. Bullet's btCompoundShape gives the
//                      body one broad-phase proxy; an engine with a proxy per collider moves
//                      16,000 of them every step.
//   (d) detailed_hulls Two 3,000-vertex hulls (a cylinder's two rims, 1,500 points each: every
//                      point an extreme one, as on a scanned part) stacked on the ground and at
//                      rest, sleeping off: the narrow phase's cost on detailed convex shapes
//                      (simreel: GJK/EPA and supporting faces past the SAT's edge-pair limit;
//                      Bullet: btConvexHullShape, GJK/EPA with a linear support scan).
//
// Bullet gets the same masses, inertias, poses and spins as simreel (Bullet bodies sit at their
// centres of mass with principal axes along the body axes, which holds for these boxes), and the
// same pair materials: Bullet multiplies the two frictions and the two restitutions where simreel
// takes sqrt(f_a f_b) and max(e_a, e_b), so each Bullet body gets sqrt(0.6) friction and the
// ground restitution 1 (ball-ground 0.9, cube-ground 0). Every Bullet step is
// stepSimulation(dt, 0): exactly one internal step of dt.
//
// stdout: CSV, comment lines start with '#': the checks (a contact in each engine with (a)'s
// colliders, every cube asleep after (b)'s warm-up, (c)'s fall against -g t^2 / 2), simreel's
// stage profile and Bullet's phases per run. wall_s and cpu_s (thread CPU time) cover the timed
// steps alone; worlds are built untimed. Options: --quick (N up to 10,000, fewer steps; under a
// minute), --only a|b|c.
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bench/bench_util.hpp"
#include "sim/geometry/convex_hull.hpp"
#include "tests/fixtures/reference_scenes.hpp"

#ifdef SIMREEL_BENCH_BULLET
#include <btBulletDynamicsCommon.h>

#include "bench/bullet_phased_world.hpp"
#endif

using namespace simreel;

namespace {

constexpr double kDt = 1.0 / 240;
constexpr double kG = 9.81;

struct Options {
  bool quick = false;
  bool a = true, b = true, c = true, d = true;
};

struct Row {
  Row(const char* scene_, const char* engine_, int n_) : scene(scene_), engine(engine_), n(n_) {}
  const char* scene;
  const char* engine;
  int n;            // bodies (a, b) or colliders (c)
  long steps = 0;   // timed steps
  double wall = 0;  // s
  double cpu = 0;   // s, thread CPU time
  int asleep = -1;  // dynamic bodies asleep at the end; -1: not asked
  std::string notes;
};

void print_header() {
  std::printf(
      "scene,engine,N,steps,wall_s,cpu_s,body_steps_per_s,ns_per_body_step,us_per_step,asleep,notes\n");
}

// body_steps: whether body-steps/s is a meaningful rate for the scene (not for one compound body).
void print_row(const Row& r, bool body_steps) {
  const double bs = (double)r.n * (double)r.steps;
  char rate[64] = "", ns[64] = "", asleep[32] = "";
  if (body_steps) {
    std::snprintf(rate, sizeof rate, "%.4e", bs / r.wall);
    std::snprintf(ns, sizeof ns, "%.1f", r.wall / bs * 1e9);
  }
  if (r.asleep >= 0) std::snprintf(asleep, sizeof asleep, "%d", r.asleep);
  std::printf("%s,%s,%d,%ld,%.4f,%.4f,%s,%s,%.2f,%s,%s\n", r.scene, r.engine, r.n, r.steps, r.wall, r.cpu,
              rate, ns, r.wall / (double)r.steps * 1e6, asleep, r.notes.c_str());
  std::fflush(stdout);
}

// Steps `steps` times, adding the stepping calls' wall and thread CPU time to the row.
template <typename F>
void timed_steps(long steps, Row& r, F step) {
  const double t0 = bench::now_s(), c0 = bench::thread_cpu_s();
  for (long s = 0; s < steps; ++s) step();
  r.cpu += bench::thread_cpu_s() - c0;
  r.wall += bench::now_s() - t0;
  r.steps += steps;
}

// simreel's stages that matter for free bodies over the timed steps (`before`: the profile when
// they began), as one comment line.
void print_profile(const char* scene, int n, const World& w, const Profile& before) {
  const Profile& p = w.profile();
  auto sec = [&](Stage s) { return p.seconds[(int)s] - before.seconds[(int)s]; };
  double total = 0;
  for (int s = 0; s < (int)Stage::count; ++s) total += sec((Stage)s);
  std::printf("# simreel profile %s N=%d over %ld steps: update_broad_phase %.3f s, collide %.3f s, ", scene,
              n, p.steps - before.steps, sec(Stage::update_broad_phase), sec(Stage::collide));
  std::printf("continuous %.3f s (ran in %ld steps), integrate %.3f s, sleep %.3f s, all stages %.3f s; ",
              sec(Stage::continuous), p.runs[(int)Stage::continuous] - before.runs[(int)Stage::continuous],
              sec(Stage::integrate), sec(Stage::sleep), total);
  std::printf("shapes %d, candidate pairs %ld, contact points %ld, swept bodies %ld, toi pairs %ld\n",
              p.shapes, p.pairs - before.pairs, p.contact_points - before.contact_points,
              p.swept_bodies - before.swept_bodies, p.toi_pairs - before.toi_pairs);
}

// ------------------------------------------------------------------------------------- scenes
// (a): the R2 boxes with the default collision filter (r2_free_boxes masks them off).
std::vector<BodyDef> r2_collider_boxes(int n) {
  std::vector<BodyDef> defs = r2_free_boxes(n);
  const uint32_t default_mask = Collider{}.mask;
  for (BodyDef& d : defs) d.colliders[0].mask = default_mask;
  return defs;
}

WorldConfig free_config(bool sleep) {
  WorldConfig c;
  c.threads = 1;
  c.dt = kDt;
  c.gravity = Vec3(0, 0, -kG);
  c.contacts.sleep = sleep;
  return c;
}

// (b): cubes on a 100 x 100 grid from the origin, the balls in a row 20 m off its y = 0 edge.
constexpr int kGrid = 100;
constexpr double kPitch = 1.5;
constexpr int kBalls = 10;
constexpr double kBallRadius = 0.25;
constexpr double kBallRestitution = 0.9;
constexpr double kFriction = 0.6;  // simreel's default, on every collider

Vec3 cube_position(int k) {
  return Vec3(kPitch * (k % kGrid), kPitch * (k / kGrid), 0.5);
}
Vec3 ball_position(int k) {
  return Vec3(10.0 + 10.0 * k, -20.0, 10.0);
}

// Cubes first, then the balls, then the ground (the scene loader's order).
std::vector<BodyDef> sleeping_world_defs() {
  std::vector<BodyDef> v;
  v.reserve(kGrid * kGrid + kBalls + 1);
  for (int k = 0; k < kGrid * kGrid; ++k) {
    BodyDef b;
    b.name = "cube" + std::to_string(k);
    b.p_WB = cube_position(k);
    b.add_collider(box_collider(Vec3::Ones(), 1000.0));
    v.push_back(std::move(b));
  }
  for (int k = 0; k < kBalls; ++k) {
    BodyDef b;
    b.name = "ball" + std::to_string(k);
    b.p_WB = ball_position(k);
    Collider c = sphere_collider(kBallRadius, 1000.0);
    c.restitution = kBallRestitution;
    b.add_collider(std::move(c));
    v.push_back(std::move(b));
  }
  BodyDef g;
  g.name = "ground";
  g.type = BodyType::static_body;
  g.add_collider(plane_collider());
  v.push_back(std::move(g));
  return v;
}

// (c): 16,000 cubes of 0.5 m touching along x, centred on the body origin (so the centre of mass is
// the origin and the principal axes are the body axes).
constexpr int kCompoundBoxes = 16000;
constexpr double kCompoundSide = 0.5;

BodyDef compound_def() {
  BodyDef b;
  b.name = "row";
  for (int k = 0; k < kCompoundBoxes; ++k) {
    Collider c = box_collider(Vec3::Constant(kCompoundSide), 1000.0);
    c.p_BC = Vec3((k - 0.5 * (kCompoundBoxes - 1)) * kCompoundSide, 0, 0);
    b.append_collider(std::move(c));  // O(n): add_collider would re-compose every earlier collider
  }
  return b;
}

// ------------------------------------------------------------------------------------- simreel
Row simreel_r2(int n, long steps, bool show_profile) {
  const std::vector<BodyDef> defs = r2_collider_boxes(n);
  World w(free_config(false), defs);
  w.set_profiling(true);  // a clock read per stage and step: nothing per body
  const Profile before = w.profile();
  Row r{"r2_colliders", "simreel", n};
  timed_steps(steps, r, [&] { w.step(); });
  char buf[160];
  std::snprintf(buf, sizeof buf, "has_contacts %d; candidate pairs %ld; swept bodies %ld",
                (int)w.has_contacts(), w.profile().pairs, w.profile().swept_bodies);
  r.notes = buf;
  if (show_profile) print_profile("r2_colliders", n, w, before);
  return r;
}

// The sleeping world's notes and check line: every cube asleep after the warm-up, and at the end.
void sleeping_checks(Row& r, const char* engine, int cubes_warm, int cubes_end, int balls_end, long warmup) {
  const int cubes = kGrid * kGrid;
  r.asleep = cubes_end + balls_end;
  char buf[200];
  std::snprintf(buf, sizeof buf, "cubes asleep after warm-up %d/%d; at end %d cubes and %d/%d balls",
                cubes_warm, cubes, cubes_end, balls_end, kBalls);
  r.notes = buf;
  std::printf("# check sleeping_world %s: %d of %d cubes asleep after %ld warm-up steps (%s)\n", engine,
              cubes_warm, cubes, warmup, cubes_warm == cubes ? "ok" : "NOT ALL ASLEEP");
}

Row simreel_sleeping(long warmup, long steps) {
  World w(free_config(true), sleeping_world_defs());
  for (long s = 0; s < warmup; ++s) w.step();
  const int cubes = kGrid * kGrid;
  auto count = [&](int from, int to) {
    int k = 0;
    for (int i = from; i < to; ++i) k += w.asleep(i);
    return k;
  };
  const int cubes_warm = count(0, cubes);
  w.set_profiling(true);
  const Profile before = w.profile();
  Row r{"sleeping_world", "simreel", cubes + kBalls};
  timed_steps(steps, r, [&] { w.step(); });
  sleeping_checks(r, "simreel", cubes_warm, count(0, cubes), count(cubes, cubes + kBalls), warmup);
  print_profile("sleeping_world", cubes + kBalls, w, before);
  return r;
}

Row simreel_compound(const BodyDef& def, long steps) {
  World w(free_config(false), {def});
  w.set_profiling(true);
  const Profile before = w.profile();
  const double z0 = w.centroid(0).z();
  Row r{"compound_16k", "simreel", kCompoundBoxes};
  timed_steps(steps, r, [&] { w.step(); });
  const double t = w.time(), z = w.centroid(0).z() - z0, expect = -0.5 * kG * t * t;
  std::printf("# check compound_16k simreel: z after %.4f s = %.6f m, -g t^2/2 = %.6f m (rel. diff %.1e)\n",
              t, z, expect, (z - expect) / expect);
  char buf[160];
  std::snprintf(buf, sizeof buf, "1 body; has_contacts %d; dz %.4f m (-g t^2/2 %.4f)", (int)w.has_contacts(),
                z, expect);
  r.notes = buf;
  print_profile("compound_16k", kCompoundBoxes, w, before);
  return r;
}

// One step with two of (a)'s boxes overlapping: the colliders as built here do touch. Returns the
// touching pairs and their contact points.
std::pair<int, int> simreel_contact_check(std::vector<BodyDef> defs) {
  defs.resize(2);
  defs[1].p_WB = defs[0].p_WB + Vec3(0.2, 0, 0);
  World w(free_config(false), defs);
  w.set_profiling(true);
  w.step();
  std::vector<ContactData> out;
  const int pairs = w.contacts(out);
  return {pairs, (int)w.profile().contact_points};
}

// (d): the cylinder of radius 0.3 m and height 0.2 m as the hull of its two rims, 1,500 points
// each (the upper rim turned a little, so no two side points are coplanar with a third).
constexpr int kRimPoints = 1500;
std::vector<Vec3> rim_points() {
  std::vector<Vec3> pts;
  for (int i = 0; i < kRimPoints; ++i) {
    const double a = 2 * M_PI * i / kRimPoints;
    pts.push_back(Vec3(0.3 * std::cos(a), 0.3 * std::sin(a), -0.1));
    pts.push_back(Vec3(0.3 * std::cos(a + 0.001), 0.3 * std::sin(a + 0.001), 0.1));
  }
  return pts;
}
const Vec3 kStackAt[2] = {Vec3(0, 0, 0.1), Vec3(0.03, -0.01, 0.3)};
const Quat kStackTurn[2] = {Quat::Identity(), Quat(Eigen::AngleAxisd(0.7, Vec3::UnitZ()))};

Row simreel_detailed(long warmup, long steps) {
  auto hull = std::make_shared<const ConvexPolyhedron>(convex_polyhedron(rim_points()));
  std::vector<BodyDef> defs;
  BodyDef g;
  g.name = "ground";
  g.type = BodyType::static_body;
  g.add_collider(plane_collider());
  defs.push_back(g);
  for (int k = 0; k < 2; ++k) {
    BodyDef b;
    b.name = "hull" + std::to_string(k);
    b.p_WB = kStackAt[k];
    b.q_WB = kStackTurn[k];
    Collider c;
    c.shape = ShapeKind::mesh;
    c.hulls = {hull};
    c.props_C = cylinder_collider(0.3, 0.2, 800.0).props_C;
    b.add_collider(c);
    defs.push_back(b);
  }
  World w(free_config(false), defs);
  for (long s = 0; s < warmup; ++s) w.step();
  w.set_profiling(true);
  const Profile before = w.profile();
  const Vec3 x0 = w.centroid(2);
  Row r{"detailed_hulls", "simreel", 2};
  timed_steps(steps, r, [&] { w.step(); });
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "2 hulls of %zu vertices; top at z %.5f m (0.3 less slops); moved %.1e m while timed",
                hull->vertices.size(), w.centroid(2).z(), (w.centroid(2) - x0).norm());
  r.notes = buf;
  print_profile("detailed_hulls", 2, w, before);
  return r;
}

// -------------------------------------------------------------------------------------- Bullet
#ifdef SIMREEL_BENCH_BULLET
using bench::PhasedWorld;

// A Bullet world of the default configuration, dbvt broad phase and sequential-impulse solver.
struct BulletWorld {
  btDefaultCollisionConfiguration cfg;
  btCollisionDispatcher disp{&cfg};
  btDbvtBroadphase bp;
  btSequentialImpulseConstraintSolver solver;
  PhasedWorld world{&disp, &bp, &solver, &cfg};
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btRigidBody>> bodies;

  BulletWorld() { world.setGravity(btVector3(0, 0, -kG)); }
  ~BulletWorld() {
    for (auto& b : bodies) world.removeRigidBody(b.get());
  }
  // A body whose frame is its principal frame at the centre of mass; default collision groups.
  btRigidBody* add(btCollisionShape* shape, const MassProperties& mp, const Vec3& p, const Quat& q,
                   double friction, double restitution) {
    const Vec3 I = mp.mass > 0 ? Vec3(mp.inertia.diagonal()) : Vec3::Zero();
    btRigidBody::btRigidBodyConstructionInfo ci(mp.mass, nullptr, shape, btVector3(I.x(), I.y(), I.z()));
    ci.m_startWorldTransform =
        btTransform(btQuaternion(q.x(), q.y(), q.z(), q.w()), btVector3(p.x(), p.y(), p.z()));
    ci.m_friction = friction;
    ci.m_restitution = restitution;
    bodies.push_back(std::make_unique<btRigidBody>(ci));
    world.addRigidBody(bodies.back().get());
    return bodies.back().get();
  }
  void step() { world.stepSimulation(btScalar(kDt), 0); }
  // Boxes of single colliders centred on the body origin with principal axes along the body axes
  // (the R2 boxes), spinning, never deactivated.
  void add_boxes(const std::vector<BodyDef>& defs) {
    for (const BodyDef& d : defs) {
      const Vec3 half = 0.5 * d.colliders[0].size;
      shapes.push_back(std::make_unique<btBoxShape>(btVector3(half.x(), half.y(), half.z())));
      btRigidBody* b = add(shapes.back().get(), d.mass_B(), d.p_WB, d.q_WB, std::sqrt(kFriction), 0.0);
      b->setActivationState(DISABLE_DEACTIVATION);
      b->setAngularVelocity(btVector3(d.w_W.x(), d.w_W.y(), d.w_W.z()));
    }
  }
  int contact_points() {
    int k = 0;
    for (int m = 0; m < disp.getNumManifolds(); ++m)
      k += disp.getManifoldByIndexInternal(m)->getNumContacts();
    return k;
  }
};

void print_phases(const char* scene, int n, const PhasedWorld& w, long steps) {
  std::printf(
      "# bullet_f64 phases %s N=%d over %ld steps: predict %.3f s, collision_detection %.3f s, islands %.3f "
      "s, "
      "solve %.3f s, integrate %.3f s, activation %.3f s\n",
      scene, n, steps, w.t[PhasedWorld::predict], w.t[PhasedWorld::collision], w.t[PhasedWorld::islands],
      w.t[PhasedWorld::solve], w.t[PhasedWorld::integrate], w.t[PhasedWorld::activation]);
}

Row bullet_r2(int n, long steps) {
  const std::vector<BodyDef> defs = r2_collider_boxes(n);
  BulletWorld B;
  B.add_boxes(defs);
  Row r{"r2_colliders", "bullet_f64", n};
  long pairs = 0;  // broad-phase overlapping pairs, summed over steps (counted outside the timing)
  for (long s = 0; s < steps; ++s) {
    timed_steps(1, r, [&] { B.step(); });
    pairs += B.bp.getOverlappingPairCache()->getNumOverlappingPairs();
  }
  char buf[160];
  std::snprintf(buf, sizeof buf, "broad-phase pairs %ld; manifolds at end %d", pairs,
                B.disp.getNumManifolds());
  r.notes = buf;
  print_phases("r2_colliders", n, B.world, steps);
  return r;
}

Row bullet_sleeping(long warmup, long steps) {
  BulletWorld B;
  const double mu = std::sqrt(kFriction);
  B.shapes.push_back(std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), 0));
  btCollisionShape* plane = B.shapes.back().get();
  B.shapes.push_back(std::make_unique<btBoxShape>(btVector3(0.5, 0.5, 0.5)));
  btCollisionShape* cube = B.shapes.back().get();
  B.shapes.push_back(std::make_unique<btSphereShape>(kBallRadius));
  btCollisionShape* ball = B.shapes.back().get();
  MassProperties ground;
  ground.inertia = Mat3::Zero();
  B.add(plane, ground, Vec3::Zero(), Quat::Identity(), mu, 1.0);
  const std::vector<BodyDef> defs = sleeping_world_defs();
  const int cubes = kGrid * kGrid;
  for (int k = 0; k < cubes + kBalls; ++k) {
    const BodyDef& d = defs[k];
    B.add(k < cubes ? cube : ball, d.mass_B(), d.p_WB, d.q_WB, mu, k < cubes ? 0.0 : kBallRestitution);
  }
  auto count = [&](int from, int to) {
    int a = 0;
    for (int i = from; i < to; ++i) a += B.bodies[i + 1]->getActivationState() == ISLAND_SLEEPING;
    return a;
  };
  for (long s = 0; s < warmup; ++s) B.step();
  const int cubes_warm = count(0, cubes);
  PhasedWorld& w = B.world;
  for (double& t : w.t) t = 0;
  Row r{"sleeping_world", "bullet_f64", cubes + kBalls};
  timed_steps(steps, r, [&] { B.step(); });
  sleeping_checks(r, "bullet_f64", cubes_warm, count(0, cubes), count(cubes, cubes + kBalls), warmup);
  print_phases("sleeping_world", cubes + kBalls, w, steps);
  return r;
}

Row bullet_compound(const BodyDef& def, long steps) {
  BulletWorld B;
  // One box shape shared by every child (the children only read it).
  B.shapes.push_back(std::make_unique<btBoxShape>(btVector3(0.5, 0.5, 0.5) * kCompoundSide));
  btCollisionShape* box = B.shapes.back().get();
  auto owned = std::make_unique<btCompoundShape>(true, kCompoundBoxes);
  btCompoundShape* compound = owned.get();
  B.shapes.push_back(std::move(owned));
  for (const Collider& c : def.colliders)
    compound->addChildShape(
        btTransform(btQuaternion::getIdentity(), btVector3(c.p_BC.x(), c.p_BC.y(), c.p_BC.z())), box);
  // The children sit at the same body-frame positions as simreel's colliders, whose centre of mass
  // is the body origin (to round-off), so the Bullet body frame is the principal frame.
  const MassProperties& mp = def.mass_B();
  btRigidBody* body = B.add(compound, mp, mp.com, Quat::Identity(), std::sqrt(kFriction), 0.0);
  body->setActivationState(DISABLE_DEACTIVATION);
  const double z0 = body->getCenterOfMassPosition().z();
  Row r{"compound_16k", "bullet_f64", kCompoundBoxes};
  timed_steps(steps, r, [&] { B.step(); });
  const double t = steps * kDt, z = body->getCenterOfMassPosition().z() - z0, expect = -0.5 * kG * t * t;
  // Semi-implicit Euler's exact result: -g dt^2 n (n + 1) / 2.
  const double euler = -0.5 * kG * kDt * kDt * steps * (steps + 1.0);
  std::printf(
      "# check compound_16k bullet_f64: z after %.4f s = %.6f m, -g t^2/2 = %.6f m (rel. diff %.1e; "
      "semi-implicit Euler's -g dt^2 n(n+1)/2 = %.6f)\n",
      t, z, expect, (z - expect) / expect, euler);
  char buf[160];
  std::snprintf(buf, sizeof buf, "1 body; btCompoundShape %d children; dz %.4f m (-g t^2/2 %.4f)",
                compound->getNumChildShapes(), z, expect);
  r.notes = buf;
  print_phases("compound_16k", kCompoundBoxes, B.world, steps);
  return r;
}

std::pair<int, int> bullet_contact_check(std::vector<BodyDef> defs) {
  defs.resize(2);
  defs[1].p_WB = defs[0].p_WB + Vec3(0.2, 0, 0);
  BulletWorld B;
  B.add_boxes(defs);
  B.step();
  int pairs = 0;
  for (int m = 0; m < B.disp.getNumManifolds(); ++m)
    pairs += B.disp.getManifoldByIndexInternal(m)->getNumContacts() > 0;
  return {pairs, B.contact_points()};
}
#endif

// ------------------------------------------------------------------------------------- scenes
void scene_a(const Options& o) {
  // --quick's 300 steps end before any box falls fast enough for the continuous stage (it first
  // runs near step 440), so quick rates leave that stage out.
  const long steps = o.quick ? 300 : 1000;
  {
    const std::vector<BodyDef> defs = r2_collider_boxes(2);
    const auto [sp, spts] = simreel_contact_check(defs);
    std::printf(
        "# check r2_colliders: two of its boxes 0.2 m apart, one step: touching pairs (contact points) ");
    std::printf("simreel %d (%d)", sp, spts);
#ifdef SIMREEL_BENCH_BULLET
    const auto [bp, bpts] = bullet_contact_check(defs);
    std::printf(", bullet_f64 %d (%d)", bp, bpts);
#endif
    std::printf("\n");
  }
  std::vector<int> ns = {1000, 10000};
  if (!o.quick) ns.insert(ns.end(), {30000, 100000});
  [[maybe_unused]] double bullet_30k = 0;  // s, Bullet's N = 30000 run
  for (int n : ns) {
    print_row(simreel_r2(n, steps, true), true);
#ifdef SIMREEL_BENCH_BULLET
    if (n == 100000 && bullet_30k > 0) {
      // Bullet's dbvt costs about N log N a step: scale the 30,000 run by that.
      const double est = bullet_30k * (n / 30000.0) * (std::log(n) / std::log(30000.0));
      if (est > 60) {
        std::printf(
            "# bullet_f64 r2_colliders N=%d skipped: estimated %.0f s from the N=30000 run (> 60 s)\n", n,
            est);
        continue;
      }
    }
    const Row r = bullet_r2(n, steps);
    if (n == 30000) bullet_30k = r.wall;
    print_row(r, true);
#endif
  }
}

#ifdef SIMREEL_BENCH_BULLET
Row bullet_detailed(long warmup, long steps) {
  BulletWorld B;
  const double mu = std::sqrt(kFriction);
  B.shapes.push_back(std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), 0));
  btCollisionShape* plane = B.shapes.back().get();
  MassProperties ground;
  ground.inertia = Mat3::Zero();
  B.add(plane, ground, Vec3::Zero(), Quat::Identity(), mu, 0.0);
  auto owned = std::make_unique<btConvexHullShape>();
  for (const Vec3& p : rim_points()) owned->addPoint(btVector3(p.x(), p.y(), p.z()), false);
  owned->recalcLocalAabb();
  owned->setMargin(0.001);  // Bullet's 4 cm default would grow the hull by that much on every side
  btCollisionShape* hull = owned.get();
  B.shapes.push_back(std::move(owned));
  const MassProperties mp = cylinder_collider(0.3, 0.2, 800.0).props_C;
  btRigidBody* top = nullptr;
  for (int k = 0; k < 2; ++k) {
    top = B.add(hull, mp, kStackAt[k], kStackTurn[k], mu, 0.0);
    top->setActivationState(DISABLE_DEACTIVATION);
  }
  for (long s = 0; s < warmup; ++s) B.step();
  const btVector3 x0 = top->getCenterOfMassPosition();
  Row r{"detailed_hulls", "bullet_f64", 2};
  timed_steps(steps, r, [&] { B.step(); });
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "btConvexHullShape of %d points, margin 1 mm; top at z %.5f m; moved %.1e m while timed",
                2 * kRimPoints, top->getCenterOfMassPosition().z(),
                (top->getCenterOfMassPosition() - x0).length());
  r.notes = buf;
  print_phases("detailed_hulls", 2, B.world, steps);
  return r;
}
#endif

void scene_d(const Options& o) {
  const long warmup = 240, steps = o.quick ? 200 : 1000;
  print_row(simreel_detailed(warmup, steps), false);
#ifdef SIMREEL_BENCH_BULLET
  print_row(bullet_detailed(warmup, steps), false);
#endif
}

void scene_b(const Options& o) {
  const long warmup = 720, steps = o.quick ? 200 : 1000;
  print_row(simreel_sleeping(warmup, steps), true);
#ifdef SIMREEL_BENCH_BULLET
  print_row(bullet_sleeping(warmup, steps), true);
#endif
}

void scene_c(const Options& o) {
  const long steps = o.quick ? 100 : 1000;
  const BodyDef def = compound_def();
  print_row(simreel_compound(def, steps), false);
#ifdef SIMREEL_BENCH_BULLET
  print_row(bullet_compound(def, steps), false);
#endif
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      o.quick = true;
    } else if (a == "--only") {
      const std::string s = bench::option_value(i, argc, argv);
      if (s != "a" && s != "b" && s != "c" && s != "d") {
        std::fprintf(stderr, "--only takes a, b, c or d\n");
        return 2;
      }
      o.a = s == "a";
      o.b = s == "b";
      o.c = s == "c";
      o.d = s == "d";
    } else {
      std::fprintf(stderr, "usage: %s [--quick] [--only a|b|c|d]\n", argv[0]);
      return 2;
    }
  }
  const double t_start = bench::now_s();
  std::printf(
      "# bench_free_bodies%s: simreel vs Bullet 3.24 double precision (%s), same run, one thread each\n",
      o.quick ? " --quick" : "",
#ifdef SIMREEL_BENCH_BULLET
      "built"
#else
      "not built"
#endif
  );
  std::printf(
      "# wall_s, cpu_s: the timed steps alone; body_steps_per_s = N steps / wall_s; us_per_step = wall_s / "
      "steps; "
      "asleep: dynamic bodies asleep at the end\n");
  print_header();
  if (o.a) scene_a(o);
  if (o.b) scene_b(o);
  if (o.c) scene_c(o);
  if (o.d) scene_d(o);
  std::printf("# total %.0f s wall\n", bench::now_s() - t_start);
}
