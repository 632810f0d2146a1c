// Collision detection: pure kernels that say whether two bodies touch, and how.
//
// Student hooks (worksheets 3 and 4; bodies in assignments/, reference bodies in solutions/):
//   sphereSphere()  sphere against sphere
//   spherePlane()   sphere against an infinite plane
//   ropeContact()   a taut rope as a contact that pulls
// Framework: collide() picks the kernel for a pair of bodies in the engine.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "gpl/body.h"
#include "gpl/contact.h"

namespace gpl {

/// Student hook (worksheet 3), solutions/sphere_sphere.cpp.
std::optional<Contact> sphereSphere(const Body& a, const Body& b);
/// Student hook (worksheet 3), solutions/sphere_plane.cpp.
std::optional<Contact> spherePlane(const Body& sphere, const Body& plane);
/// Student hook (worksheet 4), solutions/rope_contact.cpp.
std::optional<Contact> ropeContact(const Body& a, const Body& b, double length);

/// The contact between bodies[i] and bodies[j] from the kernel for their shapes, with the
/// framework's fields set (a, b, restitution); a sphere always comes first against a plane, so
/// the normal of a sphere-plane contact points into the plane. Pairs without a kernel yet (boxes:
/// worksheet 5) and pairs of static bodies have no contact.
std::optional<Contact> collide(const std::vector<Body>& bodies, std::size_t i, std::size_t j);

/// Speed (m/s) at which the bodies of the contact approach each other along its normal:
/// (v_b - v_a) . n; negative while they approach, positive while they separate.
double normalVelocity(const Contact& contact, const Body& a, const Body& b);

}  // namespace gpl
