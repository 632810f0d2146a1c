// Worksheet 6, assignment 4: the collision impulse of turning bodies.
//
// Inputs:  contact   normal n (unit, from a towards b), restitution e (0..1), points p_k (m, world
//                    frame), pointCount (1..4)
//          a, b      as for applyImpulseAtPoint(): x, v, omega, invMass, orientation, invInertia
// Outputs: a and b after an impulse at each point in turn: with r_a = p - x_a, r_b = p - x_b and the
//          normal velocity of the two material points there,
//            v_rel = (v_b + omega_b x r_b - v_a - omega_a x r_a) . n    (m/s; < 0 approaching)
//          a point that approaches gets j n at p through applyImpulseAtPoint(), with
//            j = -(1 + e) v_rel / (1/m_a + 1/m_b + n . ((I_a^-1 (r_a x n)) x r_a + (I_b^-1 (r_b x n)) x r_b))
//          (I^-1 in the world frame), so that v_rel at that point becomes -e v_rel. A point that
//          separates (v_rel >= 0) gets nothing; two static bodies get nothing.
#include "gpl/hooks.h"
#include "gpl/response.h"
#include "gpl/rotation.h"

namespace gpl {

void applyContactImpulse([[maybe_unused]] const Contact& contact, [[maybe_unused]] Body& a, [[maybe_unused]] Body& b) {
    // BEGIN SOLUTION
    const Vec3& n = contact.normal;
    const Mat3 invIa = worldInverseInertia(a), invIb = worldInverseInertia(b);
    for (int k = 0; k < contact.pointCount; ++k) {
        const Vec3& p = contact.points[k];
        const Vec3 ra = p - a.position, rb = p - b.position;  // m
        const Vec3 relative = b.velocity + b.angularVelocity.cross(rb) - a.velocity - a.angularVelocity.cross(ra);
        const double vn = relative.dot(n);  // v_n (m/s)
        if (vn >= 0.0) continue;
        // K of (5), 1 / effective mass along n at p (1/kg): the speed j = 1 N s along n there gives the pair.
        const Vec3 turning = (invIa * ra.cross(n)).cross(ra) + (invIb * rb.cross(n)).cross(rb);
        const double K = a.invMass + b.invMass + n.dot(turning);
        if (K <= 0.0) return;
        // The normal impulse of this point (N s). Worksheet 7 keeps one sum per point over the sweeps,
        // clamped at 0 so that the contact never pulls, and adds friction here, through
        // applyImpulseAtPoint() with an impulse along the tangent.
        const double j = -(1.0 + contact.restitution) * vn / K;
        applyImpulseAtPoint(a, b, p, j * n);
    }
    // ELSE STUB
    // kernelNotImplemented("applyContactImpulse()");
    // END SOLUTION
}

}  // namespace gpl
