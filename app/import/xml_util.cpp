#include "app/import/xml_util.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <simreel/error.hpp>
#include "app/scene/scene.hpp"

namespace simreel::xml {

std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path + ": cannot open the file");
  std::ostringstream s;
  s << f.rdbuf();
  if (f.bad()) throw InputError(path + ": cannot read the file");
  return s.str();
}

void parse_xml(tinyxml2::XMLDocument& doc, const std::string& text, const std::string& path) {
  if (doc.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS) {
    std::string msg = doc.ErrorStr() ? doc.ErrorStr() : "not well-formed";
    throw InputError(path + ":" + std::to_string(std::max(1, doc.ErrorLineNum())) + ": XML: " + msg);
  }
}

std::string attr_or(const tinyxml2::XMLElement* e, const char* name, const std::string& fallback) {
  const char* v = e->Attribute(name);
  return v ? std::string(v) : fallback;
}

std::optional<std::vector<double>> parse_numbers(const char* v) {
  std::vector<double> out;
  const char* s = v;
  auto gap = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == ','; };
  while (*s) {
    while (gap(*s)) ++s;
    if (!*s) break;
    char* end = nullptr;
    const double x = std::strtod(s, &end);
    if (end == s || !std::isfinite(x) || (*end && !gap(*end))) return std::nullopt;
    out.push_back(x);
    s = end;
  }
  return out;
}

std::vector<double> number_list(const tinyxml2::XMLElement* e, const char* key, const std::string& path,
                                const std::string& what) {
  const char* v = e->Attribute(key);
  auto fail = [&](const std::string& msg) {
    throw InputError(path + ":" + std::to_string(e->GetLineNum()) + ": " + what + ": <" + e->Name() + " " +
                     key + "=\"" + (v ? v : "") + "\">: " + msg);
  };
  if (!v) fail("missing");
  auto out = parse_numbers(v);
  if (!out) fail("expected numbers");
  return *out;
}

double number_attr(const tinyxml2::XMLElement* e, const char* key, const std::string& path,
                   const std::string& what) {
  const auto v = number_list(e, key, path, what);
  if (v.size() != 1)
    throw InputError(path + ":" + std::to_string(e->GetLineNum()) + ": " + what + ": <" + e->Name() + " " +
                     key + ">: expected one number, got " + std::to_string(v.size()));
  return v[0];
}

double positive_attr(const tinyxml2::XMLElement* e, const char* key, const std::string& path,
                     const std::string& what) {
  const double x = number_attr(e, key, path, what);
  if (!(x > 0))
    throw InputError(path + ":" + std::to_string(e->GetLineNum()) + ": " + what + ": <" + e->Name() + " " +
                     key + ">: must be positive");
  return x;
}

template <int N>
Eigen::Matrix<double, N, 1> numbers(const tinyxml2::XMLElement* e, const char* key, const std::string& path,
                                    const std::string& what) {
  const auto v = number_list(e, key, path, what);
  if ((int)v.size() != N)
    throw InputError(path + ":" + std::to_string(e->GetLineNum()) + ": " + what + ": <" + e->Name() + " " +
                     key + ">: expected " + std::to_string(N) + " numbers, got " + std::to_string(v.size()));
  Eigen::Matrix<double, N, 1> out;
  for (int i = 0; i < N; ++i) out[i] = v[i];
  return out;
}
template Eigen::Matrix<double, 1, 1> numbers<1>(const tinyxml2::XMLElement*, const char*, const std::string&,
                                                const std::string&);
template Eigen::Matrix<double, 3, 1> numbers<3>(const tinyxml2::XMLElement*, const char*, const std::string&,
                                                const std::string&);
template Eigen::Matrix<double, 4, 1> numbers<4>(const tinyxml2::XMLElement*, const char*, const std::string&,
                                                const std::string&);

Quat rpy_quat(const Vec3& rpy) {
  return (Quat(Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ())) * Quat(Eigen::AngleAxisd(rpy.y(), Vec3::UnitY())) *
          Quat(Eigen::AngleAxisd(rpy.x(), Vec3::UnitX())))
      .normalized();
}

std::optional<std::string> nearest_name(const std::string& w, const std::vector<std::string>& names) {
  return nearest(w, names);
}

}  // namespace simreel::xml
