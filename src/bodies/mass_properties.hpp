// Volume, centre and inertia of the shapes a rigid body can have (private
// header): closed forms for box, sphere and cylinder, and exact integrals
// over a closed triangle mesh (signed tetrahedra from the origin, the
// divergence theorem; Mirtich 1996, "Fast and accurate computation of
// polyhedral mass properties"), plus the principal axes of an inertia tensor.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "pbf/core/vec3.hpp"
#include "pbf/geometry/pose.hpp"

namespace pbf::detail {

using Matrix3 = std::array<std::array<double, 3>, 3>;

// Per unit density: volume (m^3), centre of volume, and the inertia tensor
// about that centre (m^5; times the density it is kg m^2).
struct MassProperties {
    double volume = 0.0;
    std::array<double, 3> centre{};
    Matrix3 inertia{};
};

MassProperties boxMassProperties(const Vec3& halfExtents);
MassProperties sphereMassProperties(float radius);
// Capped cylinder along the y axis, centred at the origin.
MassProperties cylinderMassProperties(float radius, float height);
// A closed triangle mesh (either winding: the sign of the volume is fixed up).
MassProperties meshMassProperties(std::span<const Vec3> vertices,
                                  std::span<const std::array<std::uint32_t, 3>> triangles);

// inertia = R diag(moments) R^T: the rotation R (a right-handed frame of
// eigenvectors, by Jacobi rotations) and the principal moments.
void principalAxes(const Matrix3& inertia, Quat& rotation, Vec3& moments);

}  // namespace pbf::detail
