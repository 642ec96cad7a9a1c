// JUnit XML for CI systems (GitLab, Jenkins, GitHub test reporters): one <testcase> per scene and
// frame, in the common schema (testsuites > testsuite > testcase with failure / error).
#pragma once
#include <string>
#include <vector>

namespace simreel {

struct JunitCase {
  std::string classname;  ///< the scene
  std::string name;       ///< the frame ("t=2.5s")
  double seconds = 0;
  std::string outcome;  ///< "" passed, "failure" (a difference) or "error" (missing golden, bad input)
  std::string message;  ///< why, one line per reason
  std::string type;     ///< the failure / error element's type; "" gives "difference" / "missing"
};

std::string junit_xml(const std::string& suite, const std::vector<JunitCase>& cases);
// Written whole (temp file, renamed); throws std::runtime_error if it cannot be.
void write_junit(const std::string& path, const std::string& suite, const std::vector<JunitCase>& cases);

}  // namespace simreel
