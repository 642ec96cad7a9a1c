#include "app/cli/junit.hpp"

#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "app/scene/text.hpp"

namespace simreel {

namespace {

// XML 1.0 text and attribute values: the five entities, and control characters (not allowed in
// XML 1.0 even as references) replaced by '?'.
std::string xml(const std::string& s) {
  std::string o;
  for (unsigned char c : s) {
    switch (c) {
      case '&':
        o += "&amp;";
        break;
      case '<':
        o += "&lt;";
        break;
      case '>':
        o += "&gt;";
        break;
      case '"':
        o += "&quot;";
        break;
      case '\'':
        o += "&apos;";
        break;
      case '\n':
        o += "&#10;";
        break;
      case '\t':
        o += "&#9;";
        break;
      default:
        o += c < 0x20 ? '?' : (char)c;
    }
  }
  return o;
}

}  // namespace

std::string junit_xml(const std::string& suite, const std::vector<JunitCase>& cases) {
  int failures = 0, errors = 0;
  double total = 0;
  for (const JunitCase& c : cases) {
    failures += c.outcome == "failure";
    errors += c.outcome == "error";
    total += c.seconds;
  }
  std::ostringstream o;
  o << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  o << "<testsuites name=\"" << xml(suite) << "\" tests=\"" << cases.size() << "\" failures=\"" << failures
    << "\" errors=\"" << errors << "\" time=\"" << total << "\">\n";
  o << "  <testsuite name=\"" << xml(suite) << "\" tests=\"" << cases.size() << "\" failures=\"" << failures
    << "\" errors=\"" << errors << "\" skipped=\"0\" time=\"" << total << "\">\n";
  for (const JunitCase& c : cases) {
    o << "    <testcase classname=\"" << xml(c.classname) << "\" name=\"" << xml(c.name) << "\" time=\""
      << c.seconds << "\"";
    if (c.outcome.empty()) {
      o << "/>\n";
      continue;
    }
    const std::string first = c.message.substr(0, c.message.find('\n'));
    o << ">\n      <" << c.outcome << " message=\"" << xml(first) << "\" type=\""
      << xml(!c.type.empty()          ? c.type
             : c.outcome == "failure" ? "difference"
                                      : "missing")
      << "\">" << xml(c.message) << "</" << c.outcome << ">\n    </testcase>\n";
  }
  o << "  </testsuite>\n</testsuites>\n";
  return o.str();
}

void write_junit(const std::string& path, const std::string& suite, const std::vector<JunitCase>& cases) {
  const std::string text = junit_xml(suite, cases);
  AtomicFile f(path);
  if (std::fwrite(text.data(), 1, text.size(), f.get()) != text.size())
    throw std::runtime_error(path + ": could not write the JUnit XML");
  f.commit();
}

}  // namespace simreel
