// What the framework's own contact solvers (soft_step.cpp, baumgarte.cpp) compute once per contact
// point and share: a tangent basis, effective masses, the point prepared for the sweeps, and the
// Coulomb cone that clamps a friction sum.
#pragma once

#include <cmath>
#include <cstddef>
#include <tuple>
#include <utility>

#include "gpl/body.h"
#include "gpl/contact.h"

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

/// A contact point prepared once per step, with its sums (started from last step's).
struct PreparedPoint {
    std::size_t a = 0, b = 0;  ///< the bodies' indices
    Vec3 ra, rb;               ///< lever arms from the centres of mass (m)
    Vec3 n, t1, t2;            ///< normal (from a towards b) and two tangents, an orthonormal basis
    double mn = 0.0, mt1 = 0.0, mt2 = 0.0;  ///< effective masses along n, t1, t2 (kg)
    double restitution = 0.0, staticFriction = 0.0, friction = 0.0;  ///< the pair's
    double normal = 0.0;                    ///< summed normal impulse (N s), >= 0
    double tangent1 = 0.0, tangent2 = 0.0;  ///< summed friction impulse along t1, t2 (N s)
};

/// Point k of the contact, prepared: invIa, invIb are worldInverseInertia() of its bodies a and b;
/// normal and tangent the sums to start from (N s; the tangent in the world frame).
inline PreparedPoint prepare(const Contact& con, int k, const Body& a, const Body& b, const Mat3& invIa,
                             const Mat3& invIb, double normal, const Vec3& tangent) {
    PreparedPoint p;
    p.a = con.a;
    p.b = con.b;
    p.ra = con.points[k] - a.position;
    p.rb = con.points[k] - b.position;
    p.n = con.normal;
    std::tie(p.t1, p.t2) = tangentBasis(p.n);
    p.mn = effectiveMass(a, b, invIa, invIb, p.ra, p.rb, p.n);
    p.mt1 = effectiveMass(a, b, invIa, invIb, p.ra, p.rb, p.t1);
    p.mt2 = effectiveMass(a, b, invIa, invIb, p.ra, p.rb, p.t2);
    p.restitution = con.restitution;
    p.staticFriction = con.staticFriction;
    p.friction = con.friction;
    p.normal = normal;
    p.tangent1 = tangent.dot(p.t1);
    p.tangent2 = tangent.dot(p.t2);
    return p;
}

/// Coulomb's cone for a friction sum (f1, f2) along the tangents: it sticks while its length is at
/// most mu_s times the normal sum; beyond, it slides, and the sum becomes mu_d times the normal sum
/// in the same direction.
inline void clampToCone(double& f1, double& f2, double normal, double staticFriction, double friction) {
    const double length = std::hypot(f1, f2);
    if (length <= staticFriction * normal) return;
    const double scale = length > 0.0 ? friction * normal / length : 0.0;
    f1 *= scale;
    f2 *= scale;
}

}  // namespace gpl
