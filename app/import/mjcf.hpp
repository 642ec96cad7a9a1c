// MJCF (MuJoCo's XML model format) read into a Model (app/import/model.hpp): a subset, and
// everything outside it a note naming file and line, never a hard failure (Debian's MuJoCo
// 2.2.2 rejects 5 of 8 current files from MuJoCo's own repository over single new attributes).
#pragma once
#include <string>

#include "app/import/model.hpp"
#include "app/import/urdf.hpp"

namespace simreel {

// Reads nested bodies (pos, quat, euler, axisangle, xyaxes, zaxis), `freejoint`, hinge, slide and
// ball joints (pos, axis, range, damping, stiffness, springref, frictionloss), `inertial`
// (diaginertia, fullinertia), geoms (plane, sphere, capsule, ellipsoid, cylinder, box, mesh;
// MuJoCo's half-size semantics, `fromto`, density or mass, contype/conaffinity, group, rgba,
// material, friction), cascading `default` classes with `childclass`, `compiler` (angle,
// eulerseq, meshdir, texturedir, assetdir), mesh assets from files (with scale) and inline
// vertices (their convex hull), materials with 2D image textures, `equality` connect and weld
// (closed loops), and `include`. A `joint` without a type is a hinge. A body with several joints
// becomes a chain of helper links (1e-9 of its mass each) carrying all but the last, in order.
// Throws InputError "FILE:LINE: body 'NAME': what" for what cannot be a model.
Model read_mjcf(const std::string& path, const ImportPaths& paths = {});

}  // namespace simreel
