// `repeat:` on bodies and joints: rows of identical bodies (a cradle's balls, a domino line) and the
// joints that hang each of them, expanded in the scene's YAML tree before it is read.
#pragma once
#include <yaml-cpp/yaml.h>

#include <string>

namespace simreel {

// Replaces each body with `repeat: { count: N, step: [dx, dy, dz] }` by N copies named NAME_1 ..
// NAME_N at position + k step (k = 0 .. N-1), and each joint with `repeat:` by N copies named
// likewise, each tying the k-th copy of a repeated body it names (the counts must agree) with its
// anchors moved by k step. Throws InputError "FILE:LINE:COL: KEY: what" on a bad `repeat:`.
void expand_repeats(YAML::Node& root, const std::string& path);

}  // namespace simreel
