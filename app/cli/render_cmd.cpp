// simreel render: scene to video, frames drawn off-screen and encoded in-process.
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <sstream>

#include <unistd.h>

#include <algorithm>

#include "app/cli/chunks.hpp"
#include "app/cli/cli.hpp"
#include "app/cli/commands.hpp"
#include "app/runner/camera_fit.hpp"
#include "app/runner/frame_loop.hpp"
#include "app/runner/run.hpp"
#include "app/scene/text.hpp"

#ifdef SIMREEL_HAVE_RENDER
#include "app/view/panes.hpp"
#include "app/view/view_state.hpp"
#include "render/png_writer.hpp"
#include "render/renderer.hpp"
#include "render/video_writer.hpp"
#endif

namespace simreel {

namespace {

struct RenderOptions {
  std::vector<std::string> scenes;
  RunOptions run;
  std::optional<std::string> out, frames, frames_dir;
  std::optional<double> at;
  bool overwrite = false, no_video = false, no_shadows = false;
  std::optional<std::string> aa, gl;
  std::optional<std::string> chunk, checkpoints;
  std::optional<int> crf, gif_width;
  std::optional<std::string> encoder;
  std::optional<double> gif_fps;
};

// render's option table.
void render_table(CLI::App& app, RenderOptions& o) {
  cli::setup(app, "render",
             "Simulates SCENE and writes a video: frame k shows simulated time k / fps exactly (the timestep "
             "is shortened, with a note, when it does not divide 1/fps); a scene's `time:` block plays it "
             "slower, faster or held (frame k then shows the step nearest f(k / fps)).",
             "The video appears at its path only when complete; Ctrl-C (SIGINT), SIGTERM, SIGHUP or SIGQUIT "
             "stops the run between steps and finishes a playable video of the frames done so far (exit 130, "
             "143, 129 or 131), however many signals follow.");
  cli::add_positionals(app, o.scenes);
  app.add_option("-o", o.out,
                 "output video, .mp4/.mov/.mkv (H.264), .webm (VP9) or .gif; default out/<scene>.mp4. With "
                 "--at: a .png")
      ->type_name("OUT");
  app.add_option(
         "--frames", o.frames,
         "render only these frames (the physics runs through the others): comma-separated frame "
         "numbers N, ranges A:B (both included; A:, :B), times Ts (the frame at or after T seconds "
         "of video) and shares P% of the video. Frame k of a partial render is byte for byte frame k of the "
         "full render, with the same PNG name and timestamp")
      ->type_name("SPEC");
  app.add_option("--at", o.at,
                 "one frame at simulated time T (seconds, need not fall on a frame) as a PNG (-o, default "
                 "out/<scene>_<T>s.png): a preview")
      ->type_name("T")
      ->check(cli::number());
  app.add_option("--frames-dir", o.frames_dir,
                 "also write every frame as DIR/frame_00000.png ... (numbered by frame k); refused if DIR "
                 "already holds frames, unless --overwrite")
      ->type_name("DIR");
  app.add_flag("--overwrite", o.overwrite,
               "with --frames-dir: delete the frame_*.png files already there first");
  app.add_flag("--no-video", o.no_video, "with --frames-dir: PNG frames only");
  app.add_option(
         "--chunk", o.chunk,
         "render chunk I of N (I from 0 to N-1, as SLURM_ARRAY_TASK_ID) as a segment that `simreel join` "
         "copies into the whole clip: -o DIR/ (MP4 segments named after the scene) or -o DIR/NAME.EXT "
         "(.mp4 .mov .mkv .webm; .gif: lossless PNG frames, the palette made once by join). Chunks "
         "start on keyframes (`simreel plan` prints the table); with --frames-dir, a chunk writes and "
         "refuses only its own frames in a shared folder")
      ->type_name("I/N");
  app.add_option(
         "--checkpoints", o.checkpoints,
         "with --chunk: start from the saved state `simreel plan --checkpoints DIR` wrote at the chunk's "
         "first frame (no physics before it, no whole-run pre-pass); a checkpoint of another scene, "
         "version or setting is refused")
      ->type_name("DIR");
  add_scene_overrides(app, o.run, true);
  app.add_option(
         "--aa", o.aa,
         "anti-aliasing: fxaa (default: cheap, on the CPU), msaa2, msaa4 (GL multisampling, smoother, "
         "~2x the render time on llvmpipe), none")
      ->check(cli::choice({"fxaa", "msaa2", "msaa4", "none"}));
  app.add_flag("--no-shadows", o.no_shadows, "skip shadow mapping");
  app.add_option(
         "--gl", o.gl,
         "OpenGL context: osmesa (the default where built) or egl (Mesa's surfaceless platform or the "
         "first EGL device); the same frames on llvmpipe")
      ->check(cli::choice({"osmesa", "egl"}));
  app.add_option("--crf", o.crf, "H.264 quality, 0-51 (default 20; lower is better and larger)")
      ->type_name("N")
      ->transform(cli::whole(0, 51));
  app.add_option(
         "--encoder", o.encoder,
         "FFmpeg video encoder for .mp4/.mov/.mkv instead of libx264: h264_nvenc, hevc_nvenc, libx265, "
         "...; one that this FFmpeg lacks or that cannot run here (no NVENC unit, VAAPI) falls back to "
         "libx264 with a note")
      ->type_name("NAME");
  app.add_option("--gif-width", o.gif_width,
                 "with a .gif output: its width (the height follows the aspect ratio), scaled from the "
                 "rendered frames with a Lanczos filter; default the video width")
      ->type_name("W")
      ->transform(cli::whole(16, 16384));
  app.add_option("--gif-fps", o.gif_fps,
                 "with a .gif output: its frame rate, at most the video's (frames are picked at the nearest "
                 "time) and at most 50 (GIF delays are whole hundredths of a second, and browsers slow "
                 "delays under 2 to 10); default the video's, up to 50")
      ->type_name("F")
      ->check(cli::positive());
  add_summary_flags(app, o.run);
}

#ifdef SIMREEL_HAVE_RENDER
// The output must be a file simreel can write, in a folder that exists or can be made: checked
// before anything runs, so a wrong name fails at once and leaves nothing behind.
void check_output(const std::string& path, const std::vector<std::string>& exts, const char* what) {
  const std::string e = lower_extension(path);
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
  const std::string e = lower_extension(path);
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
  return n.rfind("frame_", 0) == 0 && lower_extension(n) == ".png";
}

// --frames-dir: a folder of this run's frames only. Stale frames of an earlier, longer run must
// never mix with new ones: refuse a folder that holds frames unless --overwrite, which deletes
// them (and nothing else) first. A chunk (`only`) shares the folder with the others: it looks at,
// refuses and deletes only its own frames' names.
void prepare_frames_dir(const std::string& dir, bool overwrite, const ChunkSpan* only = nullptr) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw UsageError("--frames-dir '" + dir + "' exists and is not a folder");
  if (fs::is_directory(dir, ec)) {
    std::vector<fs::path> old;
    if (only) {
      for (long k = only->first; k <= only->last; ++k) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%05ld.png", k);
        if (fs::exists(fs::path(dir) / name, ec)) old.push_back(fs::path(dir) / name);
      }
    } else {
      for (const auto& e : fs::directory_iterator(dir, ec))
        if (is_frame_png(e.path())) old.push_back(e.path());
    }
    if (!old.empty() && !overwrite)
      throw UsageError("--frames-dir '" + dir + "' already holds " + std::to_string(old.size()) +
                       (only ? " of this chunk's frames" : " frames (frame_*.png)") +
                       "; add --overwrite to replace them, or choose another folder");
    for (const fs::path& p : old)
      if (!fs::remove(p, ec) || ec)
        throw std::runtime_error("cannot delete the old frame '" + p.string() + "'");
  }
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create '" + dir + "': " + ec.message());
}

// render --chunk I/N: where the chunk's segment and record go, and what it must share with the others.
struct ChunkJob {
  ChunkSpan span;
  int chunks = 0;
  long total = 0;  // frames of the whole clip
  std::string ext, segment, record_path, segment_name;
  bool frames = false;  // a GIF's chunk: lossless PNG frames in a folder of their own
  ChunkManifest manifest;
};

ChunkJob chunk_job(const RenderOptions& r, const Scene& scene, long total, const ChunkManifest& manifest) {
  namespace fs = std::filesystem;
  ChunkJob j;
  const auto [i, n] = parse_chunk_arg(*r.chunk);
  if (!r.out) throw UsageError("--chunk needs -o DIR/ (or -o DIR/NAME.mp4): the folder `simreel join` reads");
  std::string dir = *r.out, stem = scene.name;
  j.ext = ".mp4";
  std::error_code ec;
  if (!dir.empty() && dir.back() != '/' && !fs::is_directory(dir, ec)) {
    const fs::path p(*r.out);
    j.ext = lower_extension(*r.out);
    const std::vector<std::string> exts = {".mp4", ".mov", ".mkv", ".webm", ".gif"};
    if (std::find(exts.begin(), exts.end(), j.ext) == exts.end())
      throw UsageError("-o '" + *r.out +
                       "': with --chunk, give a folder (DIR/) or DIR/NAME with .mp4, .mov, "
                       ".mkv, .webm or .gif");
    dir = p.has_parent_path() ? p.parent_path().string() : ".";
    stem = p.stem().string();
  }
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create '" + dir + "': " + ec.message());
  j.chunks = n;
  j.total = total;
  j.span = chunk_table(total, keyframe_interval(scene.video.fps), n)[(size_t)i];
  j.frames = j.ext == ".gif";
  const std::string cs = chunk_stem(stem, i, n);
  j.segment_name = j.frames ? cs + ".frames" : cs + j.ext;
  j.segment = (fs::path(dir) / j.segment_name).string();
  j.record_path = (fs::path(dir) / (cs + ".json")).string();
  j.manifest = manifest;
  // A record left by an earlier run of this chunk says "complete" only for what this run writes.
  fs::remove(j.record_path, ec);
  return j;
}

ViewOptions view_options(const RenderOptions& r) {
  ViewOptions o;
  if (r.aa) o.aa = *r.aa;  // names checked by the table
  if (r.gl) {
    o.gl = *r.gl;
    if (!gl_backend_built(*gl_backend_from_name(o.gl)))
      throw UsageError("this simreel was built without the " + o.gl + " backend");
  }
  o.no_shadows = r.no_shadows;
  return o;
}

// render --at T: the one frame at simulated time T, as a PNG.
int render_at(const RenderOptions& r, const Scene& scene, FrameLoop& loop, int w, int h,
              const StopSignals& stop) {
  const double t = *r.at;
  char name[64];
  if (t < 0 || t > scene.duration) {
    std::snprintf(name, sizeof name, "%g", t);
    throw UsageError(std::string("--at ") + name + " is outside the run (0 to " +
                     std::to_string(scene.duration) + " s; --duration sets the end)");
  }
  std::snprintf(name, sizeof name, "_%gs.png", t);
  const std::string path = r.out ? *r.out : "out/" + scene.name + name;
  check_output(path, {".png"}, "--at's output");
  ViewOptions o = view_options(r);
  o.width = w, o.height = h;
  o.threads = loop.world().config().threads;
  SceneFrames view(scene, loop, o);  // one view or panes (app/view/panes.hpp)
  if (!r.run.quiet)
    for (const std::string& n : view.notes()) std::fprintf(stderr, "note: %s\n", n.c_str());
  const FrameTarget target{-1, t, step_at(t, scene.timestep, loop.plan().total_steps)};
  double render_s = 0;
  FrameLoop::Hooks hooks;
  hooks.stop = &stop.flag();
  hooks.step = view.step_hook();  // trails: every physics step, drawn or not
  // render.motion_blur: the states before the frame, drawn on the way
  view.blur_hooks(hooks, loop.video_plan());
  hooks.frame = [&](const FrameTarget&, const World& world) {
    const auto t0 = std::chrono::steady_clock::now();
    // The HUD's frame: the first video frame showing this step, if one does.
    const uint8_t* rgba = view.draw(world, nullptr, loop.video_frame_at_step(world.steps()));
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
  s.renderer = view.description();
  if (done) s.output = path;
  if (stop.signal())
    s.warnings.push_back("interrupted by signal " + std::to_string(stop.signal()) + " before the frame");
  print_summary(r.run, s);
  return stop.signal() ? 128 + stop.signal() : kExitOk;
}
#endif

}  // namespace

#ifdef SIMREEL_HAVE_RENDER
int cmd_render(const std::vector<std::string>& args) {
  RenderOptions r;
  CLI::App app;
  render_table(app, r);
  if (!cli::parse(app, args)) return kExitOk;
  if (r.scenes.size() != 1) throw UsageError("render takes one scene file");
  if (r.no_video && !r.frames_dir) throw UsageError("--no-video needs --frames-dir");
  if (r.overwrite && !r.frames_dir) throw UsageError("--overwrite needs --frames-dir");
  if (r.at && (r.frames || r.frames_dir || r.no_video || r.chunk))
    throw UsageError(
        "--at writes one PNG: it does not go with --frames, --frames-dir, --no-video or --chunk");
  const bool gif = r.out && !r.at && !r.no_video && lower_extension(*r.out) == ".gif";
  if ((r.gif_width || r.gif_fps) && !gif)
    throw UsageError(std::string(r.gif_width ? "--gif-width" : "--gif-fps") +
                     " applies to a .gif output (-o clip.gif)");
  // From here signals stop the run between steps and the outputs are finished (a playable video
  // of the frames done), however many signals follow.
  const StopSignals stop;
  Scene scene = load_scene(r.scenes[0]);
  apply_overrides(r.run, scene);
  if (!r.run.quiet)  // --quiet: nothing but errors
    for (const std::string& n : scene.notes) std::fprintf(stderr, "note: %s\n", n.c_str());
  int w = scene.video.width, h = scene.video.height;
  if (!r.at && (w % 2 || h % 2)) {
    std::fprintf(stderr, "note: %dx%d rounded up to %dx%d (yuv420p video needs even sizes)\n", w, h,
                 w + w % 2, h + h % 2);
    w += w % 2, h += h % 2;
  }
  const int threads = r.run.threads;
  // --checkpoints: `plan` ran the whole-run passes once; this chunk takes their products.
  std::optional<CheckpointPlan> ckpt;
  PrepassStore prepass(PrepassStore::Mode::replay);
  // What every chunk of one join shares (hashes of the scene and each file it reads: once).
  std::optional<ChunkManifest> manifest;
  if (r.chunk) manifest = chunk_manifest(r.scenes[0], scene, look_settings(r.aa, r.no_shadows));
  if (r.checkpoints) {
    if (!r.chunk) throw UsageError("--checkpoints needs --chunk");
    ckpt = read_checkpoint_plan(*r.checkpoints);
    const ChunkManifest& m = *manifest;
    const auto [i, n] = parse_chunk_arg(*r.chunk);
    if (ckpt->manifest != m.id || ckpt->chunks != n)
      throw InputError(*r.checkpoints + ": these checkpoints are of " +
                       (ckpt->manifest != m.id
                            ? "another scene, input file, setting or simreel version (manifest " +
                                  ckpt->manifest + ", this chunk's " + m.id + ")"
                            : "a split into " + std::to_string(ckpt->chunks) + " chunks") +
                       ": run simreel plan " + r.scenes[0] + " --chunks " + std::to_string(n) +
                       " --checkpoints " + *r.checkpoints + " again, with the chunks' options");
    (void)i;
    if (ckpt->fitted) {
      scene.camera.fit = false;  // fitted over the whole run by plan
      for (int k = 0; k < 3; ++k)
        scene.camera.position[k] = ckpt->position[k], scene.camera.look_at[k] = ckpt->look_at[k];
    }
    read_checkpoint_prepass(*r.checkpoints, m.id, prepass);
  }
  if (const std::string n = fit_camera(scene, threads); !n.empty() && !r.run.quiet)
    std::fprintf(stderr, "note: %s\n", n.c_str());
  FrameLoop loop(scene, threads);
  if (r.at) return render_at(r, scene, loop, w, h, stop);

  FrameTargets targets = loop.video_frames();
  std::optional<ChunkJob> job;
  // A chunk that fails says which one, for the scheduler's log (the error itself follows).
  struct FailureNote {
    const std::optional<ChunkJob>& job;
    int pending = std::uncaught_exceptions();
    ~FailureNote() {
      if (job && std::uncaught_exceptions() > pending)
        std::fprintf(stderr, "simreel render: chunk %d of %d (frames %ld to %ld) failed\n", job->span.index,
                     job->chunks, job->span.first, job->span.last);
    }
  } failure_note{job};
  if (r.chunk) {
    if (r.frames) throw UsageError("--chunk renders its own frames: it does not go with --frames");
    if (r.gif_width || r.gif_fps)
      throw UsageError("give --gif-width and --gif-fps to `simreel join`, which makes the GIF");
    job = chunk_job(r, scene, (long)targets.size(), *manifest);
    if (job->frames && r.frames_dir)
      throw UsageError("a GIF's chunk writes its PNG frames to " + job->segment +
                       "/ already: leave out --frames-dir");
    FrameTargets mine;
    for (const FrameTarget& t : targets)
      if (t.index >= job->span.first && t.index <= job->span.last) mine.push_back(t);
    targets = std::move(mine);
  }
  if (r.frames) {
    try {
      // Frames of the video: numbers and times of the clip (with a `time:` block, video time).
      targets = parse_frame_spec(*r.frames, loop.video_plan(), scene.video.fps, scene.timestep,
                                 loop.video_duration(), true);
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--frames: ") + e.what());
    }
  }

  VideoSettings vs;
  vs.width = w;
  vs.height = h;
  vs.fps = scene.video.fps;
  if (r.crf) vs.crf = *r.crf;
  if (r.encoder) vs.encoder = *r.encoder;
  if (r.gif_width) {
    if (*r.gif_width > w)
      throw UsageError("--gif-width " + std::to_string(*r.gif_width) + " is wider than the frames (" +
                       std::to_string(w) + " px): render them wider with --width");
    vs.gif_width = *r.gif_width;
  }
  if (r.gif_fps) {
    char f[160];
    std::snprintf(f, sizeof f, "--gif-fps %g is above ", *r.gif_fps);
    if (*r.gif_fps > 50)
      throw UsageError(std::string(f) +
                       "50 (GIF delays are whole hundredths of a second; browsers show delays "
                       "under 2 as 10)");
    if (*r.gif_fps > scene.video.fps * (1 + 1e-12)) {
      std::snprintf(f + std::strlen(f), sizeof f - std::strlen(f), "the video's frame rate (fps %g)",
                    scene.video.fps);
      throw UsageError(f);
    }
    vs.gif_fps = *r.gif_fps;
  } else if (gif && scene.video.fps > 50 && !r.run.quiet) {
    std::fprintf(stderr, "note: the GIF runs at 50 frames/s, the most GIF timing allows (--gif-fps)\n");
  }
  if (job && job->frames) {
    vs.frames_dir = job->segment;  // the chunk's own folder: emptied of earlier frames
    prepare_frames_dir(vs.frames_dir, true);
  } else if (job && !r.no_video) {
    vs.path = job->segment;
    check_codec_limits(vs.path, w, h);
    remove_stale_partials(vs.path);
  } else if (!r.no_video) {
    vs.path = r.out ? *r.out : "out/" + scene.name + ".mp4";
    check_output(vs.path, {".mp4", ".mov", ".mkv", ".webm", ".gif"}, "a video");
    check_codec_limits(vs.path, w, h);
    remove_stale_partials(vs.path);  // left by a render that was killed (SIGKILL cannot be caught)
  }
  if (r.frames_dir) {
    vs.frames_dir = *r.frames_dir;
    prepare_frames_dir(vs.frames_dir, r.overwrite, job ? &job->span : nullptr);
  }

  ViewOptions o = view_options(r);
  o.width = w, o.height = h;
  o.threads = threads;
  // The post stage (FXAA, then the screen layer) runs on the writer's thread, overlapping the next
  // frame's rendering.
  if (ckpt) o.prepass = &prepass;
  SceneFrames view(scene, loop, o, PostStage::caller);
  if (ckpt && job->span.first > 0) {
    // The world and the views' history at the frame before the chunk's first.
    const CheckpointState st = read_checkpoint_state(*r.checkpoints, job->span.index, job->manifest.id);
    if (st.frame != job->span.first - 1)
      throw InputError(*r.checkpoints + ": chunk " + std::to_string(st.index) + "'s state is at frame " +
                       std::to_string(st.frame) + ", not before frame " + std::to_string(job->span.first));
    std::istringstream ws(st.world), hs(st.history);
    loop.world().restore_state(ws);
    loop.state_restored();
    if (loop.world().steps() != st.step)
      throw InputError(*r.checkpoints + ": chunk " + std::to_string(st.index) +
                       "'s state is not at the step it names");
    view.restore_history(hs);
  }
  if (!r.run.quiet)
    for (const std::string& n : view.notes()) std::fprintf(stderr, "note: %s\n", n.c_str());
  vs.fxaa = view.caller_fxaa();
  VideoWriter writer(vs);
  if (!writer.encoder_note().empty() && !r.run.quiet)
    std::fprintf(stderr, "note: %s\n", writer.encoder_note().c_str());

  Progress progress("frames", (long)targets.size(), r.run.quiet || r.run.json);
  double render_s = 0;
  FrameLoop::Hooks hooks;
  hooks.stop = &stop.flag();
  hooks.step = view.step_hook();  // trails: every physics step, drawn or not
  // render.motion_blur: the states before each frame, drawn on the way (counted as rendering)
  view.blur_hooks(hooks, loop.video_plan());
  if (hooks.sample)
    hooks.sample = [&render_s, sample = hooks.sample](const FrameTarget& t, const World& w) {
      const auto t0 = std::chrono::steady_clock::now();
      sample(t, w);
      render_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    };
  // Frames that show no body at all: most of them empty means a camera or a scale gone wrong.
  const std::vector<double> radii = body_radii(loop.world());
  long empty = 0;
  hooks.frame = [&](const FrameTarget& t, const World& world) {
    const auto t0 = std::chrono::steady_clock::now();
    view.draw(world, writer.acquire(), t.index);  // read back straight into the writer's queue
    // (A camera inside a body sees its inside faces culled: nothing.)
    if (view.shows_nothing(world)) ++empty;
    writer.commit(t.index, &view.screen());
    render_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  hooks.progress = [&](long done) { progress.update(done); };
  // A full render goes on to the end of the duration, as simulate does, so both report the same
  // run; a partial one stops at its last frame.
  const long done = loop.run(targets, hooks, !r.frames && !job);
  progress.finish();
  if (job) {
    // A chunk's segment exists only complete, with its record beside it: `join` takes nothing else.
    if (done == job->span.count() && !stop.signal()) {
      writer.finish();
      ChunkRecord rec;
      rec.manifest = job->manifest.id;
      rec.index = job->span.index;
      rec.chunks = job->chunks;
      rec.first = job->span.first;
      rec.last = job->span.last;
      rec.total_frames = job->total;
      rec.keyint = keyframe_interval(scene.video.fps);
      rec.fps = scene.video.fps;
      rec.segment = job->segment_name;
      rec.kind = job->frames ? "frames" : r.no_video ? "none" : job->ext.substr(1);
      rec.width = w;
      rec.height = h;
      rec.scene = r.scenes[0];
      // The command that made it, for join's list of missing chunks: the same options, "{}" for I/N.
      rec.command = g_invoked_as + " render";
      for (size_t a = 0; a < args.size(); ++a) {
        std::string arg = args[a];
        if (arg.rfind("--chunk=", 0) == 0) arg = "--chunk={}";
        if (a > 0 && args[a - 1] == "--chunk") arg = "{}";
        if (arg.find_first_of(" '\"$") != std::string::npos) arg = "'" + arg + "'";
        rec.command += " " + arg;
      }
      write_chunk_record(job->record_path, rec);
    }
  } else if (done > 0) {
    writer.finish();  // with no frame at all, the destructor removes the partial file
  }

  RunSummary s = make_summary(scene, loop.world(), loop.drift(), (int)done, loop.step_seconds());
  s.render_seconds = render_s;
  s.renderer = view.description();
  s.encode_seconds = writer.encode_seconds();
  s.encoder = writer.encoder_name();
  if (done > 0 && (!job || done == job->span.count())) s.output = vs.path.empty() ? vs.frames_dir : vs.path;
  if (done > 0 && empty * 2 > done) {
    std::string msg =
        std::to_string(empty) + " of " + std::to_string(done) +
        " frames show no body: is the camera aimed at the scene (camera.look_at), or the scene in the "
        "units you meant (metres)? camera: { auto: true } frames everything";
    if (!view.split())
      if (const int inside = body_around(loop.world(), radii, scene.camera.position); inside >= 0)
        msg += "; the camera is inside body '" + loop.world().def(inside).name + "'";
    s.warnings.push_back(msg);
  }
  if (stop.signal()) {
    s.warnings.push_back("interrupted by signal " + std::to_string(stop.signal()) + " after " +
                         std::to_string(done) + " of " + std::to_string(targets.size()) + " frames");
  }
  print_summary(r.run, s);
  return stop.signal() ? 128 + stop.signal() : kExitOk;
}
#else
int cmd_render(const std::vector<std::string>& args) {
  RenderOptions r;
  CLI::App app;
  render_table(app, r);
  if (!cli::parse(app, args)) return kExitOk;
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
int cmd_plan(const std::vector<std::string>&) {
  std::fprintf(stderr, "simreel plan: this build has no renderer (configured with -DSIMREEL_RENDER=OFF)\n");
  return kExitFailure;
}
int cmd_join(const std::vector<std::string>&) {
  std::fprintf(stderr, "simreel join: this build has no renderer (configured with -DSIMREEL_RENDER=OFF)\n");
  return kExitFailure;
}
#endif

}  // namespace simreel
