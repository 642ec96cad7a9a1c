// simreel render: scene to video, frames drawn off-screen and encoded in-process.
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>

#include <unistd.h>

#include <algorithm>

#include "app/camera_fit.hpp"
#include "app/commands.hpp"
#include "app/frame_loop.hpp"
#include "app/run.hpp"
#include "app/text.hpp"

#ifdef SIMREEL_HAVE_RENDER
#include "app/scene_view.hpp"
#include "render/png_writer.hpp"
#include "render/renderer.hpp"
#include "render/video_writer.hpp"
#endif

namespace simreel {

namespace {

const char* kRenderHelp = R"(usage: simreel render SCENE [options]

Simulates SCENE and writes a video: frame k shows simulated time k / fps exactly (the timestep is
shortened, with a note, when it does not divide 1/fps). The video appears at its path only when
complete; Ctrl-C (SIGINT), SIGTERM, SIGHUP or SIGQUIT stops the run between steps and finishes a
playable video of the frames done so far (exit 130, 143, 129 or 131), however many signals follow.

options:
  -o OUT              output video, .mp4/.mov/.mkv (H.264), .webm (VP9) or .gif; default
                      out/<scene>.mp4. With --at: a .png
  --frames SPEC       render only these frames (the physics runs through the others): comma-
                      separated frame numbers N, ranges A:B (both included; A:, :B), times Ts
                      (the frame at or after T seconds) and shares P% of the duration. Frame k of
                      a partial render is byte for byte frame k of the full render, with the same
                      PNG name and timestamp
  --at T              one frame at simulated time T (seconds, need not fall on a frame) as a PNG
                      (-o, default out/<scene>_<T>s.png): a preview
  --frames-dir DIR    also write every frame as DIR/frame_00000.png ... (numbered by frame k);
                      refused if DIR already holds frames, unless --overwrite
  --overwrite         with --frames-dir: delete the frame_*.png files already there first
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
  --json              print the summary as one JSON object (also with --quiet)
  --quiet             print nothing but errors (no progress, no summary)
)";

#ifdef SIMREEL_HAVE_RENDER
std::string lower_ext(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  for (char& c : e) c = (char)std::tolower((unsigned char)c);
  return e;
}

// The output must be a file simreel can write, in a folder that exists or can be made: checked
// before anything runs, so a wrong name fails at once and leaves nothing behind.
void check_output(const std::string& path, const std::vector<std::string>& exts, const char* what) {
  const std::string e = lower_ext(path);
  if (std::find(exts.begin(), exts.end(), e) == exts.end()) {
    std::string list;
    for (const std::string& x : exts) list += (list.empty() ? "" : ", ") + x;
    throw UsageError("-o '" + path + "': " + what + " must end in " + list);
  }
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw UsageError("-o '" + path + "' is a folder, not a file");
  std::string err;
  if (!ensure_parent_dir(path, &err)) throw std::runtime_error(err);
}

// Frame sizes the encoders cannot take, refused before anything runs (FFmpeg found out after the
// first frames, 2.3 s and 3.2 GB into a 16384 x 16384 H.264 render). H.264's highest level (6.2)
// allows 139264 macroblocks of 16 x 16 px a frame, and a side of at most sqrt(8 x 139264) = 1055
// macroblocks; VP9 takes sides up to 65536 px, GIF up to 65535.
void check_codec_limits(const std::string& path, int w, int h) {
  const std::string e = lower_ext(path);
  if (e == ".gif") {
    if (w > 65535 || h > 65535)
      throw UsageError("a GIF's sides are at most 65535 px, asked " + std::to_string(w) + "x" +
                       std::to_string(h));
    return;
  }
  if (e == ".webm") return;  // VP9: up to 65536, beyond the 16384 simreel allows
  const long mbw = (w + 15) / 16, mbh = (h + 15) / 16;
  if (mbw * mbh > 139264 || mbw > 1055 || mbh > 1055)
    throw UsageError("H.264 cannot encode " + std::to_string(w) + "x" + std::to_string(h) + " (" +
                     std::to_string(mbw * mbh) +
                     " macroblocks a frame; its highest level allows 139264, e.g. 8192x4320): use a smaller "
                     "--width/--height, or .webm (VP9)");
}

bool is_frame_png(const std::filesystem::path& p) {
  const std::string n = p.filename().string();
  return n.rfind("frame_", 0) == 0 && lower_ext(n) == ".png";
}

// --frames-dir: a folder of this run's frames only. Stale frames of an earlier, longer run must
// never mix with new ones: refuse a folder that holds frames unless --overwrite, which deletes
// them (and nothing else) first.
void prepare_frames_dir(const std::string& dir, bool overwrite) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw UsageError("--frames-dir '" + dir + "' exists and is not a folder");
  if (fs::is_directory(dir, ec)) {
    std::vector<fs::path> old;
    for (const auto& e : fs::directory_iterator(dir, ec))
      if (is_frame_png(e.path())) old.push_back(e.path());
    if (!old.empty() && !overwrite)
      throw UsageError("--frames-dir '" + dir + "' already holds " + std::to_string(old.size()) +
                       " frames (frame_*.png); add --overwrite to replace them, or choose another folder");
    for (const fs::path& p : old)
      if (!fs::remove(p, ec) || ec)
        throw std::runtime_error("cannot delete the old frame '" + p.string() + "'");
  }
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create '" + dir + "': " + ec.message());
}

ViewOptions view_options(const ParsedArgs& a) {
  ViewOptions o;
  if (a.has("--aa")) {
    o.aa = a.options.at("--aa");
    if (!antialiasing_from_name(o.aa))
      throw UsageError("unknown --aa '" + o.aa + "' (fxaa, msaa2, msaa4, none)");
  }
  if (a.has("--gl")) {
    o.gl = a.options.at("--gl");
    const auto b = gl_backend_from_name(o.gl);
    if (!b) throw UsageError("unknown --gl '" + o.gl + "' (osmesa, egl)");
    if (!gl_backend_built(*b)) throw UsageError("this simreel was built without the " + o.gl + " backend");
  }
  o.no_shadows = a.has("--no-shadows");
  return o;
}

// render --at T: the one frame at simulated time T, as a PNG.
int render_at(const ParsedArgs& a, const Scene& scene, FrameLoop& loop, int w, int h,
              const StopSignals& stop) {
  const double t = a.number("--at", false);
  if (t < 0 || t > scene.duration)
    throw UsageError("--at " + a.options.at("--at") + " is outside the run (0 to " +
                     std::to_string(scene.duration) + " s; --duration sets the end)");
  char name[64];
  std::snprintf(name, sizeof name, "_%gs.png", t);
  const std::string path = a.has("-o") ? a.options.at("-o") : "out/" + scene.name + name;
  check_output(path, {".png"}, "--at's output");
  ViewOptions o = view_options(a);
  o.width = w, o.height = h;
  o.threads = loop.world().config().threads;
  SceneView view(scene, loop.world(), o);
  Renderer renderer(view.settings, view.meshes);
  const FrameTarget target{-1, t, step_at(t, scene.timestep, loop.plan().total_steps)};
  double render_s = 0;
  FrameLoop::Hooks hooks;
  hooks.stop = &stop.flag();
  hooks.step = view.step_hook();  // trails: every physics step, drawn or not
  hooks.frame = [&](const FrameTarget&, const World& world) {
    const auto t0 = std::chrono::steady_clock::now();
    const uint8_t* rgba = view.draw(renderer, world);
    const std::string tmp = path + ".partial-" + std::to_string(getpid()) + ".png";
    try {
      write_png(tmp, rgba, w, h);
      std::filesystem::rename(tmp, path);
    } catch (...) {
      std::remove(tmp.c_str());
      throw;
    }
    render_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  const long done = loop.run({target}, hooks, false);
  RunSummary s = make_summary(scene, loop.world(), loop.drift(), (int)done, loop.step_seconds());
  s.render_seconds = render_s;
  s.encode_seconds = 0;
  s.renderer = renderer.description();
  if (done) s.output = path;
  if (stop.signal())
    s.warnings.push_back("interrupted by signal " + std::to_string(stop.signal()) + " before the frame");
  print_summary(a, s);
  return stop.signal() ? 128 + stop.signal() : kExitOk;
}
#endif

}  // namespace

#ifdef SIMREEL_HAVE_RENDER
int cmd_render(const std::vector<std::string>& args) {
  const ParsedArgs a = parse_args(
      args, {{"-o", true},           {"--frames", true},    {"--at", true},         {"--frames-dir", true},
             {"--overwrite", false}, {"--no-video", false}, {"--width", true},      {"--height", true},
             {"--fps", true},        {"--duration", true},  {"--integrator", true}, {"--timestep", true},
             {"--aa", true},         {"--gl", true},        {"--threads", true},    {"--no-shadows", false},
             {"--crf", true},        {"--json", false},     {"--quiet", false},     {"--help", false},
             {"-h", false}});
  if (a.has("--help") || a.has("-h")) {
    std::fputs(kRenderHelp, stdout);
    return kExitOk;
  }
  if (a.positional.size() != 1) throw UsageError("render takes one scene file");
  if (a.has("--no-video") && !a.has("--frames-dir")) throw UsageError("--no-video needs --frames-dir");
  if (a.has("--overwrite") && !a.has("--frames-dir")) throw UsageError("--overwrite needs --frames-dir");
  if (a.has("--at") && (a.has("--frames") || a.has("--frames-dir") || a.has("--no-video")))
    throw UsageError("--at writes one PNG: it does not go with --frames, --frames-dir or --no-video");
  // From here signals stop the run between steps and the outputs are finished (a playable video
  // of the frames done), however many signals follow.
  const StopSignals stop;
  Scene scene = load_scene(a.positional[0]);
  apply_overrides(a, scene);
  for (const std::string& n : scene.notes) std::fprintf(stderr, "note: %s\n", n.c_str());
  int w = scene.video.width, h = scene.video.height;
  if (!a.has("--at") && (w % 2 || h % 2)) {
    std::fprintf(stderr, "note: %dx%d rounded up to %dx%d (yuv420p video needs even sizes)\n", w, h,
                 w + w % 2, h + h % 2);
    w += w % 2, h += h % 2;
  }
  const int threads = a.has("--threads") ? a.whole("--threads", 1, 256) : 1;
  if (const std::string n = fit_camera(scene, threads); !n.empty() && !a.has("--quiet"))
    std::fprintf(stderr, "note: %s\n", n.c_str());
  FrameLoop loop(scene, threads);
  if (a.has("--at")) return render_at(a, scene, loop, w, h, stop);

  FrameTargets targets = loop.all_frames();
  if (a.has("--frames")) {
    try {
      targets = parse_frame_spec(a.options.at("--frames"), loop.plan(), scene.video.fps, scene.timestep,
                                 scene.duration, true);
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--frames: ") + e.what());
    }
  }

  VideoSettings vs;
  vs.width = w;
  vs.height = h;
  vs.fps = scene.video.fps;
  if (a.has("--crf")) vs.crf = a.whole("--crf", 0, 51);
  if (!a.has("--no-video")) {
    vs.path = a.has("-o") ? a.options.at("-o") : "out/" + scene.name + ".mp4";
    check_output(vs.path, {".mp4", ".mov", ".mkv", ".webm", ".gif"}, "a video");
    check_codec_limits(vs.path, w, h);
    remove_stale_partials(vs.path);  // left by a render that was killed (SIGKILL cannot be caught)
  }
  if (a.has("--frames-dir")) {
    vs.frames_dir = a.options.at("--frames-dir");
    prepare_frames_dir(vs.frames_dir, a.has("--overwrite"));
  }

  ViewOptions o = view_options(a);
  o.width = w, o.height = h;
  o.threads = threads;
  SceneView view(scene, loop.world(), o);
  // The post stage (FXAA, then the screen layer) runs on the writer's thread, overlapping the next
  // frame's rendering.
  view.settings.post = PostStage::caller;
  vs.fxaa = view.settings.fxaa();
  Renderer renderer(view.settings, view.meshes);
  VideoWriter writer(vs);

  Progress progress("frames", (long)targets.size(), a.has("--quiet") || a.has("--json"));
  double render_s = 0;
  FrameLoop::Hooks hooks;
  hooks.stop = &stop.flag();
  hooks.step = view.step_hook();  // trails: every physics step, drawn or not
  // Frames that show no body at all: most of them empty means a camera or a scale gone wrong.
  const std::vector<double> radii = body_radii(loop.world());
  const double aspect = (double)w / h;
  long empty = 0;
  hooks.frame = [&](const FrameTarget& t, const World& world) {
    const auto t0 = std::chrono::steady_clock::now();
    // (A camera inside a body sees its inside faces culled: nothing.)
    if (view.follow < 0 && (!any_body_in_view(world, radii, view.camera.eye, view.camera.target,
                                              view.camera.up, view.camera.fov_deg, aspect) ||
                            body_around(world, radii, view.camera.eye) >= 0))
      ++empty;
    view.draw(renderer, world, writer.acquire(), t.index);  // read back straight into the writer's queue
    writer.commit(t.index, &view.screen());
    render_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  hooks.progress = [&](long done) { progress.update(done); };
  // A full render goes on to the end of the duration, as simulate does, so both report the same
  // run; a partial one stops at its last frame.
  const long done = loop.run(targets, hooks, !a.has("--frames"));
  progress.finish();
  if (done > 0) writer.finish();  // with no frame at all, the destructor removes the partial file

  RunSummary s = make_summary(scene, loop.world(), loop.drift(), (int)done, loop.step_seconds());
  s.render_seconds = render_s;
  s.renderer = renderer.description();
  s.encode_seconds = writer.encode_seconds();
  if (done > 0) s.output = vs.path.empty() ? vs.frames_dir : vs.path;
  if (done > 0 && empty * 2 > done) {
    std::string msg =
        std::to_string(empty) + " of " + std::to_string(done) +
        " frames show no body: is the camera aimed at the scene (camera.look_at), or the scene in the "
        "units you meant (metres)? camera: { auto: true } frames everything";
    if (const int inside = body_around(loop.world(), radii, view.camera.eye); inside >= 0)
      msg += "; the camera is inside body '" + loop.world().def(inside).name + "'";
    s.warnings.push_back(msg);
  }
  if (stop.signal()) {
    s.warnings.push_back("interrupted by signal " + std::to_string(stop.signal()) + " after " +
                         std::to_string(done) + " of " + std::to_string(targets.size()) + " frames");
  }
  print_summary(a, s);
  return stop.signal() ? 128 + stop.signal() : kExitOk;
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
// check and diff draw and decode frames: without render/ they only say so.
int cmd_check(const std::vector<std::string>&) {
  std::fprintf(stderr, "simreel check: this build has no renderer (configured with -DSIMREEL_RENDER=OFF)\n");
  return kExitFailure;
}
int cmd_diff(const std::vector<std::string>&) {
  std::fprintf(stderr, "simreel diff: this build has no renderer (configured with -DSIMREEL_RENDER=OFF)\n");
  return kExitFailure;
}
#endif

}  // namespace simreel
