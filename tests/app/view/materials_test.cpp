// A mesh file's look drawn as the render command draws it: base-colour textures through the
// file's texture coordinates (OBJ/MTL map_Kd, glTF external and embedded, a scene's `texture:`),
// a colour per material, vertex colours, sRGB-correct minification, and missing or broken images
// reported with the material colour drawn instead. Pixels are read off frames drawn with the
// camera straight above a unit quad, so where each texel lands is known without the renderer.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

#include <simreel/error.hpp>
#include "app/runner/frame_loop.hpp"
#include "app/scene/mesh_import.hpp"
#include "app/view/scene_view.hpp"
#include "render/image.hpp"
#include "render/png_writer.hpp"
#include "tests/scratch.hpp"

namespace simreel {
namespace {

namespace fs = std::filesystem;
using test::scratch;
using test::scratch_file;

constexpr int kW = 160, kH = 160;

struct Frame {
  std::vector<uint8_t> rgba;
  std::vector<std::string> notes;                      ///< the scene's and the renderer's
  std::array<int, 3> at(double fx, double fy) const {  ///< fx, fy in [0, 1] from the top left
    const int x = std::min(kW - 1, (int)(fx * kW)), y = std::min(kH - 1, (int)(fy * kH));
    const uint8_t* p = &rgba[((size_t)y * kW + x) * 4];
    return {p[0], p[1], p[2]};
  }
};

// The scene's `bodies:` drawn from straight above (+y up in the picture, +x to the right) by a
// camera whose view of z = 0 spans [-1.25, 1.25] m both ways; no shadows, no anti-aliasing.
Frame draw(const std::string& bodies) {
  const std::string yaml =
      "simulation: { duration: 0.1 }\n"
      "video: { width: 160, height: 160, fps: 10 }\n"
      "camera: { position: [0, 0, 5], look_at: [0, 0, 0], up: [0, 1, 0], fov: 28.07 }\n"
      "render: { shadows: false, antialiasing: none }\n"
      "bodies:\n" +
      bodies;
  const Scene sc = load_scene_text(yaml, scratch("scene.yaml"));
  FrameLoop loop(sc, 1);
  SceneView view(sc, loop.world(), ViewOptions{});
  Renderer r(view.settings, view.meshes);
  Frame f;
  const uint8_t* px = view.draw(r, loop.world());
  f.rgba.assign(px, px + (size_t)kW * kH * 4);
  f.notes = sc.notes;
  if (const char* d = std::getenv("SIMREEL_MATERIALS_DUMP")) {
    static int n = 0;
    write_png(std::string(d) + "/frame" + std::to_string(n++) + ".png", f.rgba.data(), kW, kH);
  }
  f.notes.insert(f.notes.end(), view.meshes.notes.begin(), view.meshes.notes.end());
  return f;
}

std::string body(const std::string& file, const std::string& extra = "") {
  return "  - { name: quad, type: static, colliders: [ { shape: mesh, file: " + file + extra + " } ] }\n";
}

// A unit-square quad in z = 0 ([-1, 1]^2) with texture coordinates (0, 0) at (-1, -1) and (1, 1)
// at (1, 1), material `mat` from `mtl`.
std::string quad_obj(const std::string& name, const std::string& mtl, const std::string& mat) {
  std::string obj = "mtllib " + mtl +
                    "\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
                    "usemtl " +
                    mat + "\nf 1/1/1 2/2/1 3/3/1 4/4/1\n";
  return scratch_file(name, obj);
}

void write_image(const std::string& path, int w, int h, const std::vector<std::array<uint8_t, 3>>& rgb) {
  std::vector<uint8_t> rgba;
  for (const auto& c : rgb) rgba.insert(rgba.end(), {c[0], c[1], c[2], 255});
  write_png(path, rgba.data(), w, h);
}

enum class Hue { red, green, blue, yellow, other };
Hue hue(const std::array<int, 3>& c) {
  const int r = c[0], g = c[1], b = c[2];
  if (r > 2 * g + 20 && r > 2 * b + 20) return Hue::red;
  if (g > 2 * r + 20 && g > 2 * b + 20) return Hue::green;
  if (b > 2 * r + 20 && b > 2 * g + 20) return Hue::blue;
  if (r > 2 * b + 20 && g > 2 * b + 20 && std::abs(r - g) < 40) return Hue::yellow;
  return Hue::other;
}

// The 2x2 image's texels land in the quad's quadrants: its top row at +y (OBJ's v up), its left
// column at -x. Each quadrant's centre samples one texel's centre exactly.
TEST(Materials, ObjTextureTexelsLandWhereTheCoordinatesSay) {
  write_image(scratch("tex.png"), 2, 2, {{230, 20, 20}, {20, 230, 20}, {20, 20, 230}, {230, 230, 20}});
  std::ofstream(scratch("quad.mtl")) << "newmtl paint\nKd 1 1 1\nmap_Kd -s 1 1 1 tex.png\n";
  const Frame f = draw(body(quad_obj("quad.obj", "quad.mtl", "paint")));
  // Frame fractions: the quad spans 0.1 .. 0.9 of the frame; quadrant centres at 0.3 and 0.7.
  EXPECT_EQ(hue(f.at(0.3, 0.3)), Hue::red) << "top left";
  EXPECT_EQ(hue(f.at(0.7, 0.3)), Hue::green) << "top right";
  EXPECT_EQ(hue(f.at(0.3, 0.7)), Hue::blue) << "bottom left";
  EXPECT_EQ(hue(f.at(0.7, 0.7)), Hue::yellow) << "bottom right";
  EXPECT_EQ(hue(f.at(0.03, 0.03)), Hue::other) << "the sky";
}

// Each face in its material's colour (Kd), not the most-used material's for the whole mesh.
TEST(Materials, EachMaterialKeepsItsColour) {
  std::ofstream(scratch("two.mtl")) << "newmtl left\nKd 0.8 0.05 0.05\nnewmtl right\nKd 0.05 0.05 0.8\n";
  scratch_file("two.obj",
               "mtllib two.mtl\nv -1 -1 0\nv 0 -1 0\nv 0 1 0\nv -1 1 0\nv 1 -1 0\nv 1 1 0\n"
               "usemtl left\nf 1 2 3 4\nusemtl right\nf 2 5 6 3\n");
  const Frame f = draw(body(scratch("two.obj")));
  EXPECT_EQ(hue(f.at(0.3, 0.5)), Hue::red);
  EXPECT_EQ(hue(f.at(0.7, 0.5)), Hue::blue);
  // A body colour overrides the file's materials.
  const Frame g = draw(
      "  - { name: quad, type: static, color: [0.02, 0.6, 0.02], colliders: [ { shape: mesh, "
      "file: " +
      scratch("two.obj") + " } ] }\n");
  EXPECT_EQ(hue(g.at(0.3, 0.5)), Hue::green);
  EXPECT_EQ(hue(g.at(0.7, 0.5)), Hue::green);
}

// PLY colours are display values (sRGB bytes): a vertex-coloured mesh keeps them per face.
TEST(Materials, PlyVertexColours) {
  scratch_file(
      "vc.ply",
      "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 2\n"
      "property list uchar int vertex_indices\nend_header\n"
      "-1 -1 0 200 10 10\n0 -1 0 200 10 10\n-1 1 0 200 10 10\n"
      "0.2 -1 0 10 200 10\n1 -1 0 10 200 10\n1 1 0 10 200 10\n3 0 1 2\n3 3 4 5\n");
  const Frame f = draw(body(scratch("vc.ply")));
  EXPECT_EQ(hue(f.at(0.2, 0.6)), Hue::red);
  EXPECT_EQ(hue(f.at(0.8, 0.6)), Hue::green);
}

// A texture that is not there: a note naming it, and the material's colour.
TEST(Materials, MissingTextureGivesANoteAndTheMaterialColour) {
  std::ofstream(scratch("m.mtl")) << "newmtl paint\nKd 0.05 0.7 0.05\nmap_Kd gone.png\n";
  const Frame f = draw(body(quad_obj("m.obj", "m.mtl", "paint")));
  EXPECT_EQ(hue(f.at(0.5, 0.5)), Hue::green);
  bool noted = false;
  for (const std::string& n : f.notes)
    noted = noted || (n.find("gone.png") != std::string::npos && n.find("not found") != std::string::npos);
  EXPECT_TRUE(noted);
}

// A texture path from another machine (Windows, absolute) is found by its name beside the mesh,
// with a note; an image that cannot be decoded is reported and its faces keep their colour.
TEST(Materials, ForeignPathsAndBrokenImages) {
  write_image(scratch("skin.png"), 1, 1, {{20, 20, 230}});
  std::ofstream(scratch("w.mtl")) << "newmtl paint\nKd 1 1 1\nmap_Kd E:\\develop\\assets\\skin.png\n";
  const Frame f = draw(body(quad_obj("w.obj", "w.mtl", "paint")));
  EXPECT_EQ(hue(f.at(0.5, 0.5)), Hue::blue);
  bool noted = false;
  for (const std::string& n : f.notes)
    noted = noted || n.find("using 'skin.png' beside the mesh") != std::string::npos;
  EXPECT_TRUE(noted);

  std::ofstream(scratch("junk.png")) << "this is not a PNG";
  std::ofstream(scratch("b.mtl")) << "newmtl paint\nKd 0.7 0.05 0.05\nmap_Kd junk.png\n";
  const Frame g = draw(body(quad_obj("b.obj", "b.mtl", "paint")));
  EXPECT_EQ(hue(g.at(0.5, 0.5)), Hue::red);
  noted = false;
  for (const std::string& n : g.notes)
    noted = noted || (n.find("junk.png") != std::string::npos && n.find("not an image") != std::string::npos);
  EXPECT_TRUE(noted);
}

// Minified, a fine black-and-white checker averages in linear light: it looks like a material
// of linear grey 0.5 (sRGB 188), not like sRGB 128 (linear 0.22), which averaging the encoded
// bytes would give; and a texel's value is sRGB. The quad is 128 px wide, the checker 512 texels of one pixel
// each: mip level 2.
TEST(Materials, MinifiedTexturesAverageInLinearLight) {
  std::vector<std::array<uint8_t, 3>> checker;
  for (int y = 0; y < 512; ++y)
    for (int x = 0; x < 512; ++x)
      checker.push_back((x + y) % 2 ? std::array<uint8_t, 3>{255, 255, 255}
                                    : std::array<uint8_t, 3>{0, 0, 0});
  write_image(scratch("fine.png"), 512, 512, checker);
  std::ofstream(scratch("c.mtl")) << "newmtl fine\nKd 1 1 1\nmap_Kd fine.png\nnewmtl grey\nKd 0.5 0.5 0.5\n";
  const Frame tex = draw(body(quad_obj("c.obj", "c.mtl", "fine")));
  const Frame grey = draw(body(quad_obj("g.obj", "c.mtl", "grey")));
  for (double fx : {0.3, 0.5, 0.7}) {
    const auto a = tex.at(fx, 0.5), b = grey.at(fx, 0.5);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 3) << fx;
  }
  // Texels are sRGB: a texel of 128 is linear 0.216 (a texture read as linear would draw 0.502).
  write_image(scratch("mid.png"), 4, 4, std::vector<std::array<uint8_t, 3>>(16, {128, 128, 128}));
  std::ofstream(scratch("d.mtl"))
      << "newmtl mid\nKd 1 1 1\nmap_Kd mid.png\nnewmtl same\nKd 0.2158605 0.2158605 0.2158605\n";
  const Frame mid = draw(body(quad_obj("d.obj", "d.mtl", "mid")));
  const Frame same = draw(body(quad_obj("e.obj", "d.mtl", "same")));
  for (double fx : {0.3, 0.5, 0.7}) {
    const auto a = mid.at(fx, 0.5), b = same.at(fx, 0.5);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 2) << fx;
  }
}

// A scene's `texture:` lays an image on a mesh through its file's coordinates (MuJoCo's way),
// and refuses a mesh without any.
TEST(Materials, SceneTextureKey) {
  write_image(scratch("t.png"), 2, 2, {{230, 20, 20}, {20, 230, 20}, {20, 20, 230}, {230, 230, 20}});
  scratch_file("bare.obj",
               "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
               "f 1/1 2/2 3/3 4/4\n");
  const Frame f = draw(body(scratch("bare.obj"), ", texture: " + scratch("t.png")));
  EXPECT_EQ(hue(f.at(0.3, 0.3)), Hue::red);
  EXPECT_EQ(hue(f.at(0.7, 0.7)), Hue::yellow);
  scratch_file("nouv.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
  try {
    draw(body(scratch("nouv.obj"), ", texture: " + scratch("t.png")));
    ADD_FAILURE() << "a mesh without texture coordinates took a texture";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("texture: mesh"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("has no texture coordinates"), std::string::npos) << e.what();
  }
}

// Debian's assimp-testmodels BoxTextured (Khronos sample, CC BY 4.0): the glb with its PNG embedded
// and the glTF with it beside draw the same frame, and the face seen shows the logo's colours in
// the proportions the image has (glTF's metallic factor of 1 does not turn it black).
TEST(Materials, BoxTexturedEmbeddedAndExternal) {
  const fs::path dir = "../shared/corpus/assimp-testmodels/glTF2";
  if (!fs::exists(dir)) GTEST_SKIP() << "no " << dir << " (the shared corpus)";
  const std::string at = ", scale: 1.6, up_axis: y";
  const Frame glb = draw(body(fs::absolute(dir / "BoxTextured-glTF-Binary/BoxTextured.glb").string(), at));
  const Frame gltf = draw(body(fs::absolute(dir / "BoxTextured-glTF/BoxTextured.gltf").string(), at));
  EXPECT_EQ(glb.rgba, gltf.rgba);
  // The top face (z up after up_axis: y) fills the middle of the frame: count its colours.
  const TextureImage logo = read_image((dir / "BoxTextured-glTF/CesiumLogoFlat.png").string());
  // The logo's greens, its light blues and its white, by chroma (lighting scales brightness).
  auto kind = [](const std::array<int, 3>& c) {
    const int r = c[0], g = c[1], b = c[2];
    if (g > r + 25 && g > b + 25) return 0;
    if (b > r + 40 && b >= g) return 1;
    if (std::min({r, g, b}) > 170 && std::max({r, g, b}) - std::min({r, g, b}) < 45) return 2;
    return 3;
  };
  auto fractions = [&](auto&& pixel, int n) {
    std::array<double, 4> c{};
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) c[kind(pixel(i, j))] += 1.0 / (n * n);
    return c;
  };
  const auto in_frame =
      fractions([&](int i, int j) { return glb.at(0.3 + 0.4 * i / 19, 0.3 + 0.4 * j / 19); }, 20);
  // The frame's 0.3 .. 0.7 is the face's 0.19 .. 0.81 (the face spans 0.18 .. 0.82 of the frame).
  const auto in_image = fractions(
      [&](int i, int j) {
        const size_t x = (size_t)((0.19 + 0.62 * i / 19) * logo.width),
                     y = (size_t)((0.19 + 0.62 * j / 19) * logo.height);
        const uint8_t* p = &logo.rgba[(y * logo.width + x) * 4];
        return std::array<int, 3>{p[0], p[1], p[2]};
      },
      20);
  EXPECT_GT(in_frame[0], 0.15) << "the logo's green is there";
  EXPECT_GT(in_frame[1], 0.15) << "the logo's blue is there";
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(in_frame[k], in_image[k], 0.08) << "colour class " << k;
}

// The image decoder takes PNG back bit for bit and refuses anything broken with a message, never
// a crash: every cut of a PNG, a JPEG and a GIF, and random byte changes (a small fuzz, run in
// every test run; tests/fuzz has the libFuzzer target).
TEST(Materials, ImageDecodingRoundTripsAndRefusesBrokenData) {
  std::vector<std::array<uint8_t, 3>> px;
  for (int i = 0; i < 12; ++i) px.push_back({(uint8_t)(20 * i), (uint8_t)(255 - 20 * i), (uint8_t)(7 * i)});
  write_image(scratch("p.png"), 4, 3, px);
  const TextureImage im = read_image(scratch("p.png"));
  ASSERT_EQ(im.width, 4);
  ASSERT_EQ(im.height, 3);
  for (int i = 0; i < 12; ++i)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(im.rgba[4 * i + k], px[i][k]);
  // Every format the decoder takes (the fuzz seeds: FFmpeg's testsrc at 16 x 12 px).
  int formats = 0;
  for (const auto& e : fs::directory_iterator("tests/fuzz/seeds/image")) {
    const TextureImage s = read_image(e.path().string());
    EXPECT_EQ(s.width, 16) << e.path();
    EXPECT_EQ(s.height, 12) << e.path();
    ++formats;
  }
  EXPECT_EQ(formats, 6) << "png jpg gif bmp tga webp";
  std::vector<std::string> files = {scratch("p.png")};
  for (const char* f :
       {"../shared/corpus/bullet3/data/checker_grid.jpg", "../shared/corpus/bullet3/data/checker_huge.gif"})
    if (fs::exists(f)) files.push_back(f);
  std::mt19937 rng(7);
  for (const std::string& f : files) {
    std::ifstream in(f, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    EXPECT_NO_THROW(decode_image(bytes, f));
    for (size_t n = 0; n < bytes.size(); n += 1 + bytes.size() / 300) {
      try {
        decode_image(std::string_view(bytes).substr(0, n), f);
      } catch (const std::runtime_error&) {
      }
    }
    for (int trial = 0; trial < 200; ++trial) {
      std::string b = bytes;
      for (int k = 0; k < 1 + trial % 8; ++k) b[rng() % b.size()] = (char)(rng() & 0xff);
      try {
        const TextureImage d = decode_image(b, f);
        EXPECT_EQ(d.rgba.size(), (size_t)d.width * d.height * 4);
      } catch (const std::runtime_error&) {
      }
    }
  }
  try {
    decode_image("GIF", "x.gif");
    ADD_FAILURE();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("not an image simreel reads"), std::string::npos) << e.what();
  }
  EXPECT_THROW(decode_image("", "empty.png"), std::runtime_error);
  // Halving averages in linear light: a 0/255 checker becomes sRGB 188 (linear 0.5), not 128.
  TextureImage big;
  big.width = 8;
  big.height = 6;
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x) {
      const uint8_t v = (x + y) % 2 ? 255 : 0;
      big.rgba.insert(big.rgba.end(), {v, v, v, 255});
    }
  shrink_image(big, 3);
  ASSERT_EQ(big.width, 2);
  ASSERT_EQ(big.height, 1);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(big.rgba[k], 188);
  EXPECT_EQ(big.rgba[3], 255);
  // Raw texels (an embedded image stored uncompressed) with a size that does not match.
  EXPECT_THROW(decode_image(raw_rgba_header(4, 4) + std::string(60, '\0'), "raw"), std::runtime_error);
  EXPECT_EQ(decode_image(raw_rgba_header(2, 2) + std::string(16, '\x7f'), "raw").width, 2);
}

}  // namespace
}  // namespace simreel
