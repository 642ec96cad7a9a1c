// The simreel commands. Each returns the process exit code: 0 done, 2 bad input (usage, scene,
// mesh), 1 anything else (a failure while running, such as a non-finite state), 128 + N when
// signal N stopped the run. Each builds its option table with CLI11 (app/cli/cli.hpp).
#pragma once
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/scene/scene.hpp"

namespace CLI {
class App;
}

namespace simreel {

constexpr int kExitOk = 0, kExitFailure = 1, kExitBadInput = 2;
constexpr const char* kVersion = "0.1.0";
// How the user invoked simreel (argv[0], e.g. "build/simreel"), for commands it prints back
// (check's accept command); "simreel" until main sets it.
inline std::string g_invoked_as = "simreel";

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

int cmd_simulate(const std::vector<std::string>& args);
int cmd_inspect(const std::vector<std::string>& args);
int cmd_render(const std::vector<std::string>& args);
int cmd_check(const std::vector<std::string>& args);
int cmd_diff(const std::vector<std::string>& args);
int cmd_plan(const std::vector<std::string>& args);
int cmd_join(const std::vector<std::string>& args);

// The commands as `simreel --help` lists them; `synopsis` follows the name in usage lines.
struct CommandInfo {
  const char* name;
  const char* synopsis;
  const char* summary;
  int (*run)(const std::vector<std::string>& args);
};
inline constexpr CommandInfo kCommands[] = {
    {"render", "SCENE", "simulate a scene and write a video, PNG frames or one frame", cmd_render},
    {"simulate", "SCENE", "run the physics alone: a summary, a CSV of every body's state, a saved state",
     cmd_simulate},
    {"inspect", "MESH", "a mesh's volume, mass, inertia and principal axes, and its defects", cmd_inspect},
    {"check", "SCENE... --goldens DIR", "compare chosen frames of scenes with committed goldens", cmd_check},
    {"diff", "A B", "compare two PNGs, folders of PNGs or videos frame by frame", cmd_diff},
    {"plan", "SCENE --chunks N",
     "split a render into chunks for Slurm or GNU parallel (and their checkpoints)", cmd_plan},
    {"join", "DIR -o OUT", "join the chunks `render --chunk` wrote, without re-encoding", cmd_join},
};

// Options simulate and render share: scene overrides and what is printed.
struct RunOptions {
  std::optional<double> duration, timestep, fps;  ///< s, s, frames/s
  std::optional<int> width, height;               ///< px
  std::optional<std::string> integrator;
  int threads = 1;
  bool json = false, quiet = false;
};
// Table rows: --width --height --fps (with `video`) --duration --integrator --timestep --threads.
void add_scene_overrides(CLI::App& app, RunOptions& o, bool video);
// --package-path DIR (repeatable): folders for package:// in URDF and MJCF files.
void add_package_path(CLI::App& app);
// Table rows: --json --quiet.
void add_summary_flags(CLI::App& app, RunOptions& o);

// The overrides applied to the scene, then prepare_run (app/scene/frame_plan.hpp): limits and frames
// exactly at k / fps. Throws UsageError / InputError naming the key.
void apply_overrides(const RunOptions& o, Scene& s);

// The run's summary on stdout: JSON with --json (even with --quiet), else text unless --quiet.
struct RunSummary;
void print_summary(const RunOptions& o, const RunSummary& s);

}  // namespace simreel
