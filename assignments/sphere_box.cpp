// Worksheet 5, assignment 2: sphere against an oriented box.
//
// Inputs:  sphere       position (m, world frame) and radius (m, > 0)
//          box          position of its centre (m, world frame), orientation (unit quaternion, box
//                       frame to world frame) and halfExtents (m, > 0, along the box's own axes)
// Outputs: no contact (std::nullopt) when the sphere does not reach the box or exactly touches it;
//          otherwise a contact with
//            normal     unit vector from the sphere into the box: from the centre towards the
//                       box's closest point; when the centre is inside the box, minus the outward
//                       normal of the face nearest to the centre (the sphere leaves through it)
//            depth      how far the sphere reaches into the box (m), > 0: the radius minus the
//                       distance to the closest point, or, with the centre inside, the radius plus
//                       the distance to the nearest face
//            points[0]  one point (m, world frame) on the line through the centre along the
//                       normal, between the sphere's deepest point and the box's surface;
//                       pointCount = 1
// The framework fills in the indices of the bodies and the restitution.
#include <optional>

#include "gpl/collision.h"
#include "gpl/hooks.h"

namespace gpl {

std::optional<Contact> sphereBox([[maybe_unused]] const Body& sphere, [[maybe_unused]] const Body& box) {
    kernelNotImplemented("sphereBox()");
    return std::nullopt;
}

}  // namespace gpl
