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
//            p = p_k,  r_a = p - x_a,  r_b = p - x_b,  n,
//            t1, t2 = tangentBasis(n): unit tangents, with n an orthonormal basis,
//            K_n = K(n), K_t1 = K(t1), K_t2 = K(t2) with the inverse effective mass along a unit d
//              K(d) = 1/m_a + 1/m_b + (r_a x d) . I_a^-1 (r_a x d) + (r_b x d) . I_b^-1 (r_b x d)   (1/kg),
//            target = -e approach  when approach < -kRestingSpeed (a collision bounces),
//                     0            otherwise (a resting contact does not),
//            mu_s and mu_d of the contact.
//          K(d) is a sum of a mass and two quadratic forms of inverse inertias: never negative (asserted).
#include <cassert>
#include <tuple>

#include "gpl/contact_point.h"
#include "gpl/friction.h"
#include "gpl/hooks.h"

namespace gpl {

ContactPoint prepareContactPoint([[maybe_unused]] const Contact& contact, [[maybe_unused]] int k,
                                 [[maybe_unused]] const Body& a, [[maybe_unused]] const Body& b,
                                 [[maybe_unused]] const Mat3& invIa, [[maybe_unused]] const Mat3& invIb,
                                 [[maybe_unused]] double approach) {
    // BEGIN SOLUTION
    ContactPoint point;
    point.p = contact.points[k];
    point.ra = point.p - a.position;
    point.rb = point.p - b.position;
    point.n = contact.normal;
    std::tie(point.t1, point.t2) = tangentBasis(point.n);
    const auto K = [&](const Vec3& d) {  // 1/kg
        const Vec3 rad = point.ra.cross(d), rbd = point.rb.cross(d);
        return a.invMass + b.invMass + rad.dot(invIa * rad) + rbd.dot(invIb * rbd);
    };
    point.Kn = K(point.n);
    point.Kt1 = K(point.t1);
    point.Kt2 = K(point.t2);
    assert(point.Kn >= 0.0 && point.Kt1 >= 0.0 && point.Kt2 >= 0.0);
    point.target = approach < -kRestingSpeed ? -contact.restitution * approach : 0.0;  // m/s
    point.staticFriction = contact.staticFriction;
    point.friction = contact.friction;
    return point;
    // ELSE STUB
    // kernelNotImplemented("prepareContactPoint()");
    // return {};
    // END SOLUTION
}

}  // namespace gpl
