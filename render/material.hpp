// A mesh file's look: materials per triangle, texture coordinates and vertex colours per triangle
// corner, and the base-colour images the materials name. Made by app/scene/mesh_import.cpp from
// the file, drawn by the renderer (render/tessellate.cpp lays it into the vertices, render/image.hpp
// decodes the images). No GL here: scenes are parsed without the renderer.
//
// A corner's base colour is material colour x vertex colour x texture sample, all linear RGB: the
// glTF 2.0 rule (baseColorFactor x COLOR_0 x baseColorTexture), which is also what OBJ/MTL's Kd
// with map_Kd means. Metalness and roughness are not drawn: the lit shader shades every surface as
// a dielectric from its base colour (glTF's default metallicFactor of 1 would otherwise draw a
// material without an environment map black).
#pragma once
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace simreel {

// Where a base-colour image comes from: a file beside the mesh, or bytes embedded in it (a glb).
struct TextureSource {
  std::string file;                          ///< resolved path, or "" when embedded
  std::shared_ptr<const std::string> bytes;  ///< an embedded image's encoded bytes (PNG, JPEG...)
  std::string name;                          ///< as the mesh file names it, for messages
};

struct SurfaceMaterial {
  std::string name;
  std::array<float, 3> color{1, 1, 1};  ///< linear RGB base colour (multiplies the texture)
  int texture = -1;                     ///< index into MeshAppearance::textures, or -1
};

struct MeshAppearance {
  std::vector<SurfaceMaterial> materials;
  std::vector<TextureSource> textures;
  std::vector<int32_t> triangle_material;  ///< per triangle of the mesh: index into materials, or -1
  /// Per triangle corner, OpenGL's convention (v up from the image's bottom row); empty if none.
  std::vector<std::array<Eigen::Vector2f, 3>> corner_uv;
  /// Per triangle corner, linear RGB; empty if the file has no vertex colours.
  std::vector<std::array<std::array<float, 3>, 3>> corner_color;
  /// More than one colour to draw: faces of different material colours, an image or vertex
  /// colours. A file with texture coordinates alone has a look that does not vary (drawn in one
  /// colour), kept for a scene's `texture:`.
  bool varies = false;
};

// One image laid over a whole mesh through the texture coordinates of `file_look` (which must
// have them): a scene collider's `texture:`, a URDF or MJCF material's image. Its material colour
// is -1, so the item's own colour tints the image.
inline std::shared_ptr<MeshAppearance> image_on_uvs(const MeshAppearance& file_look,
                                                    const std::string& image) {
  auto a = std::make_shared<MeshAppearance>();
  a->corner_uv = file_look.corner_uv;
  a->materials.push_back({"texture", {-1.f, -1.f, -1.f}, 0});
  a->textures.push_back({image, nullptr, image});
  a->triangle_material.assign(a->corner_uv.size(), 0);
  a->varies = true;
  return a;
}

// Raw texels as an image's bytes (an embedded image some formats store uncompressed): this header,
// then width x height RGBA8 texels, top row first; render/image.hpp decodes it like a PNG.
inline constexpr char kRawRgbaMagic[8] = {'S', 'R', 'R', 'G', 'B', 'A', '1', 0};
inline std::string raw_rgba_header(uint32_t width, uint32_t height) {
  std::string h(kRawRgbaMagic, 8);
  for (uint32_t v : {width, height})
    for (int k = 0; k < 4; ++k) h += (char)((v >> (8 * k)) & 0xff);
  return h;
}

// An sRGB-encoded component in [0, 1] (a PNG's texel, a PLY file's colour byte / 255) to linear
// light (IEC 61966-2-1).
inline float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

}  // namespace simreel
