// The scene's `imports:` list (scenes/README.md, "Robots and rigs from files"): URDF files placed
// into the scene as bodies and joints (app/import/).
#pragma once
#include <string>

namespace YAML {
class Node;
}

namespace simreel {

struct Scene;
class MeshLibrary;

// Reads each entry and places its file's links and joints after the scene's bodies. Throws
// InputError "FILE:LINE:COL: imports[K].KEY: what" for the scene's mistakes, and the imported
// file's own "FILE:LINE: link 'NAME': what" for its.
void load_imports(const YAML::Node& list, const std::string& path, Scene& scene, MeshLibrary& meshes);

// The scene a robot file makes alone (`simreel simulate robot.urdf`): the file as the only import,
// on a ground, seen by an automatic camera, for 5 s.
std::string scene_for_model_file(const std::string& path);

// True when `path` names a file that `imports` takes (.urdf, .xacro, .xml, .mjcf).
bool is_model_file(const std::string& path);

}  // namespace simreel
