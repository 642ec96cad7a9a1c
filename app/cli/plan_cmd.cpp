// simreel plan: how a render splits into chunks for a scheduler (Slurm job arrays, GNU parallel,
// Kubernetes indexed jobs), and with --checkpoints the one pass that lets every chunk start at its
// own first frame.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>
#include <simreel/error.hpp>
#include "app/cli/chunks.hpp"
#include "app/cli/cli.hpp"
#include "app/cli/commands.hpp"
#include "app/runner/camera_fit.hpp"
#include "app/runner/frame_loop.hpp"
#include "app/scene/text.hpp"
#include "app/view/panes.hpp"
#include "app/view/view_state.hpp"
#include "render/render_settings.hpp"

namespace simreel {

namespace {

namespace fs = std::filesystem;

struct PlanOptions {
  std::vector<std::string> scenes;
  RunOptions run;
  int chunks = 0;
  std::optional<std::string> checkpoints, out, aa;
  bool no_shadows = false;
};

void plan_table(CLI::App& app, PlanOptions& o) {
  cli::setup(
      app, "plan",
      "Splits the render of SCENE into N chunks for a scheduler: prints the chunk table (boundaries on "
      "keyframe intervals, so the joined clip keeps a straight render's keyframe cadence), the manifest "
      "every chunk must share (the scene's hash and its input files', the settings that change physics "
      "or pixels, simreel's version) and the commands to run: `simreel render SCENE --chunk I/N -o DIR/` "
      "for each I, then `simreel join DIR -o OUT`. Give it the same overrides the chunks get.",
      "With --checkpoints DIR it also runs the scene once and writes, for each chunk, the saved state at the "
      "frame before its first plus what a chunk cannot make alone (the pre-passes' arrow scales and plot "
      "samples, the fitted camera, trails' and measured periods' history, every variant's world): a chunk "
      "given --checkpoints DIR then simulates only its own frames.");
  cli::add_positionals(app, o.scenes);
  app.add_option("--chunks", o.chunks, "the number of chunks, N")
      ->type_name("N")
      ->required()
      ->transform(cli::whole(1, 100000));
  app.add_option("--checkpoints", o.checkpoints, "write the chunks' starting states here (one physics pass)")
      ->type_name("DIR");
  app.add_option("-o", o.out,
                 "the folder the chunks write to, for the printed commands (default out/chunks/)")
      ->type_name("DIR");
  add_scene_overrides(app, o.run, true);
  app.add_option("--aa", o.aa, "as render's --aa (part of the manifest)")
      ->check(cli::choice({"fxaa", "msaa2", "msaa4", "none"}));
  app.add_flag("--no-shadows", o.no_shadows, "as render's --no-shadows (part of the manifest)");
  add_summary_flags(app, o.run);
}

// The overrides as command-line options, for the printed commands: the chunks must get the same.
std::string override_args(const PlanOptions& o) {
  std::string s;
  char b[64];
  auto num = [&](const char* flag, double v) {
    std::snprintf(b, sizeof b, " %s %.17g", flag, v);
    s += b;
  };
  if (o.run.duration) num("--duration", *o.run.duration);
  if (o.run.timestep) num("--timestep", *o.run.timestep);
  if (o.run.fps) num("--fps", *o.run.fps);
  if (o.run.width) s += " --width " + std::to_string(*o.run.width);
  if (o.run.height) s += " --height " + std::to_string(*o.run.height);
  if (o.run.integrator) s += " --integrator " + *o.run.integrator;
  if (o.aa) s += " --aa " + *o.aa;
  if (o.no_shadows) s += " --no-shadows";
  return s;
}

}  // namespace

int cmd_plan(const std::vector<std::string>& args) {
  PlanOptions o;
  CLI::App app;
  plan_table(app, o);
  if (!cli::parse(app, args)) return kExitOk;
  if (o.scenes.size() != 1) throw UsageError("plan takes one scene file");
  const StopSignals stop;
  const std::string& path = o.scenes[0];
  Scene scene = load_scene(path);
  apply_overrides(o.run, scene);
  const int w = scene.video.width + scene.video.width % 2, h = scene.video.height + scene.video.height % 2;
  const ChunkManifest manifest = chunk_manifest(path, scene, look_settings(o.aa, o.no_shadows));
  const auto t0 = std::chrono::steady_clock::now();

  CheckpointPlan cp;
  cp.manifest = manifest.id;
  cp.chunks = o.chunks;
  if (o.checkpoints && scene.camera.fit) {
    // The camera a straight render fits over the whole run: fitted once here for every chunk.
    fit_camera(scene, o.run.threads);
    cp.fitted = true;
    for (int k = 0; k < 3; ++k)
      cp.position[k] = scene.camera.position[k], cp.look_at[k] = scene.camera.look_at[k];
  }
  FrameLoop loop(scene, o.run.threads);
  const FrameTargets all = loop.video_frames();
  const long keyint = keyframe_interval(scene.video.fps);
  const std::vector<ChunkSpan> table = chunk_table((long)all.size(), keyint, o.chunks);
  cp.total_frames = (long)all.size();

  uintmax_t checkpoint_bytes = 0;
  if (o.checkpoints) {
    const std::string& dir = *o.checkpoints;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw std::runtime_error("cannot create '" + dir + "': " + ec.message());
    // A plan.json from an earlier plan is removed first: a chunk must never pair it with states
    // written now (or the other way round) if this pass is stopped.
    fs::remove(fs::path(dir) / "plan.json", ec);
    PrepassStore store(PrepassStore::Mode::record);
    ViewOptions vo;
    vo.width = w, vo.height = h;
    if (o.aa) vo.aa = *o.aa;
    vo.no_shadows = o.no_shadows;
    vo.threads = o.run.threads;
    vo.prepass = &store;
    SceneFrames view(scene, loop, vo);  // runs the views' pre-passes, recording their products
    checkpoint_bytes += write_checkpoint_prepass(dir, manifest.id, store);
    // The frames before each chunk's first: there the world and the views' history are saved.
    FrameTargets at;
    for (const ChunkSpan& c : table)
      if (c.first > 0) at.push_back(all[(size_t)c.first - 1]);
    FrameLoop::Hooks hooks;
    hooks.stop = &stop.flag();
    hooks.step = view.step_hook();
    size_t next = 1;
    hooks.frame = [&](const FrameTarget& t, const World& world) {
      view.sync(world);  // the variants where a straight render has them at this frame
      CheckpointState st;
      st.index = table[next++].index;
      st.frame = t.index;
      st.step = world.steps();
      std::ostringstream ws, hs;
      world.save_state(ws);
      view.save_history(hs);
      st.world = ws.str(), st.history = hs.str();
      checkpoint_bytes += write_checkpoint_state(dir, manifest.id, st);
    };
    const long done = loop.run(at, hooks, false);
    if (stop.signal() || done != (long)at.size()) {
      std::fprintf(stderr, "plan: interrupted by signal %d: no checkpoint plan written\n", stop.signal());
      return 128 + stop.signal();
    }
    write_checkpoint_plan(dir, cp);  // last: its presence says every state is there
  }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  const std::string outdir = o.out ? *o.out : "out/chunks/";
  const std::string extra = override_args(o) + (o.checkpoints ? " --checkpoints " + *o.checkpoints : "");
  const double fps = scene.video.fps;
  if (o.run.json) {
    nlohmann::json j;
    j["scene"] = path;
    j["frames"] = (long)all.size();
    j["fps"] = fps;
    j["keyframe_interval"] = keyint;
    j["width"] = w;
    j["height"] = h;
    for (const ChunkSpan& c : table)
      j["chunks"].push_back({{"index", c.index},
                             {"frames", {c.first, c.last}},
                             {"start", c.first / fps},
                             {"end", (c.last + 1) / fps},
                             {"command", "simreel render " + path + " --chunk " + std::to_string(c.index) +
                                             "/" + std::to_string(o.chunks) + " -o " + outdir + extra}});
    j["manifest"] = {{"id", manifest.id},
                     {"scene_hash", manifest.scene_hash},
                     {"inputs", manifest.inputs},
                     {"settings", manifest.settings},
                     {"version", manifest.version}};
    j["join"] = "simreel join " + outdir + " -o out/" + scene.name + ".mp4";
    if (o.checkpoints) {
      j["checkpoints"] = {{"dir", *o.checkpoints}, {"bytes", checkpoint_bytes}, {"seconds", secs}};
      if (cp.fitted) j["checkpoints"]["camera_fitted"] = true;
    }
    std::printf("%s\n", j.dump().c_str());
    return kExitOk;
  }
  if (o.run.quiet) return kExitOk;
  std::printf("%s: %zu frames at %g fps (%.3f s of video), %dx%d, a keyframe every %ld frames: %d chunks\n",
              path.c_str(), all.size(), fps, all.size() / fps, w, h, keyint, o.chunks);
  std::printf("manifest %s: scene %s, %zu input files, %s, simreel %s\n", manifest.id.c_str(),
              manifest.scene_hash.c_str(), manifest.inputs.size(), manifest.settings.c_str(),
              manifest.version.c_str());
  std::printf("%-6s %-14s %7s  %s\n", "chunk", "frames", "count", "command");
  for (const ChunkSpan& c : table) {
    const std::string span = std::to_string(c.first) + "-" + std::to_string(c.last);
    std::printf("%-6d %-14s %7ld  simreel render %s --chunk %d/%d -o %s%s\n", c.index, span.c_str(),
                c.count(), path.c_str(), c.index, o.chunks, outdir.c_str(), extra.c_str());
  }
  std::printf("then:  simreel join %s -o out/%s.mp4\n", outdir.c_str(), scene.name.c_str());
  if (o.checkpoints)
    std::printf("checkpoints: %s, %.1f MB, one pass of %.2f s: each chunk simulates only its own frames\n",
                o.checkpoints->c_str(), checkpoint_bytes / 1e6, secs);
  else
    std::printf(
        "without --checkpoints each chunk simulates from t = 0 to its last frame (and reruns any "
        "whole-run pre-pass)\n");
  return kExitOk;
}

}  // namespace simreel
