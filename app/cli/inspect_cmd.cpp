// simreel inspect: a mesh's volume, mass, inertia and principal axes, and its defects; a robot
// file's links, masses and joints as simreel reads them.
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/cli/cli.hpp"
#include "app/cli/commands.hpp"
#include "app/scene/mesh_import.hpp"
#include "app/scene/scene.hpp"
#include "app/scene/scene_imports.hpp"

namespace simreel {

namespace {

struct InspectOptions {
  std::vector<std::string> meshes;
  bool json = false;
  double density = MeshMassOptions{}.density, thickness = MeshMassOptions{}.thickness, scale = 1;
  std::string mode = to_string(MeshMassOptions{}.mode);
};

// inspect's option table.
void inspect_table(CLI::App& app, InspectOptions& o) {
  cli::setup(
      app, "inspect",
      "Prints a mesh's mass properties: volume, mass, centroid, inertia tensor about the centroid (mesh "
      "axes), principal moments and axes, and what was found and done about defects (open, "
      "inside-out, inconsistent winding, degenerate faces), and its bounding box. Given a URDF or MJCF "
      "file (.urdf, .xml), prints its bodies (mass, principal moments, shapes drawn and colliding) and "
      "joints as simreel places them, with the notes and inertia warnings.",
      "");
  cli::add_positionals(app, o.meshes);
  app.add_flag("--json", o.json, "print one JSON object");
  add_package_path(app);
  app.add_option("--density", o.density, "kg/m^3, default 1000")->type_name("RHO")->check(cli::positive());
  app.add_option("--mode", o.mode, "solid (default), shell (mass on the surface), hull (convex hull)")
      ->check(cli::choice({"solid", "shell", "hull"}));
  app.add_option("--thickness", o.thickness, "m, shell wall thickness (default 0.001)")
      ->type_name("T")
      ->check(cli::positive());
  app.add_option("--scale", o.scale, "multiply every coordinate (meshes authored in mm: 0.001)")
      ->type_name("S")
      ->check(cli::positive());
}

// A URDF or MJCF file as the importer places it (docs/import.md): each body with its links' mass
// properties, each joint, and the notes and warnings.
int inspect_model(const std::string& path, bool json) {
  const Scene s = load_scene(path);
  std::vector<int> bodies;
  for (size_t i = 0; i < s.bodies.size(); ++i)
    if (!(s.ground && i + 1 == s.bodies.size())) bodies.push_back((int)i);
  auto name = [&](int i) { return i < 0 ? std::string("world") : s.bodies[i].name; };
  if (json) {
    using J = nlohmann::ordered_json;
    auto vec = [](const Vec3& v) { return J::array({v.x(), v.y(), v.z()}); };
    J o;
    o["file"] = path;
    J jb = J::array();
    for (int i : bodies) {
      const BodyDef& b = s.bodies[i];
      J e;
      e["name"] = b.name;
      e["type"] = to_string(b.type);
      if (b.mass_override) {
        e["mass"] = b.mass_override->mass;
        e["center_of_mass"] = vec(b.mass_override->com);
        e["principal_moments"] = vec(principal_axes(b.mass_override->inertia).moments);
      }
      int drawn = 0, colliding = 0;
      for (size_t k = 0; k < b.colliders.size(); ++k) {
        drawn += s.looks[i].colliders[k].drawn;
        colliding += b.colliders[k].collide;
      }
      e["shapes_drawn"] = drawn;
      e["shapes_colliding"] = colliding;
      jb.push_back(e);
    }
    J jj = J::array();
    for (const JointDef& j : s.joints) {
      J e;
      e["name"] = j.name;
      e["type"] = to_string(j.type);
      e["parent"] = name(j.parent);
      e["child"] = name(j.child);
      e["anchor"] = vec(j.anchor_W);
      e["axis"] = vec(j.axis_W);
      if (j.limits) e["limits"] = J::array({j.limits->lower, j.limits->upper});
      jj.push_back(e);
    }
    o["bodies"] = jb;
    o["joints"] = jj;
    o["notes"] = s.notes;
    o["warnings"] = s.warnings;
    std::printf("%s\n", o.dump(-1, ' ', false, J::error_handler_t::replace).c_str());
    return kExitOk;
  }
  std::printf("%s: %zu bodies, %zu joints (as placed on the ground at the origin)\n", path.c_str(),
              bodies.size(), s.joints.size());
  for (int i : bodies) {
    const BodyDef& b = s.bodies[i];
    std::printf("  body %-28s %-8s", ("'" + b.name + "'").c_str(), to_string(b.type));
    if (b.mass_override) {
      const Vec3 m = principal_axes(b.mass_override->inertia).moments;
      std::printf(" mass %.6g kg, principal moments [%.4g, %.4g, %.4g] kg m^2", b.mass_override->mass, m[0],
                  m[1], m[2]);
    }
    int drawn = 0, colliding = 0;
    for (size_t k = 0; k < b.colliders.size(); ++k) {
      drawn += s.looks[i].colliders[k].drawn;
      colliding += b.colliders[k].collide;
    }
    std::printf(", %d drawn / %d colliding shapes\n", drawn, colliding);
  }
  for (const JointDef& j : s.joints) {
    std::printf("  joint %-27s %-9s %s -> %s", ("'" + j.name + "'").c_str(), to_string(j.type),
                name(j.parent).c_str(), name(j.child).c_str());
    if (j.limits) std::printf(", limits [%.4g, %.4g]", j.limits->lower, j.limits->upper);
    std::printf("\n");
  }
  for (const std::string& n : s.notes) std::printf("  note: %s\n", n.c_str());
  for (const std::string& w : s.warnings) std::printf("  warning: %s\n", w.c_str());
  return kExitOk;
}

}  // namespace

int cmd_inspect(const std::vector<std::string>& args) {
  InspectOptions o;
  CLI::App app;
  inspect_table(app, o);
  if (!cli::parse(app, args)) return kExitOk;
  if (o.meshes.size() != 1) throw UsageError("inspect takes one mesh file");
  MeshMassOptions opt;
  opt.density = o.density;
  opt.thickness = o.thickness;
  opt.mode = *mass_mode_from_name(o.mode);  // the table checked the name
  const double scale = o.scale;
  const std::string path = o.meshes[0];
  if (is_model_file(path)) return inspect_model(path, o.json);
  {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& ch : ext) ch = (char)std::tolower((unsigned char)ch);
    if (ext == ".yaml" || ext == ".yml")
      throw UsageError("'" + path +
                       "' is a scene file, not a mesh: inspect weighs one mesh (OBJ, OFF, STL, PLY, or "
                       "any format assimp reads); simulate and render take scenes");
  }
  const ImportedMesh im = import_mesh(path, Vec3::Constant(scale));
  const TriangleMesh& mesh = im.mesh;
  MeshReport r;
  try {
    r = analyze_mesh(mesh, opt);
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
  r.warnings.insert(r.warnings.begin(), im.notes.begin(), im.notes.end());
  const PrincipalAxes pa = principal_axes(r.props.inertia);
  // The bounding box (mesh axes), and what it suggests about the file's units.
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Vec3& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  if (const double big = (hi - lo).maxCoeff(); big > 50 && scale == 1)
    r.warnings.push_back("the mesh is " + std::to_string((int)std::lround(big)) +
                         " m across: if the file is in millimetres, weigh it with --scale 0.001 (a scene's "
                         "collider: scale: 0.001)");
  // The file's look as render draws it (render/material.hpp): its materials (colour, image), and
  // whether it has texture coordinates and vertex colours.
  const MeshAppearance* look = im.appearance.get();
  auto image_of = [&](const SurfaceMaterial& m) -> std::string {
    if (!look || m.texture < 0 || m.texture >= (int)look->textures.size()) return "";
    const TextureSource& t = look->textures[m.texture];
    return t.bytes ? "embedded " + t.name : t.file;
  };
  if (o.json) {
    using J = nlohmann::ordered_json;
    auto vec = [](const Vec3& v) { return J::array({v.x(), v.y(), v.z()}); };
    auto mat = [&](const Mat3& m) { return J::array({vec(m.row(0)), vec(m.row(1)), vec(m.row(2))}); };
    J o;
    o["file"] = path;
    o["reader"] = im.reader;
    o["precision"] = im.double_precision() ? "double" : "float32";
    o["mode"] = to_string(opt.mode);
    o["density"] = opt.density;
    o["bounds_min"] = vec(lo);
    o["bounds_max"] = vec(hi);
    o["extents"] = vec(hi - lo);
    o["vertices"] = mesh.vertices.size();
    o["faces"] = mesh.triangles.size();
    o["volume"] = r.volume;
    o["area"] = r.area;
    o["mass"] = r.props.mass;
    o["centroid"] = vec(r.props.com);
    o["inertia"] = mat(r.props.inertia);
    o["principal_moments"] = vec(pa.moments);
    o["principal_axes"] = mat(pa.R.transpose());
    o["closed"] = r.closed;
    o["consistently_oriented"] = r.consistently_oriented;
    o["welded_vertices"] = r.welded_vertices;
    o["degenerate_faces"] = r.degenerate_faces;
    o["reoriented_faces"] = r.reoriented_faces;
    o["inverted"] = r.inverted;
    J materials = J::array();
    if (look)
      for (const SurfaceMaterial& m : look->materials) {
        J jm;
        jm["name"] = m.name;
        jm["color"] = m.color[0] >= 0 ? J::array({m.color[0], m.color[1], m.color[2]}) : J();
        jm["image"] = image_of(m).empty() ? J() : J(image_of(m));
        materials.push_back(jm);
      }
    o["look"] = {{"materials", materials},
                 {"texture_coordinates", look && !look->corner_uv.empty()},
                 {"vertex_colors", look && !look->corner_color.empty()},
                 {"drawn_with_it", look && look->varies}};
    o["warnings"] = r.warnings;
    std::printf("%s\n", o.dump(-1, ' ', false, J::error_handler_t::replace).c_str());
    return kExitOk;
  }
  auto row = [](const Vec3& v) {
    char b[128];
    std::snprintf(b, sizeof b, "[% .10g, % .10g, % .10g]", v.x(), v.y(), v.z());
    return std::string(b);
  };
  std::printf("%s (%s, %zu vertices, %zu faces as loaded; read by %s in %s precision)\n", path.c_str(),
              to_string(opt.mode), mesh.vertices.size(), mesh.triangles.size(), im.reader.c_str(),
              im.double_precision() ? "double" : "single");
  std::printf("  bounds:   %s .. %s m (extents %s)\n", row(lo).c_str(), row(hi).c_str(),
              row(hi - lo).c_str());
  std::printf("  closed: %s, consistently oriented: %s\n", r.closed ? "yes" : "no",
              r.consistently_oriented ? "yes" : "no");
  std::printf("  volume:   %.12g m^3\n  area:     %.12g m^2\n  mass:     %.12g kg (density %g kg/m^3)\n",
              r.volume, r.area, r.props.mass, opt.density);
  std::printf("  centroid: %s m\n", row(r.props.com).c_str());
  std::printf("  inertia about the centroid, mesh axes (kg m^2):\n");
  for (int i = 0; i < 3; ++i) std::printf("    %s\n", row(r.props.inertia.row(i)).c_str());
  std::printf("  principal moments: %s kg m^2\n", row(pa.moments).c_str());
  for (int i = 0; i < 3; ++i) std::printf("  axis %d: %s\n", i + 1, row(pa.R.col(i)).c_str());
  if (look) {
    std::printf(
        "  look: %zu material%s%s%s%s\n", look->materials.size(), look->materials.size() == 1 ? "" : "s",
        look->corner_uv.empty() ? "" : ", texture coordinates",
        look->corner_color.empty() ? "" : ", vertex colours", look->varies ? "" : " (drawn in one colour)");
    for (const SurfaceMaterial& m : look->materials) {
      char c[96] = "no colour";
      if (m.color[0] >= 0)
        std::snprintf(c, sizeof c, "colour [%.3g, %.3g, %.3g]", m.color[0], m.color[1], m.color[2]);
      const std::string img = image_of(m);
      std::printf("    %s: %s%s\n", m.name.empty() ? "(unnamed)" : m.name.c_str(), c,
                  img.empty() ? "" : (", image " + img).c_str());
    }
  } else if (im.color) {
    std::printf("  look: one colour [%.3g, %.3g, %.3g]\n", (*im.color)[0], (*im.color)[1], (*im.color)[2]);
  }
  for (const std::string& w : r.warnings) std::printf("  warning: %s\n", w.c_str());
  return kExitOk;
}

}  // namespace simreel
