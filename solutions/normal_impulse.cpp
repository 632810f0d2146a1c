// Worksheet 7, assignment 4: the normal impulse of resting contact, summed over the sweeps.
//
// Inputs:  point  the contact point as prepareContactPoint() left it: p (m, world frame), lever arms
//                 r_a, r_b (m), unit normal n (from a towards b), K_n (1/kg), target (m/s)
//          a, b   v, omega (and what applyImpulseAtPoint() reads)
//          sum    normal: lambda_n, the normal impulse this point has had in the earlier sweeps of
//                 this step (N s, >= 0; last step's when warm started)
// Outputs: with the relative velocity of the material points at p now and its normal part
//            u = v_b + omega_b x r_b - v_a - omega_a x r_a,   u_n = u . n   (m/s)
//          the sum becomes
//            lambda_n' = max(lambda_n + (target - u_n) / K_n, 0)
//          and the difference (lambda_n' - lambda_n) n goes to the bodies at p through
//          applyImpulseAtPoint(). The sum is clamped, not the step: a later sweep may take back what
//          an earlier one gave too much, but the contact never pulls. Where neither body can move
//          (K_n = 0) nothing happens.
#include <algorithm>

#include "gpl/friction.h"
#include "gpl/hooks.h"
#include "gpl/response.h"

namespace gpl {

void applyNormalImpulse([[maybe_unused]] const ContactPoint& point, [[maybe_unused]] Body& a, [[maybe_unused]] Body& b,
                        [[maybe_unused]] PointImpulse& sum) {
    // BEGIN SOLUTION
    if (!(point.Kn > 0.0)) return;
    const Vec3 u = b.velocity + b.angularVelocity.cross(point.rb) - a.velocity - a.angularVelocity.cross(point.ra);
    const double un = u.dot(point.n);                                                  // m/s
    const double lambda = std::max(sum.normal + (point.target - un) / point.Kn, 0.0);  // N s
    applyImpulseAtPoint(a, b, point.p, (lambda - sum.normal) * point.n);
    sum.normal = lambda;
    // ELSE STUB
    // kernelNotImplemented("applyNormalImpulse()");
    // END SOLUTION
}

}  // namespace gpl
