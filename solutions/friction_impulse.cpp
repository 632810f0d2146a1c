// Worksheet 7, assignment 5: the Coulomb friction impulse, summed over the sweeps.
//
// Inputs:  point  the contact point as prepareContactPoint() left it: p (m, world frame), lever arms
//                 r_a, r_b (m), unit tangents t1, t2 (with n an orthonormal basis), K_t1, K_t2 (1/kg),
//                 staticFriction mu_s, friction mu_d (sliding, mu_d <= mu_s)
//          a, b   v, omega (and what applyImpulseAtPoint() reads)
//          sum    normal: lambda_n, this point's normal sum as the normal impulse just left it (N s,
//                 >= 0); tangent: its friction sum J_t so far (N s, world frame, perpendicular to n)
// Outputs: with the relative velocity of the material points at p
//            u = v_b + omega_b x r_b - v_a - omega_a x r_a   (m/s)
//          and its slip along each tangent, u . t1 and u . t2, the candidate sum stops the slip along
//          each tangent:
//            J = J_t - (u . t1 / K_t1) t1 - (u . t2 / K_t2) t2   (N s).
//          Coulomb: the point sticks while |J| <= mu_s lambda_n (the sum becomes J); otherwise it
//          slides and the sum becomes mu_d lambda_n J / |J|. The difference (new sum - old sum) goes
//          to the bodies at p through applyImpulseAtPoint(). With no normal sum and no friction sum
//          the cone is a point: the sum stays zero.
#include <cassert>

#include "gpl/friction.h"
#include "gpl/hooks.h"
#include "gpl/response.h"

namespace gpl {

void applyFrictionImpulse([[maybe_unused]] const ContactPoint& point, [[maybe_unused]] Body& a,
                          [[maybe_unused]] Body& b, [[maybe_unused]] PointImpulse& sum) {
    // BEGIN SOLUTION
    if (sum.normal == 0.0 && sum.tangent.isZero(0.0)) return;
    assert(point.Kt1 > 0.0 && point.Kt2 > 0.0);  // a point with a normal sum has a body that can move
    const Vec3 u = b.velocity + b.angularVelocity.cross(point.rb) - a.velocity - a.angularVelocity.cross(point.ra);
    Vec3 J = sum.tangent - (u.dot(point.t1) / point.Kt1) * point.t1 - (u.dot(point.t2) / point.Kt2) * point.t2;
    const double size = J.norm();                                                           // N s
    if (size > point.staticFriction * sum.normal) J *= point.friction * sum.normal / size;  // slides
    applyImpulseAtPoint(a, b, point.p, J - sum.tangent);
    sum.tangent = J;
    // ELSE STUB
    // kernelNotImplemented("applyFrictionImpulse()");
    // END SOLUTION
}

}  // namespace gpl
