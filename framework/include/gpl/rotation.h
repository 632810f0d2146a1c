// Rotation (worksheet 6): pure kernels for the orientation and angular velocity of rigid bodies,
// and what the framework measures of them.
//
// Student hooks (bodies in assignments/, reference bodies in solutions/):
//   worldInverseInertia()  the inverse inertia tensor in the world frame, R I^-1 R^T
//   integrateRotation()    one time step of orientation and angular velocity
// (The impulses of turning bodies, applyImpulseAtPoint() and applyContactImpulse(), are in
// gpl/response.h.)
// Framework:
//   velocityAt(), normalVelocityAt()  how fast a material point of a body moves
//   angularMomentum()                 of a body about the origin
#pragma once

#include "gpl/body.h"
#include "gpl/contact.h"

namespace gpl {

/// Student hook (worksheet 6), solutions/world_inverse_inertia.cpp.
Mat3 worldInverseInertia(const Body& body);
/// Student hook (worksheet 6), solutions/integrate_rotation.cpp.
void integrateRotation(Body& body, double h);

/// Velocity (m/s, world frame) of the body's material point that is at `point` (m, world frame)
/// now: v + omega x (point - x).
inline Vec3 velocityAt(const Body& body, const Vec3& point) {
    return body.velocity + body.angularVelocity.cross(point - body.position);
}

/// Speed (m/s) at which the material points of a and b at `point` approach each other along the
/// contact's normal: (v_b(p) - v_a(p)) . n; negative while they approach.
inline double normalVelocityAt(const Contact& contact, const Body& a, const Body& b, const Vec3& point) {
    return (velocityAt(b, point) - velocityAt(a, point)).dot(contact.normal);
}

/// Angular momentum of the body about the origin (kg m^2/s): x × m v + R I R^T omega; zero for a
/// static body.
Vec3 angularMomentum(const Body& body);

}  // namespace gpl
