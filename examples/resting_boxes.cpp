// Boxes dropped on the ground come to rest, and the ground carries their weight: the contact
// read-out's forces under each box add up to m g. At rest the last substep's impulses cancel
// gravity's over that substep, so the sum equals the weight to rounding (1e-16 here); the check
// allows 1e-6 of it. A read-out that divided by the step instead of the substep would be 4x off.
#include <cmath>
#include <cstdio>
#include <vector>

#include <simreel/simreel.hpp>

using namespace simreel;

int main() {
  std::vector<BodyDef> bodies;
  BodyDef ground;
  ground.name = "ground";
  ground.type = BodyType::static_body;
  ground.add_collider(plane_collider());
  bodies.push_back(ground);

  // Three boxes of different sizes and densities, dropped from 10-30 cm, side by side.
  const Vec3 sizes[3] = {{0.2, 0.2, 0.2}, {0.4, 0.3, 0.1}, {0.1, 0.1, 0.5}};
  const double densities[3] = {500.0, 2700.0, 7800.0};  // kg/m^3: pine, aluminium, steel
  for (int k = 0; k < 3; ++k) {
    BodyDef box;
    box.name = "box " + std::to_string(k);
    box.p_WB = Vec3(0.6 * k, 0, sizes[k].z() / 2 + 0.1 * (k + 1));  // m
    box.add_collider(box_collider(sizes[k], densities[k]));
    bodies.push_back(box);
  }

  WorldConfig config;
  config.dt = 1.0 / 240;  // s
  World world(config, bodies);
  for (int step = 0; step < 480; ++step) world.step();  // 2 s: dropped, landed, settled

  const double g = -config.gravity.z();
  std::vector<ContactData> contacts;
  int failures = 0;
  for (int i = 1; i < world.body_count(); ++i) {
    contacts.clear();
    world.body_contacts(i, contacts);
    // The ground is side a of each of the box's pairs here: its force on the box is what holds it.
    Vec3 support = Vec3::Zero();
    int points = 0;
    for (const ContactData& c : contacts) {
      if (c.body_a != 0) continue;
      support += c.force_W();
      points += c.count;
    }
    const double weight = world.mass(i) * g;
    const double rel = std::abs(support.z() - weight) / weight;
    std::printf(
        "%s: mass %.3f kg, weight %.3f N, ground pushes %.3f N up at %d points (%.2e of the weight "
        "off), %s\n",
        world.def(i).name.c_str(), world.mass(i), weight, support.z(), points, rel,
        world.asleep(i) ? "asleep" : "awake");
    if (!(rel < 1e-6) || points < 4) ++failures;
  }
  std::printf(failures ? "FAILED: a box is not held by its weight\n" : "every box rests on its weight\n");
  return failures ? 1 : 0;
}
