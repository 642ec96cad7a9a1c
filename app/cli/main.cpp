// simreel: scene file in, simulated rigid-body video (or trajectory, or mass properties) out.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/cli/cli.hpp"
#include "app/cli/commands.hpp"
#include "app/runner/frame_loop.hpp"
#include "app/scene/mesh_import.hpp"
#include "app/runner/run.hpp"
#include "app/scene/text.hpp"
#include <simreel/error.hpp>
#include <simreel/mass_properties.hpp>

namespace simreel {

namespace {

// simreel --help: the commands of the registry (app/cli/commands.hpp), each with its synopsis.
std::string top_help() {
  std::string s = "simreel: scene file in, simulated rigid-body video out.\n\ncommands:\n";
  for (const CommandInfo& c : kCommands)
    s += std::string("  simreel ") + c.name + " " + c.synopsis + " [options]\n      " + c.summary + "\n";
  s += "\n'simreel COMMAND --help' lists a command's options; 'simreel --version' prints the version.\n"
       "Exit codes: 0 done, 2 bad input (usage, scene, mesh), 1 other failure, 128 + N when stopped by\n"
       "signal N. Scene format: scenes/README.md.\n";
  return s;
}

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
      "of mass).",
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

struct InspectOptions {
  std::vector<std::string> meshes;
  bool json = false;
  double density = MeshMassOptions{}.density, thickness = MeshMassOptions{}.thickness, scale = 1;
  std::string mode = to_string(MeshMassOptions{}.mode);
};

// inspect's option table.
void inspect_table(CLI::App& app, InspectOptions& o) {
  cli::setup(
      app, "inspect",
      "Prints a mesh's mass properties: volume, mass, centroid, inertia tensor about the centroid (mesh "
      "axes), principal moments and axes, and what was found and done about defects (open, "
      "inside-out, inconsistent winding, degenerate faces).",
      "");
  cli::add_positionals(app, o.meshes);
  app.add_flag("--json", o.json, "print one JSON object");
  app.add_option("--density", o.density, "kg/m^3, default 1000")->type_name("RHO")->check(cli::positive());
  app.add_option("--mode", o.mode, "solid (default), shell (mass on the surface), hull (convex hull)")
      ->check(cli::choice({"solid", "shell", "hull"}));
  app.add_option("--thickness", o.thickness, "m, shell wall thickness (default 0.001)")
      ->type_name("T")
      ->check(cli::positive());
  app.add_option("--scale", o.scale, "multiply every coordinate (meshes authored in mm: 0.001)")
      ->type_name("S")
      ->check(cli::positive());
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

int cmd_inspect(const std::vector<std::string>& args) {
  InspectOptions o;
  CLI::App app;
  inspect_table(app, o);
  if (!cli::parse(app, args)) return kExitOk;
  if (o.meshes.size() != 1) throw UsageError("inspect takes one mesh file");
  MeshMassOptions opt;
  opt.density = o.density;
  opt.thickness = o.thickness;
  opt.mode = *mass_mode_from_name(o.mode);  // the table checked the name
  const double scale = o.scale;
  const std::string path = o.meshes[0];
  {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& ch : ext) ch = (char)std::tolower((unsigned char)ch);
    if (ext == ".yaml" || ext == ".yml")
      throw UsageError("'" + path +
                       "' is a scene file, not a mesh: inspect weighs one mesh (OBJ, OFF, STL, PLY, or "
                       "any format assimp reads); simulate and render take scenes");
  }
  const ImportedMesh im = import_mesh(path, Vec3::Constant(scale));
  const TriangleMesh& mesh = im.mesh;
  MeshReport r;
  try {
    r = analyze_mesh(mesh, opt);
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
  r.warnings.insert(r.warnings.begin(), im.notes.begin(), im.notes.end());
  const PrincipalAxes pa = principal_axes(r.props.inertia);
  if (o.json) {
    using J = nlohmann::ordered_json;
    auto vec = [](const Vec3& v) { return J::array({v.x(), v.y(), v.z()}); };
    auto mat = [&](const Mat3& m) { return J::array({vec(m.row(0)), vec(m.row(1)), vec(m.row(2))}); };
    J o;
    o["file"] = path;
    o["reader"] = im.reader;
    o["precision"] = im.double_precision() ? "double" : "float32";
    o["mode"] = to_string(opt.mode);
    o["density"] = opt.density;
    o["vertices"] = mesh.vertices.size();
    o["faces"] = mesh.triangles.size();
    o["volume"] = r.volume;
    o["area"] = r.area;
    o["mass"] = r.props.mass;
    o["centroid"] = vec(r.props.com);
    o["inertia"] = mat(r.props.inertia);
    o["principal_moments"] = vec(pa.moments);
    o["principal_axes"] = mat(pa.R.transpose());
    o["closed"] = r.closed;
    o["consistently_oriented"] = r.consistently_oriented;
    o["welded_vertices"] = r.welded_vertices;
    o["degenerate_faces"] = r.degenerate_faces;
    o["reoriented_faces"] = r.reoriented_faces;
    o["inverted"] = r.inverted;
    o["warnings"] = r.warnings;
    std::printf("%s\n", o.dump(-1, ' ', false, J::error_handler_t::replace).c_str());
    return kExitOk;
  }
  auto row = [](const Vec3& v) {
    char b[128];
    std::snprintf(b, sizeof b, "[% .10g, % .10g, % .10g]", v.x(), v.y(), v.z());
    return std::string(b);
  };
  std::printf("%s (%s, %zu vertices, %zu faces as loaded; read by %s in %s precision)\n", path.c_str(),
              to_string(opt.mode), mesh.vertices.size(), mesh.triangles.size(), im.reader.c_str(),
              im.double_precision() ? "double" : "single");
  std::printf("  closed: %s, consistently oriented: %s\n", r.closed ? "yes" : "no",
              r.consistently_oriented ? "yes" : "no");
  std::printf("  volume:   %.12g m^3\n  area:     %.12g m^2\n  mass:     %.12g kg (density %g kg/m^3)\n",
              r.volume, r.area, r.props.mass, opt.density);
  std::printf("  centroid: %s m\n", row(r.props.com).c_str());
  std::printf("  inertia about the centroid, mesh axes (kg m^2):\n");
  for (int i = 0; i < 3; ++i) std::printf("    %s\n", row(r.props.inertia.row(i)).c_str());
  std::printf("  principal moments: %s kg m^2\n", row(pa.moments).c_str());
  for (int i = 0; i < 3; ++i) std::printf("  axis %d: %s\n", i + 1, row(pa.R.col(i)).c_str());
  for (const std::string& w : r.warnings) std::printf("  warning: %s\n", w.c_str());
  return kExitOk;
}

}  // namespace simreel

int main(int argc, char** argv) {
  using namespace simreel;
  std::vector<std::string> args(argv + 1, argv + argc);
  if (argc > 0 && argv[0] && std::strchr(argv[0], '/')) g_invoked_as = argv[0];  // else on the PATH
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    std::fputs(top_help().c_str(), args.empty() ? stderr : stdout);
    return args.empty() ? kExitBadInput : kExitOk;
  }
  if (args[0] == "--version") {
    std::printf("simreel %s\n", kVersion);
    return kExitOk;
  }
  const std::string cmd = args[0];
  args.erase(args.begin());
  const CommandInfo* command = nullptr;
  for (const CommandInfo& c : kCommands)
    if (cmd == c.name) command = &c;
  try {
    if (!command) {
      std::vector<std::string> names;
      for (const CommandInfo& c : kCommands) names.push_back(c.name);
      std::string msg = "unknown command '" + cmd + "'";
      if (auto s = nearest(cmd, names)) msg += "; did you mean '" + *s + "'?";
      throw UsageError(msg);
    }
    return command->run(args);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "simreel %s: %s (see simreel %s--help)\n", cmd.c_str(), e.what(),
                 command ? (cmd + " ").c_str() : "");
    return kExitBadInput;
  } catch (const InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  } catch (const StateError& e) {
    std::fprintf(stderr, "simulation stopped: %s\n", e.what());
    return kExitFailure;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitFailure;
  }
}
