// Worksheet 7, assignment 4: the normal impulse of resting contact, summed over the sweeps.
//
// Inputs:  point  the contact point as prepareContactPoint() left it: its normal axis n (unit direction
//                 n.d from a towards b, n.raXd = r_a x n, n.rbXd = r_b x n, n.invIaRaXd = I_a^-1 (r_a x n),
//                 n.invIbRbXd = I_b^-1 (r_b x n), n.K = K_n (1/kg)) and target (m/s)
//          a, b   v, omega, invMass
//          sum    normal: lambda_n, the normal impulse this point has had in the earlier sweeps of
//                 this step (N s, >= 0; last step's when warm started)
// Outputs: with the normal velocity of the two material points at p now
//            u_n = (v_b + omega_b x r_b - v_a - omega_a x r_a) . n
//                = n . (v_b - v_a) + (r_b x n) . omega_b - (r_a x n) . omega_a   (m/s)
//          the sum becomes
//            lambda_n' = max(lambda_n + (target - u_n) / K_n, 0)
//          and the difference dl = lambda_n' - lambda_n acts along n at p: on b
//            v_b += dl n / m_b     omega_b += dl I_b^-1 (r_b x n)
//          and its opposite on a. The sum is clamped, not the step: a later sweep may take back what
//          an earlier one gave too much, but the contact never pulls. Where neither body can move
//          (K_n = 0) nothing happens.
#include <algorithm>

#include "gpl/friction.h"
#include "gpl/hooks.h"
#include "gpl/response.h"

namespace gpl {

void applyNormalImpulse([[maybe_unused]] const ContactPoint& point, [[maybe_unused]] Body& a, [[maybe_unused]] Body& b,
                        [[maybe_unused]] PointImpulse& sum) {
    kernelNotImplemented("applyNormalImpulse()");
}

}  // namespace gpl
