#include "app/cli/goldens.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include <simreel/error.hpp>
#include "app/scene/text.hpp"
#include "sim/base/hash.hpp"

namespace simreel {

using nlohmann::json;

std::string fingerprint_value(const Fingerprint& f, const std::string& key) {
  for (const auto& [k, v] : f)
    if (k == key) return v;
  return "";
}

std::vector<BodyState> body_states(const World& w) {
  std::vector<BodyState> out;
  out.reserve((size_t)w.body_count());
  for (int i = 0; i < w.body_count(); ++i)
    out.push_back(
        {w.def(i).name, w.origin_position(i), w.orientation(i), w.linear_velocity(i), w.angular_velocity(i)});
  return out;
}

const GoldenFrame* Manifest::find(double time) const {
  for (const GoldenFrame& f : frames)
    if (std::fabs(f.time - time) <= 1e-9) return &f;
  return nullptr;
}

std::string golden_file_name(double time) {
  char b[64];
  std::snprintf(b, sizeof b, "t%.9gs.png", time);
  return b;
}

namespace {

json vec(const Vec3& v) {
  return json::array({v.x(), v.y(), v.z()});
}

Vec3 vec3(const json& j) {
  if (!j.is_array() || j.size() != 3) throw std::invalid_argument("expected 3 numbers");
  return Vec3(j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>());
}

json fingerprint_json(const Fingerprint& f) {
  json o = json::object();
  for (const auto& [k, v] : f) o[k] = v;
  return o;
}

Fingerprint fingerprint_from(const json& j) {
  Fingerprint f;
  for (const auto& [k, v] : j.items()) f.emplace_back(k, v.get<std::string>());
  return f;
}

}  // namespace

Manifest read_manifest(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the golden manifest");
  Manifest m;
  try {
    const json j = json::parse(in);
    m.simreel_version = j.at("simreel").get<std::string>();
    m.scene = j.at("scene").get<std::string>();
    m.scene_hash = j.value("scene_hash", "");
    if (j.contains("inputs"))
      for (const auto& [k, v] : j.at("inputs").items()) m.inputs[k] = v.get<std::string>();
    if (j.contains("masses"))
      for (const json& b : j.at("masses")) {
        BodyMass bm;
        bm.name = b.at("name").get<std::string>();
        bm.mass = b.at("mass").get<double>();
        bm.center_of_mass = vec3(b.at("center_of_mass"));
        const json& I = b.at("inertia");
        if (!I.is_array() || I.size() != 6) throw std::invalid_argument("inertia: expected 6 numbers");
        for (int k = 0; k < 6; ++k) bm.inertia[k] = I.at(k).get<double>();
        m.masses.push_back(bm);
      }
    for (const json& f : j.at("frames")) {
      GoldenFrame g;
      g.time = f.at("time").get<double>();
      g.step = f.at("step").get<long>();
      g.file = f.at("file").get<std::string>();
      g.pixel_hash = f.at("pixel_hash").get<std::string>();
      g.width = f.at("width").get<int>();
      g.height = f.at("height").get<int>();
      if (g.file.find('/') != std::string::npos || g.file.find("..") != std::string::npos)
        throw std::invalid_argument("frame file '" + g.file + "' must be a plain name in the golden folder");
      g.fingerprint = fingerprint_from(f.at("fingerprint"));
      for (const json& b : f.at("bodies")) {
        BodyState s;
        s.name = b.at("name").get<std::string>();
        s.position = vec3(b.at("position"));
        const json& q = b.at("orientation");
        if (!q.is_array() || q.size() != 4)
          throw std::invalid_argument("orientation: expected 4 numbers [w, x, y, z]");
        s.orientation =
            Quat(q.at(0).get<double>(), q.at(1).get<double>(), q.at(2).get<double>(), q.at(3).get<double>());
        s.linear_velocity = vec3(b.at("linear_velocity"));
        s.angular_velocity = vec3(b.at("angular_velocity"));
        g.bodies.push_back(s);
      }
      m.frames.push_back(std::move(g));
    }
  } catch (const std::exception& e) {
    throw InputError(path + ": not a golden manifest simreel can read (" + e.what() + ")");
  }
  return m;
}

void write_manifest(const std::string& path, const Manifest& m) {
  json j;
  j["simreel"] = m.simreel_version;
  j["scene"] = m.scene;
  j["scene_hash"] = m.scene_hash;
  if (!m.inputs.empty()) {
    json in = json::object();
    for (const auto& [k, v] : m.inputs) in[k] = v;
    j["inputs"] = in;
  }
  if (!m.masses.empty()) {
    json ms = json::array();
    for (const BodyMass& b : m.masses)
      ms.push_back({{"name", b.name},
                    {"mass", b.mass},
                    {"center_of_mass", vec(b.center_of_mass)},
                    {"inertia", json::array({b.inertia[0], b.inertia[1], b.inertia[2], b.inertia[3],
                                             b.inertia[4], b.inertia[5]})}});
    j["masses"] = std::move(ms);
  }
  j["frames"] = json::array();
  for (const GoldenFrame& g : m.frames) {
    json f;
    f["time"] = g.time;
    f["step"] = g.step;
    f["file"] = g.file;
    f["pixel_hash"] = g.pixel_hash;
    f["width"] = g.width;
    f["height"] = g.height;
    f["fingerprint"] = fingerprint_json(g.fingerprint);
    json bodies = json::array();
    for (const BodyState& s : g.bodies)
      bodies.push_back({{"name", s.name},
                        {"position", vec(s.position)},
                        {"orientation", json::array({s.orientation.w(), s.orientation.x(), s.orientation.y(),
                                                     s.orientation.z()})},
                        {"linear_velocity", vec(s.linear_velocity)},
                        {"angular_velocity", vec(s.angular_velocity)}});
    f["bodies"] = std::move(bodies);
    j["frames"].push_back(std::move(f));
  }
  // nlohmann writes doubles in their shortest form that reads back exactly.
  const std::string text = j.dump(1) + "\n";
  AtomicFile out(path);
  if (std::fwrite(text.data(), 1, text.size(), out.get()) != text.size())
    throw std::runtime_error(path + ": could not write the golden manifest");
  out.commit();
}

std::vector<std::string> compare_states(const std::vector<BodyState>& golden,
                                        const std::vector<BodyState>& now, double rtol) {
  std::vector<std::string> out;
  auto fmt = [](double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.10g", v);
    return std::string(b);
  };
  auto check = [&](const std::string& body, const char* what, const double* g, const double* n, int dims,
                   const char* unit, const char* names) {
    int worst = -1;
    double worst_excess = 0;
    for (int i = 0; i < dims; ++i) {
      const double tol = rtol * std::max(1.0, std::fabs(g[i]));
      const double d = std::fabs(n[i] - g[i]);
      if (!(d <= tol) && (worst < 0 || d / tol > worst_excess)) worst = i, worst_excess = d / tol;
    }
    if (worst < 0) return;
    out.push_back("body '" + body + "' " + what + "." + names[worst] + ": " + fmt(n[worst]) + " (golden " +
                  fmt(g[worst]) + ", by " + fmt(n[worst] - g[worst]) + (*unit ? " " : "") + unit + ")");
  };
  for (const BodyState& g : golden) {
    const BodyState* n = nullptr;
    for (const BodyState& c : now)
      if (c.name == g.name) n = &c;
    if (!n) {
      out.push_back("body '" + g.name + "' is gone");
      continue;
    }
    check(g.name, "position", g.position.data(), n->position.data(), 3, "m", "xyz");
    // q and -q are the same rotation: compare with the golden's sign.
    const double sg = g.orientation.coeffs().dot(n->orientation.coeffs()) < 0 ? -1.0 : 1.0;
    const double gq[4] = {g.orientation.w(), g.orientation.x(), g.orientation.y(), g.orientation.z()};
    const double nq[4] = {sg * n->orientation.w(), sg * n->orientation.x(), sg * n->orientation.y(),
                          sg * n->orientation.z()};
    check(g.name, "orientation", gq, nq, 4, "", "wxyz");
    check(g.name, "linear_velocity", g.linear_velocity.data(), n->linear_velocity.data(), 3, "m/s", "xyz");
    check(g.name, "angular_velocity", g.angular_velocity.data(), n->angular_velocity.data(), 3, "rad/s",
          "xyz");
  }
  for (const BodyState& c : now) {
    bool known = false;
    for (const BodyState& g : golden) known |= g.name == c.name;
    if (!known) out.push_back("body '" + c.name + "' is new");
  }
  return out;
}

std::vector<BodyMass> body_masses(const World& w) {
  std::vector<BodyMass> out;
  for (int i = 0; i < w.body_count(); ++i) {
    BodyMass b;
    b.name = w.def(i).name;
    b.mass = w.mass(i);
    b.center_of_mass = w.local_centroid(i);
    const Mat3 I = w.inertia_world(i);
    const double v[6] = {I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2)};
    for (int k = 0; k < 6; ++k) b.inertia[k] = v[k];
    out.push_back(b);
  }
  return out;
}

std::vector<std::string> compare_masses(const std::vector<BodyMass>& golden, const std::vector<BodyMass>& now,
                                        double rtol) {
  std::vector<std::string> out;
  auto fmt = [](double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.10g", v);
    return std::string(b);
  };
  auto differs = [&](double g, double n) {
    return !(std::fabs(n - g) <= rtol * std::max(1.0, std::fabs(g)));
  };
  for (const BodyMass& g : golden) {
    const BodyMass* n = nullptr;
    for (const BodyMass& c : now)
      if (c.name == g.name) n = &c;
    if (!n) continue;  // compare_states names bodies that are gone
    if (differs(g.mass, n->mass)) {
      out.push_back("body '" + g.name + "': mass " + fmt(n->mass) + " kg (golden " + fmt(g.mass) + " kg)");
      continue;
    }
    for (int k = 0; k < 3; ++k)
      if (differs(g.center_of_mass[k], n->center_of_mass[k])) {
        out.push_back("body '" + g.name + "': centre of mass " + "xyz"[k] + " " + fmt(n->center_of_mass[k]) +
                      " m in the body frame (golden " + fmt(g.center_of_mass[k]) + " m)");
        break;
      }
    static const char* names[6] = {"xx", "yy", "zz", "xy", "xz", "yz"};
    for (int k = 0; k < 6; ++k)
      if (differs(g.inertia[k], n->inertia[k])) {
        out.push_back("body '" + g.name + "': inertia I" + names[k] + " " + fmt(n->inertia[k]) +
                      " kg m^2 (golden " + fmt(g.inertia[k]) + " kg m^2)");
        break;
      }
  }
  return out;
}

std::string file_hash(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  // FNV-1a seeded with its offset basis short of the last digit: kept, since committed manifests
  // record hashes made with it.
  uint64_t h = 1469598103934665603ull;
  char buf[65536];
  while (in) {
    in.read(buf, sizeof buf);
    h = fnv1a(h, buf, (size_t)in.gcount());
  }
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", (unsigned long long)h);
  return out;
}

}  // namespace simreel
