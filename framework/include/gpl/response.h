// Collision response: pure kernels that answer a contact by moving the two bodies apart or by
// changing their velocities.
//
// Student hooks (bodies in assignments/, reference bodies in solutions/):
//   resolveInterpenetration()  worksheet 3: positions apart, shared by mass
//   applyCollisionImpulse()    worksheet 4: the linear impulse with restitution
#pragma once

#include "gpl/body.h"
#include "gpl/contact.h"

namespace gpl {

/// Student hook (worksheet 3), solutions/resolve_interpenetration.cpp.
void resolveInterpenetration(const Contact& contact, Body& a, Body& b);
/// Student hook (worksheet 4), solutions/collision_impulse.cpp.
void applyCollisionImpulse(const Contact& contact, Body& a, Body& b);

}  // namespace gpl
