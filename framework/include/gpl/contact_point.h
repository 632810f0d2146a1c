// What the framework's own contact solvers (soft_step.cpp, baumgarte.cpp) compute once per contact
// point: a tangent basis and the effective mass of a pair of bodies along a direction.
#pragma once

#include <cmath>
#include <utility>

#include "gpl/body.h"

namespace gpl {

/// A unit vector t1 perpendicular to the unit normal n, and t2 = n x t1: with n an orthonormal basis.
inline std::pair<Vec3, Vec3> tangentBasis(const Vec3& n) {
    const Vec3 t1 = (std::abs(n.x()) < 0.57 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
    return {t1, n.cross(t1)};
}

/// The effective mass (kg) of bodies a and b at lever arms ra, rb along the unit direction d:
/// 1 / (1/m_a + 1/m_b + (ra x d) . Ia^-1 (ra x d) + (rb x d) . Ib^-1 (rb x d)); 0 when neither body
/// can move that way.
inline double effectiveMass(const Body& a, const Body& b, const Mat3& invIa, const Mat3& invIb, const Vec3& ra,
                            const Vec3& rb, const Vec3& d) {
    const Vec3 rad = ra.cross(d), rbd = rb.cross(d);
    const double w = a.invMass + b.invMass + rad.dot(invIa * rad) + rbd.dot(invIb * rbd);
    return w > 0.0 ? 1.0 / w : 0.0;
}

}  // namespace gpl
