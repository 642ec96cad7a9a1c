#include "sim/scene_builders.hpp"

#include <cmath>

#include "sim/primitives.hpp"

namespace simreel {

uint64_t SplitMix64::next() {
  uint64_t z = (s += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
double SplitMix64::uniform() {
  return (double)(next() >> 11) * (1.0 / 9007199254740992.0);
}
double SplitMix64::uniform(double a, double b) {
  return a + (b - a) * uniform();
}

BodyDef box_body(const char* name, const Vec3& size, double mass) {
  BodyDef b;
  b.name = name;
  Collider c;
  c.shape = ShapeKind::box;
  c.size = size;
  c.props_C = box_mass(size, mass / box_volume(size));
  c.label = "box";
  b.add_collider(c);
  return b;
}

BodyDef r1_tumble_body() {
  BodyDef b = box_body("tumbler", Vec3(3, 2, 1), 6.0);
  b.w_W = Vec3(0.01, 5.0, 0.01);
  return b;
}

std::vector<BodyDef> r2_free_boxes(int n, uint64_t seed) {
  SplitMix64 rng(seed);
  std::vector<BodyDef> v;
  v.reserve(n);
  const int side = (int)std::ceil(std::cbrt((double)n));
  for (int i = 0; i < n; ++i) {
    // Draw order as in the anchors: half extents, orientation, spin direction, spin rate.
    const Vec3 half(rng.uniform(0.1, 0.5), rng.uniform(0.1, 0.5), rng.uniform(0.1, 0.5));
    const Vec3 size = 2.0 * half;
    BodyDef b = box_body("box", size, 1000.0 * box_volume(size));
    // Free bodies, as the anchors run R2 (Bullet: collision group 1, mask 0, no pair ever tested):
    // the boxes fly 3 m apart and never meet, and the benchmark measures integration alone.
    b.colliders[0].mask = 0;
    b.name = "box" + std::to_string(i);
    const int ix = i % side, iy = (i / side) % side, iz = i / (side * side);
    b.p_WB = Vec3(3.0 * ix, 3.0 * iy, 3.0 * iz + 100.0);
    const double qw = rng.uniform(-1, 1), qx = rng.uniform(-1, 1), qy = rng.uniform(-1, 1),
                 qz = rng.uniform(-1, 1);
    b.q_WB = Quat(qw, qx, qy, qz).normalized();
    const double dx = rng.uniform(-1, 1), dy = rng.uniform(-1, 1), dz = rng.uniform(-1, 1);
    b.w_W = Vec3(dx, dy, dz).normalized() * rng.uniform(0.0, 10.0);
    v.push_back(std::move(b));
  }
  return v;
}

BodyDef r3_cube(const std::string& name, const Vec3& p_W) {
  BodyDef b;
  b.name = name;
  Collider c;
  c.shape = ShapeKind::box;
  c.size = Vec3::Ones();
  c.props_C = box_mass(c.size, 1.0);  // density 1 kg/m^3: mass 1
  c.friction = kR3Friction;
  c.restitution = 0.0;
  c.label = "box";
  b.add_collider(c);
  b.p_WB = p_W;
  return b;
}

BodyDef r3_ground(double height, double friction) {
  BodyDef g;
  g.name = "ground";
  g.type = BodyType::static_body;
  Collider plane;
  plane.shape = ShapeKind::plane;
  plane.p_BC = Vec3(0, 0, height);
  plane.friction = friction;
  plane.restitution = 0.0;
  plane.props_C.mass = 0;
  plane.props_C.inertia = Mat3::Zero();
  plane.label = "plane (ground)";
  g.add_collider(std::move(plane));
  return g;
}

std::vector<BodyDef> r3_pile() {
  std::vector<BodyDef> v;
  v.reserve(1001);
  for (int k = 0; k < 10; ++k)
    for (int j = 0; j < 10; ++j)
      for (int i = 0; i < 10; ++i)
        v.push_back(r3_cube("cube" + std::to_string(v.size()),
                            Vec3((i - 4.5) * 1.1, (j - 4.5) * 1.1, 1.0 + k * 1.1)));
  v.push_back(r3_ground());
  return v;
}

std::vector<BodyDef> r3_column(int n) {
  std::vector<BodyDef> v;
  v.reserve(n + 1);
  for (int k = 0; k < n; ++k) v.push_back(r3_cube("cube" + std::to_string(k), Vec3(0, 0, 1.0 + k * 1.1)));
  v.push_back(r3_ground());
  return v;
}

std::vector<BodyDef> r3_tower(int n) {
  std::vector<BodyDef> v;
  v.reserve(n + 1);
  for (int k = 0; k < n; ++k) v.push_back(r3_cube("cube" + std::to_string(k), Vec3(0, 0, 0.5 + k)));
  v.push_back(r3_ground());
  return v;
}

std::vector<BodyDef> r3_pyramid(int base) {
  std::vector<BodyDef> v;
  v.reserve(base * (base + 1) / 2 + 1);
  for (int r = 0; r < base; ++r)
    for (int j = r; j < base; ++j) {
      // Box3D's x = (r + 1) h + 2 (j - r) h - h base with h = 0.5 m.
      BodyDef b =
          r3_cube("cube" + std::to_string(v.size()), Vec3(0.5 * (r + 1) + (j - r) - 0.5 * base, 0, 0.5 + r));
      for (Collider& c : b.colliders) c.friction = kPyramidFriction;
      v.push_back(std::move(b));
    }
  v.push_back(r3_ground(0.0, kPyramidFriction));
  return v;
}

std::vector<BodyDef> r3_cube_grid_drop(int nx, int ny, double spacing, double height) {
  std::vector<BodyDef> v;
  v.reserve(nx * ny + 1);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      v.push_back(r3_cube("cube" + std::to_string(v.size()),
                          Vec3((i - 0.5 * (nx - 1)) * spacing, (j - 0.5 * (ny - 1)) * spacing, height)));
  v.push_back(r3_ground());
  return v;
}

}  // namespace simreel
