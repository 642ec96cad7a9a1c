// Simulation state to a draw list: what to draw, where, in which colour. sim/ knows nothing of GL;
// the GL passes in renderer.cpp know nothing of bodies. A frame is the bodies (items), the unlit
// 3D overlay geometry (render/overlay.hpp) and the 2D screen layer (render/screen.hpp); app/
// fills the last two from a scene's `show:` and `overlays:` (app/overlays.hpp).
#pragma once
#include <Eigen/Core>
#include <array>
#include <vector>

#include "render/camera.hpp"
#include "render/overlay.hpp"
#include "render/screen.hpp"
#include "render/tessellate.hpp"
#include "sim/world.hpp"

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
};
using SceneStyles = std::vector<std::vector<ColliderStyle>>;  ///< per body, per collider

// The static side: one render mesh per drawn collider, in body order, made once.
struct SceneMeshes {
  std::vector<RenderMesh> meshes;
  std::vector<std::array<float, 3>> colors;  ///< per mesh, linear RGB
  std::vector<std::vector<int>> mesh_of;     ///< per body, per collider: its mesh, -1 if not drawn
  // Bodies or colliders that `styles` does not reach get ColliderStyle{} (drawn, light grey).
  explicit SceneMeshes(const World& w, const SceneStyles& styles = {});
};

// Fills `out`'s bodies, bounds and camera (reusing its storage) from the world's current state;
// leaves its overlay and screen layer alone. With follow >= 0 the camera
// target tracks that body's centre of mass and the eye keeps its offset from it.
void build_draw_list(const World& w, const SceneMeshes& sm, const CameraView& cam, int follow, DrawList& out);

}  // namespace simreel
