// Render and encode throughput: a 300-frame 1280x720 clip of 100 tumbling boxes over a
// checker ground, with shadows and anti-aliasing, timed
//   - render only (frames/s of the GL passes, for several anti-aliasing settings),
//   - end to end in-process (simulate + draw + encode to H.264 MP4 on the encoder thread),
//   - against the ceiling: the `ffmpeg` command-line tool encoding the same raw RGBA frames with
//     the same encoder settings (libx264 veryfast, CRF 20, yuv420p), i.e. encoding alone.
// And memory per body: the peak resident memory of a process that loads N copies of one
// 100,000-triangle mesh (N = 1, 10, 100, 1000), or N boxes, spheres of one size or of N sizes,
// and draws one frame of them; each case in a fresh process of its own, this program started
// again with `memory-case` (rows `memory_*`).
// CSV on stdout. Usage:
//   bench_render_throughput [FRAMES [overlays|teaching|memory|pairs|post|render [NAME,...]|png K PATH]]
// (FRAMES default 300; `memory`: only the memory rows; `pairs`: only the end-to-end / ceiling
// pairs; `post`: only the writer thread's CPU stages; `render`: only the render-only rows, of the
// settings named if given; `png`: frame K of the clip as drawn by default, FXAA included, written to
// PATH, to look at). ffmpeg must be on PATH for the ceiling row; the raw frames need FRAMES
// x 3.7 MB in the temp folder). The number of end-to-end / ceiling pairs is SIMREEL_BENCH_PAIRS
// (default 7).
#include <spawn.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <simreel/world.hpp>
#include "app/runner/frame_loop.hpp"
#include "app/view/overlays.hpp"
#include "bench/bench_util.hpp"
#include "render/draw_list.hpp"
#include "render/fxaa.hpp"
#include "render/png_writer.hpp"
#include "render/renderer.hpp"
#include "render/video_writer.hpp"
#include "render/yuv.hpp"
#include "tests/fixtures/reference_scenes.hpp"

using namespace simreel;

namespace {

constexpr int W = 1280, H = 720, kFps = 30;

// CPU seconds of this process so far, every thread (llvmpipe's, the encoder's): steadier than
// wall time on a machine shared with other work.
double cpu_s() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return (double)(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * (double)(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// 100 boxes of assorted sizes in a 10 x 10 grid, 1.5 m apart, 1 m over the ground, spinning
// with random angular velocities (no gravity, so the view stays full for the whole clip).
struct Boxes {
  std::vector<BodyDef> bodies;
  SceneStyles styles;  ///< a colour per box
};
Boxes hundred_boxes() {
  SplitMix64 rng(2026);
  Boxes out;
  for (int i = 0; i < 100; ++i) {
    const Vec3 size(0.3 + 0.5 * rng.uniform(), 0.3 + 0.5 * rng.uniform(), 0.3 + 0.5 * rng.uniform());
    BodyDef b = box_body(("box" + std::to_string(i)).c_str(), size, 1.0);
    b.p_WB = Vec3(1.5 * (i % 10) - 6.75, 1.5 * (i / 10) - 6.75, 1.0);
    b.w_W = Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5) * 4.0;
    ColliderStyle st;
    st.color = {0.25f + 0.7f * (float)rng.uniform(), 0.25f + 0.7f * (float)rng.uniform(),
                0.25f + 0.7f * (float)rng.uniform()};
    out.styles.push_back({st});
    out.bodies.push_back(b);
  }
  return out;
}

// The scene through the app's one frame loop (app/runner/frame_loop.hpp), as `simreel render` runs it:
// `frames` frames at kFps, physics at 240 Hz.
struct Setup {
  FrameLoop loop;
  SceneMeshes meshes;
  CameraView cam;
  Setup(const Boxes& b, int frames)
      : loop(config(), b.bodies, (frames - 1) / (double)kFps, kFps), meshes(loop.world(), b.styles) {
    cam.eye = Vec3(0, -16, 9);
    cam.target = Vec3(0, 0, 0.5);
  }
  static WorldConfig config() {
    WorldConfig c;
    c.dt = 1.0 / 240;
    c.gravity = Vec3::Zero();
    return c;
  }
  // Runs the clip, calling draw(world) at each frame.
  void run(const std::function<void(const World&)>& draw) {
    FrameLoop::Hooks h;
    h.frame = [&](const FrameTarget&, const World& w) { draw(w); };
    loop.run(loop.all_frames(), h, true);
  }
};

// The same clip as a scene with teaching overlays: an angular velocity arrow on every
// box, scaled by the pre-pass (which simulates the clip once more first), and a three-line HUD.
Scene overlay_scene(const Boxes& b, int frames, int parts = 3) {  // parts: 1 arrows, 2 HUD, 3 both
  Scene sc;
  sc.name = "bench_overlays";
  sc.timestep = Setup::config().dt;
  sc.gravity = Setup::config().gravity;
  sc.duration = (frames - 1) / (double)kFps;
  sc.video.fps = kFps;
  sc.bodies = b.bodies;
  ShowItem omega;
  omega.kind = ShowKind::angular_velocity;
  sc.overlays.show.assign(b.bodies.size(), {});
  if (parts & 1) sc.overlays.show.assign(b.bodies.size(), {omega});
  auto field = [](const char* name, int body, bool norm, const char* printf) {
    HudField f;
    f.name = name, f.body = body, f.norm = norm, f.printf = printf;
    return f;
  };
  auto line = [](std::vector<std::string> text, HudField f) {
    HudLine l;
    l.text = std::move(text);
    l.fields = {std::move(f)};
    return l;
  };
  sc.overlays.hud = {line({"t = ", " s"}, field("t", -1, false, "%.2f")),
                     line({"E/E\u2080 \u2212 1 = ", ""}, field("E_drift", -1, false, "%+.1e")),
                     line({"|\u03c9| of box0 = ", " rad/s"}, field("omega", 0, true, "%.3f"))};
  sc.overlays.title = "100 boxes";
  if (!(parts & 2)) sc.overlays.hud.clear(), sc.overlays.title.clear();
  return sc;
}

// aa: "fxaa" (the default), "msaa4", "msaa2" or "none".
RenderSettings settings(const std::string& aa, bool shadows = true, int shadow_size = 1024) {
  RenderSettings rs;
  rs.width = W;
  rs.height = H;
  rs.antialiasing = aa == "msaa4"   ? AntiAliasing::msaa4
                    : aa == "msaa2" ? AntiAliasing::msaa2
                    : aa == "fxaa"  ? AntiAliasing::fxaa
                                    : AntiAliasing::none;
  rs.shadow_size = shadow_size;
  rs.shadows = shadows;
  rs.ground = true;
  rs.ground_size = 40;
  return rs;
}

// ---- memory per body -------------------------------------------------------------------------

// A torus (R 0.5 m, r 0.15 m) of 224 x 224 quads: 100,352 triangles, an 8.4 MB render mesh.
std::shared_ptr<const TriangleMesh> torus_100k() {
  auto m = std::make_shared<TriangleMesh>();
  const int n = 224;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double u = 2 * M_PI * i / n, v = 2 * M_PI * j / n;
      m->vertices.push_back(Vec3((0.5 + 0.15 * std::cos(v)) * std::cos(u),
                                 (0.5 + 0.15 * std::cos(v)) * std::sin(u), 0.15 * std::sin(v)));
    }
  auto at = [n](int i, int j) { return (i % n) * n + (j % n); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      m->triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m->triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return m;
}

// What one memory case loads: N bodies of a shape, in a grid 1.5 m apart, each its own colour.
enum class Copies { mesh, box, box_sizes, sphere, sphere_sizes };
const char* name_of(Copies c) {
  switch (c) {
    case Copies::mesh:
      return "mesh100k";
    case Copies::box:
      return "box";
    case Copies::box_sizes:
      return "box_sizes";
    case Copies::sphere:
      return "sphere";
    case Copies::sphere_sizes:
      return "sphere_sizes";
  }
  return "";
}

struct MemoryCase {
  double seconds = 0;  ///< drawing the frame
  long meshes = 0;     ///< GPU meshes
  size_t mesh_bytes = 0;
  long triangles = 0;  ///< drawn in the frame (each pass)
};

// In the calling (child) process: loads and draws one frame of n bodies. W x H, shadows, FXAA.
MemoryCase load_and_draw(Copies what, int n) {
  const auto torus = what == Copies::mesh ? torus_100k() : nullptr;
  std::vector<BodyDef> bodies;
  SceneStyles styles;
  const int side = (int)std::ceil(std::cbrt((double)n));
  for (int i = 0; i < n; ++i) {
    Collider c;
    c.collide = false;  // drawing is measured, not contacts
    if (what == Copies::mesh) {
      c.shape = ShapeKind::mesh;
      c.mesh = torus;
    } else if (what == Copies::box || what == Copies::box_sizes) {
      c.shape = ShapeKind::box;
      c.size = Vec3(0.8, 0.6, 0.4) * (what == Copies::box_sizes ? 1 + 1e-4 * i : 1.0);
    } else {
      c.shape = ShapeKind::sphere;
      c.radius = 0.5 * (what == Copies::sphere_sizes ? 1 + 1e-4 * i : 1.0);
    }
    c.props_C.mass = 1;
    c.props_C.inertia = Mat3::Identity();
    BodyDef b;
    b.name = "b" + std::to_string(i);
    b.colliders = {c};
    b.p_WB = 1.5 * Vec3(i % side, (i / side) % side, 1 + i / (side * side));
    bodies.push_back(b);
    ColliderStyle st;
    st.color = {0.3f + 0.6f * (float)(i % 7) / 7, 0.5f, 0.3f + 0.6f * (float)(i % 5) / 5};
    styles.push_back({st});
  }
  WorldConfig wc;
  wc.gravity = Vec3::Zero();
  World w(wc, bodies);
  SceneMeshes sm(w, styles);
  Renderer r(settings("fxaa"), sm);
  CameraView cam;
  const double span = 1.5 * side;
  cam.target = Vec3(0.5 * span, 0.5 * span, 0.5 * span);
  cam.eye = cam.target + Vec3(1.2, -2.0, 1.2) * span + Vec3(2, -3, 2);
  DrawList dl;
  build_draw_list(w, sm, cam, -1, dl);
  const double t0 = bench::now_s();
  r.render(dl);
  MemoryCase out;
  out.seconds = bench::now_s() - t0;
  out.meshes = r.stats().meshes;
  out.mesh_bytes = r.stats().mesh_bytes;
  for (const DrawItem& it : dl.items) out.triangles += (long)sm.meshes[it.mesh].indices.size() / 3;
  return out;
}

// Runs load_and_draw in a fresh process: this program again (/proc/self/exe), started by
// posix_spawn with the arguments `<frames> memory-case <copies> <n>`, which draws the one case and
// prints what it measured on its stdout, a pipe to us. Never fork-and-continue: by the time these
// rows run, llvmpipe's and the encoder's threads are up, and a forked child that draws can block
// forever on a lock one of them held at the fork. Returns the child's peak resident memory (MB),
// which the child reads itself (VmHWM of /proc/self/status: its own memory since the exec; wait4's
// ru_maxrss would also count the parent's, whose memory a spawned child shares until its exec),
// and what it reported, or -1.
std::pair<double, MemoryCase> in_child(Copies what, int n) {
  int fd[2];
  if (pipe(fd) != 0) return {-1, {}};
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_adddup2(&fa, fd[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&fa, fd[0]);
  posix_spawn_file_actions_addclose(&fa, fd[1]);
  const std::string count = std::to_string(n);
  std::vector<std::string> argv = {"bench_render_throughput", "1", "memory-case", name_of(what), count};
  std::vector<char*> args;
  for (std::string& a : argv) args.push_back(a.data());
  args.push_back(nullptr);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, "/proc/self/exe", &fa, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  close(fd[1]);
  if (rc != 0) {
    close(fd[0]);
    return {-1, {}};
  }
  std::string out;
  char buf[256];
  for (ssize_t k; (k = read(fd[0], buf, sizeof buf)) > 0;) out.append(buf, (size_t)k);
  close(fd[0]);
  int st = 0;
  if (waitpid(pid, &st, 0) != pid || !WIFEXITED(st) || WEXITSTATUS(st) != 0) return {-1, {}};
  MemoryCase c;
  long hwm_kb = -1;
  if (std::sscanf(out.c_str(), "%lf %ld %zu %ld %ld", &c.seconds, &c.meshes, &c.mesh_bytes, &c.triangles,
                  &hwm_kb) != 5 ||
      hwm_kb <= 0)
    return {-1, {}};
  return {hwm_kb / 1024.0, c};
}

// The child's side of in_child: one case, its figures on stdout.
int memory_case(const char* copies, int n) {
  for (Copies c : {Copies::mesh, Copies::box, Copies::box_sizes, Copies::sphere, Copies::sphere_sizes})
    if (std::string(copies) == name_of(c)) {
      const MemoryCase m = load_and_draw(c, n);
      long hwm_kb = -1;
      if (FILE* f = std::fopen("/proc/self/status", "r")) {
        char line[256];
        while (std::fgets(line, sizeof line, f))
          if (std::sscanf(line, "VmHWM: %ld", &hwm_kb) == 1) break;
        std::fclose(f);
      }
      std::printf("%.9g %ld %zu %ld %ld\n", m.seconds, m.meshes, m.mesh_bytes, m.triangles, hwm_kb);
      return 0;
    }
  return 2;
}

void memory_rows() {
  struct Series {
    Copies what;
    std::vector<int> counts;
  };
  for (const Series& s :
       {Series{Copies::mesh, {1, 10, 100, 1000}}, Series{Copies::box, {1, 10, 100, 1000, 10000}},
        Series{Copies::box_sizes, {1, 10, 100, 1000, 10000}},
        Series{Copies::sphere, {1, 10, 100, 1000, 10000}},
        Series{Copies::sphere_sizes, {1, 10, 100, 1000, 10000}}}) {
    double one = -1;
    for (int n : s.counts) {
      const auto [mb, c] = in_child(s.what, n);
      if (mb < 0) {
        std::printf("memory_%s_x%d,1,%d,%d,,,\"the child failed\"\n", name_of(s.what), n, W, H);
        continue;
      }
      if (n == 1) one = mb;
      char per[64] = "";
      if (n > 1 && one > 0) std::snprintf(per, sizeof per, " per_body_kb=%.1f", (mb - one) * 1024 / (n - 1));
      std::printf(
          "memory_%s_x%d,1,%d,%d,%.3f,%.2f,\"peak_rss_mb=%.1f%s bodies=%d gpu_meshes=%ld mesh_mb=%.2f "
          "triangles_drawn=%ld; per_body_kb is the peak's growth a body above one body; one frame drawn "
          "(shadows, FXAA) in a child process\"\n",
          name_of(s.what), n, W, H, c.seconds, 1 / c.seconds, mb, per, n, c.meshes, c.mesh_bytes / 1e6,
          c.triangles);
      std::fflush(stdout);
    }
  }
}

// One end-to-end run as `simreel render` does it: simulate, draw, FXAA and the screen layer on the
// writer's thread, libx264 on its own; with `overlays`, their pre-pass and fonts inside the timed
// span. Used by the end_to_end rows and by the teaching-overlay pairs.
struct EndToEnd {
  double wall = 0, cpu = 0, setup = 0, encode = 0;
  uintmax_t bytes = 0;
};
EndToEnd end_to_end_run(const Boxes& bodies, int frames, const char* aa, const Scene* overlays,
                        const std::filesystem::path& out) {
  EndToEnd e;
  const double t0 = bench::now_s(), c0 = cpu_s();
  Setup s(bodies, frames);
  RenderSettings rs = settings(aa);
  rs.post = PostStage::caller;
  Renderer r(rs, s.meshes);
  std::unique_ptr<SceneOverlays> ov;
  if (overlays) {
    const double s0 = bench::now_s();
    std::vector<double> radius;
    for (int i = 0; i < s.loop.world().body_count(); ++i)
      radius.push_back(s.meshes.meshes[s.meshes.mesh_of[i][0]].radius);
    ov = std::make_unique<SceneOverlays>(*overlays, s.loop.world(), radius, W, H, 1);
    e.setup = bench::now_s() - s0;
  }
  VideoSettings vs;
  vs.fxaa = rs.fxaa();
  vs.path = out.string();
  vs.width = W;
  vs.height = H;
  vs.fps = kFps;
  VideoWriter v(vs);
  DrawList dl;
  long k = 0;
  s.run([&](const World& w) {
    build_draw_list(w, s.meshes, s.cam, -1, dl);
    if (ov) ov->build(w, k, dl);
    r.render(dl, v.acquire());
    v.commit(k++, &dl.screen);
  });
  v.finish();
  e.wall = bench::now_s() - t0;
  e.cpu = cpu_s() - c0;
  e.encode = v.encode_seconds();
  e.bytes = std::filesystem::file_size(out);
  return e;
}

// The teaching overlays' speed target, in a function of its own: a HUD, an inset plot and 100
// arrows on the 100-box clip cost at most 15% more end-to-end time than the plain clip. Plain and
// overlaid runs alternate, `pairs` pairs, each end to end as `simreel render` runs (FXAA and the
// screen layer on the writer's thread, the overlays' pre-pass and fonts inside the timed span); the
// row is the median of the pairs' wall-clock ratios, with the CPU-seconds ratios beside it.
void teaching_overlay_rows(const Boxes& bodies, int frames, const std::filesystem::path& dir, int pairs,
                           const std::function<void(const char*, double, const std::string&)>& row) {
  Scene sc = overlay_scene(bodies, frames, 3);  // an arrow per box, a title and a 3-line HUD
  PlotSpec plot;
  for (int c = 0; c < 3; ++c) {
    HudField f;
    f.name = "omega_body";
    f.body = 0;
    f.component = c;
    plot.quantities.push_back(f);
    plot.labels.push_back(std::string("\\omega_") + (char)('1' + c));
    plot.colors.push_back(std::nullopt);
  }
  plot.rect[0] = 0.6, plot.rect[1] = 0.6, plot.rect[2] = 0.38, plot.rect[3] = 0.36;
  plot.title = "box0";
  sc.overlays.plots = {plot};
  auto run = [&](bool overlays, double& cpu, double& setup) {
    const EndToEnd e =
        end_to_end_run(bodies, frames, "fxaa", overlays ? &sc : nullptr, dir / "e2e_teaching.mp4");
    cpu = e.cpu, setup = e.setup;
    return e.wall;
  };
  std::vector<double> wall, cpu;
  for (int pair = 1; pair <= pairs; ++pair) {
    double c_plain = 0, c_ov = 0, setup = 0, ignored = 0;
    const double plain = run(false, c_plain, ignored);
    row("end_to_end_fxaa_plain_b", plain, "the plain clip, as end_to_end_fxaa; pair " + std::to_string(pair));
    const double with = run(true, c_ov, setup);
    row("end_to_end_fxaa_hud_plot_arrows", with,
        "100 auto-scaled angular velocity arrows, a title, a 3-line HUD and an inset plot of box0's omega "
        "(3 curves); pre-pass and fonts " +
            std::to_string(setup).substr(0, 5) + " s; pair " + std::to_string(pair));
    wall.push_back(with / plain);
    cpu.push_back(c_ov / c_plain);
  }
  auto list = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    std::string s;
    for (double q : v) s += (s.empty() ? "" : " ") + std::to_string(q).substr(0, 5);
    return std::pair<double, std::string>{v[v.size() / 2], s};
  };
  const auto [w, ws] = list(wall);
  const auto [c, cs] = list(cpu);
  std::printf(
      "hud_plot_arrows_over_plain,%d,%d,%d,,,\"wall: median %.3f of the pairs' ratios (%s); CPU seconds: "
      "median "
      "%.3f (%s); target 1.15\"\n",
      frames, W, H, w, ws.c_str(), c, cs.c_str());
  std::fflush(stdout);
}

// Runs `argv` (searched on PATH) as a child process (posix_spawnp: nothing runs between the fork
// and the exec) and waits for it: its wall seconds, or -1 if it could not run or failed; `cpu`
// gets the CPU seconds of the child's threads (user + system, from wait4's rusage).
double ffmpeg_child(const std::vector<std::string>& argv, double& cpu) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const double t0 = bench::now_s();
  pid_t pid = -1;
  if (posix_spawnp(&pid, args[0], nullptr, nullptr, args.data(), environ) != 0) return -1;
  int st = 0;
  rusage u{};
  if (wait4(pid, &st, 0, &u) != pid) return -1;
  const double wall = bench::now_s() - t0;
  cpu = (double)(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
        1e-6 * (double)(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
  return WIFEXITED(st) && WEXITSTATUS(st) == 0 ? wall : -1;
}

// The 1-minute load average, for the notes (how busy the machine was).
double load1() {
  double l[1] = {-1};
  return getloadavg(l, 1) == 1 ? l[0] : -1;
}

// Median of v (the upper one of an even count) and v sorted as text, for the notes.
std::pair<double, std::string> median_and_list(std::vector<double> v, int digits = 3) {
  std::sort(v.begin(), v.end());
  std::string s;
  char b[32];
  for (double q : v) {
    std::snprintf(b, sizeof b, "%.*f", digits, q);
    s += (s.empty() ? "" : " ") + std::string(b);
  }
  return {v.empty() ? 0.0 : v[v.size() / 2], s};
}

// The writer thread's CPU work per frame (`bench_render_throughput N post`): every 10th frame of
// the clip, rendered without anti-aliasing and kept, then FXAA and RGBA to YUV 4:2:0, each timed
// over all the kept frames in turn (five rounds, the median), in CPU seconds of this thread, scaled
// to `frames` frames.
void post_rows(const Boxes& bodies, int frames) {
  Setup s(bodies, frames);
  RenderSettings rs = settings("fxaa");
  rs.post = PostStage::caller;
  Renderer r(rs, s.meshes);
  DrawList dl;
  std::vector<std::vector<uint8_t>> kept;
  long k = 0;
  s.run([&](const World& w) {
    build_draw_list(w, s.meshes, s.cam, -1, dl);
    const uint8_t* img = r.render(dl);
    if (k++ % 10 == 0) kept.emplace_back(img, img + (size_t)W * H * 4);
  });
  std::vector<uint8_t> work((size_t)W * H * 4), yuv((size_t)W * H * 3 / 2);
  FxaaBuffers fb;
  double changes = 0;
  for (int what = 0; what < 2; ++what) {
    std::vector<double> runs;
    for (int round = 0; round < 5; ++round) {
      double c = 0;
      for (const auto& f : kept) {
        work = f;
        const double c0 = bench::thread_cpu_s();
        if (what == 0) fxaa(work.data(), W, H, fb);
        if (what == 1)
          rgba_to_yuv420_bt709(work.data(), W, H, yuv.data(), W, yuv.data() + W * H, W / 2,
                               yuv.data() + W * H * 5 / 4, W / 2);
        c += bench::thread_cpu_s() - c0;
        if (what == 0 && round == 0) changes += (double)fb.changes.size() / kept.size();
      }
      runs.push_back(c * frames / kept.size());
    }
    const auto [m, all] = median_and_list(runs);
    std::printf(
        "%s,%d,%d,%d,%.3f,%.1f,\"CPU seconds of the writer's thread for %d frames (%zu frames timed, 5 "
        "rounds: %s)%s\"\n",
        what == 0 ? "post_fxaa" : "post_yuv420", frames, W, H, m, frames / m, frames, kept.size(),
        all.c_str(),
        what == 0 ? ("; " + std::to_string((long)changes) + " pixels blended a frame").c_str() : "");
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  // `memory-case COPIES N`: one memory row's case, drawn in this fresh process (in_child).
  if (argc > 4 && std::string(argv[2]) == "memory-case") return memory_case(argv[3], std::atoi(argv[4]));
  const int frames = argc > 1 ? std::atoi(argv[1]) : 300;
  // `overlays`: only the render-only rows with and without overlays (a quick look at their cost).
  const bool only_overlays = argc > 2 && std::string(argv[2]) == "overlays";
  // `teaching`: only the teaching end-to-end row (HUD, inset plot, 100 arrows against the plain clip).
  const bool only_teaching = argc > 2 && std::string(argv[2]) == "teaching";
  // `pairs`: only the end-to-end / ceiling pairs (after one untimed-for-the-target render-only run
  // of the defaults, which writes the ceiling's raw frames).
  const bool only_pairs = argc > 2 && std::string(argv[2]) == "pairs";
  // `render [NAME,NAME...]`: only the render-only rows (of the settings named, default all).
  const bool only_render = argc > 2 && std::string(argv[2]) == "render";
  const std::string pick = only_render && argc > 3 ? argv[3] : "";
  const char* pairs_env = std::getenv("SIMREEL_BENCH_PAIRS");
  const int pairs = std::max(1, pairs_env ? std::atoi(pairs_env) : 7);
  const auto bodies = hundred_boxes();
  std::printf("case,frames,width,height,seconds,fps,note\n");
  if (argc > 2 && std::string(argv[2]) == "memory") {
    memory_rows();
    return 0;
  }
  if (argc > 4 && std::string(argv[2]) == "png") {
    const long want = std::atol(argv[3]);
    Setup s(bodies, frames);
    Renderer r(settings("fxaa"), s.meshes);
    DrawList dl;
    long k = 0;
    s.run([&](const World& w) {
      if (k++ != want) return;
      build_draw_list(w, s.meshes, s.cam, -1, dl);
      write_png(argv[4], r.render(dl), W, H);
    });
    return 0;
  }
  if (argc > 2 && std::string(argv[2]) == "post") {
    post_rows(bodies, frames);
    return 0;
  }
  // The note is quoted (RFC 4180): renderer strings hold commas.
  auto row = [&](const char* name, double s, const std::string& note) {
    std::string q;
    for (char c : note) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    std::printf("%s,%d,%d,%d,%.3f,%.1f,\"%s\"\n", name, frames, W, H, s, frames / s, q.c_str());
    std::fflush(stdout);
  };
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "simreel-bench";
  std::filesystem::create_directories(dir);
  const std::string raw = (dir / "frames.rgba").string();
  if (only_teaching) {
    teaching_overlay_rows(bodies, frames, dir, 5, row);
    return 0;
  }

  // Render only, each setting in a fresh context. The settings run in turn, three rounds, and each
  // row is the median of its three runs: this VM's speed drifts within a run. The first round of
  // the defaults keeps the raw frames for the ffmpeg ceiling.
  struct Mode {
    const char* name;
    const char* aa;
    bool shadows;
    int shadow_size;
    GlBackend gl = default_gl_backend();
    int overlays = 0;  // overlay_scene's parts: 1 an arrow per box, 2 a title and HUD, 3 both
  };
  std::vector<Mode> modes;
  for (const Mode m :
       {Mode{"fxaa_shadow1024", "fxaa", true, 1024}, Mode{"msaa4_shadow1024", "msaa4", true, 1024},
        Mode{"none_shadow1024", "none", true, 1024}, Mode{"fxaa_shadow2048", "fxaa", true, 2048},
        Mode{"fxaa_no_shadows", "fxaa", false, 0}, Mode{"none_no_shadows", "none", false, 0},
        Mode{"fxaa_shadow1024_egl", "fxaa", true, 1024, GlBackend::egl},
        Mode{"fxaa_shadow1024_overlays", "fxaa", true, 1024, default_gl_backend(), 3},
        Mode{"fxaa_shadow1024_arrows", "fxaa", true, 1024, default_gl_backend(), 1},
        Mode{"fxaa_shadow1024_hud", "fxaa", true, 1024, default_gl_backend(), 2}})
    if (gl_backend_built(m.gl) &&
        (!only_overlays || m.overlays || std::string(m.name) == "fxaa_shadow1024") &&
        (!only_pairs || std::string(m.name) == "fxaa_shadow1024") &&
        (!only_render || pick.empty() ||
         ("," + pick + ",").find(std::string(",") + m.name + ",") != std::string::npos))
      modes.push_back(m);
  std::vector<std::vector<double>> seconds(modes.size()), cpu(modes.size());
  std::vector<std::string> described(modes.size());
  const int rounds = only_pairs ? 1 : 3;
  for (int round = 0; round < rounds; ++round)
    for (size_t i = 0; i < modes.size(); ++i) {
      const Mode& m = modes[i];
      Setup s(bodies, frames);
      RenderSettings rs = settings(m.aa, m.shadows, m.shadow_size);
      rs.gl = m.gl;
      Renderer r(rs, s.meshes);
      std::unique_ptr<SceneOverlays> ov;
      if (m.overlays) {
        std::vector<double> radius;
        for (int b = 0; b < s.loop.world().body_count(); ++b)
          radius.push_back(s.meshes.meshes[s.meshes.mesh_of[b][0]].radius);
        ov = std::make_unique<SceneOverlays>(overlay_scene(bodies, frames, m.overlays), s.loop.world(),
                                             radius, W, H, 1);
      }
      DrawList dl;
      build_draw_list(s.loop.world(), s.meshes, s.cam, -1, dl);
      if (ov) ov->build(s.loop.world(), 0, dl);
      r.render(dl);  // first frame compiles shaders: not timed
      FILE* out = round == 0 && i == 0 && !only_overlays && !only_render ? std::fopen(raw.c_str(), "wb")
                                                                         : nullptr;  // the defaults
      double t = 0, c = 0;
      long k = 0;
      s.run([&](const World& w) {
        const double t0 = bench::now_s(), c0 = cpu_s();
        build_draw_list(w, s.meshes, s.cam, -1, dl);
        if (ov) ov->build(w, k++, dl);
        const uint8_t* img = r.render(dl);
        t += bench::now_s() - t0;
        c += cpu_s() - c0;
        if (out) std::fwrite(img, 1, (size_t)W * H * 4, out);
      });
      if (out) std::fclose(out);
      seconds[i].push_back(t);
      cpu[i].push_back(c);
      described[i] = r.description();
    }
  for (size_t i = 0; i < modes.size(); ++i) {
    std::vector<double> v = seconds[i];
    std::sort(v.begin(), v.end());
    std::vector<double> c = cpu[i];
    std::sort(c.begin(), c.end());
    std::string runs = "runs";
    for (double q : seconds[i]) runs += " " + std::to_string(q).substr(0, 5);
    runs += " s, the median reported; CPU median " + std::to_string(c[c.size() / 2]).substr(0, 5) + " s; ";
    row((std::string("render_only_") + modes[i].name).c_str(), v[v.size() / 2],
        std::string("draw list + GL passes + readback (+ FXAA); ") + runs + described[i]);
  }
  if (only_overlays || only_render) return 0;

  // End to end, in process: what `simreel render` does (FXAA on the writer's thread).
  double last_cpu = 0;  // CPU seconds of the last end_to_end run
  auto end_to_end = [&](const char* aa, std::string& note, bool overlays = false) {
    const Scene ov = overlay_scene(bodies, frames);
    const EndToEnd e = end_to_end_run(bodies, frames, aa, overlays ? &ov : nullptr, dir / "e2e.mp4");
    last_cpu = e.cpu;
    note = std::string(overlays ? "overlays set up (pre-pass, fonts) in " +
                                      std::to_string(e.setup).substr(0, 5) + " s; "
                                : "") +
           "simulate + render + libx264 veryfast crf20 on its thread; CPU " +
           std::to_string(e.cpu).substr(0, 6) + " s (all threads); encoder busy " + std::to_string(e.encode) +
           " s; " + std::to_string(e.bytes) + " bytes";
    return e.wall;
  };
  // The ceiling: encoding alone, by the ffmpeg CLI, with VideoWriter's settings (veryfast, CRF 20, a keyframe
  // every 2 s), run as a child process whose CPU seconds (all its threads) come back from wait4.
  const std::vector<std::string> cmd = {"ffmpeg",
                                        "-loglevel",
                                        "error",
                                        "-y",
                                        "-f",
                                        "rawvideo",
                                        "-pix_fmt",
                                        "rgba",
                                        "-s",
                                        std::to_string(W) + "x" + std::to_string(H),
                                        "-r",
                                        std::to_string(kFps),
                                        "-i",
                                        raw,
                                        "-c:v",
                                        "libx264",
                                        "-preset",
                                        "veryfast",
                                        "-crf",
                                        "20",
                                        "-g",
                                        std::to_string(2 * kFps),
                                        "-pix_fmt",
                                        "yuv420p",
                                        "-movflags",
                                        "+faststart",
                                        (dir / "ceiling.mp4").string()};
  double ceiling_cpu = 0;  // CPU seconds of the last ceiling run
  auto ceiling = [&] { return ffmpeg_child(cmd, ceiling_cpu); };
  // The target compares end to end with the ceiling; this machine's speed drifts by up to 30%
  // over minutes, so they run in alternation, `pairs` pairs (SIMREEL_BENCH_PAIRS, default 7), and
  // the ratio is the median of the pairs' ratios. Beside the wall-clock ratio (the target), the
  // ratio of CPU seconds: ours of all the process's threads, ffmpeg's of all its threads (wait4),
  // which other work on the machine disturbs much less.
  // Each pair of a full run also runs the clip with overlays (an arrow per box and a HUD) right
  // after the plain one: their ratio is the overlays' cost (target: at most 1.15).
  std::vector<double> ratios, cpu_ratios, overlay_ratios, overlay_cpu_ratios;
  const double load_before = load1();
  for (int pair = 1; pair <= pairs; ++pair) {
    std::string note;
    const double e2e = end_to_end("fxaa", note);
    const double plain_cpu = last_cpu;
    row("end_to_end_fxaa", e2e,
        note + "; load " + std::to_string(load1()).substr(0, 4) + "; pair " + std::to_string(pair));
    if (!only_pairs) {
      const double e2e_ov = end_to_end("fxaa", note, true);
      row("end_to_end_fxaa_overlays", e2e_ov,
          "100 angular velocity arrows (auto-scaled: one more simulation first) and a title and 3-line "
          "HUD; " +
              note + "; pair " + std::to_string(pair));
      overlay_ratios.push_back(e2e_ov / e2e);
      overlay_cpu_ratios.push_back(last_cpu / plain_cpu);
    }
    const double c = ceiling();
    if (c < 0) {
      std::printf(
          "ffmpeg_cli_encode_only,%d,%d,%d,,,\"ffmpeg not available (SIMREEL_BENCH=1 bash .ci/setup)\"\n",
          frames, W, H);
      continue;
    }
    row("ffmpeg_cli_encode_only", c,
        "the ceiling: raw RGBA from a file -> libx264 veryfast crf20; CPU " +
            std::to_string(ceiling_cpu).substr(0, 6) + " s (all its threads); pair " + std::to_string(pair) +
            ": wall ratio " + std::to_string(e2e / c).substr(0, 5) + ", CPU ratio " +
            std::to_string(plain_cpu / ceiling_cpu).substr(0, 5));
    ratios.push_back(e2e / c);
    cpu_ratios.push_back(plain_cpu / ceiling_cpu);
  }
  if (!ratios.empty()) {
    const auto [w, ws] = median_and_list(ratios, 2);
    const auto [c, cs] = median_and_list(cpu_ratios, 2);
    std::printf(
        "end_to_end_over_ceiling,%d,%d,%d,,,\"wall: median %.2f of the %zu pairs' ratios (%s), highest %.2f; "
        "CPU "
        "seconds: median %.2f (%s); load average %.1f before, %.1f after; target: median under 1.4, no pair "
        "over 1.5\"\n",
        frames, W, H, w, ratios.size(), ws.c_str(), *std::max_element(ratios.begin(), ratios.end()), c,
        cs.c_str(), load_before, load1());
    std::fflush(stdout);
  }
  if (only_pairs) {
    std::filesystem::remove(raw);
    return 0;
  }
  if (!overlay_ratios.empty()) {
    std::sort(overlay_ratios.begin(), overlay_ratios.end());
    std::string all;
    for (double q : overlay_ratios) all += (all.empty() ? "" : " ") + std::to_string(q).substr(0, 5);
    std::sort(overlay_cpu_ratios.begin(), overlay_cpu_ratios.end());
    std::string cpu;
    for (double q : overlay_cpu_ratios) cpu += (cpu.empty() ? "" : " ") + std::to_string(q).substr(0, 5);
    std::printf(
        "overlays_over_plain,%d,%d,%d,,,\"wall: median %.3f of the pairs' ratios (%s); CPU seconds: median "
        "%.3f "
        "(%s); target 1.15\"\n",
        frames, W, H, overlay_ratios[overlay_ratios.size() / 2], all.c_str(),
        overlay_cpu_ratios[overlay_cpu_ratios.size() / 2], cpu.c_str());
  }
  teaching_overlay_rows(bodies, frames, dir, 3, row);
  {
    std::string note;
    row("end_to_end_msaa4", end_to_end("msaa4", note), note);
  }
  std::filesystem::remove(raw);
  memory_rows();
  return 0;
}
