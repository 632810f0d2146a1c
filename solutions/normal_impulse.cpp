// Worksheet 7, assignment 1: the normal impulse of resting contact, summed over the sweeps.
//
// Inputs:  contact   normal n (unit, from a towards b), restitution e (0..1), points p_k (m, world frame)
//          point     k: which of contact.points
//          invIa, invIb  worldInverseInertia() of a and b (1/(kg m^2), world frame), computed once per step
//          a, b      x, v, omega, invMass (and what applyImpulseAtPoint() reads)
//          sum       normal: the normal impulse this point has had in the earlier sweeps of this step
//                    (N s, >= 0, last step's when warm started); approach: the normal velocity at the
//                    point when the stage began (m/s; < 0 approaching)
// Outputs: with r_a = p - x_a, r_b = p - x_b, the normal velocity there now
//            v_n = (v_b + omega_b x r_b - v_a - omega_a x r_a) . n
//          and the velocity the point should leave with
//            v_target = -e approach   when approach < -kRestingSpeed (a collision bounces)
//            v_target = 0             otherwise (a resting contact does not)
//          the sum becomes max(sum.normal + (v_target - v_n) / w_n, 0) with the inverse effective mass
//            w_n = 1/m_a + 1/m_b + n . ((I_a^-1 (r_a x n)) x r_a + (I_b^-1 (r_b x n)) x r_b)
//          and the difference (new sum - old sum) n goes to the bodies at p through applyImpulseAtPoint().
//          The sum is clamped, not the step: a later sweep may take back what an earlier one gave too
//          much, but the contact never pulls. Two static bodies get nothing.
#include <algorithm>

#include "gpl/friction.h"
#include "gpl/hooks.h"
#include "gpl/response.h"

namespace gpl {

void applyNormalImpulse([[maybe_unused]] const Contact& contact, [[maybe_unused]] int point,
                        [[maybe_unused]] const Mat3& invIa, [[maybe_unused]] const Mat3& invIb,
                        [[maybe_unused]] Body& a, [[maybe_unused]] Body& b, [[maybe_unused]] PointImpulse& sum) {
    // BEGIN SOLUTION
    const Vec3& n = contact.normal;
    const Vec3& p = contact.points[point];
    const Vec3 ra = p - a.position, rb = p - b.position;  // m
    const Vec3 moving = b.velocity + b.angularVelocity.cross(rb) - (a.velocity + a.angularVelocity.cross(ra));
    const double vn = n.dot(moving);  // m/s
    // 1 / effective mass along n at p (1/kg); its angular terms as (r x n) . I^-1 (r x n), which is
    // n . ((I^-1 (r x n)) x r) (a scalar triple product read the other way).
    const Vec3 ran = ra.cross(n), rbn = rb.cross(n);
    const double spin = rbn.dot(invIb * rbn) + ran.dot(invIa * ran);
    const double wn = b.invMass + a.invMass + spin;
    if (!(wn > 0.0)) return;
    const double target = sum.approach < -kRestingSpeed ? -contact.restitution * sum.approach : 0.0;
    const double total = std::max(0.0, sum.normal + (target - vn) / wn);  // N s, the clamped sum
    applyImpulseAtPoint(a, b, p, (total - sum.normal) * n);
    sum.normal = total;
    // ELSE STUB
    // kernelNotImplemented("applyNormalImpulse()");
    // END SOLUTION
}

}  // namespace gpl
