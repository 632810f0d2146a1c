// Worksheet 7, assignment 2: the Coulomb friction impulse, summed over the sweeps.
//
// Inputs:  contact   normal n (unit, from a towards b), staticFriction mu_s, friction mu_d (sliding,
//                    mu_d <= mu_s), points p_k (m, world frame)
//          point     k: which of contact.points
//          invIa, invIb  worldInverseInertia() of a and b (1/(kg m^2), world frame), computed once per step
//          a, b      x, v, omega, invMass (and what applyImpulseAtPoint() reads)
//          sum       normal: this point's accumulated normal impulse j_n (N s, >= 0); tangent: its
//                    accumulated friction impulse J_t so far (N s, world frame, perpendicular to n)
// Outputs: with r_a = p - x_a, r_b = p - x_b and the relative velocity of the material points at p,
//            u = v_b + omega_b x r_b - v_a - omega_a x r_a,   its tangential part u_t = u - (u . n) n,
//          the tangent t = u_t / |u_t| and the inverse effective mass along it
//            w_t = 1/m_a + 1/m_b + t . ((I_a^-1 (r_a x t)) x r_a + (I_b^-1 (r_b x t)) x r_b),
//          the impulse that stops the sliding is -(|u_t| / w_t) t; added to the sum it gives J.
//          Coulomb: the point sticks while |J| <= mu_s j_n (the sum becomes J); otherwise it slides
//          and the sum becomes mu_d j_n J / |J| (against the sliding). The difference (new sum - old
//          sum) goes to the bodies at p through applyImpulseAtPoint(). A point that does not slide
//          (u_t = 0) keeps its sum, clamped likewise.
#include <cmath>

#include "gpl/friction.h"
#include "gpl/hooks.h"
#include "gpl/response.h"

namespace gpl {

void applyFrictionImpulse([[maybe_unused]] const Contact& contact, [[maybe_unused]] int point,
                          [[maybe_unused]] const Mat3& invIa, [[maybe_unused]] const Mat3& invIb,
                          [[maybe_unused]] Body& a, [[maybe_unused]] Body& b, [[maybe_unused]] PointImpulse& sum) {
    kernelNotImplemented("applyFrictionImpulse()");
}

}  // namespace gpl
