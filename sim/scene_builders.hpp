// Reference scenes shared by tests, benchmarks and the demo scenes (one definition each).
//   R1 tumble: solid box 3 x 2 x 1 m, 6 kg, I = (2.5, 5, 6.5) kg m^2, no gravity, body angular
//              velocity (0.01, 5, 0.01) rad/s about its intermediate axis: it flips three times
//              in 20 s (the Dzhanibekov effect). Same scene as ../shared/anchors R1.
//   R2 free boxes: N boxes, sides uniform in 0.2..1 m, density 1000, random orientation, |w| up
//              to 10 rad/s, g = -9.81 z, on a 3 m grid; the same splitmix64 sequence as the
//              anchors, so the bodies are identical to the ones Bullet and MuJoCo stepped;
//              collision masked off, as there (they never meet: integration alone is measured).
//   R3 pile:   1000 unit cubes (mass 1, friction 0.5, restitution 0) in a 10 x 10 x 10 grid with
//              0.1 m gaps, centred on the z axis ((i - 4.5) 1.1 m in x and y), lowest centres at
//              z = 1, over the static plane z = 0 (friction 0.5); dt 1/240, 10 s. Same layout and
//              body order as ../shared/anchors/src/common.hpp (x fastest, then y, then z).
//   R3 tower:  n unit cubes stacked touching, centres at (0, 0, 0.5 + k), same cubes and ground.
//   Large pyramid (Box3D's shared/benchmarks.c, CreateLargePyramid, with a base of 100 as in
//              ../shared/anchors/CONTACTS.md): a wall one cube deep, row r (0 at the bottom) holds
//              base - r unit cubes touching side by side, centres at z = 0.5 + r, each row shifted
//              half a cube along x; 5,050 cubes for base 100. Cubes of density 1 (mass 1 kg) with
//              Box3D's default friction 0.6, restitution 0, on the plane z = 0 (friction 0.6).
//              Sleeping off, 200 steps of 1/60 s.
// The R3 builders list the cubes first (in the anchors' order) and the ground last, as the scene
// loader appends its top-level ground: cube k is body k.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "sim/body.hpp"
#include "sim/world.hpp"

namespace simreel {

// splitmix64 (Steele, Lea, Flood 2014): identical sequences on every platform.
struct SplitMix64 {
  uint64_t s;
  explicit SplitMix64(uint64_t seed) : s(seed) {}
  uint64_t next();
  double uniform();                    ///< [0, 1)
  double uniform(double a, double b);  ///< [a, b)
};

BodyDef box_body(const char* name, const Vec3& size, double mass);
BodyDef r1_tumble_body();  ///< identity orientation, w_W = (0.01, 5, 0.01) rad/s
constexpr double kR1Duration = 20.0;
std::vector<BodyDef> r2_free_boxes(int n, uint64_t seed = 12345);

constexpr double kR3Dt = 1.0 / 240.0;  ///< s
constexpr double kR3Duration = 10.0;   ///< s
constexpr double kR3Friction = 0.5;
/// Unit cube, mass 1 (I = 1/6 kg m^2), friction 0.5, restitution 0, centre at p_W.
BodyDef r3_cube(const std::string& name, const Vec3& p_W);
/// Static body named "ground" with one plane collider through z = height (massless, friction 0.5).
BodyDef r3_ground(double height = 0.0, double friction = kR3Friction);
std::vector<BodyDef> r3_pile();              ///< 1000 cubes, then the ground
std::vector<BodyDef> r3_column(int n = 10);  ///< one column of the pile, at x = y = 0, then the ground
std::vector<BodyDef> r3_tower(int n = 20);   ///< n cubes bottom to top, then the ground
constexpr double kPyramidDt = 1.0 / 60.0;    ///< s
constexpr int kPyramidSteps = 200;
constexpr double kPyramidFriction = 0.6;
std::vector<BodyDef> r3_pyramid(
    int base = 100);  ///< base (base + 1) / 2 cubes, row by row from the bottom, then the ground
/// Sanity scene for box-plane contact only: nx x ny cubes `spacing` m apart (centre to centre,
/// grid centred on the z axis) with centres at z = height, then the ground.
std::vector<BodyDef> r3_cube_grid_drop(int nx = 10, int ny = 10, double spacing = 1.5, double height = 1.0);

}  // namespace simreel
