// Tiny renders (160 x 120) checked pixel by pixel, and a video encoded then decoded back.
#include <gtest/gtest.h>
#include <png.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <vector>

#include <simreel/mesh.hpp>
#include "render/draw_list.hpp"
#include "render/png_writer.hpp"
#include "render/renderer.hpp"
#include "render/shaders.hpp"
#include "render/video_writer.hpp"
#include "sim/mass/primitives.hpp"
#include "tests/fixtures/reference_scenes.hpp"
#include "tests/render/decode.hpp"
#include "tests/scratch.hpp"

namespace simreel {
namespace {

constexpr int W = 160, H = 120;

struct Px {
  int r, g, b;
  int sum() const { return r + g + b; }
};
Px at(const uint8_t* img, int x, int y) {
  const uint8_t* p = img + ((size_t)y * W + x) * 4;
  return {p[0], p[1], p[2]};
}

// A body and the colour its colliders are drawn in (appearance is not part of sim/'s BodyDef).
struct Painted {
  BodyDef body;
  std::array<float, 3> color{0.8f, 0.8f, 0.8f};
};

Painted colored(BodyDef b, std::array<float, 3> c, Vec3 pos) {
  b.p_WB = pos;
  return {b, c};
}

std::vector<Painted> grey(const std::vector<BodyDef>& bodies) {
  std::vector<Painted> out;
  for (const BodyDef& b : bodies) out.push_back({b});
  return out;
}

struct Fixture {
  std::unique_ptr<World> world;
  std::unique_ptr<SceneMeshes> meshes;
  std::unique_ptr<Renderer> renderer;
  CameraView cam;
  std::vector<uint8_t> frame;
  Fixture(std::vector<BodyDef> bodies, CameraView c, bool ground, bool shadows = true,
          void (*tweak)(RenderSettings&) = nullptr)
      : Fixture(grey(bodies), c, ground, shadows, tweak) {}
  Fixture(std::vector<Painted> painted, CameraView c, bool ground, bool shadows = true,
          void (*tweak)(RenderSettings&) = nullptr)
      : cam(c) {
    WorldConfig wc;
    wc.gravity = Vec3::Zero();
    std::vector<BodyDef> bodies;
    SceneStyles styles;
    for (const Painted& p : painted) {
      bodies.push_back(p.body);
      styles.emplace_back(p.body.colliders.size(), ColliderStyle{p.color});
    }
    world = std::make_unique<World>(wc, bodies);
    meshes = std::make_unique<SceneMeshes>(*world, styles);
    RenderSettings rs;
    rs.width = W;
    rs.height = H;
    rs.ground = ground;
    rs.shadows = shadows;
    rs.ground_size = 40;
    rs.ground_tile = 100;  // one colour: no checker edges in the way of the shadow test
    if (tweak) tweak(rs);
    renderer = std::make_unique<Renderer>(rs, *meshes);
  }
  const uint8_t* render() {
    DrawList dl;
    build_draw_list(*world, *meshes, cam, -1, dl);
    const uint8_t* p = renderer->render(dl);
    frame.assign(p, p + (size_t)W * H * 4);
    return frame.data();
  }
};

CameraView top_down() {
  CameraView c;
  c.eye = Vec3(0, 0, 10);
  c.target = Vec3::Zero();
  c.up = Vec3::UnitY();
  c.fov_deg = 40;
  return c;
}

TEST(Render, RedBoxAtTheCentreAndBackgroundAtTheCorners) {
  Fixture s({colored(box_body("b", Vec3(1, 1, 1), 1), {0.9f, 0.05f, 0.05f}, Vec3::Zero())}, top_down(),
            false);
  const uint8_t* img = s.render();
  const Px c = at(img, W / 2, H / 2);
  EXPECT_GT(c.r, 2 * c.g) << c.r << " " << c.g << " " << c.b;
  EXPECT_GT(c.r, 2 * c.b);
  // Looking straight down, every corner's ray is 45-55 degrees below the horizon: the backdrop's
  // end, 0.7x the horizon colour (0.78, 0.84, 0.91), sRGB-encoded: (195, 202, 209).
  for (auto [x, y] : {std::pair{0, 0}, {W - 1, 0}, {0, H - 1}, {W - 1, H - 1}}) {
    const Px p = at(img, x, y);
    EXPECT_NEAR(p.r, 195, 2);
    EXPECT_NEAR(p.g, 202, 2);
    EXPECT_NEAR(p.b, 209, 2);
  }
}

TEST(Render, SideFacingTheLightIsBrighter) {
  // A sphere seen from above; the key light comes from (-0.45, -0.30, 0.84): image left and
  // bottom. A point toward the light is brighter than the mirror point away from it.
  BodyDef b;
  b.name = "s";
  Collider c;
  c.shape = ShapeKind::sphere;
  c.radius = 1.5;
  c.props_C = sphere_mass(1.5, 1);
  b.add_collider(c);
  Fixture s({colored(b, {0.7f, 0.7f, 0.7f}, Vec3::Zero())}, top_down(), false);
  const uint8_t* img = s.render();
  const int d = 14;  // px: well inside the sphere's 30 px image radius
  EXPECT_GT(at(img, W / 2 - d, H / 2 + d).sum(), at(img, W / 2 + d, H / 2 - d).sum() + 60);
}

TEST(Render, ShadowedGroundIsDarkerThanLitGround) {
  // Box at z = 2 over the ground z = 0: its shadow lands 2/0.84 along (0.45, 0.30), at (1.07, 0.71),
  // which projects to about pixel (98, 48); the box itself covers 75..85.
  Fixture s({colored(box_body("b", Vec3(0.5, 0.5, 0.5), 1), {0.8f, 0.8f, 0.8f}, Vec3(0, 0, 2))}, top_down(),
            true);
  const uint8_t* img = s.render();
  // Same checker tile (x > 0, y > 0), away from the shadow: lit.
  const int shadow = at(img, 98, 48).sum(), lit = at(img, 135, 15).sum();
  EXPECT_LT(shadow, lit - 100) << "shadow " << shadow << " lit " << lit;
  // With shadows off the very same pixel is lit.
  Fixture n({colored(box_body("b", Vec3(0.5, 0.5, 0.5), 1), {0.8f, 0.8f, 0.8f}, Vec3(0, 0, 2))}, top_down(),
            true, false);
  EXPECT_GT(at(n.render(), 98, 48).sum(), shadow + 100);
}

// Shadows on the ground against geometry: a ground point is in shadow exactly when the ray from it
// towards the key light meets a body, found here by casting that ray at the body's triangles
// (independent of how the renderer draws shadows). Seen from straight above, every ground pixel
// away from a shadow's edge (2.5 px, beyond FXAA's reach) and from the checker's lines must be the
// ground's colour in shadow, ambient only, gamma 2.2 (std::pow here), within 2 levels, or, in the
// light, much brighter. Three bodies: a box tilted both ways in the air; a tall box sunk halfway
// into the ground, whose part below the plane casts nothing on it (its projection would darken
// ground on the light's side of the box); a square ring (a mesh: non-convex, two-sided), whose
// hole lets the light through.
struct Tri {
  Vec3 a, b, c;
};
// Möller-Trumbore: does the ray o + t d, t > 1e-9, meet triangle q?
bool meets(const Tri& q, const Vec3& o, const Vec3& d, double t_max = INFINITY) {
  const Vec3 e1 = q.b - q.a, e2 = q.c - q.a, p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::fabs(det) < 1e-14) return false;
  const Vec3 s = o - q.a;
  const double u = s.dot(p) / det;
  if (u < 0 || u > 1) return false;
  const Vec3 qv = s.cross(e1);
  const double v = d.dot(qv) / det;
  if (v < 0 || u + v > 1) return false;
  const double t = e2.dot(qv) / det;
  return t > 1e-9 && t < t_max;
}
bool meets_any(const std::vector<Tri>& tris, const Vec3& o, const Vec3& d, double t_max = INFINITY) {
  for (const Tri& q : tris)
    if (meets(q, o, d, t_max)) return true;
  return false;
}
// A closed mesh from quads (each split in two; corners within 1e-9 m are one vertex), wound
// outward: `out` points away from the solid.
void add_quad(TriangleMesh& m, Vec3 a, Vec3 b, Vec3 c, Vec3 d, const Vec3& out) {
  if ((b - a).cross(c - a).dot(out) < 0) std::swap(b, d);
  auto index = [&](const Vec3& p) {
    for (size_t i = 0; i < m.vertices.size(); ++i)
      if ((m.vertices[i] - p).norm() < 1e-9) return (int)i;
    m.vertices.push_back(p);
    return (int)m.vertices.size() - 1;
  };
  const int ia = index(a), ib = index(b), ic = index(c), id = index(d);
  m.triangles.push_back({ia, ib, ic});
  m.triangles.push_back({ia, ic, id});
}
// The box [-h, h] in the body frame as 12 triangles.
TriangleMesh box_mesh(const Vec3& h) {
  TriangleMesh m;
  for (int axis = 0; axis < 3; ++axis)
    for (double side : {-1.0, 1.0}) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      Vec3 c[4];
      for (int k = 0; k < 4; ++k) {
        c[k] = Vec3::Zero();
        c[k][axis] = side * h[axis];
        c[k][u] = (k == 1 || k == 2 ? 1 : -1) * h[u];
        c[k][v] = (k >= 2 ? 1 : -1) * h[v];
      }
      add_quad(m, c[0], c[1], c[2], c[3], side * Vec3::Unit(axis));
    }
  return m;
}
// A flat square ring: outer half-width 1 m, inner 0.5 m, 0.2 m thick.
TriangleMesh ring_mesh() {
  TriangleMesh m;
  const double ro = 1, ri = 0.5, hz = 0.1;
  for (int side = 0; side < 4; ++side) {
    const double a = side * M_PI / 2;
    const Vec3 e(std::cos(a), std::sin(a), 0), f(-std::sin(a), std::cos(a), 0);
    auto at = [&](double r, double s, double z) -> Vec3 { return r * e + s * r * f + Vec3(0, 0, z); };
    for (double z : {-hz, hz})  // top and bottom: a trapezoid
      add_quad(m, at(ri, -1, z), at(ro, -1, z), at(ro, 1, z), at(ri, 1, z), Vec3(0, 0, z));
    add_quad(m, at(ro, -1, -hz), at(ro, 1, -hz), at(ro, 1, hz), at(ro, -1, hz), e);   // outer wall
    add_quad(m, at(ri, -1, -hz), at(ri, 1, -hz), at(ri, 1, hz), at(ri, -1, hz), -e);  // inner wall
  }
  return m;
}

TEST(Render, GroundShadowsAreTheBodiesCastAlongTheLight) {
  const Vec3 L = Vec3(-0.45, -0.30, 0.84).normalized();  // towards the key light (render/renderer.cpp)
  const Quat tilt(Eigen::AngleAxisd(0.5, Vec3(1, 2, 0.5).normalized()));
  struct Case {
    const char* name;
    TriangleMesh shape;  // in the body frame
    bool mesh;           // a mesh collider, else a box
    Vec3 half, at;
    Quat q;
    long min_shadow;  // shadow pixels checked (away from edges): a sunk box hides most of its own
  };
  const std::vector<Case> cases = {
      {"tilted box in the air", box_mesh(Vec3(0.8, 0.5, 0.3)), false, Vec3(0.8, 0.5, 0.3),
       Vec3(-1.4, -1.0, 3.0), tilt, 100},
      {"tall box sunk halfway", box_mesh(Vec3(0.5, 0.5, 1.0)), false, Vec3(0.5, 0.5, 1.0),
       Vec3(-0.9, -0.6, 0.0), Quat(Eigen::AngleAxisd(0.35, Vec3::UnitZ())), 20},
      {"square ring (mesh)", ring_mesh(), true, Vec3::Zero(), Vec3(-1.2, -0.8, 2.5),
       Quat(Eigen::AngleAxisd(0.25, Vec3(1, 1, 0).normalized())), 100}};
  for (const Case& c : cases) {
    BodyDef b;
    if (c.mesh) {
      Collider col;
      col.shape = ShapeKind::mesh;
      col.mesh = std::make_shared<const TriangleMesh>(c.shape);
      col.props_C = analyze_mesh(c.shape, MeshMassOptions{}).props;
      b.name = "ring";
      b.colliders = {col};
    } else {
      b = box_body("box", 2 * c.half, 1);
    }
    b.p_WB = c.at;
    b.q_WB = c.q;
    std::vector<Tri> tris;
    for (const auto& t : c.shape.triangles) {
      Vec3 p[3];
      for (int k = 0; k < 3; ++k) p[k] = c.at + c.q * c.shape.vertices[t[k]];
      tris.push_back({p[0], p[1], p[2]});
    }
    auto checker = [](RenderSettings& rs) { rs.ground_tile = 2; };
    Fixture s({colored(b, {0.8f, 0.8f, 0.8f}, c.at)}, top_down(), true, true, checker);
    const uint8_t* img = s.render();
    if (const char* dir = std::getenv("SIMREEL_TEST_PNG_DIR"))  // to look at
      write_png(std::string(dir) + "/ground_shadow_" + std::to_string(&c - cases.data()) + ".png", img, W, H);
    // Straight down from 10 m: pixel centre (i + 0.5, j + 0.5) sees the ground point below.
    const double f = (H / 2.0) / std::tan(20 * M_PI / 180), m_per_px = 10 / f, tile = 2;
    const Vec3 eye(0, 0, 10);
    auto shadowed = [&](const Vec3& g) { return meets_any(tris, g, L); };
    auto hidden = [&](const Vec3& g) { return meets_any(tris, eye, g - eye, 1 - 1e-9); };
    // Where what lies below the ground would cast if it were not cut off (the ray away from the
    // light meets the body), and the ring's hole: both must be seen lit somewhere.
    auto below = [&](const Vec3& g) { return meets_any(tris, g, -L); };
    long in_shadow = 0, in_light = 0, lit_below = 0;
    for (int j = 0; j < H; ++j)
      for (int i = 0; i < W; ++i) {
        const Vec3 g((i + 0.5 - W / 2.0) * m_per_px, -(j + 0.5 - H / 2.0) * m_per_px, 0);
        const double r = 2.5 * m_per_px;
        if (std::fabs(std::remainder(g.x(), tile)) < r || std::fabs(std::remainder(g.y(), tile)) < r)
          continue;
        const bool sh = shadowed(g);
        bool edge = false;
        for (int k = 0; k < 16 && !edge; ++k) {
          const double a = k * M_PI / 8;
          const Vec3 n = g + r * Vec3(std::cos(a), std::sin(a), 0);
          edge = shadowed(n) != sh || hidden(n);
        }
        if (edge || hidden(g)) continue;
        const bool odd = ((int)std::floor(g.x() / tile) + (int)std::floor(g.y() / tile)) & 1;
        const Px p = at(img, i, j);
        int want[3];
        for (int k = 0; k < 3; ++k) {
          const double base = odd ? RenderSettings{}.ground_color2[k] : RenderSettings{}.ground_color[k];
          const double l = base * kFillSky[k];  // sRGB-encoded
          want[k] =
              (int)std::lround(255 * (l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1 / 2.4) - 0.055));
        }
        if (sh) {
          ++in_shadow;
          ASSERT_NEAR(p.r, want[0], 2) << c.name << ": shadow at pixel " << i << ", " << j;
          ASSERT_NEAR(p.g, want[1], 2) << c.name << ": shadow at pixel " << i << ", " << j;
          ASSERT_NEAR(p.b, want[2], 2) << c.name << ": shadow at pixel " << i << ", " << j;
        } else {
          ++in_light;
          lit_below += below(g);
          ASSERT_GT(p.sum(), want[0] + want[1] + want[2] + 150)
              << c.name << ": lit at pixel " << i << ", " << j;
        }
      }
    EXPECT_GT(in_shadow, c.min_shadow) << c.name;
    EXPECT_GT(in_light, 5000) << c.name;
    if (c.at.z() - c.half.z() < 0) {
      EXPECT_GT(lit_below, 30) << c.name;
    }
    if (c.mesh) {  // lit pixels in the hole's shadow: the light through the ring
      const Vec3 hole = c.at - L * (c.at.z() / L.z());
      long lit_hole = 0;
      for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
          const Vec3 g((i + 0.5 - W / 2.0) * m_per_px, -(j + 0.5 - H / 2.0) * m_per_px, 0);
          lit_hole += (g - hole).norm() < 0.2 && !shadowed(g) && at(img, i, j).sum() > 400;
        }
      EXPECT_GT(lit_hole, 20) << c.name;
    }
  }
}

// Shadows on bodies against geometry: a tilted box over a wide slab (both convex primitives, so
// the renderer draws only the bodies that can shadow another into its shadow map and looks up only
// on those another can shadow). Seen from straight above, each point of the slab's top is in shadow
// exactly when the ray from it towards the light meets the box: away from the shadow's edge
// (2.5 px) such pixels must be much darker than the slab's lit top, and the others as bright.
TEST(Render, BodyShadowsOnBodiesAreWhereTheLightIsBlocked) {
  const Vec3 L = Vec3(-0.45, -0.30, 0.84).normalized();
  const Vec3 half(0.7, 0.4, 0.25), pos(-0.9, -0.6, 2.4);
  const Quat q(Eigen::AngleAxisd(0.5, Vec3(1, 2, 0.5).normalized()));
  BodyDef box = box_body("box", 2 * half, 1), slab = box_body("slab", Vec3(7, 5, 0.2), 1);
  box.q_WB = q;
  const double top = 0.6;  // the slab's top: centre 0.5, 0.2 thick
  std::vector<Tri> tris;
  const TriangleMesh m = box_mesh(half);
  for (const auto& t : m.triangles)
    tris.push_back({pos + q * m.vertices[t[0]], pos + q * m.vertices[t[1]], pos + q * m.vertices[t[2]]});
  Fixture s({colored(box, {0.8f, 0.8f, 0.8f}, pos), colored(slab, {0.8f, 0.8f, 0.8f}, Vec3(0, 0, top - 0.1))},
            top_down(), false);
  const uint8_t* img = s.render();
  const double f = (H / 2.0) / std::tan(20 * M_PI / 180), m_per_px = (10 - top) / f;
  const Vec3 eye(0, 0, 10);
  auto shadowed = [&](const Vec3& g) { return meets_any(tris, g, L); };
  auto hidden = [&](const Vec3& g) { return meets_any(tris, eye, g - eye, 1 - 1e-9); };
  std::vector<int> lit, dark;
  for (int j = 0; j < H; ++j)
    for (int i = 0; i < W; ++i) {
      const Vec3 g((i + 0.5 - W / 2.0) * m_per_px, -(j + 0.5 - H / 2.0) * m_per_px, top);
      const double r = 2.5 * m_per_px;
      if (std::fabs(g.x()) > 3.5 - r || std::fabs(g.y()) > 2.5 - r) continue;  // off the slab's top
      const bool sh = shadowed(g);
      bool edge = hidden(g);
      for (int k = 0; k < 16 && !edge; ++k) {
        const double a = k * M_PI / 8;
        const Vec3 n = g + r * Vec3(std::cos(a), std::sin(a), 0);
        edge = shadowed(n) != sh || hidden(n);
      }
      if (!edge) (sh ? dark : lit).push_back(at(img, i, j).sum());
    }
  ASSERT_GT(dark.size(), 100u);
  ASSERT_GT(lit.size(), 3000u);
  const auto [lit_lo, lit_hi] = std::minmax_element(lit.begin(), lit.end());
  const int dark_hi = *std::max_element(dark.begin(), dark.end());
  EXPECT_LE(*lit_hi - *lit_lo, 6) << "the slab's lit top is one colour";
  EXPECT_LT(dark_hi, *lit_lo - 150) << "shadow on the slab";
}

TEST(Render, BodyHighInTheSceneIsInTheUpperHalf) {
  // GL rows run bottom-up; the frame must come out upright.
  CameraView side;
  side.eye = Vec3(0, -10, 0);
  side.target = Vec3::Zero();
  side.up = Vec3::UnitZ();
  Fixture s({colored(box_body("b", Vec3(0.5, 0.5, 0.5), 1), {0.1f, 0.1f, 0.9f}, Vec3(0, 0, 2))}, side, false);
  const uint8_t* img = s.render();
  int lo = H, hi = -1;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const Px p = at(img, x, y);
      if (p.b > p.r + 60) lo = std::min(lo, y), hi = std::max(hi, y);
    }
  ASSERT_GE(hi, 0) << "box not visible";
  EXPECT_LT(hi, H / 2);
}

// A mesh from a file may be wound inside-out (the mass code flips it and says so). It must render
// like the correctly wound mesh, not show its inside: same frame within shading rounding.
TEST(Render, InsideOutMeshLooksLikeTheCorrectOne) {
  TriangleMesh cube;
  for (int i = 0; i < 8; ++i)
    cube.vertices.push_back(Vec3((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1));
  cube.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  TriangleMesh inverted = cube;
  for (auto& t : inverted.triangles) std::swap(t[1], t[2]);
  auto frame_of = [](const TriangleMesh& m) {
    Collider c;
    c.shape = ShapeKind::mesh;
    c.mesh = std::make_shared<const TriangleMesh>(m);
    c.props_C = analyze_mesh(m, MeshMassOptions{}).props;
    BodyDef b;
    b.name = "cube";
    b.colliders = {c};
    b.q_WB = Quat(Eigen::AngleAxisd(0.6, Vec3(1, 2, 0).normalized()));
    CameraView cam;
    cam.eye = Vec3(5, -6, 4);
    Fixture f({Painted{b, {0.2f, 0.5f, 0.9f}}}, cam, /*ground=*/true);
    f.render();
    return f.frame;
  };
  const std::vector<uint8_t> good = frame_of(cube), bad = frame_of(inverted);
  int worst = 0;
  for (size_t i = 0; i < good.size(); ++i) worst = std::max(worst, std::abs(good[i] - bad[i]));
  EXPECT_LE(worst, 2) << "inside-out mesh rendered differently";
}

// The cached ground plus per-body shadow footprints must look like drawing the whole ground with
// shadows every frame: bodies tumbling over a checker ground (the camera still, so the cache is
// reused), frame by frame within 2 levels per channel (the footprints interpolate the same plane
// from other vertices), and the shadows really there (footprints not missing any).
// render.quality: high against standard. Ambient occlusion alone (shadows off), a 2 m box on a
// one-colour ground seen obliquely: nothing gets brighter, open ground far from the box is the same
// (a plane occludes nothing), and the ground along the box's foot and the box's lower walls get
// darker. Soft shadows alone (from straight above, 16.5 px a metre): the shadow's edge has a
// penumbra of levels between shadowed and lit ground where standard's edge is hard.
TEST(Render, HighQualityOccludesCreasesAndSoftensShadowEdges) {
  auto frame = [](bool high, bool shadows, const CameraView& cam) {
    static bool hq;
    hq = high;
    Fixture s(
        {colored(box_body("b", Vec3(2, 2, 2), 1), {0.8f, 0.8f, 0.8f}, Vec3(0, 0, 1))}, cam, true, shadows,
        +[](RenderSettings& r) {
          r.antialiasing = AntiAliasing::none;
          r.ground_color2 = r.ground_color;
          if (hq) r.quality = RenderQuality::high;
        });
    s.render();
    return s.frame;
  };
  const auto lum = [](const std::vector<uint8_t>& img, int x, int y) { return at(img.data(), x, y).sum(); };
  CameraView side;
  side.eye = Vec3(-7, -5, 4);
  side.target = Vec3(0, 0, 0.8);
  side.fov_deg = 40;
  const std::vector<uint8_t> a = frame(false, false, side), b = frame(true, false, side);
  int darker = 0, brighter = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      darker += lum(b, x, y) < lum(a, x, y) - 6;
      brighter += lum(b, x, y) > lum(a, x, y) + 3;
    }
  EXPECT_GT(darker, 40) << "the box's foot";
  EXPECT_EQ(brighter, 0);
  for (auto [x, y] : {std::pair{5, H - 5}, {W - 5, H - 5}, {W / 2, H - 3}})
    EXPECT_NEAR(lum(b, x, y), lum(a, x, y), 3) << "open ground at " << x << ", " << y;

  const std::vector<uint8_t> hard = frame(false, true, top_down()), soft = frame(true, true, top_down());
  const int lit = lum(hard, 5, 5);
  int shadow = lit;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) shadow = std::min(shadow, lum(hard, x, y));
  auto between = [&](const std::vector<uint8_t>& img) {  // right of and above the box: its shadow
    int n = 0;
    for (int y = 10; y < 70; ++y)
      for (int x = 85; x < 130; ++x) n += lum(img, x, y) > shadow + 6 && lum(img, x, y) < lit - 6;
    return n;
  };
  EXPECT_GT(between(soft), between(hard) + 20) << between(soft) << " vs " << between(hard);
}

TEST(Render, CachedGroundLooksLikeTheFullGround) {
  // Three times: all bodies above the ground (the cache's colour only, no ground depth), with one
  // body sunk halfway into it (ground depth copied too, footprints offset in depth), and with 4x
  // MSAA (a multisampled cache).
  for (int variant = 0; variant < 3; ++variant) {
    const bool sunk = variant == 1, msaa = variant == 2;  // the cache is multisampled with MSAA
    std::vector<BodyDef> bodies = r2_free_boxes(27);
    for (BodyDef& b : bodies) b.p_WB = 0.5 * b.p_WB - Vec3(2, 2, 49);  // a 3 x 3 x 3 block over z = 0
    if (sunk) bodies[0].p_WB.z() = 0.0;
    CameraView c;
    c.eye = Vec3(6, -9, 7);
    c.target = Vec3(-0.5, -0.5, 1);
    auto checker = [](RenderSettings& rs) { rs.ground_tile = 0.5; };
    auto full = [](RenderSettings& rs) {
      rs.ground_tile = 0.5;
      rs.cache_ground = false;
    };
    auto checker4 = [](RenderSettings& rs) {
      rs.ground_tile = 0.5;
      rs.antialiasing = AntiAliasing::msaa4;
    };
    auto full4 = [](RenderSettings& rs) {
      rs.ground_tile = 0.5;
      rs.cache_ground = false;
      rs.antialiasing = AntiAliasing::msaa4;
    };
    Fixture a(bodies, c, true, true, msaa ? +checker4 : +checker),
        b(bodies, c, true, true, msaa ? +full4 : +full);
    int worst = 0;
    for (int f = 0; f < 5; ++f) {
      for (int k = 0; k < 8; ++k) a.world->step(), b.world->step();
      a.render();
      b.render();
      for (size_t i = 0; i < a.frame.size(); ++i) worst = std::max(worst, std::abs(a.frame[i] - b.frame[i]));
    }
    EXPECT_LE(worst, 2) << (sunk ? "with a sunk body" : msaa ? "4x MSAA" : "all above the ground");
    // Frame 1 fills the cache (drawn the same way as every later frame: a frame must not depend
    // on the frames before it), frames 2-5 copy it.
    EXPECT_EQ(a.renderer->stats().ground_cached, 1);
    EXPECT_EQ(a.renderer->stats().ground_reused, 4);
    // Shadows are really there: many ground pixels darker than without shadows.
    Fixture d(bodies, c, true, false, checker);
    for (int f = 0; f < 5; ++f)
      for (int k = 0; k < 8; ++k) d.world->step();
    d.render();
    long shadowed = 0;
    for (size_t i = 0; i < a.frame.size(); i += 4) shadowed += a.frame[i] + 20 < d.frame[i];
    EXPECT_GT(shadowed, 200) << "no shadows on the ground";
  }
}

// Bodies are drawn in one batched call when the draw list has one item per mesh; a list that
// draws a mesh twice (an overlay might) takes the one-draw-per-item path. Both copies must show,
// and the batched frame must equal the per-item frame of the same single item.
// The drawn ground is fixed in the world: a body moving 3 m aside changes nothing of the ground
// away from it (it used to re-centre on the bodies in two-tile jumps, moving its edges).
TEST(Render, GroundStaysPutWhenTheBodiesMove) {
  auto small = [](RenderSettings& rs) {
    rs.ground_size = 4;  // edges in view
    rs.ground_tile = 0.5;
  };
  std::vector<uint8_t> frames[2];
  for (int k = 0; k < 2; ++k) {
    Fixture s({colored(box_body("b", Vec3(0.3, 0.3, 0.3), 1), {0.9f, 0.1f, 0.1f}, Vec3(3.0 * k, 0, 1))},
              top_down(), true, false, small);
    frames[k] = std::vector<uint8_t>(s.render(), s.render() + (size_t)W * H * 4);
  }
  // The box is at the centre in frame 0, ~55 px right of it in frame 1: compare the left 70 columns,
  // which hold the ground's left half and its edge (the ground is ~66 px wide, centred).
  int differ = 0, ground = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < 70; ++x) {
      const Px a = at(frames[0].data(), x, y), b = at(frames[1].data(), x, y);
      differ += a.r != b.r || a.g != b.g || a.b != b.b;
      ground += std::abs(a.r - 202) + std::abs(a.g - 217) + std::abs(a.b - 234) > 15;  // not sky
    }
  EXPECT_EQ(differ, 0);
  EXPECT_GT(ground, 1000) << "no ground in view";
}

// The scene's ground body is drawn by the renderer's ground, not as a collider; a plane of the
// scene's own is a finite square of the style's size; an ellipsoid is a scaled sphere.
TEST(Render, PlaneAndEllipsoidColliders) {
  BodyDef floor;
  floor.name = "ground";
  floor.type = BodyType::static_body;
  Collider plane;
  plane.shape = ShapeKind::plane;
  plane.props_C.mass = 1;  // World still wants a positive mass
  plane.props_C.inertia = Mat3::Identity();
  floor.add_collider(plane);
  BodyDef slab = floor;
  slab.name = "slab";
  BodyDef egg;
  egg.name = "egg";
  Collider e;
  e.shape = ShapeKind::ellipsoid;
  e.radii = Vec3(1.5, 0.5, 0.5);
  e.props_C = ellipsoid_mass(e.radii, 1);
  egg.add_collider(e);
  egg.p_WB = Vec3(0, 0, 1);
  WorldConfig wc;
  wc.gravity = Vec3::Zero();
  World w(wc, {floor, slab, egg});
  SceneStyles styles(3, std::vector<ColliderStyle>(1));
  styles[0][0].drawn = false;
  styles[1][0].plane_size = 3;
  styles[2][0].color = {0.9f, 0.1f, 0.1f};
  const SceneMeshes sm(w, styles);
  ASSERT_EQ(sm.meshes.size(), 2u);
  EXPECT_EQ(sm.mesh_of[0][0], -1);
  EXPECT_EQ(sm.mesh_of[1][0], 0);
  EXPECT_EQ(sm.mesh_of[2][0], 1);
  EXPECT_NEAR(sm.meshes[0].radius, 1.5 * std::sqrt(2.0), 1e-6);  // a 3 m square
  EXPECT_TRUE(sm.meshes[0].two_sided);
  EXPECT_NEAR(sm.meshes[1].radius, 1.5, 1e-6);
  DrawList dl;
  build_draw_list(w, sm, top_down(), -1, dl);
  ASSERT_EQ(dl.items.size(), 2u);
  EXPECT_EQ(dl.items[1].color, styles[2][0].color);

  // Ellipsoid normals: the gradient of x^2/a^2 + y^2/b^2 + z^2/c^2, i.e. along diag(1/r^2) p.
  const RenderMesh m = tessellate_ellipsoid(Vec3(1.5, 0.5, 0.25));
  double worst = 0;
  for (size_t v = 0; v < m.vertices.size(); v += 6) {
    const Vec3 p(m.vertices[v], m.vertices[v + 1], m.vertices[v + 2]);
    const Vec3 n(m.vertices[v + 3], m.vertices[v + 4], m.vertices[v + 5]);
    const Vec3 q = p.cwiseQuotient(Vec3(1.5, 0.5, 0.25));
    EXPECT_NEAR(q.norm(), 1.0, 1e-5);  // on the surface
    const Vec3 g = p.cwiseQuotient(Vec3(2.25, 0.25, 0.0625));
    if (g.norm() > 1e-9) worst = std::max(worst, (g.normalized() - n).norm());
  }
  EXPECT_LT(worst, 1e-5);
}

TEST(Render, MeshDrawnTwiceUsesThePerItemPathAndShowsBoth) {
  Fixture s({colored(box_body("b", Vec3(1, 1, 1), 1), {0.9f, 0.1f, 0.1f}, Vec3::Zero())}, top_down(), false);
  DrawList dl;
  build_draw_list(*s.world, *s.meshes, s.cam, -1, dl);
  const uint8_t* one = s.renderer->render(dl);
  const std::vector<uint8_t> single(one, one + (size_t)W * H * 4);
  DrawItem left = dl.items[0], right = dl.items[0];
  left.model(0, 3) = -2.0f;
  right.model(0, 3) = 2.0f;
  dl.items = {left, right};
  const uint8_t* two = s.renderer->render(dl);
  // x = -2 and +2 m at 10 m with a 40 degree fov: about 41 px either side of the centre.
  // Red: much more red than green; the sky between them is bluish grey (g > r - 20).
  auto red = [](Px p) { return p.r > p.g + 60; };
  EXPECT_TRUE(red(at(two, W / 2 - 41, H / 2)));
  EXPECT_TRUE(red(at(two, W / 2 + 41, H / 2)));
  EXPECT_FALSE(red(at(two, W / 2, H / 2)));
  EXPECT_TRUE(red(at(single.data(), W / 2, H / 2)));
}

TEST(Render, SameSceneTwiceGivesIdenticalFrames) {
  std::vector<uint8_t> a, b;
  for (auto* out : {&a, &b}) {
    CameraView c;
    c.eye = Vec3(4, -4, 3);
    Fixture s(r2_free_boxes(8), c, true);
    for (int k = 0; k < 10; ++k) s.world->step();
    s.cam.target = s.world->centroid(0);
    s.cam.eye = s.cam.target + Vec3(6, -6, 4);
    s.render();
    *out = s.frame;
  }
  EXPECT_EQ(a, b);
}

// The EGL backend (headless, no window system) draws the same frames as OSMesa: both are Mesa's
// llvmpipe here, so byte for byte. A moving scene with shadows over a checker ground, three
// frames (the cached ground is drawn on the second and reused on the third), then 4x MSAA. One
// backend after the other, each renderer destroyed before the next is made.
TEST(Render, EglBackendDrawsTheSameFramesAsOsMesa) {
  if (!gl_backend_built(GlBackend::egl) || !gl_backend_built(GlBackend::osmesa))
    GTEST_SKIP() << "built without both backends";
  for (bool msaa : {false, true}) {
    std::vector<uint8_t> frames[2];
    std::string description[2];
    for (int k = 0; k < 2; ++k) {
      CameraView c;
      c.eye = Vec3(6, -9, 7);
      c.target = Vec3(-0.5, -0.5, 1);
      std::vector<BodyDef> bodies = r2_free_boxes(8);
      for (BodyDef& b : bodies) b.p_WB = 0.5 * b.p_WB - Vec3(1, 1, 49);
      auto osmesa = [](RenderSettings& rs) { rs.gl = GlBackend::osmesa, rs.ground_tile = 0.5; };
      auto egl = [](RenderSettings& rs) { rs.gl = GlBackend::egl, rs.ground_tile = 0.5; };
      auto osmesa4 = [](RenderSettings& rs) {
        rs.gl = GlBackend::osmesa, rs.ground_tile = 0.5, rs.antialiasing = AntiAliasing::msaa4;
      };
      auto egl4 = [](RenderSettings& rs) {
        rs.gl = GlBackend::egl, rs.ground_tile = 0.5, rs.antialiasing = AntiAliasing::msaa4;
      };
      Fixture s(bodies, c, true, true, k == 0 ? (msaa ? +osmesa4 : +osmesa) : (msaa ? +egl4 : +egl));
      description[k] = s.renderer->description();
      for (int f = 0; f < 3; ++f) {
        for (int i = 0; i < 8; ++i) s.world->step();
        s.render();
        frames[k].insert(frames[k].end(), s.frame.begin(), s.frame.end());
      }
    }
    EXPECT_EQ(description[0].rfind("OSMesa: ", 0), 0u) << description[0];
    EXPECT_EQ(description[1].rfind("EGL: ", 0), 0u) << description[1];
    EXPECT_TRUE(frames[0] == frames[1])
        << (msaa ? "4x MSAA: " : "") << description[0] << " vs " << description[1];
  }
}

TEST(Render, ShadowMapIsReusedWhileNothingMoves) {
  Fixture s({box_body("b", Vec3(1, 1, 1), 1)}, top_down(), true);
  s.render();
  s.render();
  EXPECT_EQ(s.renderer->stats().shadow_passes, 1);
  EXPECT_EQ(s.renderer->stats().shadow_reused, 1);
}

double psnr_rgb(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  double se = 0;
  size_t n = 0;
  for (size_t i = 0; i < a.size(); i += 4)
    for (int c = 0; c < 3; ++c, ++n) se += std::pow((double)a[i + c] - b[i + c], 2);
  return 10 * std::log10(255.0 * 255.0 / (se / n));
}

// Renders 30 frames of a tumbling body, encodes them to `name` and decodes the file back.
struct RoundTrip {
  test::Decoded decoded;
  std::vector<uint8_t> first;  ///< the first frame as rendered
};
RoundTrip encode_thirty(const std::string& name, const std::string& encoder = "", std::string* note = nullptr,
                        std::string* used = nullptr) {
  const std::string path = test::scratch(name);
  std::remove(path.c_str());
  CameraView c;
  c.eye = Vec3(3, -3, 2);
  Fixture s({colored(r1_tumble_body(), {0.8f, 0.4f, 0.2f}, Vec3::Zero())}, c, true);
  VideoSettings vs;
  vs.path = path;
  vs.width = W;
  vs.height = H;
  vs.fps = 30;
  vs.encoder = encoder;
  RoundTrip r;
  {
    VideoWriter v(vs);
    if (note) *note = v.encoder_note();
    if (used) *used = v.encoder_name();
    for (int k = 0; k < 30; ++k) {
      for (int j = 0; j < 8; ++j) s.world->step();
      const uint8_t* img = s.render();
      if (k == 0) r.first = s.frame;
      v.push(img);
    }
    EXPECT_FALSE(std::filesystem::exists(path)) << "visible before finish()";
    v.finish();
  }
  r.decoded = test::decode(path);
  // Nothing else was left beside it.
  for (const auto& e : std::filesystem::directory_iterator(test::scratch_dir()))
    EXPECT_EQ(e.path().filename().string().find(".partial-"), std::string::npos) << "left beside the video";
  return r;
}

void expect_thirty_frames_at_30_fps(const test::Decoded& d) {
  EXPECT_EQ(d.width, W);
  EXPECT_EQ(d.height, H);
  EXPECT_EQ(d.frames, 30);
  EXPECT_NEAR(d.fps, 30.0, 1e-9);
  EXPECT_NEAR(d.duration, 1.0, 0.05);
}

// A YUV 4:2:0 video: codec, pixel format, timing, and the first frame close to the rendered one.
void expect_yuv_round_trip(const std::string& name, const std::string& codec) {
  const RoundTrip r = encode_thirty(name);
  EXPECT_EQ(r.decoded.codec, codec);
  EXPECT_EQ(r.decoded.pix_fmt, "yuv420p");
  EXPECT_EQ(r.decoded.chroma_location, "center");  // as render/yuv.hpp samples chroma
  expect_thirty_frames_at_30_fps(r.decoded);
  ASSERT_EQ(r.decoded.first_rgba.size(), r.first.size());
  EXPECT_GT(psnr_rgb(r.decoded.first_rgba, r.first), 35.0);
}

TEST(Video, EncodeThirtyFramesAndDecodeThemBack) {
  expect_yuv_round_trip("video_test.mp4", "h264");
}

// --encoder: a named encoder this FFmpeg lacks, or one that cannot open on this machine (NVENC
// without an NVIDIA card), falls back to libx264 with a note saying why; the video is whole.
TEST(Video, NamedEncoderFallsBackToX264WithANote) {
  for (const std::string name : {"no_such_encoder", "h264_nvenc"}) {
    std::string note, used;
    const RoundTrip r = encode_thirty("enc_" + name + ".mp4", name, &note, &used);
    if (name == "h264_nvenc" && used == "h264_nvenc") continue;  // a machine with NVENC: it ran
    EXPECT_EQ(used, "libx264") << name;
    EXPECT_NE(note.find(name), std::string::npos) << note;
    EXPECT_NE(note.find("encoding with libx264"), std::string::npos) << note;
    EXPECT_EQ(r.decoded.codec, "h264");
    expect_thirty_frames_at_30_fps(r.decoded);
  }
  std::string note, used;
  encode_thirty("plain.mp4", "", &note, &used);
  EXPECT_EQ(used, "libx264");
  EXPECT_EQ(note, "");
}

TEST(Video, WebmRoundTripIsVp9) {
  expect_yuv_round_trip("video_test.webm", "vp9");
}

// GIF: palette-based (FFmpeg's palettegen and paletteuse; tests/render/gif_frames_test.cpp), timed
// in hundredths of a second. 33.7 dB on this frame with the median-cut palette fitted to the first
// frame used before, 19.9 dB with the fixed 3-3-2 palette before that.
TEST(Video, GifRoundTripUsesAPaletteFittedToTheClip) {
  const RoundTrip r = encode_thirty("video_test.gif");
  EXPECT_EQ(r.decoded.codec, "gif");
  EXPECT_EQ(r.decoded.width, W);
  EXPECT_EQ(r.decoded.height, H);
  EXPECT_EQ(r.decoded.frames, 30);
  ASSERT_EQ(r.decoded.first_rgba.size(), r.first.size());
  const double psnr = psnr_rgb(r.decoded.first_rgba, r.first);
  EXPECT_GT(psnr, 30.0);
}

std::vector<uint8_t> read_png(const std::string& path) {
  png_image im{};
  im.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&im, path.c_str())) return {};
  im.format = PNG_FORMAT_RGBA;
  std::vector<uint8_t> px(PNG_IMAGE_SIZE(im));
  if (!png_image_finish_read(&im, nullptr, px.data(), 0, nullptr)) return {};
  return px;
}

// `simreel render` hands FXAA to the writer's thread; the frames must be those the renderer
// makes with FXAA itself, byte for byte.
TEST(Video, WriterFxaaMatchesRendererFxaa) {
  CameraView c;
  c.eye = Vec3(3, -3, 2);
  auto raw = [](RenderSettings& rs) { rs.antialiasing = AntiAliasing::none; };
  Fixture with({colored(r1_tumble_body(), {0.8f, 0.4f, 0.2f}, Vec3::Zero())}, c, true);
  Fixture without({colored(r1_tumble_body(), {0.8f, 0.4f, 0.2f}, Vec3::Zero())}, c, true, true, raw);
  with.render();
  without.render();
  ASSERT_NE(with.frame, without.frame) << "FXAA changed nothing";
  VideoSettings vs;
  vs.frames_dir = test::scratch_dir().string();
  vs.width = W;
  vs.height = H;
  vs.fxaa = true;
  {
    VideoWriter v(vs);
    v.push(without.frame.data());
    v.finish();
  }
  EXPECT_EQ(read_png(test::scratch("frame_00000.png")), with.frame);
}

TEST(Video, WriterDestroyedWithoutFinishLeavesNothing) {
  const std::string path = test::scratch("abort_test.mp4");
  std::remove(path.c_str());
  {
    VideoSettings vs;
    vs.path = path;
    vs.width = W;
    vs.height = H;
    VideoWriter v(vs);
    std::vector<uint8_t> grey((size_t)W * H * 4, 128);
    v.push(grey.data());
  }
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(Video, OddSizeIsRejected) {
  VideoSettings vs;
  vs.path = test::scratch("odd.mp4");
  vs.width = 161;
  vs.height = 120;
  EXPECT_THROW(VideoWriter{vs}, std::runtime_error);
}

// A mesh file's own shading normals (carried by the app, not by sim/) are the ones drawn; without
// them each corner gets the crease-averaged face normal.
TEST(Render, MeshShadingNormalsFromTheFileAreUsed) {
  TriangleMesh tm;
  tm.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  tm.triangles = {{0, 1, 2}};
  const RenderMesh plain = tessellate_mesh(tm);
  ASSERT_EQ(plain.vertices.size(), 18u);
  EXPECT_FLOAT_EQ(plain.vertices[5], 1.0f);  // the face normal +z
  const Eigen::Vector3f tilted = Eigen::Vector3f(0.6f, 0, 0.8f);
  const CornerNormals normals = {{tilted, tilted, tilted}};
  const RenderMesh from_file = tessellate_mesh(tm, &normals);
  EXPECT_FLOAT_EQ(from_file.vertices[3], 0.6f);
  EXPECT_FLOAT_EQ(from_file.vertices[5], 0.8f);
}

}  // namespace
}  // namespace simreel
