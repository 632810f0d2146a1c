// Worksheet 7, assignment 5: the Coulomb friction impulse, summed over the sweeps.
//
// Inputs:  point  the contact point as prepareContactPoint() left it: its tangent axes t1 and t2 (unit
//                 directions t1.d, t2.d, with n an orthonormal basis; for each t: t.raXd = r_a x t,
//                 t.rbXd = r_b x t, t.invIaRaXd = I_a^-1 (r_a x t), t.invIbRbXd = I_b^-1 (r_b x t),
//                 t.K = K(t) (1/kg)), staticFriction mu_s, friction mu_d (sliding, mu_d <= mu_s)
//          a, b   v, omega, invMass
//          sum    normal: lambda_n, this point's normal sum as the normal impulse just left it (N s,
//                 >= 0); tangent: its friction sum J_t so far (N s, world frame, perpendicular to n)
// Outputs: with the slip of the two material points at p along each tangent t,
//            u . t = t . (v_b - v_a) + (r_b x t) . omega_b - (r_a x t) . omega_a   (m/s),
//          the candidate sum stops the slip along each tangent:
//            J = J_t - (u . t1 / K_t1) t1 - (u . t2 / K_t2) t2   (N s).
//          Coulomb: the point sticks while |J| <= mu_s lambda_n (the sum becomes J); otherwise it
//          slides and the sum becomes mu_d lambda_n J / |J|. The difference, new sum - old sum
//          = dl_1 t1 + dl_2 t2, acts at p: on b
//            v_b += (dl_1 t1 + dl_2 t2) / m_b     omega_b += dl_1 I_b^-1 (r_b x t1) + dl_2 I_b^-1 (r_b x t2)
//          and its opposite on a. With no normal sum and no friction sum the cone is a point: the sum
//          stays zero.
#include <cassert>

#include "gpl/friction.h"
#include "gpl/hooks.h"
#include "gpl/response.h"

namespace gpl {

void applyFrictionImpulse([[maybe_unused]] const ContactPoint& point, [[maybe_unused]] Body& a,
                          [[maybe_unused]] Body& b, [[maybe_unused]] PointImpulse& sum) {
    // BEGIN SOLUTION
    const ContactAxis& t1 = point.t1;
    const ContactAxis& t2 = point.t2;
    assert(t1.K > 0.0 && t2.K > 0.0);  // a contact has a body that can move
    const Vec3 dv = b.velocity - a.velocity;
    const double ut1 = t1.d.dot(dv) + t1.rbXd.dot(b.angularVelocity) - t1.raXd.dot(a.angularVelocity);  // u . t1
    const double ut2 = t2.d.dot(dv) + t2.rbXd.dot(b.angularVelocity) - t2.raXd.dot(a.angularVelocity);  // u . t2
    Vec3 J = sum.tangent - (ut1 / t1.K) * t1.d - (ut2 / t2.K) * t2.d;
    const double size = J.norm();                                                           // N s
    if (size > point.staticFriction * sum.normal) J *= point.friction * sum.normal / size;  // slides
    const Vec3 step = J - sum.tangent;
    const double dl1 = step.dot(t1.d), dl2 = step.dot(t2.d);  // N s
    a.velocity -= a.invMass * step;
    a.angularVelocity -= dl1 * t1.invIaRaXd + dl2 * t2.invIaRaXd;
    b.velocity += b.invMass * step;
    b.angularVelocity += dl1 * t1.invIbRbXd + dl2 * t2.invIbRbXd;
    sum.tangent = J;
    // ELSE STUB
    // kernelNotImplemented("applyFrictionImpulse()");
    // END SOLUTION
}

}  // namespace gpl
