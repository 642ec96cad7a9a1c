// The simreel commands. Each returns the process exit code: 0 done, 2 bad input (usage, scene,
// mesh), 1 anything else (a failure while running, such as a non-finite state).
#pragma once
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/scene.hpp"

namespace simreel {

constexpr int kExitOk = 0, kExitFailure = 1, kExitBadInput = 2;
constexpr const char* kVersion = "0.1.0";

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Options of one command: name -> takes a value. Parsing throws UsageError for unknown options
// (suggesting the nearest), missing values and surplus positional arguments.
struct ParsedArgs {
  std::vector<std::string> positional;
  std::map<std::string, std::string> options;
  bool has(const std::string& k) const { return options.count(k) > 0; }
  double number(const std::string& k, bool positive) const;
  int whole(const std::string& k, int lo, int hi) const;
};
ParsedArgs parse_args(const std::vector<std::string>& args, const std::map<std::string, bool>& spec);

// Scene overrides shared by simulate and render, then prepare_run (app/run.hpp): limits and
// frames exactly at k / fps. Throws UsageError / InputError naming the key.
void apply_overrides(const ParsedArgs& a, Scene& s);

// The run's summary on stdout: JSON with --json (even with --quiet), else text unless --quiet.
struct RunSummary;
void print_summary(const ParsedArgs& a, const RunSummary& s);

int cmd_simulate(const std::vector<std::string>& args);
int cmd_inspect(const std::vector<std::string>& args);
int cmd_render(const std::vector<std::string>& args);
int cmd_check(const std::vector<std::string>& args);
int cmd_diff(const std::vector<std::string>& args);

}  // namespace simreel
