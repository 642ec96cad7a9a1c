#include "app/scene/scene_yaml.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "app/scene/scene.hpp"

namespace simreel::scene_yaml {

std::string Ctx::where(const YAML::Node& n) const {
  return scene_yaml::where(n, *this);
}

std::string show(const YAML::Node& n) {
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  if (n.IsSequence()) return "a list";
  if (n.IsMap()) return "a mapping";
  return "nothing";
}

void check_keys(const YAML::Node& map, const Ctx& c, const std::vector<std::string>& known) {
  if (!map.IsMap()) c.fail(map, "expected a mapping of keys, got " + show(map));
  for (const auto& kv : map) {
    if (!kv.first.IsScalar()) c.fail(kv.first, "a key must be a plain name, got " + show(kv.first));
    const std::string k = kv.first.Scalar();
    if (std::find(known.begin(), known.end(), k) != known.end()) continue;
    std::string msg = "unknown key '" + k + "'";
    if (auto s = nearest(k, known)) msg += "; did you mean '" + *s + "'?";
    c.child(k).fail(kv.first, msg);
  }
}

void untagged(const YAML::Node& n, const Ctx& c, const char* expected,
              std::initializer_list<const char*> tags) {
  const std::string& t = n.Tag();
  if (t == "?") return;
  for (const char* ok : tags)
    if (t == std::string("tag:yaml.org,2002:") + ok) return;
  std::string what = t == "!" ? "text (it is quoted)" : "a value tagged " + t;
  const std::string core = "tag:yaml.org,2002:";
  if (t.rfind(core, 0) == 0) what = "a value tagged !!" + t.substr(core.size());
  c.fail(n, "expected " + std::string(expected) + ", got " + show(n) + ", " + what);
}

double number(const YAML::Node& n, const Ctx& c) {
  if (!n.IsScalar()) c.fail(n, "expected a number, got " + show(n));
  untagged(n, c, "a number", {"float", "int"});
  const std::string& s = n.Scalar();
  // YAML 1.2 spells the non-finite floats .inf, -.inf, .nan (any case).
  std::string low = s;
  for (char& ch : low) ch = (char)std::tolower((unsigned char)ch);
  if (low == ".inf" || low == "+.inf" || low == "-.inf" || low == ".nan")
    c.fail(n, "must be a finite number, got " + show(n));
  // Decimal only (from_chars: no hex, no locale, no leading space); a leading '+' is allowed.
  double v = 0;
  const char* b = s.data() + (!s.empty() && s[0] == '+');
  const auto r = std::from_chars(b, s.data() + s.size(), v);
  if (r.ec == std::errc::result_out_of_range)
    c.fail(n, "is out of the range of double precision (about 1e-308 .. 1e308), got " + show(n));
  if (s.empty() || r.ec != std::errc() || r.ptr != s.data() + s.size()) {
    if (s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X' || s[1] == 'o'))
      c.fail(n, "expected a decimal number, got " + show(n) +
                    " (hexadecimal and octal are for collision bits only)");
    c.fail(n, "expected a number, got " + show(n));
  }
  if (!std::isfinite(v)) c.fail(n, "must be a finite number, got " + show(n));
  return v;
}

double positive(const YAML::Node& n, const Ctx& c) {
  const double v = number(n, c);
  if (!(v > 0)) c.fail(n, "must be positive, got " + show(n));
  return v;
}

double non_negative(const YAML::Node& n, const Ctx& c) {
  const double v = number(n, c);
  if (!(v >= 0)) c.fail(n, "must not be negative, got " + show(n));
  return v;
}

double unit_interval(const YAML::Node& n, const Ctx& c) {
  const double v = number(n, c);
  if (!(v >= 0 && v <= 1)) c.fail(n, "must lie in [0, 1], got " + show(n));
  return v;
}

uint32_t bits(const YAML::Node& n, const Ctx& c) {
  if (n.IsSequence()) {
    uint32_t v = 0;
    for (size_t i = 0; i < n.size(); ++i) {
      const double b = number(n[i], c.index(i));
      if (b != std::floor(b) || b < 0 || b > 31)
        c.index(i).fail(n[i], "expected a bit number from 0 to 31, got " + show(n[i]));
      v |= 1u << (int)b;
    }
    return v;
  }
  if (!n.IsScalar())
    c.fail(n, "expected a whole number from 0 to 4294967295 or a list of bit numbers, got " + show(n));
  const std::string& s = n.Scalar();
  if (s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {  // hexadecimal: 0xF0
    untagged(n, c, "a whole number", {"int"});
    uint32_t h = 0;
    const auto r = std::from_chars(s.data() + 2, s.data() + s.size(), h, 16);
    if (r.ec != std::errc() || r.ptr != s.data() + s.size())
      c.fail(n, "expected a whole number from 0 to 0xFFFFFFFF, got " + show(n));
    return h;
  }
  const double v = number(n, c);
  if (v != std::floor(v) || v < 0 || v > 4294967295.0)
    c.fail(n, "expected a whole number from 0 to 4294967295 or a list of bit numbers, got " + show(n));
  return (uint32_t)v;
}

std::string where(const YAML::Node& n, const Ctx& c) {
  std::string s = c.file();
  if (n.IsDefined() && n.Mark().line >= 0) s += ":" + std::to_string(n.Mark().line + 1);
  return s + ": " + c.key();
}

bool boolean(const YAML::Node& n, const Ctx& c) {
  if (n.IsScalar()) {
    untagged(n, c, "true or false", {"bool"});
    const std::string& s = n.Scalar();
    if (s == "true" || s == "yes" || s == "on") return true;
    if (s == "false" || s == "no" || s == "off") return false;
  }
  c.fail(n, "expected true or false, got " + show(n));
}

std::string text(const YAML::Node& n, const Ctx& c) {
  if (!n.IsScalar() || n.Scalar().empty()) c.fail(n, "expected a text value, got " + show(n));
  return n.Scalar();
}

Integrator integrator(const YAML::Node& n, const Ctx& c) {
  const std::string name = text(n, c);
  const auto i = integrator_from_name(name);
  if (!i) {
    std::string msg = "unknown integrator '" + name + "' (" + integrator_names() + ")";
    if (auto s = nearest(name, {"auto", "seed", "euler_gyro", "rk4", "splitting"}))
      msg += "; did you mean '" + *s + "'?";
    c.fail(n, msg);
  }
  return *i;
}

Quat unit_quaternion(const YAML::Node& n, const Ctx& c) {
  const Eigen::Vector4d q = vec<4>(n, c);
  const double norm = q.norm();
  if (std::fabs(norm - 1.0) > 1e-3)
    c.fail(n, "must be a unit quaternion [w, x, y, z], its norm is " + std::to_string(norm));
  return Quat(q[0], q[1], q[2], q[3]).normalized();
}

// An orientation in any of three forms, exactly one of them present in the mapping `n`:
//   orientation: [w, x, y, z]            a unit quaternion
//   euler: [roll, pitch, yaw]            degrees, rotations about x, y and z applied intrinsically
//                                        in the order z-y-x (aerospace): q = qz(yaw) qy(pitch) qx(roll)
//   axis_angle: { axis: [x, y, z], angle: degrees }
// Returns false (q untouched) when none is given.
bool orientation(const YAML::Node& n, const Ctx& c, Quat& q) {
  const char* keys[3] = {"orientation", "euler", "axis_angle"};
  const char* given = nullptr;
  for (const char* k : keys)
    if (n[k]) {
      if (given) c.child(k).fail(n[k], std::string("give one orientation: '") + given + "' is already given");
      given = k;
    }
  if (!given) return false;
  constexpr double kDeg = M_PI / 180;
  if (given[0] == 'o') {
    q = unit_quaternion(n["orientation"], c.child("orientation"));
  } else if (given[0] == 'e') {
    const Vec3 e = vec<3>(n["euler"], c.child("euler")) * kDeg;
    q = (Eigen::AngleAxisd(e.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(e.y(), Vec3::UnitY()) *
         Eigen::AngleAxisd(e.x(), Vec3::UnitX()))
            .normalized();
  } else {
    const YAML::Node a = n["axis_angle"];
    const Ctx ac = c.child("axis_angle");
    if (!a.IsMap()) ac.fail(a, "expected { axis: [x, y, z], angle: degrees }, got " + show(a));
    check_keys(a, ac, {"axis", "angle"});
    if (!a["axis"] || !a["angle"]) ac.fail(a, "needs both 'axis' and 'angle' (degrees)");
    const Vec3 axis = vec<3>(a["axis"], ac.child("axis"));
    if (!(axis.norm() > 0)) ac.child("axis").fail(a["axis"], "must not be zero");
    q = Quat(Eigen::AngleAxisd(number(a["angle"], ac.child("angle")) * kDeg, axis.normalized()));
  }
  return true;
}

}  // namespace simreel::scene_yaml
