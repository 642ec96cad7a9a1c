// Simulation state to a draw list: what to draw, where, in which colour. sim/ knows nothing of GL;
// the GL passes in renderer.cpp know nothing of bodies. A frame is the bodies (items), the unlit
// 3D overlay geometry (render/overlay.hpp) and the 2D screen layer (render/screen.hpp); app/
// fills the last two from a scene's `show:` and `overlays:` (app/view/overlays.hpp).
#pragma once
#include <Eigen/Core>
#include <array>
#include <vector>

#include <simreel/world.hpp>
#include "render/camera.hpp"
#include "render/image.hpp"
#include "render/overlay.hpp"
#include "render/screen.hpp"
#include "render/tessellate.hpp"

namespace simreel {

struct DrawItem {
  int mesh = 0;                  ///< index into the renderer's uploaded meshes
  Eigen::Matrix4f model;         ///< collider frame to world
  std::array<float, 3> color{};  ///< linear RGB
};

struct DrawList {
  std::vector<DrawItem> items;
  CameraView camera;
  Vec3 bounds_center = Vec3::Zero();  ///< m, sphere holding every body this frame
  double bounds_radius = 1;           ///< m
  OverlayList overlay;                ///< 3D overlay pass: empty for a scene without overlays
  ScreenLayer screen;                 ///< 2D, composited after anti-aliasing
};

// How one collider is drawn. Appearance is not part of sim/: app/ makes these from the scene.
struct ColliderStyle {
  std::array<float, 3> color{0.8f, 0.8f, 0.8f};  ///< linear RGB
  bool drawn = true;       ///< false: left out (the scene's ground plane, which the renderer's ground draws)
  double plane_size = 10;  ///< m, side of the square drawn for a plane collider
  /// A mesh collider's shading normals per triangle corner (app's, from the file), or none.
  const std::vector<std::array<Eigen::Vector3f, 3>>* normals = nullptr;
  /// A mesh collider's materials, texture coordinates, vertex colours and images from its file
  /// (render/material.hpp), or none: drawn in `color`, which a face without a material colour takes.
  const MeshAppearance* look = nullptr;
};
using SceneStyles = std::vector<std::vector<ColliderStyle>>;  ///< per body, per collider

// Bytes this process can still allocate: the least of the system's available memory
// (/proc/meminfo MemAvailable) and what the address-space and data limits (ulimit -v, -d) leave.
size_t available_memory();

// The static side, made once: one render mesh per distinct drawn shape (equal RenderMeshKeys,
// render/tessellate.hpp: a thousand bodies of one mesh file at one scale, or of boxes of one size,
// share one mesh), and per drawn collider its mesh and colour.
struct SceneMeshes {
  std::vector<RenderMesh> meshes;         ///< distinct
  std::vector<std::vector<int>> mesh_of;  ///< per body, per collider: its mesh, -1 if not drawn
  std::vector<std::vector<std::array<float, 3>>> color_of;  ///< per body, per collider: linear RGB
  size_t bytes = 0;                                         ///< vertex and index data of `meshes`
  std::vector<TextureImage> textures;  ///< decoded once per distinct image (RenderMesh::Part::texture)
  std::vector<std::string> notes;      ///< images that could not be decoded, and what was drawn instead
  // Bodies or colliders that `styles` does not reach get ColliderStyle{} (drawn, light grey).
  // `budget`: bytes this process may still allocate (default: available_memory()); the meshes
  // are held twice (here and in the GL, whose llvmpipe crashes with SIGSEGV when an upload finds
  // no memory), so more than half of it throws std::runtime_error saying how much is needed.
  explicit SceneMeshes(const World& w, const SceneStyles& styles = {}, size_t budget = available_memory());
};

// Fills `out`'s bodies, bounds and camera (reusing its storage) from the world's current state;
// leaves its overlay and screen layer alone. With follow >= 0 the camera
// target tracks that body's centre of mass and the eye keeps its offset from it.
void build_draw_list(const World& w, const SceneMeshes& sm, const CameraView& cam, int follow, DrawList& out);

}  // namespace simreel
