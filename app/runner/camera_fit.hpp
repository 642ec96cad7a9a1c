// Cameras that see the scene: `camera: { auto: true }` fitted to everything over the whole run,
// and the check behind the warning that most frames show no body at all (a scene in metres by
// mistake, a camera inside a 100 m box).
#pragma once
#include <string>
#include <vector>

#include "app/scene/scene.hpp"
#include <simreel/world.hpp>

namespace simreel {

// m, a sphere about each body's origin... about its centre of mass holding all its colliders
// (planes excluded: they are infinite, and drawn as the ground). 0 for a body of planes only.
std::vector<double> body_radii(const World& w);

// Fits scene.camera when scene.camera.fit: runs the scene once (threads as given), takes the box
// holding every body's bounding sphere at every frame, then aims look_at at its centre and moves
// the camera along its viewing direction (position - look_at, kept) to the nearest distance at
// which all eight corners of the box are in view with a 10% margin. Returns a note saying where
// the camera went, "" when nothing was done.
std::string fit_camera(Scene& scene, int threads);

// Whether any body's bounding sphere reaches into the view of a camera at `eye` looking at
// `target` (vertical field of view fov_deg, width / height = aspect), at this state.
bool any_body_in_view(const World& w, const std::vector<double>& radii, const Vec3& eye, const Vec3& target,
                      const Vec3& up, double fov_deg, double aspect);

// The body whose bounding sphere holds the point, or -1 (a camera inside a body sees nothing).
int body_around(const World& w, const std::vector<double>& radii, const Vec3& p);

}  // namespace simreel
