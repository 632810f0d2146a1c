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
    // BEGIN SOLUTION
    // No normal impulse and no friction sum: the cone is a point and the sum stays zero.
    if (sum.normal == 0.0 && sum.tangent.isZero(0.0)) return;
    const Vec3& n = contact.normal;
    const Vec3& p = contact.points[point];
    const Vec3 ra = p - a.position, rb = p - b.position;  // m
    const Vec3 u = b.velocity + b.angularVelocity.cross(rb) - (a.velocity + a.angularVelocity.cross(ra));
    const Vec3 slip = u - n.dot(u) * n;  // u_t (m/s)
    const double slip2 = slip.squaredNorm();  // |u_t|^2
    Vec3 total = sum.tangent;  // N s
    if (slip2 > 0.0) {
        // w_t is a quadratic form in t, so w_t |u_t|^2 is the same form in u_t: the impulse
        // -(|u_t| / w_t) t = -(|u_t|^2 / (w_t |u_t|^2)) u_t needs neither t nor a square root.
        // Its angular terms as (r x u_t) . I^-1 (r x u_t), which is u_t . ((I^-1 (r x u_t)) x r).
        const Vec3 raSlip = ra.cross(slip), rbSlip = rb.cross(slip);
        const double spin = rbSlip.dot(invIb * rbSlip) + raSlip.dot(invIa * raSlip);
        const double wSlip2 = (b.invMass + a.invMass) * slip2 + spin;  // w_t |u_t|^2 (m^2/(s^2 kg))
        if (wSlip2 > 0.0) total -= (slip2 / wSlip2) * slip;
    }
    // Sticks while |J| <= mu_s j_n, compared squared: a point that sticks takes no square root.
    const double limit = contact.staticFriction * sum.normal;
    if (total.squaredNorm() > limit * limit) total *= contact.friction * sum.normal / total.norm();  // slides
    applyImpulseAtPoint(a, b, p, total - sum.tangent);
    sum.tangent = total;
    // ELSE STUB
    // kernelNotImplemented("applyFrictionImpulse()");
    // END SOLUTION
}

}  // namespace gpl
