// Goldens of `simreel check`: per scene a folder DIR/<scene>/ with one PNG per checked moment and
// manifest.json, which records what produced them and what they show:
//   simreel version, scene file hash, renderer fingerprint (who drew them), frame size, and per
//   frame: time, step, PNG file, hash of the decoded pixels, the fingerprint of the machine that
//   wrote it, and every body's pose and velocity in double precision (17 significant digits).
// Goldens are compared physics first (the body states, relative tolerance 1e-9), then pixels.
#pragma once
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <simreel/math.hpp>
#include <simreel/world.hpp>

namespace simreel {

// key -> value, in a fixed order. See fingerprint() in check_cmd.cpp for the keys.
using Fingerprint = std::vector<std::pair<std::string, std::string>>;
std::string fingerprint_value(const Fingerprint& f, const std::string& key);

struct BodyState {
  std::string name;
  Vec3 position = Vec3::Zero();  ///< m, body origin
  Quat orientation = Quat::Identity();
  Vec3 linear_velocity = Vec3::Zero();   ///< m/s, centre of mass
  Vec3 angular_velocity = Vec3::Zero();  ///< rad/s, world frame
};
std::vector<BodyState> body_states(const World& w);

struct GoldenFrame {
  double time = 0;  ///< s
  long step = 0;
  std::string file;  ///< PNG, relative to the scene's golden folder
  std::string pixel_hash;
  int width = 0, height = 0;
  Fingerprint fingerprint;  ///< of the machine that wrote this frame
  std::vector<BodyState> bodies;
};

// What a body weighs as the scene builds it (mass properties at the start): a golden records them,
// so that a changed mass or inertia is named as physics from frame 0 on.
struct BodyMass {
  std::string name;
  double mass = 0;                     ///< kg
  Vec3 center_of_mass = Vec3::Zero();  ///< m, body frame
  double inertia[6] = {0, 0, 0,
                       0, 0, 0};  ///< kg m^2 about the centre of mass, world axes at t = 0: xx yy zz xy xz yz
};
std::vector<BodyMass> body_masses(const World& w);
// One message per body whose mass, centre of mass or inertia differs beyond rtol (relative, floor
// rtol in SI units): "body 'ball': mass 0.42 kg (golden 0.4 kg)"; bodies added or gone are named.
std::vector<std::string> compare_masses(const std::vector<BodyMass>& golden, const std::vector<BodyMass>& now,
                                        double rtol = 1e-9);

struct Manifest {
  std::string simreel_version;
  std::string scene;       ///< scene name
  std::string scene_hash;  ///< of the scene file's bytes when written
  /// The files the scene read (meshes, images, robot files; paths relative to the scene's folder)
  /// and their hashes when written. Empty in manifests written before inputs were recorded.
  std::map<std::string, std::string> inputs;
  /// Every body's mass properties when written; empty in manifests written before they were recorded.
  std::vector<BodyMass> masses;
  std::vector<GoldenFrame> frames;
  const GoldenFrame* find(double time) const;  ///< the frame at this time (within 1e-9 s), or null
};

// Throws InputError naming the file for anything unreadable or malformed.
Manifest read_manifest(const std::string& path);
// Written whole (temp file, then renamed); throws std::runtime_error if it cannot be.
void write_manifest(const std::string& path, const Manifest& m);

// The PNG's name for a moment: "t2.5s.png" (shortest exact-enough decimal of the time).
std::string golden_file_name(double time);

// The physics comparison: every body of the golden, each quantity's components, within
// |now - golden| <= rtol * max(1, |golden|) (relative, with a floor of rtol in SI units so values
// near zero are not held to nothing; quaternions compared up to sign). One message per body and
// quantity that moved: "body 'ball' position.z: 1.25 (golden 1.2, by 0.05 m)"; bodies added or
// gone are named too. Empty when the physics is the same.
std::vector<std::string> compare_states(const std::vector<BodyState>& golden,
                                        const std::vector<BodyState>& now, double rtol = 1e-9);

// 64-bit FNV-1a of a file's bytes, hex; "" if it cannot be read.
std::string file_hash(const std::string& path);

}  // namespace simreel
