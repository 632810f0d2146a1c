// Collision response: pure kernels that answer a contact by moving the two bodies apart or by
// changing their velocities.
//
// Student hooks (bodies in assignments/, reference bodies in solutions/):
//   resolveInterpenetration()  worksheet 3: positions apart, shared by mass
//   applyCollisionImpulse()    worksheet 4: the linear impulse with restitution
//   applyImpulseAtPoint()      worksheet 6: an impulse at a world point turns the bodies too
//   applyContactImpulse()      worksheet 6: the impulse with restitution at every contact point
#pragma once

#include "gpl/body.h"
#include "gpl/contact.h"

namespace gpl {

/// Student hook (worksheet 3), solutions/resolve_interpenetration.cpp.
void resolveInterpenetration(const Contact& contact, Body& a, Body& b);
/// Student hook (worksheet 4), solutions/collision_impulse.cpp.
void applyCollisionImpulse(const Contact& contact, Body& a, Body& b);
/// Student hook (worksheet 6), solutions/impulse_at_point.cpp: `impulse` (N s, world frame) acts on
/// b at `point` (m, world frame) and its opposite on a. Worksheet 7's friction goes through it too.
void applyImpulseAtPoint(Body& a, Body& b, const Vec3& point, const Vec3& impulse);
/// Student hook (worksheet 6), solutions/contact_impulse.cpp.
void applyContactImpulse(const Contact& contact, Body& a, Body& b);

}  // namespace gpl
