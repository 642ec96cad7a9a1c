// simreel inspect: a mesh's volume, mass, inertia and principal axes, and its defects.
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/cli/cli.hpp"
#include "app/cli/commands.hpp"
#include "app/scene/mesh_import.hpp"

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
      "inside-out, inconsistent winding, degenerate faces).",
      "");
  cli::add_positionals(app, o.meshes);
  app.add_flag("--json", o.json, "print one JSON object");
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
