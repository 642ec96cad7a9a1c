// What every command that runs a scene shares (app/cli/commands.hpp): the scene overrides and
// summary flags of its option table, the overrides applied to the loaded scene, the summary printed.
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/cli/cli.hpp"
#include "app/cli/commands.hpp"
#include "app/runner/run.hpp"
#include "app/scene/frame_plan.hpp"

namespace simreel {

namespace {

const std::vector<std::string> kIntegrators = {"auto", "seed", "euler_gyro", "rk4", "splitting"};

}  // namespace

void add_scene_overrides(CLI::App& app, RunOptions& o, bool video) {
  if (video) {
    app.add_option("--width", o.width, "video width, overriding the scene's")
        ->type_name("W")
        ->transform(cli::whole(16, 16384));
    app.add_option("--height", o.height, "video height, overriding the scene's")
        ->type_name("H")
        ->transform(cli::whole(16, 16384));
    app.add_option("--fps", o.fps, "frames per second of simulated time, overriding the scene's")
        ->type_name("F")
        ->check(cli::positive());
  }
  app.add_option("--duration", o.duration, "simulated time, s, overriding the scene's")
      ->type_name("S")
      ->check(cli::positive());
  app.add_option("--integrator", o.integrator, "the integrator, overriding the scene's")
      ->check(cli::choice(kIntegrators));
  app.add_option("--timestep", o.timestep, "fixed physics step, s, overriding the scene's")
      ->type_name("DT")
      ->check(cli::positive());
  app.add_option("--threads", o.threads,
                 std::string("integration threads (") + (video ? "frames" : "results") +
                     " are identical for any N); default 1")
      ->type_name("N")
      ->transform(cli::whole(1, 256));
  add_package_path(app);
}

void add_package_path(CLI::App& app) {
  // Read by the URDF and MJCF readers (app/import/urdf.cpp, resolve_asset) through the
  // environment, before ROS_PACKAGE_PATH: set while the command line is parsed, before any thread.
  app.add_option_function<std::vector<std::string>>(
         "--package-path",
         [](const std::vector<std::string>& dirs) {
           std::string joined;
           for (const std::string& d : dirs) joined += (joined.empty() ? "" : ":") + d;
           setenv("SIMREEL_PACKAGE_PATH", joined.c_str(), 1);
         },
         "folder searched for package://NAME/... in URDF and MJCF files (the package folder or one holding "
         "it; repeatable), after an import's package_paths, before ROS_PACKAGE_PATH")
      ->type_name("DIR");
}

void add_summary_flags(CLI::App& app, RunOptions& o) {
  app.add_flag("--json", o.json, "print the summary as one JSON object (also with --quiet)");
  app.add_flag("--quiet", o.quiet, "print nothing but errors (no progress, no summary)");
}

void apply_overrides(const RunOptions& o, Scene& s) {
  if (o.duration) s.duration = *o.duration;
  if (o.timestep) s.timestep = *o.timestep;
  if (o.integrator) s.integrator = *integrator_from_name(*o.integrator);  // the table checked the name
  if (o.fps) s.video.fps = *o.fps;
  if (o.width) s.video.width = *o.width;
  if (o.height) s.video.height = *o.height;
  if (s.timestep > s.duration) throw UsageError("the timestep is longer than the duration");
  try {
    prepare_run(s);
  } catch (const std::invalid_argument& e) {
    throw InputError(s.path + ": " + e.what());
  }
}

void print_summary(const RunOptions& o, const RunSummary& s) {
  if (o.json)
    std::fputs((summary_json(s) + "\n").c_str(), stdout);
  else if (!o.quiet)
    std::fputs(summary_text(s).c_str(), stdout);
}

}  // namespace simreel
