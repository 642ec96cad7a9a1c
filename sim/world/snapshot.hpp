// Saving and restoring the whole world state, so that a resumed run equals a straight one bit for
// bit (Box2D's "snapshot equals real"). The file is binary, versioned and written field by field
// (never raw struct bytes): every number little-endian, doubles as their IEEE-754 bits.
//
// Layout (version 2; version 1, without the last line, still reads):
//   magic "SIMREEL-STATE\n", u32 version, u64 model fingerprint (body count, names and types,
//   shape count and kinds, dt: a state only restores into the world it came from),
//   i64 steps,
//   per body: q_WP (w x y z), x_W, v_W, w_P (13 doubles), wrench f_W, tau_W (6 doubles);
//   contact stats: i32 contacts_max, f64 max_penetration;
//   u32 contact count, per contact: i32 shape_a, shape_b, body_a, body_b, normal (3 f64), i32 count,
//   per point: u32 id, p_W (3), separation, normal_impulse; friction impulse (3), twist impulse,
//   rolling impulse (3); the narrow-phase cache: u8 type, i32 a, b; friction, restitution;
//   u32 force count, per force: u8 1 if it is an impulse already applied, else 0.
// Version 3 adds the impact settling substeps and each body's still time and island, then the
// mechanisms' coordinates, velocities, step proposals and modes; version 4 then u32 n and n times
// (i32 body, f64 s): the rolling bodies' proposed next internal step (sim/solver/rolling_contact.hpp);
// version 5 then u32 n and n times (i32 mechanism, f64 start, length and last read time in s, f64 x3
// gravity, f64 x (nq + nv) start state): the mechanisms' steps running past the frame
// (Mechanism::Span); version 6 then u32 n and n times (i32 mechanism, u8 carry, f64 rate in 1/s,
// f64 growth, f64 x3 gravity, i64 next measured frame, i32 frames between measurements,
// f64 x (nq + nv) power-iteration vector, f64 x nv carried acceleration): the Verlet mechanisms'
// state (Mechanism::Verlet).
// The fingerprint also covers the force list (kinds and bodies) when there is one.
#pragma once
#include <cstdint>
#include <iosfwd>

namespace simreel {

constexpr uint32_t kStateVersion = 6;

}  // namespace simreel
