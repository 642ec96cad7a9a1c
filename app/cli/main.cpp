// simreel: scene file in, simulated rigid-body video (or trajectory, or mass properties) out.
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <simreel/error.hpp>
#include <simreel/mass_properties.hpp>
#include "app/cli/commands.hpp"
#include "app/scene/scene.hpp"
#include "app/scene/text.hpp"

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

}  // namespace

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
