// The scene's `joints:` list (scenes/README.md, "Joints") read into <simreel/joints.hpp> records.
#pragma once
#include <string>
#include <vector>

#include <simreel/body.hpp>
#include <simreel/joints.hpp>

namespace YAML {
class Node;
}

namespace simreel {

// `list` is the value of the top-level `joints` key; bodies are named against `bodies` (the ground
// body included), `world` (or `ground` when no body has that name) is the fixed frame. Throws
// InputError "FILE:LINE:COL: joints[K].KEY: what is wrong" for anything a user could get wrong;
// an anchor far from both of its bodies is a note.
std::vector<JointDef> load_joints(const YAML::Node& list, const std::string& file,
                                  const std::vector<BodyDef>& bodies, std::vector<std::string>& notes);

}  // namespace simreel
