// A ghost: the closed-form motion of a free body (sim/dynamics/free_motion.hpp) drawn as a translucent copy
// over or beside the simulated body, so numerical error becomes visible (the body's `ghost:` key,
// scenes/README.md). Only where a closed form exists: a dynamic body that no force of the scene's
// `forces:` list acts on and that can touch nothing (every other body that could collide with it
// filtered out or in simulation.ignore_pairs). Uniform gravity is allowed: it exerts no torque,
// and the centre of mass follows the parabola.
#pragma once
#include <yaml-cpp/yaml.h>

#include <array>
#include <optional>
#include <string>

#include "app/scene/scene_yaml.hpp"
#include "sim/dynamics/free_motion.hpp"
#include <simreel/world.hpp>

namespace simreel {

struct Scene;

struct GhostSpec {
  bool on = false;
  std::optional<std::array<float, 3>> color;  ///< linear RGB; default: the body's colour, lighter
  double opacity = 0.35;                      ///< in (0, 1]
  Vec3 offset = Vec3::Zero();                 ///< m, world: drawn beside the body instead of over it
};

// A body's `ghost:` value: true / false, or { color, opacity, offset }.
GhostSpec parse_ghost(const YAML::Node& n, const scene_yaml::Ctx& c);

// Refuses (InputError naming the body's ghost key) every ghost without a closed form. Called by
// load_scene once bodies, forces and ignore_pairs are read; `root` for the keys' lines.
void check_ghosts(const YAML::Node& root, const std::string& path, const Scene& s);

// The closed form from body i's present state (the run's start), in world `w` (its gravity).
FreeMotion ghost_motion(const World& w, int i);

}  // namespace simreel
