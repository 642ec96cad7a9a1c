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

#include "app/commands.hpp"
#include "app/frame_loop.hpp"
#include "app/mesh_import.hpp"
#include "app/run.hpp"
#include "app/text.hpp"
#include "sim/error.hpp"
#include "sim/mass_properties.hpp"

namespace simreel {

namespace {

const char* kTopHelp = R"(simreel: scene file in, simulated rigid-body video out.

usage:
  simreel render   SCENE [-o OUT.mp4] [--frames-dir DIR] [--width W] [--height H] [--fps F] [--duration S] [--quiet]
  simreel simulate SCENE [--csv OUT.csv] [--json] [--integrator NAME] [--timestep DT] [--duration S] [--quiet]
  simreel inspect  MESH  [--json] [--density RHO]
  simreel check    SCENE... --goldens DIR [--update missing|changed|all|none] [--frames SPEC]
                   [--report DIR] [--junit FILE] [--tolerance auto|exact|portable]
  simreel diff     A B [--out DIR]     (PNGs, folders of PNGs or videos)

'simreel COMMAND --help' describes each command. Exit codes: 0 done, 2 bad input, 1 other failure.
Scene format: scenes/README.md.
)";

const char* kSimulateHelp = R"(usage: simreel simulate SCENE [options]

Runs the physics of SCENE with no rendering and prints a summary: steps, bodies, wall time spent
stepping, and the relative drift of total energy and angular momentum (about the centre of mass).

options:
  --csv FILE          write the state of every body at every video frame (t = 0 .. duration):
                      t,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz
                      (body origin position m, body-to-world quaternion, centre-of-mass velocity
                      m/s, world angular velocity rad/s)
  --json              print the summary as one JSON object
  --integrator NAME   auto (default), seed, euler_gyro, rk4, splitting
  --timestep DT       fixed physics step, s
  --duration S        simulated time, s
  --threads N         integration threads (results are identical for any N); default 1
  --profile           time each stage of the step and report what was skipped
  --save-state FILE   write the whole world state at the end (poses, velocities, step count,
                      contacts and their warm-start impulses) to FILE
  --resume FILE       start from a state saved from the same scene and continue to --duration
                      (absolute time); the CSV starts at the saved time. Bit-identical to a
                      straight run
  --quiet             print nothing but errors (no progress, no summary; --json still prints)

Ctrl-C (SIGINT), SIGTERM, SIGHUP or SIGQUIT stops the run between steps: the CSV keeps the rows
done and --save-state the state reached; exit 128 + the signal (130, 143, 129, 131).
)";

const char* kInspectHelp = R"(usage: simreel inspect MESH [options]

Prints a mesh's mass properties: volume, mass, centroid, inertia tensor about the centroid (mesh
axes), principal moments and axes, and what was found and done about defects (open, inside-out,
inconsistent winding, degenerate faces).

options:
  --json            one JSON object
  --density RHO     kg/m^3, default 1000
  --mode MODE       solid (default), shell (mass on the surface), hull (convex hull)
  --thickness T     m, shell wall thickness (default 0.001)
  --scale S         multiply every coordinate (meshes authored in mm: 0.001)
)";

}  // namespace

double ParsedArgs::number(const std::string& k, bool positive) const {
  const std::string& s = options.at(k);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v))
    throw UsageError(k + " expects a number, got '" + s + "'");
  if (positive && !(v > 0)) throw UsageError(k + " must be positive, got '" + s + "'");
  return v;
}

int ParsedArgs::whole(const std::string& k, int lo, int hi) const {
  const double v = number(k, false);
  if (v != std::floor(v) || v < lo || v > hi)
    throw UsageError(k + " expects a whole number from " + std::to_string(lo) + " to " + std::to_string(hi));
  return (int)v;
}

ParsedArgs parse_args(const std::vector<std::string>& args, const std::map<std::string, bool>& spec) {
  ParsedArgs a;
  for (size_t i = 0; i < args.size(); ++i) {
    std::string k = args[i], v;
    if (k.size() > 1 && k[0] == '-') {
      const size_t eq = k.find('=');
      bool inline_value = false;
      if (k.rfind("--", 0) == 0 && eq != std::string::npos) {
        v = k.substr(eq + 1);
        k = k.substr(0, eq);
        inline_value = true;
      }
      const auto it = spec.find(k);
      if (it == spec.end()) {
        std::vector<std::string> names;
        for (const auto& [n, _] : spec) names.push_back(n);
        std::string msg = "unknown option " + k;
        if (auto s = nearest(k, names)) msg += "; did you mean " + *s + "?";
        throw UsageError(msg);
      }
      if (it->second) {
        if (!inline_value) {
          if (i + 1 >= args.size()) throw UsageError(k + " needs a value");
          v = args[++i];
          // "--csv --quiet" must not write a file called --quiet: an option is never a value.
          if (v.size() > 1 && v[0] == '-' && spec.count(v.substr(0, v.find('='))))
            throw UsageError(k + " needs a value, got the option " + v);
        }
      } else if (inline_value) {
        throw UsageError(k + " takes no value");
      }
      a.options[k] = v;
    } else {
      a.positional.push_back(k);
    }
  }
  return a;
}

void apply_overrides(const ParsedArgs& a, Scene& s) {
  if (a.has("--duration")) s.duration = a.number("--duration", true);
  if (a.has("--timestep")) s.timestep = a.number("--timestep", true);
  if (a.has("--integrator")) {
    const std::string& n = a.options.at("--integrator");
    const auto i = integrator_from_name(n);
    if (!i) {
      std::string msg = "unknown integrator '" + n + "' (" + integrator_names() + ")";
      if (auto m = nearest(n, {"auto", "seed", "euler_gyro", "rk4", "splitting"}))
        msg += "; did you mean '" + *m + "'?";
      throw UsageError(msg);
    }
    s.integrator = *i;
  }
  if (a.has("--fps")) s.video.fps = a.number("--fps", true);
  if (a.has("--width")) s.video.width = a.whole("--width", 16, 16384);
  if (a.has("--height")) s.video.height = a.whole("--height", 16, 16384);
  if (s.timestep > s.duration) throw UsageError("the timestep is longer than the duration");
  try {
    prepare_run(s);
  } catch (const std::invalid_argument& e) {
    throw InputError(s.path + ": " + e.what());
  }
}

void print_summary(const ParsedArgs& a, const RunSummary& s) {
  if (a.has("--json"))
    std::fputs((summary_json(s) + "\n").c_str(), stdout);
  else if (!a.has("--quiet"))
    std::fputs(summary_text(s).c_str(), stdout);
}

int cmd_simulate(const std::vector<std::string>& args) {
  const ParsedArgs a = parse_args(args, {{"--csv", true},
                                         {"--json", false},
                                         {"--integrator", true},
                                         {"--timestep", true},
                                         {"--duration", true},
                                         {"--quiet", false},
                                         {"--profile", false},
                                         {"--threads", true},
                                         {"--save-state", true},
                                         {"--resume", true},
                                         {"--help", false},
                                         {"-h", false}});
  if (a.has("--help") || a.has("-h")) {
    std::fputs(kSimulateHelp, stdout);
    return kExitOk;
  }
  if (a.positional.size() != 1) throw UsageError("simulate takes one scene file");
  // From here a signal ends the run between steps (before the first one if it comes while the
  // scene loads); the CSV keeps the rows done.
  const StopSignals stop;
  Scene scene = load_scene(a.positional[0]);
  apply_overrides(a, scene);
  const int threads = a.has("--threads") ? a.whole("--threads", 1, 256) : 1;
  FrameLoop loop(scene, threads);
  World& world = loop.world();
  world.set_profiling(a.has("--profile"));
  for (const std::string& n : scene.notes) std::fprintf(stderr, "note: %s\n", n.c_str());
  if (a.has("--resume")) {
    const std::string& path = a.options.at("--resume");
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
  if (a.has("--save-state")) {
    std::string err;
    if (!ensure_parent_dir(a.options.at("--save-state"), &err)) throw std::runtime_error(err);
    saved = std::make_unique<AtomicFile>(a.options.at("--save-state"));
  }

  std::unique_ptr<AtomicFile> csv;
  if (a.has("--csv")) {
    std::string err;
    if (!ensure_parent_dir(a.options.at("--csv"), &err)) throw std::runtime_error(err);
    csv = std::make_unique<AtomicFile>(a.options.at("--csv"));
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
  Progress progress("frames", (long)targets.size(), a.has("--quiet") || a.has("--json"));
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
      throw std::runtime_error(a.options.at("--save-state") + ": could not write the saved state");
    saved->commit();
  }

  RunSummary s = make_summary(scene, world, loop.drift(), (int)plan.frames, loop.step_seconds());
  if (a.has("--profile")) s.profile = &world.profile();
  if (csv) s.output = a.options.at("--csv");
  if (stop.signal())
    s.warnings.push_back("interrupted by signal " + std::to_string(stop.signal()) +
                         " at t = " + std::to_string(world.time()) + " s" +
                         (csv ? ": the CSV holds the rows up to then" : ""));
  print_summary(a, s);
  return stop.signal() ? 128 + stop.signal() : kExitOk;
}

int cmd_inspect(const std::vector<std::string>& args) {
  const ParsedArgs a = parse_args(args, {{"--json", false},
                                         {"--density", true},
                                         {"--mode", true},
                                         {"--thickness", true},
                                         {"--scale", true},
                                         {"--help", false},
                                         {"-h", false}});
  if (a.has("--help") || a.has("-h")) {
    std::fputs(kInspectHelp, stdout);
    return kExitOk;
  }
  if (a.positional.size() != 1) throw UsageError("inspect takes one mesh file");
  MeshMassOptions opt;
  if (a.has("--density")) opt.density = a.number("--density", true);
  if (a.has("--thickness")) opt.thickness = a.number("--thickness", true);
  if (a.has("--mode")) {
    const auto mode = mass_mode_from_name(a.options.at("--mode"));
    if (!mode) throw UsageError("unknown --mode '" + a.options.at("--mode") + "' (solid, shell or hull)");
    opt.mode = *mode;
  }
  const double scale = a.has("--scale") ? a.number("--scale", true) : 1.0;
  const std::string path = a.positional[0];
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
  if (a.has("--json")) {
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
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    std::fputs(kTopHelp, args.empty() ? stderr : stdout);
    return args.empty() ? kExitBadInput : kExitOk;
  }
  if (args[0] == "--version") {
    std::printf("simreel %s\n", kVersion);
    return kExitOk;
  }
  const std::string cmd = args[0];
  args.erase(args.begin());
  try {
    if (cmd == "simulate") return cmd_simulate(args);
    if (cmd == "inspect") return cmd_inspect(args);
    if (cmd == "render") return cmd_render(args);
    if (cmd == "check") return cmd_check(args);
    if (cmd == "diff") return cmd_diff(args);
    std::string msg = "unknown command '" + cmd + "'";
    if (auto s = nearest(cmd, {"render", "simulate", "inspect", "check", "diff"}))
      msg += "; did you mean '" + *s + "'?";
    throw UsageError(msg);
  } catch (const UsageError& e) {
    const bool known =
        cmd == "render" || cmd == "simulate" || cmd == "inspect" || cmd == "check" || cmd == "diff";
    std::fprintf(stderr, "simreel %s: %s (see simreel %s--help)\n", cmd.c_str(), e.what(),
                 known ? (cmd + " ").c_str() : "");
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
