// simreel's dynamics core in one include: math and frame conventions, errors, mass properties and
// meshes, bodies and colliders, settings, applied forces, contacts, the profile, the world.
// Build with find_package(simreel) and target_link_libraries(app simreel::sim); examples/ shows
// two programs (a mesh body under thrust; boxes resting on the ground with their contact forces).
#pragma once
#include <simreel/body.hpp>
#include <simreel/contacts.hpp>
#include <simreel/error.hpp>
#include <simreel/forces.hpp>
#include <simreel/joints.hpp>
#include <simreel/mass_properties.hpp>
#include <simreel/math.hpp>
#include <simreel/mesh.hpp>
#include <simreel/profile.hpp>
#include <simreel/settings.hpp>
#include <simreel/world.hpp>
