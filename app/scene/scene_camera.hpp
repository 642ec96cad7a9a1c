// Reading the moving camera's keys (`camera.path`, `camera.orbit`, `camera.follow: { body,
// damping }`) and the shutter (`render.motion_blur`); what they do is in
// app/scene/camera_motion.hpp, the keys in scenes/README.md.
#pragma once
#include <yaml-cpp/yaml.h>

#include <string>

#include "app/scene/camera_motion.hpp"
#include "app/scene/scene_yaml.hpp"

namespace simreel {

struct Scene;

// `camera.follow`: a body name, or { body: NAME, damping: S } (damping: s, >= 0; 0 is rigid).
// Returns the name (checked against the bodies by load_scene).
std::string camera_follow(const YAML::Node& n, const scene_yaml::Ctx& c, double& damping);

// `camera.path` and `camera.orbit` into s.camera, once the camera block and the bodies are read,
// with every combination that makes no sense refused (a path or an orbit with `auto` or `follow`,
// an orbit with `frame` or a path). Throws InputError "FILE:LINE:COL: KEY: what".
void load_camera_motion(const YAML::Node& root, const std::string& path, Scene& s);

// `render.motion_blur: { samples: N, shutter: S }`.
MotionBlurSpec motion_blur(const YAML::Node& n, const scene_yaml::Ctx& c);

}  // namespace simreel
