// Position-based constraints as pure kernels: positions and inverse masses in, corrected positions
// out (the Verlet sandbox way: move the particles, and the velocity follows). Inverse masses
// share each correction; a static body (inverse mass 0) never moves.
#pragma once

#include <cstddef>

#include "gpl/math.h"

namespace gpl {

/// Two bodies held at a fixed distance: a pendulum rod, a chain link.
struct DistanceConstraint {
    std::size_t a = 0;    ///< index of the first body
    std::size_t b = 0;    ///< index of the second body
    double length = 0.0;  ///< m, > 0
};

/// A spherical container that keeps every movable sphere inside (a circle when the spheres all
/// lie in one plane through its centre).
struct Container {
    Vec3 centre = Vec3::Zero();  ///< m
    double radius = 0.0;         ///< m, > 0
};

/// Moves xa and xb along the line between them so that their distance becomes `length`; wa and
/// wb are the inverse masses (1/kg). Does nothing when both are static or the points coincide.
void projectDistance(Vec3& xa, Vec3& xb, double wa, double wb, double length);

/// Moves a sphere of radius r (m) at x back inside the container so that it touches the wall
/// from inside; a sphere inside already stays where it is.
void keepInside(Vec3& x, double r, const Container& container);

/// Pushes two overlapping spheres apart along the line of centres until they touch, shared by
/// inverse mass; spheres that do not overlap (or coincide exactly) stay where they are.
void separateSpheres(Vec3& xa, Vec3& xb, double ra, double rb, double wa, double wb);

}  // namespace gpl
