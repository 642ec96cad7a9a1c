// The scene's `forces:` list (scenes/README.md, "Forces") read into sim/dynamics/forces.hpp records.
#pragma once
#include <string>
#include <vector>

#include <simreel/body.hpp>
#include "sim/dynamics/forces.hpp"

namespace YAML {
class Node;
}

namespace simreel {

// `list` is the value of the top-level `forces` key; bodies are named against `bodies` (the
// ground body included). Throws InputError "FILE:LINE:COL: forces[K].KEY: what is wrong" for
// anything a user could get wrong; notes (an impulse after the end of the run) are appended to
// `notes`. A spring without `rest_length` is unstretched at the start. A `drag` without bodies and an entry
// with `bodies: [...]` become one record per body.
std::vector<ForceDef> load_forces(const YAML::Node& list, const std::string& file,
                                  const std::vector<BodyDef>& bodies, double duration,
                                  std::vector<std::string>& notes);

}  // namespace simreel
