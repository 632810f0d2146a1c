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
    // BEGIN SOLUTION
    const Vec3 m = plane.orientation * plane.normal;
    const Mat3 axes = box.orientation.toRotationMatrix();
    // The corners with their heights above the plane (m); behind it: height < 0.
    std::array<Vec3, 8> corners;
    std::array<double, 8> heights;
    int behind = 0;  // corners behind the plane
    for (int j = 0; j < 8; ++j) {
        const Vec3 signs(j & 1 ? 1.0 : -1.0, j & 2 ? 1.0 : -1.0, j & 4 ? 1.0 : -1.0);  // of corner j
        const Vec3 x = box.position + axes * signs.cwiseProduct(box.halfExtents);
        corners[j] = x;
        heights[j] = m.dot(x - plane.position);
        if (heights[j] < 0.0) ++behind;
    }
    if (behind == 0) return std::nullopt;
    // The corners by height, the deepest first.
    std::array<int, 8> order{0, 1, 2, 3, 4, 5, 6, 7};
    std::sort(order.begin(), order.end(), [&heights](int p, int q) { return heights[p] < heights[q]; });
    Contact c;
    c.normal = -m;
    c.depth = -heights[order[0]];
    c.pointCount = std::min(behind, kMaxContactPoints);
    for (int k = 0; k < c.pointCount; ++k) {
        const int j = order[k];
        c.points[k] = corners[j] - 0.5 * heights[j] * m;  // halfway between the corner and the plane's surface
    }
    return c;
    // ELSE STUB
    // kernelNotImplemented("boxPlane()");
    // return std::nullopt;
    // END SOLUTION
}

}  // namespace gpl
