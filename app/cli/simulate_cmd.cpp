// simreel simulate: the physics alone, no rendering: a summary, a CSV of every body's state, a
// saved state to resume from.
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/cli/cli.hpp"
#include "app/cli/commands.hpp"
#include "app/runner/frame_loop.hpp"
#include "app/runner/run.hpp"
#include "app/scene/text.hpp"

namespace simreel {

namespace {

struct SimulateOptions {
  std::vector<std::string> scenes;
  RunOptions run;
  std::optional<std::string> csv, save_state, resume;
  bool profile = false;
};

// simulate's option table.
void simulate_table(CLI::App& app, SimulateOptions& o) {
  cli::setup(
      app, "simulate",
      "Runs the physics of SCENE with no rendering and prints a summary: steps, bodies, wall time "
      "spent stepping, and the relative drift of total energy and angular momentum (about the centre "
      "of mass) where the scene conserves them (else what does not: contacts, a pivot, drag, ...).",
      "Ctrl-C (SIGINT), SIGTERM, SIGHUP or SIGQUIT stops the run between steps: the CSV keeps the rows "
      "done and --save-state the state reached; exit 128 + the signal (130, 143, 129, 131).");
  cli::add_positionals(app, o.scenes);
  app.add_option("--csv", o.csv,
                 "write the state of every body at every video frame (t = 0 .. duration):\n"
                 "t,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n"
                 "(body origin position m, body-to-world quaternion, centre-of-mass velocity m/s, world "
                 "angular velocity rad/s)")
      ->type_name("FILE");
  add_summary_flags(app, o.run);
  add_scene_overrides(app, o.run, false);
  app.add_flag("--profile", o.profile, "time each stage of the step and report what was skipped");
  app.add_option("--save-state", o.save_state,
                 "write the whole world state at the end (poses, velocities, step count, contacts and their "
                 "warm-start impulses) to FILE")
      ->type_name("FILE");
  app.add_option("--resume", o.resume,
                 "start from a state saved from the same scene and continue to --duration (absolute time); "
                 "the CSV starts at the saved time. Bit-identical to a straight run")
      ->type_name("FILE");
}

}  // namespace

int cmd_simulate(const std::vector<std::string>& args) {
  SimulateOptions o;
  CLI::App app;
  simulate_table(app, o);
  if (!cli::parse(app, args)) return kExitOk;
  if (o.scenes.size() != 1) throw UsageError("simulate takes one scene file");
  // From here a signal ends the run between steps (before the first one if it comes while the
  // scene loads); the CSV keeps the rows done.
  const StopSignals stop;
  Scene scene = load_scene(o.scenes[0]);
  apply_overrides(o.run, scene);
  FrameLoop loop(scene, o.run.threads);
  World& world = loop.world();
  world.set_profiling(o.profile);
  if (!o.run.quiet)  // --quiet: nothing but errors (the JSON still carries the notes)
    for (const std::string& n : scene.notes) std::fprintf(stderr, "note: %s\n", n.c_str());
  if (o.resume) {
    const std::string& path = *o.resume;
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open the saved state");
    try {
      world.restore_state(in);
    } catch (const InputError& e) {
      throw InputError(path + ": " + e.what());
    }
    loop.state_restored();
    if (world.time() > scene.duration + 0.5 * scene.timestep)
      throw UsageError("--duration is the absolute end time and must not be before the saved time (" +
                       std::to_string(world.time()) + " s)");
  }
  std::unique_ptr<AtomicFile> saved;  // created before the run so a bad path fails at once
  if (o.save_state) {
    std::string err;
    if (!ensure_parent_dir(*o.save_state, &err)) throw std::runtime_error(err);
    saved = std::make_unique<AtomicFile>(*o.save_state);
  }

  std::unique_ptr<AtomicFile> csv;
  if (o.csv) {
    std::string err;
    if (!ensure_parent_dir(*o.csv, &err)) throw std::runtime_error(err);
    csv = std::make_unique<AtomicFile>(*o.csv);
    std::fputs("t,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n", csv->get());
  }

  // Rows at every frame of the plan; a resumed run starts with the saved time's row, and the CSV
  // ends at t = duration even when the duration is not a whole number of frames.
  const FramePlan& plan = loop.plan();
  FrameTargets targets = loop.all_frames();
  if (targets.empty() || targets.front().step != world.steps())
    targets.push_front(FrameTarget{-1, world.time(), world.steps()});
  if (targets.back().step < plan.total_steps)
    targets.push_back(FrameTarget{-1, scene.duration, plan.total_steps});
  Progress progress("frames", (long)targets.size(), o.run.quiet || o.run.json);
  FrameLoop::Hooks hooks;
  hooks.stop = &stop.flag();
  if (csv)
    hooks.frame = [&](const FrameTarget&, const World& w) {
      for (int i = 0; i < w.body_count(); ++i) {
        const Vec3 p = w.origin_position(i), v = w.linear_velocity(i), om = w.angular_velocity(i);
        const Quat q = w.orientation(i);
        std::fprintf(
            csv->get(),
            "%.17g,%s,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n",
            w.time(), w.def(i).name.c_str(), p.x(), p.y(), p.z(), q.w(), q.x(), q.y(), q.z(), v.x(), v.y(),
            v.z(), om.x(), om.y(), om.z());
      }
    };
  hooks.progress = [&](long done) { progress.update(done); };
  loop.run(targets, hooks, true);
  progress.finish();
  if (csv) csv->commit();
  if (saved) {
    std::ostringstream bytes;
    world.save_state(bytes);
    const std::string b = bytes.str();
    if (std::fwrite(b.data(), 1, b.size(), saved->get()) != b.size())
      throw std::runtime_error(*o.save_state + ": could not write the saved state");
    saved->commit();
  }

  RunSummary s = make_summary(scene, world, loop.drift(), (int)plan.frames, loop.step_seconds());
  if (o.profile) s.profile = &world.profile();
  if (csv) s.output = *o.csv;
  if (stop.signal())
    s.warnings.push_back("interrupted by signal " + std::to_string(stop.signal()) +
                         " at t = " + std::to_string(world.time()) + " s" +
                         (csv ? ": the CSV holds the rows up to then" : ""));
  print_summary(o.run, s);
  return stop.signal() ? 128 + stop.signal() : kExitOk;
}

}  // namespace simreel
