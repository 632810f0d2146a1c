// Worksheet 6, assignment 3: an impulse that acts at a point.
//
// Inputs:  a, b      position x (m, centre of mass), velocity v (m/s), angularVelocity omega (rad/s,
//                    world frame), invMass (1/kg) and what worldInverseInertia() reads (orientation,
//                    invInertia); a static body has invMass 0 and a zero inverse inertia
//          point     p (m, world frame): where the impulse acts
//          impulse   J (N s, world frame): J acts on b, -J on a
// Outputs: with r_b = p - x_b and r_a = p - x_a (m),
//            v_b += J / m_b     omega_b += I_b,world^-1 (r_b x J)
//            v_a -= J / m_a     omega_a -= I_a,world^-1 (r_a x J)
//          Momentum and angular momentum (about any fixed point) of the pair stay as they were.
#include "gpl/hooks.h"
#include "gpl/response.h"
#include "gpl/rotation.h"

namespace gpl {

void applyImpulseAtPoint([[maybe_unused]] Body& a, [[maybe_unused]] Body& b, [[maybe_unused]] const Vec3& point,
                         [[maybe_unused]] const Vec3& impulse) {
    // BEGIN SOLUTION
    // Eq. (4). A static body has w = 0 and a zero inverse inertia: it does not change.
    const Vec3 ra = point - a.position, rb = point - b.position;  // m
    a.velocity -= a.invMass * impulse;
    a.angularVelocity -= worldInverseInertia(a) * ra.cross(impulse);
    b.velocity += b.invMass * impulse;
    b.angularVelocity += worldInverseInertia(b) * rb.cross(impulse);
    // ELSE STUB
    // kernelNotImplemented("applyImpulseAtPoint()");
    // END SOLUTION
}

}  // namespace gpl
