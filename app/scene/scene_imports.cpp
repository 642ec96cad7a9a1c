#include "app/scene/scene_imports.hpp"

#include <yaml-cpp/yaml.h>

#include <filesystem>

#include "app/import/mjcf.hpp"
#include "app/import/place.hpp"
#include "app/import/urdf.hpp"
#include "app/scene/mesh_library.hpp"
#include "app/scene/scene.hpp"
#include "app/scene/scene_yaml.hpp"
#include "app/scene/text.hpp"

namespace simreel {

using namespace scene_yaml;
namespace fs = std::filesystem;

bool is_model_file(const std::string& path) {
  const std::string e = lower_extension(path);
  return e == ".urdf" || e == ".xacro" || e == ".xml" || e == ".mjcf";
}

std::string scene_for_model_file(const std::string& path) {
  std::string name = fs::path(path).filename().string(), quoted = "\"";
  for (char c : name) {
    if (c == '"' || c == '\\') quoted += '\\';
    quoted += c;
  }
  quoted += '"';
  return "simulation: { duration: 5 }\n"
         "camera: { auto: true }\n"
         "ground: true\n"
         "imports:\n"
         "  - { file: " +
         quoted + ", on_ground: true }\n";
}

void load_imports(const YAML::Node& list, const std::string& path, Scene& scene, MeshLibrary& meshes) {
  const Ctx top(path, "imports");
  if (!list.IsSequence())
    top.fail(list, "expected a list of files to place ({ file: robot.urdf, ... }), got " + show(list));
  const fs::path dir = fs::path(path).parent_path();
  for (size_t k = 0; k < list.size(); ++k) {
    const YAML::Node n = list[k];
    const Ctx c = top.index(k);
    if (!n.IsMap()) c.fail(n, "expected { file: robot.urdf, name, position, ... }, got " + show(n));
    check_keys(n, c,
               {"file", "name", "position", "orientation", "euler", "axis_angle", "fixed_base", "inertia",
                "package_paths", "show", "hold", "self_collision", "on_ground", "joint_positions",
                "collision", "keyframe", "camera"});
    if (!n["file"]) c.fail(n, "missing key 'file' (a URDF file)");
    ImportSpec spec;
    const std::string f = text(n["file"], c.child("file"));
    const fs::path fp = fs::path(f).is_absolute() ? fs::path(f) : dir / f;
    std::error_code ec;
    if (!fs::is_regular_file(fp, ec))
      c.child("file").fail(n["file"], "file '" + f + "' not found (looked for " +
                                          fs::absolute(fp, ec).lexically_normal().string() + ")");
    spec.file = fp.lexically_normal().string();
    spec.src = {path, n.Mark().line + 1, "imports[" + std::to_string(k) + "]"};
    if (n["name"]) {
      spec.name = text(n["name"], c.child("name"));
      if (spec.name.find('/') != std::string::npos)
        c.child("name").fail(n["name"], "must not contain '/' (it prefixes the model's names: NAME/link)");
    }
    if (n["position"]) spec.pose.p = vec<3>(n["position"], c.child("position"));
    orientation(n, c, spec.pose.q);
    if (n["fixed_base"]) spec.fixed_base = boolean(n["fixed_base"], c.child("fixed_base"));
    if (n["on_ground"]) {
      spec.on_ground = boolean(n["on_ground"], c.child("on_ground"));
      if (spec.on_ground && n["position"] && spec.pose.p.z() != 0)
        c.child("on_ground")
            .fail(n["on_ground"], "sets the height: give position's z as 0, or leave on_ground out");
      spec.ground_height = scene.ground ? scene.ground->height : 0;
    }
    if (const YAML::Node jp = n["joint_positions"]) {
      const Ctx jc = c.child("joint_positions");
      if (!jp.IsMap()) jc.fail(jp, "expected { JOINT: value, ... } (rad or m), got " + show(jp));
      for (const auto& kv : jp) {
        const std::string name = kv.first.as<std::string>();
        spec.joint_positions[name] = number(kv.second, jc.child(name));
      }
    }
    if (n["keyframe"]) spec.keyframe = text(n["keyframe"], c.child("keyframe"));
    if (n["camera"]) {
      spec.camera = text(n["camera"], c.child("camera"));
      if (scene.camera_given)
        c.child("camera").fail(n["camera"],
                               "the scene gives its own camera: give one of camera, imports' camera");
    }
    if (n["collision"]) {
      const std::string v = text(n["collision"], c.child("collision"));
      if (v != "hull" && v != "decompose")
        c.child("collision").fail(n["collision"], "expected hull or decompose, got '" + v + "'");
      spec.decompose = v == "decompose";
    }
    if (n["hold"]) spec.hold = boolean(n["hold"], c.child("hold"));
    if (n["self_collision"]) spec.self_collision = boolean(n["self_collision"], c.child("self_collision"));
    if (n["inertia"]) {
      const std::string v = text(n["inertia"], c.child("inertia"));
      if (v == "check")
        spec.inertia = InertiaPolicy::check;
      else if (v == "geometry")
        spec.inertia = InertiaPolicy::geometry;
      else if (v == "file")
        spec.inertia = InertiaPolicy::file;
      else {
        std::string msg = "unknown inertia policy '" + v + "' (check, geometry, file)";
        if (auto s = nearest(v, {"check", "geometry", "file"})) msg += "; did you mean '" + *s + "'?";
        c.child("inertia").fail(n["inertia"], msg);
      }
    }
    if (const YAML::Node pp = n["package_paths"]) {
      const Ctx pc = c.child("package_paths");
      if (!pp.IsSequence()) pc.fail(pp, "expected a list of folders, got " + show(pp));
      for (size_t i = 0; i < pp.size(); ++i) {
        const std::string d = text(pp[i], pc.index(i));
        const fs::path dp = fs::path(d).is_absolute() ? fs::path(d) : dir / d;
        if (!fs::is_directory(dp, ec))
          pc.index(i).fail(pp[i], "folder '" + d + "' not found (looked for " +
                                      fs::absolute(dp, ec).lexically_normal().string() + ")");
        spec.paths.package_paths.push_back(dp.lexically_normal().string());
      }
    }
    if (const YAML::Node sh = n["show"]) {
      const Ctx sc = c.child("show");
      if (!sh.IsSequence()) sc.fail(sh, "expected a list such as [colliders], got " + show(sh));
      for (size_t i = 0; i < sh.size(); ++i) {
        const std::string item = text(sh[i], sc.index(i));
        if (item != "colliders")
          sc.index(i).fail(sh[i], "unknown item '" + item + "' (colliders: draw the collision shapes)");
        spec.show_colliders = true;
      }
    }
    const std::string ext = lower_extension(spec.file);
    Model model;
    if (ext == ".urdf" || ext == ".xacro") {
      if (!spec.keyframe.empty())
        c.child("keyframe").fail(n["keyframe"], "a URDF file has no keyframes (give joint_positions)");
      if (!spec.camera.empty())
        c.child("camera").fail(n["camera"], "a URDF file has no cameras (give the scene a camera)");
      model = read_urdf(spec.file, spec.paths);
    } else if (ext == ".xml" || ext == ".mjcf") {
      model = read_mjcf(spec.file, spec.paths);
      if (!spec.keyframe.empty()) apply_keyframe(model, spec, scene.notes);
    } else {
      c.child("file").fail(n["file"], "'" + f + "' is not a URDF (.urdf) or MJCF (.xml, .mjcf) file");
    }
    place_model(model, spec, scene, meshes);
  }
}

}  // namespace simreel
