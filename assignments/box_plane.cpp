// Worksheet 5, assignment 3: box against an infinite plane.
//
// Inputs:  box          position of its centre (m, world frame), orientation (unit quaternion, box
//                       frame to world frame) and halfExtents (m, > 0, along the box's own axes)
//          plane        a point on it: position (m, world frame); its unit normal in the plane's
//                       own frame: normal, turned into the world frame by orientation. Everything
//                       behind the plane is inside it.
// Outputs: no contact (std::nullopt) when no corner of the box is behind the plane (a corner, an
//          edge or a face exactly on the plane only touches it); otherwise a contact with
//            normal     unit vector from the box into the plane: minus the plane's world normal
//            depth      how far the deepest corner is behind the plane (m), > 0
//            points     one point per corner behind the plane (m, world frame), each between that
//                       corner and the plane's surface along the normal; a box lying flat has
//                       four. With more than four corners behind the plane, the four deepest.
//            pointCount 1..4
// The box comes first, as the sphere does in spherePlane(). The framework fills in the indices of
// the bodies and the restitution.
#include <algorithm>
#include <array>
#include <optional>
#include <utility>

#include "gpl/collision.h"
#include "gpl/hooks.h"

namespace gpl {

std::optional<Contact> boxPlane([[maybe_unused]] const Body& box, [[maybe_unused]] const Body& plane) {
    kernelNotImplemented("boxPlane()");
    return std::nullopt;
}

}  // namespace gpl
