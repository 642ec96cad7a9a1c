// Ghosts drawn: each ghost body's render meshes at its closed-form pose (app/scene/ghost.hpp), as
// translucent triangles of the overlay pass (render/overlay.hpp's ribbons: unlit, blended, depth-
// tested against the bodies), shaded on the CPU by a headlight so the shape reads. The ghost is
// grown by kGhostInflate about its centre of mass: where it agrees with the simulated body it
// wraps it in a thin translucent skin (no depth fighting with the body's own faces); where the
// integrator has drifted, it stands out. A frame's ghost is a function of the frame's time alone.
#pragma once
#include <array>
#include <vector>

#include <simreel/world.hpp>
#include "app/scene/scene.hpp"
#include "render/draw_list.hpp"

namespace simreel {

inline constexpr double kGhostInflate = 1.03;

// A body's colour lightened halfway to white: a ghost's and a snapshot's default.
inline std::array<float, 3> lightened(const std::array<float, 3>& c) {
  return {0.5f + 0.5f * c[0], 0.5f + 0.5f * c[1], 0.5f + 0.5f * c[2]};
}

// Body `body`'s render meshes as translucent overlay triangles with its centre of mass at x and its
// body frame at q_WB, grown by `inflate` about the centre of mass and lit by a headlight (the
// ghosts, and the `snapshot` item's copies of a body as it was).
void draw_body_copy(const World& w, const SceneMeshes& meshes, int body, const Vec3& x, const Quat& q_WB,
                    const Rgba& color, double inflate, DrawList& dl);

class GhostView {
 public:
  // `world` at the scene's initial state. Throws InputError naming the body when its motion has
  // no closed form after all (spinning exactly on the separatrix).
  GhostView(const Scene& scene, const World& world);
  bool empty() const { return ghosts_.empty(); }
  // Appends the ghosts at the world's time to dl.overlay (dl.camera set already), drawn with the
  // bodies' render meshes.
  void build(const World& w, const SceneMeshes& meshes, DrawList& dl) const;

 private:
  struct Ghost {
    int body;
    FreeMotion motion;
    Quat q_PB;  // body frame to principal axes
    Rgba color;
    Vec3 offset;
  };
  std::vector<Ghost> ghosts_;
};

}  // namespace simreel
