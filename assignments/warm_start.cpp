// Worksheet 7, assignment 3: warm starting, last step's impulses applied again.
//
// Inputs:  contact   normal n (unit, from a towards b), points p_k (m, world frame)
//          point     k: which of contact.points
//          a, b      x, v, omega, invMass (and what applyImpulseAtPoint() reads)
//          sum       what the sweeps of last step summed up at this point: normal j_n (N s, >= 0) and
//                    tangent J_t (N s, world frame, perpendicular to n); the framework found it by the
//                    pair of bodies and the nearest point of last step
// Outputs: a and b after the impulse j_n n + J_t at p through applyImpulseAtPoint(): J on b, -J on
//          a, as every impulse of the sweeps. A box at rest then starts the sweeps with the impulse
//          that held it last step, and a few sweeps suffice to correct it.
#include "gpl/friction.h"
#include "gpl/hooks.h"
#include "gpl/response.h"

namespace gpl {

void applyWarmStart([[maybe_unused]] const Contact& contact, [[maybe_unused]] int point, [[maybe_unused]] Body& a,
                    [[maybe_unused]] Body& b, [[maybe_unused]] const PointImpulse& sum) {
    kernelNotImplemented("applyWarmStart()");
}

}  // namespace gpl
