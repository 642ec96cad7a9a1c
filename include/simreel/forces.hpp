// Applied forces, the scene's `forces:` list: one record per acting force (a WorldConfig holds
// them by body index). Kinds:
//   force            constant vector (N), world or body frame, at a body point (default the
//                    centre of mass), over a time window [from, to)
//   torque           constant vector (N m), world or body frame, over [from, to)
//   impulse          N s at a body point, once, at `time`
//   angular_impulse  N m s, once, at `time`
//   spring           a body point to a fixed world anchor, or two bodies' points: Hooke's law
//                    along the line with a dashpot on its rate of change, over [from, to)
//   drag             -(linear + quadratic |v|) v at the centre of mass, over [from, to)
// Points are in the body frame relative to the body origin (the body's `position`), not to its
// centre of mass. A force that depends on the state or on time is integrated to fourth order: the
// free-flight RK4 evaluates it again at every stage.
#pragma once
#include <limits>

#include <simreel/math.hpp>

namespace simreel {

enum class ForceKind : unsigned char { force, torque, impulse, angular_impulse, spring, drag };
const char* to_string(ForceKind k);

enum class ForceFrame : unsigned char { world, body };

struct ForceDef {
  ForceKind kind = ForceKind::force;
  int body = -1;                         ///< index of the body acted on (spring: its first end)
  int body_b = -1;                       ///< spring: the second body's index, or -1 for a fixed world anchor
  ForceFrame frame = ForceFrame::world;  ///< of `vector`: world axes, or axes turning with the body
  Vec3 vector = Vec3::Zero();            ///< N (force), N m (torque), N s (impulse), N m s (angular_impulse)
  bool at_centroid = true;               ///< no point given: at the centre of mass (no torque)
  Vec3 at_B = Vec3::Zero();      ///< m, point of action in the body frame, relative to the body origin
  bool at_b_centroid = true;     ///< spring: the second end at the second body's centre of mass
  Vec3 at_b_B = Vec3::Zero();    ///< m, spring: the second end in the second body's frame
  Vec3 anchor_W = Vec3::Zero();  ///< m, spring: the fixed world anchor (body_b == -1)
  double from = -std::numeric_limits<double>::infinity();  ///< s, active from (included)
  double to = std::numeric_limits<double>::infinity();     ///< s, active until (excluded)
  double time = 0;                                         ///< s, impulses: when
  double stiffness = 0;                                    ///< N/m, spring
  double rest_length = 0;                                  ///< m, spring
  double damping = 0;    ///< N s/m, spring: on the rate of change of its length
  double linear = 0;     ///< N s/m (N per m/s), drag
  double quadratic = 0;  ///< N s^2/m^2 (N per (m/s)^2), drag
};

}  // namespace simreel
