// Closed-form mass properties of primitive solids, centred at their frame origin. Axis-symmetric
// shapes have their axis along z. Inertia formulas: any mechanics table, e.g. Goldstein 3rd ed.,
// or Wikipedia "List of moments of inertia"; capsule: the cylinder plus two hemispheres, each
// hemisphere's centroid 3r/8 from its flat face, shifted by the parallel axis theorem.
#pragma once
#include <simreel/mass_properties.hpp>

namespace simreel {

double box_volume(const Vec3& size);                   ///< m^3; size = full extents (m)
double sphere_volume(double radius);                   ///< m^3
double cylinder_volume(double radius, double height);  ///< m^3
double ellipsoid_volume(const Vec3& radii);            ///< m^3; semi-axes

MassProperties box_mass(const Vec3& size, double density);
MassProperties sphere_mass(double radius, double density);
MassProperties cylinder_mass(double radius, double height, double density);
MassProperties capsule_mass(double radius, double height, double density);
MassProperties ellipsoid_mass(const Vec3& radii, double density);

}  // namespace simreel
