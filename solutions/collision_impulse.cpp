// Worksheet 4, assignment 2: the linear collision impulse with restitution.
//
// Inputs:  contact      normal n (unit, from a towards b) and restitution e (0..1: the pair's
//                       coefficient, combined by the framework with combineRestitution())
//          a, b         velocity (m/s) and invMass (1/kg; 0 for a static body)
// Outputs: a.velocity and b.velocity after an impulse j n on b and -j n on a (j in N s) such that
//          the relative velocity along the normal, v_rel = (v_b - v_a) . n, becomes -e times what
//          it was. Nothing changes when the bodies already separate (v_rel >= 0) or both are static.
//          Tangential velocities stay as they are (no friction yet: worksheet 7).
#include "gpl/hooks.h"
#include "gpl/response.h"

namespace gpl {

void applyCollisionImpulse([[maybe_unused]] const Contact& contact, [[maybe_unused]] Body& a,
                           [[maybe_unused]] Body& b) {
    // BEGIN SOLUTION
    const double w = a.invMass + b.invMass;
    const double vn = (b.velocity - a.velocity).dot(contact.normal);  // v_n (m/s)
    if (w == 0.0 || vn >= 0.0) return;
    const double j = -(1.0 + contact.restitution) * vn / w;  // N s
    a.velocity -= (j * a.invMass) * contact.normal;
    b.velocity += (j * b.invMass) * contact.normal;
    // ELSE STUB
    // kernelNotImplemented("applyCollisionImpulse()");
    // END SOLUTION
}

}  // namespace gpl
