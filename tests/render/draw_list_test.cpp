// Render meshes shared between colliders (render/draw_list.hpp, render/tessellate.hpp): one render
// mesh and one GPU mesh per distinct shape however many bodies draw it, drawn exactly as
// unshared meshes are, memory per copy small, and a scene too big for memory refused up front.
#include <gtest/gtest.h>
#include <malloc.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "render/draw_list.hpp"
#include "render/renderer.hpp"
#include <simreel/mesh.hpp>
#include "sim/mass/primitives.hpp"
#include "tests/fixtures/reference_scenes.hpp"
#include "tests/sim/mass/mesh_fixtures.hpp"

namespace simreel {
namespace {

using test::uv_sphere;
constexpr int W = 160, H = 120;

Collider mesh_collider_of(std::shared_ptr<const TriangleMesh> m) {
  Collider c;
  c.shape = ShapeKind::mesh;
  c.props_C = analyze_mesh(*m, MeshMassOptions{}).props;
  c.mesh = std::move(m);
  return c;
}

BodyDef body_at(const std::string& name, Collider c, const Vec3& p, double turn) {
  BodyDef b;
  b.name = name;
  b.colliders = {std::move(c)};
  b.p_WB = p;
  b.q_WB = Quat(Eigen::AngleAxisd(turn, Vec3(1, 2, 3).normalized()));
  return b;
}

Collider box_collider(const Vec3& size) {
  Collider c;
  c.shape = ShapeKind::box;
  c.size = size;
  c.props_C = primitive_mass(c, 1000);
  return c;
}

World world_of(std::vector<BodyDef> bodies) {
  WorldConfig wc;
  wc.gravity = Vec3::Zero();
  return World(wc, bodies);
}

// A colour per body, so that shared meshes must still draw each body in its own.
SceneStyles painted(const World& w) {
  SceneStyles s(w.body_count());
  for (int i = 0; i < w.body_count(); ++i)
    s[i].push_back(ColliderStyle{{0.2f + 0.06f * (float)(i % 12), 0.9f - 0.05f * (float)(i % 15), 0.4f}});
  return s;
}

RenderSettings small_settings() {
  RenderSettings rs;
  rs.width = W;
  rs.height = H;
  rs.ground_size = 40;
  return rs;
}

CameraView view_of_grid() {
  CameraView c;
  c.eye = Vec3(9, -12, 9);
  c.target = Vec3(3, 3, 1);
  return c;
}

// Bytes held on the heap now (in use from the arena and from mmap); Mesa's buffers are malloc'd.
size_t heap_bytes() {
  const struct mallinfo2 m = mallinfo2();
  return m.uordblks + m.hblkhd;
}

// 100 bodies of one mesh file, 100 boxes of one size and 3 boxes of other sizes: five render
// meshes and five GPU meshes; each collider still has its own colour. Equal content is not
// enough (meshes count by identity: the scene loader shares one per file and scale), and the
// file's shading normals are part of the mesh.
TEST(SceneMeshes, CopiesOfOneShapeShareOneRenderAndGpuMesh) {
  auto sphere = std::make_shared<const TriangleMesh>(uv_sphere(0.4, 12));
  std::vector<BodyDef> bodies;
  for (int i = 0; i < 100; ++i)
    bodies.push_back(body_at("m" + std::to_string(i), mesh_collider_of(sphere), Vec3(i % 10, i / 10, 1), i));
  for (int i = 0; i < 100; ++i)
    bodies.push_back(
        body_at("b" + std::to_string(i), box_collider(Vec3(0.3, 0.2, 0.1)), Vec3(i % 10, i / 10, 3), i));
  for (double s : {0.31, 0.32, 0.33})
    bodies.push_back(body_at("odd", box_collider(Vec3(s, 0.2, 0.1)), Vec3(s, 0, 5), 0));
  const World w = world_of(bodies);
  const SceneStyles styles = painted(w);
  const SceneMeshes sm(w, styles);
  ASSERT_EQ(sm.meshes.size(), 5u);
  for (int i = 0; i < 100; ++i) {
    EXPECT_EQ(sm.mesh_of[i][0], 0);
    EXPECT_EQ(sm.mesh_of[100 + i][0], 1);
    EXPECT_EQ(sm.color_of[i][0], styles[i][0].color);
  }
  EXPECT_EQ(sm.mesh_of[200][0], 2);
  EXPECT_EQ(sm.mesh_of[202][0], 4);
  EXPECT_EQ(sm.bytes, sm.meshes[0].bytes() + sm.meshes[1].bytes() + sm.meshes[2].bytes() +
                          sm.meshes[3].bytes() + sm.meshes[4].bytes());
  const Renderer r(small_settings(), sm);
  EXPECT_EQ(r.stats().meshes, 5);
  EXPECT_EQ(r.stats().mesh_bytes, sm.bytes);
  DrawList dl;
  build_draw_list(w, sm, view_of_grid(), -1, dl);
  ASSERT_EQ(dl.items.size(), 203u);
  EXPECT_EQ(dl.items[7].color, styles[7][0].color);

  // A copy of the same triangles, or the same triangles with the file's normals: other meshes.
  auto copy = std::make_shared<const TriangleMesh>(*sphere);
  const CornerNormals normals(sphere->triangles.size(),
                              {Eigen::Vector3f::UnitZ(), Eigen::Vector3f::UnitZ(), Eigen::Vector3f::UnitZ()});
  const World w2 = world_of({body_at("a", mesh_collider_of(sphere), Vec3::Zero(), 0),
                             body_at("b", mesh_collider_of(copy), Vec3::Zero(), 0),
                             body_at("c", mesh_collider_of(sphere), Vec3::Zero(), 0)});
  SceneStyles with_normals(3, std::vector<ColliderStyle>(1));
  with_normals[2][0].normals = &normals;
  EXPECT_EQ(SceneMeshes(w2, with_normals).meshes.size(), 3u);
  EXPECT_EQ(SceneMeshes(w2).meshes.size(), 2u);
}

// What SceneMeshes checks against the memory left is what the meshes then take, for every shape.
TEST(SceneMeshes, PredictedBytesAreTheMeshesBytes) {
  std::vector<Collider> cs;
  cs.push_back(box_collider(Vec3(1, 2, 3)));
  for (ShapeKind k :
       {ShapeKind::sphere, ShapeKind::cylinder, ShapeKind::capsule, ShapeKind::ellipsoid, ShapeKind::plane}) {
    Collider c;
    c.shape = k;
    c.radius = 0.3;
    c.height = 1.1;
    c.radii = Vec3(0.5, 0.3, 0.2);
    cs.push_back(c);
  }
  cs.push_back(mesh_collider_of(std::make_shared<const TriangleMesh>(uv_sphere(1, 9))));
  for (const Collider& c : cs)
    EXPECT_EQ(render_mesh_bytes(c), tessellate_collider(c).bytes()) << to_string(c.shape);
}

// Meshes that would not fit in half the memory left (they are held twice: here and in the GL,
// whose llvmpipe crashed with SIGSEGV when an upload found no memory) are refused before any is
// made, saying how much is needed; shared meshes count once.
TEST(SceneMeshes, TooBigForMemoryIsRefusedUpFront) {
  std::vector<BodyDef> bodies;
  for (int i = 0; i < 50; ++i) {
    Collider c;
    c.shape = ShapeKind::sphere;
    c.radius = 0.3 + 1e-3 * i;  // 50 distinct meshes
    c.props_C = primitive_mass(c, 1000);
    bodies.push_back(body_at("s" + std::to_string(i), c, Vec3(i, 0, 0), 0));
  }
  const World w = world_of(bodies);
  const size_t need = 50 * render_mesh_bytes(bodies[0].colliders[0]);
  EXPECT_NO_THROW(SceneMeshes(w, {}, 2 * need));
  try {
    SceneMeshes sm(w, {}, 2 * need - 1);
    ADD_FAILURE() << "accepted";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("50 distinct render meshes"), std::string::npos) << m;
    char gb[32];
    std::snprintf(gb, sizeof gb, "%.3g GB", 2e-9 * (double)need);
    EXPECT_NE(m.find(gb), std::string::npos) << gb << " not in: " << m;
  }
  for (BodyDef& b : bodies) b.colliders[0].radius = 0.3;  // one mesh
  EXPECT_NO_THROW(SceneMeshes(world_of(bodies), {}, 2 * need / 50));
}

// The default budget sees `ulimit -v`: 20000 distinct spheres (2.3 GB of meshes held twice)
// under an address-space limit 1 GB above what the process already maps are refused with the
// message, in a child process, instead of crashing.
TEST(SceneMeshes, AddressSpaceLimitIsSeen) {
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<BodyDef> bodies;
    for (int i = 0; i < 20000; ++i) {
      Collider c;
      c.shape = ShapeKind::sphere;
      c.radius = 0.3 + 1e-6 * i;
      c.props_C = primitive_mass(c, 1000);
      c.collide = false;  // nothing to find contacts between
      BodyDef b;
      b.colliders = {c};
      bodies.push_back(b);
    }
    const World w = world_of(bodies);
    long vm_kb = 0;
    std::ifstream in("/proc/self/status");
    for (std::string line; std::getline(in, line);)
      if (line.rfind("VmSize:", 0) == 0) vm_kb = std::atol(line.c_str() + 7);
    const rlimit lim{(rlim_t)vm_kb * 1024 + (1ul << 30), (rlim_t)vm_kb * 1024 + (1ul << 30)};
    setrlimit(RLIMIT_AS, &lim);
    try {
      SceneMeshes sm(w);
      _exit(10);  // made them: the limit was not seen
    } catch (const std::runtime_error& e) {
      _exit(std::string(e.what()).find("20000 distinct render meshes") != std::string::npos ? 0 : 11);
    } catch (...) {
      _exit(12);
    }
  }
  int st = 0;
  waitpid(pid, &st, 0);
  ASSERT_TRUE(WIFEXITED(st)) << "killed by signal " << WTERMSIG(st);
  EXPECT_EQ(WEXITSTATUS(st), 0) << "10: not refused, 11: another message, 12: another exception";
}

// Bodies of one shared mesh are drawn exactly as the same bodies each with its own copy of it
// (one instanced draw against one draw per body): meshes, boxes and two-sided planes mixed, in
// colours, with shadows, frame for frame.
TEST(Render, SharedMeshesDrawExactlyAsUnsharedOnes) {
  auto sphere = std::make_shared<const TriangleMesh>(uv_sphere(0.45, 10));
  std::vector<uint8_t> frames[2];
  for (int shared = 0; shared < 2; ++shared) {
    std::vector<BodyDef> bodies;
    for (int i = 0; i < 16; ++i) {
      const Vec3 p(1.4 * (i % 4) + 1, 1.4 * (i / 4) + 1, 0.6 + 0.1 * i);
      if (i % 3 == 1)
        bodies.push_back(body_at("box", box_collider(Vec3(0.6, 0.4, 0.3)), p, 0.3 * i));
      else
        bodies.push_back(
            body_at("m", mesh_collider_of(shared ? sphere : std::make_shared<const TriangleMesh>(*sphere)), p,
                    0.3 * i));
    }
    const World w = world_of(bodies);
    const SceneMeshes sm(w, painted(w));
    EXPECT_EQ(sm.meshes.size(), shared ? 2u : 12u);  // 11 spheres and one box size
    Renderer r(small_settings(), sm);
    DrawList dl;
    for (int f = 0; f < 2; ++f) {
      build_draw_list(w, sm, view_of_grid(), -1, dl);
      if (f == 1)
        for (DrawItem& it : dl.items) it.model(2, 3) += 0.25f;  // moved: the shadow pass redrawn
      const uint8_t* px = r.render(dl);
      frames[shared].insert(frames[shared].end(), px, px + (size_t)W * H * 4);
    }
  }
  EXPECT_TRUE(frames[0] == frames[1]);
  // Something was drawn: the frames are not the empty scene's.
  int coloured = 0;
  for (size_t i = 0; i < frames[0].size(); i += 4) coloured += frames[0][i + 1] > frames[0][i + 2] + 40;
  EXPECT_GT(coloured, 200);
}

// A thousand copies of one 20,000-triangle mesh (a 1.7 MB render mesh) cost a few hundred bytes
// each once made and uploaded: the heap held grows by less than 16 KB a body from 10 to 1000
// copies (it grew by 4 copies of the mesh, 6.9 MB, per body when each had its own). Drawing them
// is left out: 2e7 triangles take llvmpipe minutes here (bench_render_throughput measures the peak
// with drawing).
TEST(Render, MemoryPerCopyOfOneMeshIsSmall) {
  auto mesh = std::make_shared<const TriangleMesh>(uv_sphere(0.4, 72));
  ASSERT_GT(mesh->triangles.size(), 20000u);
  Collider c = mesh_collider_of(mesh);
  c.collide = false;
  auto held = [&](int n) {
    std::vector<BodyDef> bodies;
    for (int i = 0; i < n; ++i) bodies.push_back(body_at("m", c, Vec3(i % 32, i / 32, 1), i));
    const World w = world_of(bodies);
    const size_t before = heap_bytes();
    const SceneMeshes sm(w, painted(w));
    const Renderer r(small_settings(), sm);
    EXPECT_EQ(r.stats().meshes, 1);
    return (double)heap_bytes() - (double)before;
  };
  held(1);  // the first context's one-time set-up (Mesa, LLVM) out of the way
  const double ten = held(10), thousand = held(1000);
  const double per_body = (thousand - ten) / 990;
  std::printf("heap held: 10 copies %.2f MB, 1000 copies %.2f MB: %.0f bytes a body\n", ten / 1e6,
              thousand / 1e6, per_body);
  EXPECT_LT(per_body, 16384);
}

// The scene limit, 100,000 bodies, of one box: one mesh, drawn (the batch of every body's own
// copy took 1.3 GB here, and under a memory limit crashed inside Mesa). About 20 s: stress label.
TEST(StressRender, HundredThousandBodiesOfOneShape) {
  std::vector<BodyDef> bodies;
  for (int i = 0; i < 100000; ++i)
    bodies.push_back(
        body_at("b", box_collider(Vec3(0.5, 0.5, 0.5)), Vec3(i % 100, (i / 100) % 100, 1 + i / 10000), i));
  const World w = world_of(bodies);
  const SceneMeshes sm(w, painted(w));
  ASSERT_EQ(sm.meshes.size(), 1u);
  Renderer r(small_settings(), sm);
  DrawList dl;
  CameraView cam;
  cam.eye = Vec3(50, -80, 60);
  cam.target = Vec3(50, 50, 5);
  build_draw_list(w, sm, cam, -1, dl);
  ASSERT_EQ(dl.items.size(), 100000u);
  const uint8_t* px = r.render(dl);
  int coloured = 0;
  for (size_t i = 0; i < (size_t)W * H * 4; i += 4) coloured += px[i + 1] > px[i + 2] + 40;
  EXPECT_GT(coloured, W * H / 20);
}

}  // namespace
}  // namespace simreel
