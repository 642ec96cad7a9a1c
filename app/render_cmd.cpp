// simreel render: scene to video, frames drawn off-screen and encoded in-process.
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>

#include "app/commands.hpp"
#include "app/run.hpp"
#include "app/text.hpp"

#ifdef SIMREEL_HAVE_RENDER
#include "render/draw_list.hpp"
#include "render/renderer.hpp"
#include "render/video_writer.hpp"
#endif

namespace simreel {

namespace {

const char* kRenderHelp = R"(usage: simreel render SCENE [options]

Simulates SCENE and writes a video: a frame each time simulation time crosses the next 1/fps.
The video appears at its path only when complete; Ctrl-C (SIGINT) or SIGTERM finishes a playable
video of the frames done so far.

options:
  -o OUT              output video, .mp4 (H.264), .webm (VP9) or .gif; default out/<scene>.mp4
  --frames-dir DIR    also write every frame as DIR/frame_00000.png ...
  --no-video          with --frames-dir: PNG frames only
  --width W, --height H, --fps F, --duration S    override the scene (odd sizes round up to even)
  --integrator NAME, --timestep DT                 override the scene's physics
  --threads N         integration threads (frames are identical for any N); default 1
  --aa MODE           anti-aliasing: fxaa (default: cheap, on the CPU), msaa2, msaa4 (GL
                      multisampling, smoother, ~2x the render time on llvmpipe), none
  --no-shadows        skip shadow mapping
  --gl BACKEND        OpenGL context: osmesa (the default where built) or egl (Mesa's surfaceless
                      platform or the first EGL device); the same frames on llvmpipe
  --crf N             H.264 quality, 0-51 (default 20; lower is better and larger)
  --json              print the summary as one JSON object
  --quiet             no progress bar
)";

std::atomic<int> g_signal{0};

#ifdef SIMREEL_HAVE_RENDER
// The scene's appearance as the renderer takes it: a colour per collider (its file's material,
// else the body's), whether it is drawn, and the drawn size of planes.
SceneStyles styles_of(const Scene& scene) {
  SceneStyles out(scene.looks.size());
  for (size_t i = 0; i < scene.looks.size(); ++i) {
    const BodyLook& L = scene.looks[i];
    for (size_t k = 0; k < L.colliders.size(); ++k)
      out[i].push_back(
          {L.collider_color(k), L.drawn, L.colliders[k].plane_size, L.colliders[k].normals.get()});
  }
  return out;
}
#endif
extern "C" void on_signal(int sig) {
  g_signal = sig;
}

}  // namespace

#ifdef SIMREEL_HAVE_RENDER
int cmd_render(const std::vector<std::string>& args) {
  const ParsedArgs a = parse_args(args, {{"-o", true},
                                         {"--frames-dir", true},
                                         {"--no-video", false},
                                         {"--width", true},
                                         {"--height", true},
                                         {"--fps", true},
                                         {"--duration", true},
                                         {"--integrator", true},
                                         {"--timestep", true},
                                         {"--aa", true},
                                         {"--gl", true},
                                         {"--threads", true},
                                         {"--no-shadows", false},
                                         {"--crf", true},
                                         {"--json", false},
                                         {"--quiet", false},
                                         {"--help", false},
                                         {"-h", false}});
  if (a.has("--help") || a.has("-h")) {
    std::fputs(kRenderHelp, stdout);
    return kExitOk;
  }
  if (a.positional.size() != 1) throw UsageError("render takes one scene file");
  if (a.has("--no-video") && !a.has("--frames-dir")) throw UsageError("--no-video needs --frames-dir");
  Scene scene = load_scene(a.positional[0]);
  apply_overrides(a, scene);
  for (const std::string& n : scene.notes) std::fprintf(stderr, "note: %s\n", n.c_str());
  int w = scene.video.width, h = scene.video.height;
  if (w % 2 || h % 2) {
    std::fprintf(stderr, "note: %dx%d rounded up to %dx%d (yuv420p video needs even sizes)\n", w, h,
                 w + w % 2, h + h % 2);
    w += w % 2, h += h % 2;
  }

  VideoSettings vs;
  vs.width = w;
  vs.height = h;
  vs.fps = scene.video.fps;
  if (a.has("--crf")) vs.crf = a.whole("--crf", 0, 51);
  if (!a.has("--no-video")) vs.path = a.has("-o") ? a.options.at("-o") : "out/" + scene.name + ".mp4";
  std::string err;
  if (!vs.path.empty() && !ensure_parent_dir(vs.path, &err)) throw std::runtime_error(err);
  if (a.has("--frames-dir")) {
    vs.frames_dir = a.options.at("--frames-dir");
    std::error_code ec;
    std::filesystem::create_directories(vs.frames_dir, ec);
    if (ec) throw std::runtime_error("cannot create '" + vs.frames_dir + "': " + ec.message());
  }

  const int threads = a.has("--threads") ? a.whole("--threads", 1, 256) : 1;
  World world(world_config(scene, threads), scene.bodies);
  const SceneMeshes meshes(world, styles_of(scene));
  RenderSettings rs;
  if (a.has("--gl")) {
    const auto b = gl_backend_from_name(a.options.at("--gl"));
    if (!b) throw UsageError("unknown --gl '" + a.options.at("--gl") + "' (osmesa, egl)");
    if (!gl_backend_built(*b))
      throw UsageError("this simreel was built without the " + a.options.at("--gl") + " backend");
    rs.gl = *b;
  }
  rs.width = w;
  rs.height = h;
  AntiAliasing aa = scene.render.antialiasing;
  if (a.has("--aa")) {
    const auto m = antialiasing_from_name(a.options.at("--aa"));
    if (!m) throw UsageError("unknown --aa '" + a.options.at("--aa") + "' (fxaa, msaa2, msaa4, none)");
    aa = *m;
  }
  rs.msaa = aa == AntiAliasing::msaa4 ? 4 : aa == AntiAliasing::msaa2 ? 2 : 1;
  rs.fxaa = false;  // FXAA runs on the writer's thread, overlapping the next frame's rendering
  vs.fxaa = aa == AntiAliasing::fxaa;
  rs.shadows = scene.render.shadows && !a.has("--no-shadows");
  rs.background = scene.render.background;
  rs.ground = scene.render.ground;
  rs.ground_height = scene.render.ground_height;
  rs.ground_size = scene.render.ground_size;
  rs.ground_tile = scene.render.ground_tile;
  Renderer renderer(rs, meshes);
  VideoWriter writer(vs);

  CameraView cam;
  cam.eye = scene.camera.position;
  cam.target = scene.camera.look_at;
  cam.up = scene.camera.up;
  cam.fov_deg = scene.camera.fov;
  int follow = -1;
  for (int i = 0; i < world.body_count(); ++i)
    if (world.def(i).name == scene.camera.follow) follow = i;

  g_signal = 0;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  const FramePlan plan = plan_frames(scene.duration, scene.timestep, scene.video.fps);
  Drift drift(world);
  Progress progress("frames", (long)plan.frame_step.size(), a.has("--quiet") || a.has("--json"));
  DrawList dl;
  double step_s = 0, render_s = 0;
  size_t done = 0;
  for (; done < plan.frame_step.size() && !g_signal; ++done) {
    const auto t0 = std::chrono::steady_clock::now();
    while (world.steps() < plan.frame_step[done]) world.step();
    const auto t1 = std::chrono::steady_clock::now();
    world.check_spin();
    drift.sample(world);
    build_draw_list(world, meshes, cam, follow, dl);
    renderer.render(dl, writer.acquire());  // read back straight into the writer's queue
    writer.commit();
    const auto t2 = std::chrono::steady_clock::now();
    step_s += std::chrono::duration<double>(t1 - t0).count();
    render_s += std::chrono::duration<double>(t2 - t1).count();
    progress.update((long)done + 1);
  }
  progress.finish();
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  if (done > 0) writer.finish();  // with no frame at all, the destructor removes the partial file

  RunSummary s = make_summary(scene, world, drift, (int)done, step_s);
  s.render_seconds = render_s;
  s.renderer = renderer.description();
  s.encode_seconds = writer.encode_seconds();
  if (done > 0) s.output = vs.path.empty() ? vs.frames_dir : vs.path;
  if (g_signal) {
    s.warnings.push_back("interrupted by signal " + std::to_string(g_signal.load()) + " after " +
                         std::to_string(done) + " of " + std::to_string(plan.frame_step.size()) + " frames");
  }
  std::fputs(a.has("--json") ? (summary_json(s) + "\n").c_str() : summary_text(s).c_str(), stdout);
  return g_signal ? 128 + g_signal.load() : kExitOk;
}
#else
int cmd_render(const std::vector<std::string>& args) {
  if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
    std::fputs(kRenderHelp, stdout);
    return kExitOk;
  }
  std::fprintf(stderr, "simreel render: this build has no renderer (configured with -DSIMREEL_RENDER=OFF)\n");
  return kExitFailure;
}
#endif

}  // namespace simreel
