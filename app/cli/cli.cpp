#include "app/cli/cli.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "app/cli/commands.hpp"

namespace simreel::cli {

namespace {

constexpr size_t kWidth = 100;      // help lines wrap before this column
constexpr size_t kNameColumn = 22;  // option descriptions start here

const CommandInfo& info(const std::string& name) {
  for (const CommandInfo& c : kCommands)
    if (name == c.name) return c;
  throw std::logic_error("no command named " + name);
}

// `text` wrapped to kWidth columns, every line after the first indented by `indent` spaces (the
// first is the caller's). A newline in `text` always breaks the line.
std::string wrap(const std::string& text, size_t indent, size_t first_column) {
  std::string out;
  size_t col = first_column;
  std::istringstream lines(text);
  std::string line;
  bool first_line = true;
  while (std::getline(lines, line)) {
    if (!first_line) out += "\n" + std::string(indent, ' '), col = indent;
    first_line = false;
    std::istringstream words(line);
    std::string w;
    bool first_word = true;
    while (words >> w) {
      if (!first_word && col + 1 + w.size() > kWidth) {
        out += "\n" + std::string(indent, ' ');
        col = indent;
      } else if (!first_word) {
        out += ' ';
        ++col;
      }
      out += w;
      col += w.size();
      first_word = false;
    }
  }
  return out;
}

bool is_flag(const CLI::Option* o) {
  return o->get_expected_max() == 0;
}

// What the help shows for an option's value: the table's type name, or a choice's a|b|c.
std::string metavar(const CLI::Option* o) {
  const std::string t = o->get_type_name();  // "TYPE" or "TYPE:validator description"
  const size_t colon = t.rfind(':');
  return colon == std::string::npos ? t : t.substr(colon + 1);
}

std::string option_names(const CLI::Option* o) {
  std::string s;
  for (const std::string& n : o->get_snames()) s += (s.empty() ? "-" : ", -") + n;
  for (const std::string& n : o->get_lnames()) s += (s.empty() ? "--" : ", --") + n;
  if (!is_flag(o)) s += " " + metavar(o);
  return s;
}

// simreel's help layout: usage, description, options, footer; every paragraph wrapped.
class Formatter : public CLI::FormatterBase {
 public:
  std::string make_help(const CLI::App* app, std::string, CLI::AppFormatMode) const override {
    const CommandInfo& c = info(app->get_name());
    std::string out = std::string("usage: simreel ") + c.name + " " + c.synopsis + " [options]\n\n";
    out += wrap(app->get_description(), 0, 0) + "\n\n";
    out += "options:\n";
    std::vector<const CLI::Option*> opts = app->get_options(
        [app](const CLI::Option* o) { return o->nonpositional() && o != app->get_help_ptr(); });
    opts.push_back(app->get_help_ptr());  // last
    for (const CLI::Option* o : opts) {
      const std::string names = "  " + option_names(o);
      out += names;
      if (names.size() + 2 > kNameColumn)
        out += "\n" + std::string(kNameColumn, ' ');
      else
        out += std::string(kNameColumn - names.size(), ' ');
      out += wrap(o->get_description(), kNameColumn, kNameColumn) + "\n";
    }
    if (!app->get_footer().empty()) out += "\n" + wrap(app->get_footer(), 0, 0) + "\n";
    return out;
  }
};

const CLI::Option* find_option(const CLI::App& app, const std::string& name) {
  for (const CLI::Option* o : app.get_options([](const CLI::Option* o) { return o->nonpositional(); }))
    if (o->check_name(name)) return o;
  return nullptr;
}

std::vector<std::string> all_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::Option* o : app.get_options([](const CLI::Option* o) { return o->nonpositional(); })) {
    for (const std::string& n : o->get_snames()) names.push_back("-" + n);
    for (const std::string& n : o->get_lnames()) names.push_back("--" + n);
  }
  return names;
}

bool is_option_word(const std::string& w) {
  return w.size() > 1 && w[0] == '-';
}

// The rules CLI11 does not have, checked on the words before it parses them: --help first; an
// unknown option names the nearest; an option's value is never another option (CLI11 takes the
// next word, whatever it is); a flag takes no value. True when help was asked for.
bool prescan(const CLI::App& app, const std::vector<std::string>& args) {
  std::string error;  // the first, thrown unless help was asked for
  auto fail = [&](const std::string& msg) {
    if (error.empty()) error = msg;
  };
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& w = args[i];
    if (w == "--") break;  // the rest are positional
    if (!is_option_word(w)) continue;
    const size_t eq = w.rfind("--", 0) == 0 ? w.find('=') : std::string::npos;
    const std::string name = w.substr(0, eq);
    const CLI::Option* o = find_option(app, name);
    if (!o) {
      std::string msg = "unknown option " + name;
      if (auto s = nearest(name, all_names(app))) msg += "; did you mean " + *s + "?";
      fail(msg);
    } else if (o == app.get_help_ptr()) {
      return true;
    } else if (is_flag(o)) {
      if (eq != std::string::npos) fail(name + " takes no value");
    } else if (eq == std::string::npos) {
      if (i + 1 >= args.size()) {
        fail(name + " needs a value");
      } else {
        const std::string& v = args[i + 1];
        if (is_option_word(v) && find_option(app, v.substr(0, v.rfind("--", 0) == 0 ? v.find('=') : v.npos)))
          fail(name + " needs a value, got the option " + v);
        else
          ++i;  // the value
      }
    }
  }
  if (!error.empty()) throw UsageError(error);
  return false;
}

std::string with_name(std::string msg, const std::string& name) {
  for (size_t p; (p = msg.find("{}")) != std::string::npos;) msg.replace(p, 2, name);
  return msg;
}

// Parses a number as the tables want it: the whole word, finite.
std::optional<double> to_number(const std::string& s) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

}  // namespace

void setup(CLI::App& app, const std::string& name, const std::string& description,
           const std::string& footer) {
  info(name);  // a command of the registry
  app.name(name);
  app.description(description);
  app.footer(footer);
  app.formatter(std::make_shared<Formatter>());
  app.set_help_flag("-h,--help", "print this help");
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
}

CLI::Option* add_positionals(CLI::App& app, std::vector<std::string>& into) {
  return app.add_option("args", into)->group("");
}

bool parse(CLI::App& app, const std::vector<std::string>& args) {
  if (prescan(app, args)) {
    std::fputs(app.help().c_str(), stdout);
    return false;
  }
  std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them last first
  try {
    app.parse(reversed);
  } catch (const CLI::ValidationError& e) {
    // CLI11 says "NAME: MESSAGE"; the validators' messages hold "{}" where the name goes.
    const std::string what = e.what();
    const size_t colon = what.find(": ");
    if (colon == std::string::npos || what.find("{}", colon) == std::string::npos) throw UsageError(what);
    throw UsageError(with_name(what.substr(colon + 2), what.substr(0, colon)));
  } catch (const CLI::ParseError& e) {
    throw UsageError(e.what());
  }
  return true;
}

CLI::Validator number() {
  return CLI::Validator(
      [](std::string& s) { return to_number(s) ? std::string() : "{} expects a number, got '" + s + "'"; },
      "");
}

CLI::Validator positive() {
  return CLI::Validator(
      [](std::string& s) {
        const auto v = to_number(s);
        if (!v) return "{} expects a number, got '" + s + "'";
        return *v > 0 ? std::string() : "{} must be positive, got '" + s + "'";
      },
      "");
}

CLI::Validator whole(int lo, int hi) {
  return CLI::Validator(
      [lo, hi](std::string& s) {
        const auto v = to_number(s);
        if (!v || *v != std::floor(*v) || *v < lo || *v > hi)
          return "{} expects a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) +
                 ", got '" + s + "'";
        s = std::to_string((long)*v);  // "3.0" and "3e0" are 3 to CLI11's integer conversion too
        return std::string();
      },
      "");
}

CLI::Validator choice(std::vector<std::string> names) {
  std::string list, bar;
  for (const std::string& n : names)
    list += (list.empty() ? "" : ", ") + n, bar += (bar.empty() ? "" : "|") + n;
  return CLI::Validator(
      [names, list](std::string& s) {
        for (const std::string& n : names)
          if (s == n) return std::string();
        std::string msg = "unknown {} '" + s + "' (" + list + ")";
        if (auto m = nearest(s, names)) msg += "; did you mean '" + *m + "'?";
        return msg;
      },
      bar);
}

}  // namespace simreel::cli
