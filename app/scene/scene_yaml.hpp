// Reading scene YAML: where each value sits (file, line, column, dotted key) and the value
// readers every part of the scene format shares (app/scene/scene.cpp, app/scene/scene_forces.cpp,
// app/scene/scene_overlays.cpp), so a number or a key is read, and refused, the same way everywhere.
#pragma once
#include <yaml-cpp/yaml.h>

#include "sim/dynamics/integrators.hpp"

#include <cstdint>
#include <initializer_list>
#include <sstream>
#include <string>
#include <vector>

#include <simreel/error.hpp>
#include <simreel/math.hpp>

namespace simreel::scene_yaml {

// Where a value sits: the file, its line and column, and the dotted key path to it.
class Ctx {
 public:
  Ctx(std::string file, std::string key) : file_(std::move(file)), key_(std::move(key)) {}
  Ctx child(const std::string& k) const { return Ctx(file_, key_.empty() ? k : key_ + "." + k); }
  Ctx index(size_t i) const { return Ctx(file_, key_ + "[" + std::to_string(i) + "]"); }
  [[noreturn]] void fail(const YAML::Node& n, const std::string& what) const {
    throw InputError(message(n, what));
  }
  // What fail() would say: "FILE:LINE:COL: KEY: what".
  std::string message(const YAML::Node& n, const std::string& what) const {
    std::ostringstream os;
    os << file_;
    if (n.IsDefined() && n.Mark().line >= 0) os << ":" << n.Mark().line + 1 << ":" << n.Mark().column + 1;
    os << ": " << (key_.empty() ? std::string("scene") : key_) << ": " << what;
    return os.str();
  }
  const std::string& key() const { return key_; }
  std::string where(const YAML::Node& n) const;  ///< "FILE:LINE: KEY", for notes
  const std::string& file() const { return file_; }

 private:
  std::string file_, key_;
};

std::string show(const YAML::Node& n);  ///< "'5'", "a list", "a mapping", "nothing"
// Every key of a mapping must be known; a typo gets the nearest known key suggested.
void check_keys(const YAML::Node& map, const Ctx& c, const std::vector<std::string>& known);
// A plain scalar, or one tagged with one of `tags` (!!float, !!int, ...): a quoted "5" or a
// `!!str 5` is text, and text is not read as a number or a yes/no.
void untagged(const YAML::Node& n, const Ctx& c, const char* expected,
              std::initializer_list<const char*> tags);
double number(const YAML::Node& n, const Ctx& c);  ///< finite, decimal
double positive(const YAML::Node& n, const Ctx& c);
double non_negative(const YAML::Node& n, const Ctx& c);
double unit_interval(const YAML::Node& n, const Ctx& c);
// A 32-bit collision bit set: a whole number 0 .. 4294967295 (0x hex works too), or a list of bit
// numbers 0 .. 31 ([0, 3] is 9).
uint32_t bits(const YAML::Node& n, const Ctx& c);
std::string where(const YAML::Node& n, const Ctx& c);  ///< "FILE:LINE: KEY", for notes
bool boolean(const YAML::Node& n, const Ctx& c);
std::string text(const YAML::Node& n, const Ctx& c);       ///< a non-empty scalar
Integrator integrator(const YAML::Node& n, const Ctx& c);  ///< a name; a typo gets the nearest

// An orientation in any of three forms, exactly one of them present in the mapping `n`:
//   orientation: [w, x, y, z]            a unit quaternion
//   euler: [roll, pitch, yaw]            degrees, rotations about x, y and z applied intrinsically
//                                        in the order z-y-x (aerospace): q = qz(yaw) qy(pitch) qx(roll)
//   axis_angle: { axis: [x, y, z], angle: degrees }
// Returns false (q untouched) when none is given.
bool orientation(const YAML::Node& n, const Ctx& c, Quat& q);
Quat unit_quaternion(const YAML::Node& n, const Ctx& c);  ///< [w, x, y, z], norm within 1e-3 of 1

template <int N>
Eigen::Matrix<double, N, 1> vec(const YAML::Node& n, const Ctx& c) {
  if (!n.IsSequence() || n.size() != N)
    c.fail(n, "expected a list of " + std::to_string(N) + " numbers, got " +
                  (n.IsSequence() ? "a list of " + std::to_string(n.size()) : show(n)));
  Eigen::Matrix<double, N, 1> v;
  for (int i = 0; i < N; ++i) v[i] = number(n[i], c.index(i));
  return v;
}

}  // namespace simreel::scene_yaml
