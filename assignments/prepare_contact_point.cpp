// Worksheet 7, assignment 2: a contact point prepared once per step for the sweeps.
//
// Inputs:  contact   normal n (unit, from a towards b), restitution e (0..1), staticFriction mu_s,
//                    friction mu_d (mu_d <= mu_s), points p_k (m, world frame)
//          k         which of contact.points
//          a, b      x (m), invMass (1/kg)
//          invIa, invIb  worldInverseInertia() of a and b (1/(kg m^2), world frame), computed once per step
//          approach  the normal velocity of the two material points at p when the stage began, before
//                    any impulse of this step (m/s; < 0 approaching)
// Outputs: the ContactPoint the sweeps read while the velocities change and the positions do not:
//            p = p_k,  r_a = p - x_a,  r_b = p - x_b,
//            three axes: n along the normal, t1 and t2 along the unit tangents tangentBasis(n) (with
//            n an orthonormal basis), each for its unit direction d:
//              d,  r_a x d,  r_b x d,  I_a^-1 (r_a x d),  I_b^-1 (r_b x d)  and the inverse effective mass
//              K(d) = 1/m_a + 1/m_b + (r_a x d) . I_a^-1 (r_a x d) + (r_b x d) . I_b^-1 (r_b x d)   (1/kg),
//            target = -e approach  when approach < -kRestingSpeed (a collision bounces),
//                     0            otherwise (a resting contact does not),
//            mu_s and mu_d of the contact.
//          K(d) is a sum of a mass and two quadratic forms of inverse inertias: never negative (asserted).
#include <cassert>

#include "gpl/contact_point.h"
#include "gpl/friction.h"
#include "gpl/hooks.h"

namespace gpl {

ContactPoint prepareContactPoint([[maybe_unused]] const Contact& contact, [[maybe_unused]] int k,
                                 [[maybe_unused]] const Body& a, [[maybe_unused]] const Body& b,
                                 [[maybe_unused]] const Mat3& invIa, [[maybe_unused]] const Mat3& invIb,
                                 [[maybe_unused]] double approach) {
    kernelNotImplemented("prepareContactPoint()");
    return {};
}

}  // namespace gpl
