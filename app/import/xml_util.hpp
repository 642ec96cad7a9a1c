// What the URDF and MJCF readers share: reading a file into tinyxml2 with the error's line, and
// attributes read as numbers strictly ("1.5e" or "nan" is an error naming file, line and key).
#pragma once
#include <tinyxml2.h>

#include <optional>
#include <string>
#include <vector>

#include <simreel/math.hpp>

namespace simreel::xml {

std::string read_text(const std::string& path);  ///< InputError if unreadable
// Parses `text`; InputError "PATH:LINE: XML: what" if it is not well-formed XML.
void parse_xml(tinyxml2::XMLDocument& doc, const std::string& text, const std::string& path);
std::string attr_or(const tinyxml2::XMLElement* e, const char* name, const std::string& fallback);
// The numbers of a whitespace- (or comma-) separated text; nullopt if any is not a finite number.
std::optional<std::vector<double>> parse_numbers(const char* text);
// All the numbers of a whitespace-separated attribute; InputError "PATH:LINE: WHAT: KEY=...".
std::vector<double> number_list(const tinyxml2::XMLElement* e, const char* key, const std::string& path,
                                const std::string& what);
double number_attr(const tinyxml2::XMLElement* e, const char* key, const std::string& path,
                   const std::string& what);
double positive_attr(const tinyxml2::XMLElement* e, const char* key, const std::string& path,
                     const std::string& what);
template <int N>
Eigen::Matrix<double, N, 1> numbers(const tinyxml2::XMLElement* e, const char* key, const std::string& path,
                                    const std::string& what);
// URDF's fixed-axis roll, pitch, yaw: R = Rz(yaw) Ry(pitch) Rx(roll).
Quat rpy_quat(const Vec3& rpy);
std::optional<std::string> nearest_name(const std::string& w, const std::vector<std::string>& names);

}  // namespace simreel::xml
