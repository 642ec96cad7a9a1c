// The command line's conventions on top of CLI11 (Debian libcli11-dev). Each command builds one
// option table, a CLI::App, in one function beside its code (render_table in app/cli/render_cmd.cpp,
// ...): adding an option is one line there, and its help, its README entry (a test compares them)
// and its checks follow from that line. What these helpers add to CLI11:
// - one help layout for every command (usage, description, options with wrapped descriptions,
//   footer), generated from the table;
// - parsing rules CLI11 does not have: an unknown option names the nearest known one; an option
//   that needs a value never takes the next option as it (`--csv --quiet` wrote a file called
//   --quiet); a flag given a value is refused; --help wins over every other error; the last of a
//   repeated option wins;
// - value checks whose messages name the option, and CLI11's errors turned into UsageError
//   (exit 2).
#pragma once
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace simreel::cli {

// Makes `app` the command `name` of the registry (app/cli/commands.hpp): its usage line, its help
// layout, -h/--help. `description` comes after the usage line, `footer` after the options.
void setup(CLI::App& app, const std::string& name, const std::string& description, const std::string& footer);

// The command's positional arguments (scene files, meshes, ...) in order; the command checks
// their number, with its own message.
CLI::Option* add_positionals(CLI::App& app, std::vector<std::string>& into);

// Parses `args` (the words after the command's name) into the table. Returns false when help was
// asked for: it has been printed to stdout. Throws UsageError.
bool parse(CLI::App& app, const std::vector<std::string>& args);

// Value checks for the tables. Their messages name the option: "--width expects a whole number
// from 16 to 16384, got '8'".
CLI::Validator number();                                // a finite number
CLI::Validator positive();                              // a finite number > 0
CLI::Validator whole(int lo, int hi);                   // a whole number in [lo, hi]: ->transform()
                                                        // ("3.0" becomes "3" for CLI11's int parse)
CLI::Validator choice(std::vector<std::string> names);  // one of `names`; the help shows them as a|b|c

}  // namespace simreel::cli
