// The contact solver's fixed constants (the settings users choose are ContactSettings in
// include/simreel/settings.hpp; docs/contacts.md explains each and why its default was chosen).
#pragma once
#include <simreel/settings.hpp>

namespace simreel {

// Automatic substeps (substeps: 0): at least kContactSubstepRate substeps per second, and more
// while a body in contact turns faster than kContactMaxSubstepAngle per substep, up to
// kContactMaxSubsteps a step.
constexpr double kContactSubstepRate = 960;       ///< 1/s: 4 substeps of the default 1/240 s step
constexpr double kContactMaxSubstepAngle = 0.05;  ///< rad
constexpr int kContactMaxSubsteps = 16;

// Impacts: a substep in which a point that was apart at its start is struck at more than
// kImpactSpeed gets one more solve sweep, and the substeps of the next kImpactSettleTime one more
// solve and relax sweep each (docs/contacts.md "Impacts"). Gauss-Seidel moves an impulse one contact
// per sweep: with one sweep, the R3 pile's top layers landing (5 m/s) pushed the layers below
// 2.9 mm into each other; with these, 0.91 mm, for 25 struck substeps in its 10 s (1/60 s of
// settling: 1.03 mm; two more sweeps instead of one: no better).
constexpr double kImpactSpeed = 0.5;              ///< m/s, normal approach speed
constexpr double kImpactSettleTime = 1.0 / 30.0;  ///< s

}  // namespace simreel
