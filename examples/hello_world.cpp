// simreel's dynamics core from C++: a body made from a mesh (a square pyramid, mass properties
// exact from its geometry), a thrust on it, a loop of fixed steps, the state printed.
#include <cstdio>
#include <memory>

#include <simreel/simreel.hpp>

using namespace simreel;

int main() {
  // A square pyramid, 1 m base, 1.5 m tall: five vertices, six triangles wound counter-clockwise
  // seen from outside.
  auto mesh = std::make_shared<TriangleMesh>();
  mesh->vertices = {{-0.5, -0.5, 0}, {0.5, -0.5, 0}, {0.5, 0.5, 0}, {-0.5, 0.5, 0}, {0, 0, 1.5}};
  mesh->triangles = {{0, 2, 1}, {0, 3, 2}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};

  BodyDef pyramid;
  pyramid.name = "pyramid";
  pyramid.p_WB = Vec3(0, 0, 2);                                                // m
  pyramid.w_W = Vec3(0, 0, 3);                                                 // rad/s, a spin about its axis
  const MassProperties& m = pyramid.add_collider(mesh_collider(mesh, 700.0));  // kg/m^3: pine
  std::printf("mass %.4f kg (exact: 700 x 0.5 m^3 = 350), centroid height %.4f m (exact: 1.5 / 4)\n", m.mass,
              m.com.z());

  WorldConfig config;
  config.dt = 1.0 / 240;  // s
  World world(config, {pyramid});
  for (int step = 1; step <= 240; ++step) {
    world.apply_force(0, Vec3(0, 0, 4000), world.centroid(0));  // N, upward thrust through the centroid
    world.step();
    if (step % 60 == 0) {
      const Vec3 p = world.centroid(0), v = world.linear_velocity(0), w = world.angular_velocity(0);
      std::printf("t = %.2f s: centroid (%.4f, %.4f, %.4f) m, velocity z %.4f m/s, spin %.4f rad/s\n",
                  world.time(), p.x(), p.y(), p.z(), v.z(), w.z());
    }
  }
  // With thrust 4000 N on 350 kg: a = 4000/350 - 9.81 = 1.6186 m/s^2 upward, so v(1 s) = 1.6186.
  return 0;
}
