// Unlit 3D overlay geometry, in world space: what the overlay pass draws after the bodies (arrows,
// axes, trails, curves, translucent surfaces). Depth-tested against the bodies; an item with
// `xray` > 0 also shows its hidden parts, faded to that opacity. Colours are linear RGB, as the
// bodies' (the pass gamma-encodes them), with an alpha. The lists are refilled every frame and
// keep their storage: no allocation per frame once they have grown.
#pragma once
#include <Eigen/Core>
#include <array>
#include <vector>

#include <simreel/math.hpp>

namespace simreel {

using Rgba = std::array<float, 4>;  ///< linear RGB and alpha in [0, 1]

// Unit meshes the overlay pass instances: cylinder and cone of radius 1 along +z from 0 to 1
// (capped), sphere of radius 1.
enum class OverlayShape { cylinder, cone, sphere };
inline constexpr int kOverlayShapes = 3;

struct OverlayInstance {
  Eigen::Matrix4f model;  ///< unit mesh to world: affine, its 3x3 part with orthogonal columns
  Rgba color{1, 1, 1, 1};
  float xray = 0;  ///< opacity of the parts hidden behind bodies; 0: hidden parts not drawn
};

struct OverlayVertex {
  float pos[3];   ///< m, world
  float rgba[4];  ///< linear RGB, alpha
};

struct OverlayList {
  std::array<std::vector<OverlayInstance>, kOverlayShapes> instances;
  std::vector<OverlayVertex> ribbons;  ///< triangles, drawn translucent after the solids
  float ribbon_xray = 0;               ///< as OverlayInstance::xray, for every ribbon

  void clear() {
    for (auto& v : instances) v.clear();
    ribbons.clear();
  }
  bool empty() const {
    for (const auto& v : instances)
      if (!v.empty()) return false;
    return ribbons.empty();
  }

  // An arrow from `from` to `from + vec` (m): a shaft of radius `radius` and a cone head of
  // radius 2.5 * radius and length min(6 * radius, 0.4 |vec|), its tip exactly at from + vec.
  // Nothing for a vector shorter than a tenth of the radius.
  void arrow(const Vec3& from, const Vec3& vec, double radius, const Rgba& color, float xray = 0);
  // A cone with its apex at `apex`, opening along `axis` (m: apex to the base's centre), base
  // radius `radius` (m).
  void cone(const Vec3& apex, const Vec3& axis, double radius, const Rgba& color, float xray = 0);
  // A rod (capped cylinder) from a to b.
  void rod(const Vec3& a, const Vec3& b, double radius, const Rgba& color, float xray = 0);
  // A sphere, or an ellipsoid: centre, semi-axes (m) along the columns of `axes` (orthonormal).
  void ellipsoid(const Vec3& center, const Mat3& axes, const Vec3& semi_axes, const Rgba& color,
                 float xray = 0);
  // A parallelogram centred on `center` with half-sides `u` and `v` (m), translucent with the ribbons.
  void quad(const Vec3& center, const Vec3& u, const Vec3& v, const Rgba& color);
  // A polyline as a flat ribbon `width` m wide facing `eye`, one colour per point (a fade).
  // `n` points; nothing for fewer than two.
  void ribbon(const Vec3* points, const Rgba* colors, int n, const Vec3& eye, double width);
};

// Two unit vectors completing d (unit) to a right-handed orthonormal basis (e1 x e2 = d), chosen
// the same way every time for the same d.
void orthonormal_basis(const Vec3& d, Vec3& e1, Vec3& e2);

}  // namespace simreel
