// Collision detection: pure kernels that say whether two bodies touch, and how.
//
// Student hooks (worksheets 3, 4 and 5; bodies in assignments/, reference bodies in solutions/):
//   sphereSphere()  sphere against sphere
//   spherePlane()   sphere against an infinite plane
//   ropeContact()   a taut rope as a contact that pulls
//   sphereBox()     sphere against an oriented box
//   boxPlane()      oriented box against an infinite plane
//   boxBox()        oriented box against oriented box (separating axes)
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
/// Student hook (worksheet 5), solutions/sphere_box.cpp. The normal points from the sphere into the box.
std::optional<Contact> sphereBox(const Body& sphere, const Body& box);
/// Student hook (worksheet 5), solutions/box_plane.cpp. The box comes first, as the sphere does in
/// spherePlane(): the normal points from the box into the plane.
std::optional<Contact> boxPlane(const Body& box, const Body& plane);
/// Student hook (worksheet 5), solutions/box_box.cpp. The normal points from a towards b.
std::optional<Contact> boxBox(const Body& a, const Body& b);

/// The contact between bodies[i] and bodies[j] from the kernel for their shapes, with the
/// framework's fields set (a, b, restitution). The shapes come in the order sphere, box, plane: a
/// sphere first against a box or a plane, a box first against a plane, so the normal points from
/// the sphere into the box or plane and from the box into the plane. Two planes and two static
/// bodies have no contact. With a margin (m, > 0), bodies that come within it of touching have a
/// contact too: the kernel sees them grown by the margin between them (half each, all of it for a
/// plane's partner), and the contact's depth is the overlap less the margin, negative across a gap.
std::optional<Contact> collide(const std::vector<Body>& bodies, std::size_t i, std::size_t j, double margin = 0.0);

/// Speed (m/s) at which the bodies of the contact approach each other along its normal:
/// (v_b - v_a) . n; negative while they approach, positive while they separate.
double normalVelocity(const Contact& contact, const Body& a, const Body& b);

}  // namespace gpl
