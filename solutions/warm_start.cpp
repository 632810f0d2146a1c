// Worksheet 7, assignment 3: warm starting, last step's impulses applied again.
//
// Inputs:  point  the contact point as prepareContactPoint() left it: p (m, world frame), the unit
//                 normal n = n.d (from a towards b)
//          a, b   what applyImpulseAtPoint() reads and changes: x, v, omega, invMass, orientation, invInertia
//          sum    what the sweeps of last step summed up at this point: normal lambda_n (N s, >= 0)
//                 and tangent J_t (N s, world frame, perpendicular to n); the framework found it by the
//                 pair of bodies and the nearest point of last step
// Outputs: a and b after the impulse lambda_n n + J_t at p through applyImpulseAtPoint(): J on b, -J
//          on a, as every impulse of the sweeps. A box at rest then starts the sweeps with the
//          impulse that held it last step, and a few sweeps suffice to correct it.
#include "gpl/friction.h"
#include "gpl/hooks.h"
#include "gpl/response.h"

namespace gpl {

void applyWarmStart([[maybe_unused]] const ContactPoint& point, [[maybe_unused]] Body& a, [[maybe_unused]] Body& b,
                    [[maybe_unused]] const PointImpulse& sum) {
    // BEGIN SOLUTION
    applyImpulseAtPoint(a, b, point.p, sum.normal * point.n.d + sum.tangent);
    // ELSE STUB
    // kernelNotImplemented("applyWarmStart()");
    // END SOLUTION
}

}  // namespace gpl
