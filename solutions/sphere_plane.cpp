// Worksheet 3, assignment 2: sphere against an infinite plane.
//
// Inputs:  sphere       position (m, world frame) and radius (m, > 0)
//          plane        a point on it: position (m, world frame); its unit normal in the plane's
//                       own frame: normal, turned into the world frame by orientation. The normal
//                       points out of the solid side: everything behind the plane is inside it.
// Outputs: no contact (std::nullopt) when the sphere is in front of the plane and does not reach
//          it, or exactly touches it; otherwise a contact with
//            normal     unit vector from the sphere into the plane: minus the plane's world normal
//            depth      how far the sphere reaches behind the plane's surface (m), > 0; more than
//                       the radius when the centre itself is behind the plane
//            points[0]  one point (m, world frame) on the line through the centre along the
//                       normal, between the sphere's deepest point and the plane; pointCount = 1
// The framework fills in the indices of the bodies and the restitution.
#include <optional>

#include "gpl/collision.h"
#include "gpl/hooks.h"

namespace gpl {

std::optional<Contact> spherePlane([[maybe_unused]] const Body& sphere, [[maybe_unused]] const Body& plane) {
    // BEGIN SOLUTION
    const Vec3 m = plane.orientation * plane.normal;
    const double height = m.dot(sphere.position - plane.position);  // of the centre above the plane (m)
    const double depth = sphere.radius - height;
    if (depth <= 0.0) return std::nullopt;
    // The point halfway between the sphere's deepest point and the plane's surface.
    return Contact::at(sphere.position - (sphere.radius - 0.5 * depth) * m, -m, depth);
    // ELSE STUB
    // kernelNotImplemented("spherePlane()");
    // return std::nullopt;
    // END SOLUTION
}

}  // namespace gpl
