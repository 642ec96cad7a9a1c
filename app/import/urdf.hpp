// URDF (ROS's Unified Robot Description Format) read into a Model (app/import/model.hpp).
#pragma once
#include <string>
#include <vector>

#include "app/import/model.hpp"

namespace simreel {

struct ImportPaths {
  /// Folders searched for `package://NAME/...`: each may be the package folder itself (its name
  /// is NAME) or hold it; then ROS_PACKAGE_PATH's folders the same way; then the file's own
  /// folder and its ancestors (a URDF inside its package finds it).
  std::vector<std::string> package_paths;
};

// Reads a URDF file: links (inertials with their origin's rotation, visual and collision geometry:
// box, cylinder, sphere, mesh with scale, and capsule, which URDF 1.0 lacks but Bullet and
// Gazebo files use), materials (colour and texture, named at the top level or inline), joints
// (revolute, continuous, prismatic, fixed, floating, planar, and Bullet's spherical) with
// origin, axis, limits and dynamics. What it does not use (gazebo, transmission, mimic,
// safety_controller, calibration, unknown elements) is a note naming file and line.
// Throws InputError "FILE:LINE: link 'NAME': what" for a file that cannot be a robot: not XML, no
// <robot>, a xacro file (expand it first), a bad number, a joint naming an unknown link, a link
// with two parents, a loop, more than one root.
Model read_urdf(const std::string& path, const ImportPaths& paths = {});

// A mesh or texture path as URDF and MJCF files write it, resolved to a file: `package://P/x`
// through `paths`, `file://` URLs, relative paths against `base_dir`, and an absolute or Windows
// path from another machine by its file name beside `base_dir` (with a note). Throws InputError
// "WHERE: WHAT 'PATH' not found (looked in ...)" naming where it looked.
std::string resolve_asset(const std::string& path, const std::string& base_dir, const std::string& file,
                          const ImportPaths& paths, const std::string& where, const char* what,
                          std::vector<std::string>& notes);

}  // namespace simreel
