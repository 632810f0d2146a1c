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
    // BEGIN SOLUTION
    const Mat3 axes = box.orientation.toRotationMatrix();  // columns: the box's axes in the world frame
    const Vec3 local = axes.transpose() * (sphere.position - box.position);  // centre in the box frame (m)
    const Vec3 closest = local.cwiseMax(-box.halfExtents).cwiseMin(box.halfExtents);
    Vec3 normal;   // world frame, from the sphere into the box
    double depth;  // m
    if (closest != local) {  // the centre is outside: the closest point is on the surface
        const Vec3 towardsBox = axes * (closest - local);
        const double distance = towardsBox.norm();
        depth = sphere.radius - distance;
        if (depth <= 0.0) return std::nullopt;  // apart, or touching at one point
        normal = towardsBox / distance;
    } else {  // the centre is inside: out through the nearest face
        int k = 0;  // the axis of the nearest face
        const Vec3 room = box.halfExtents - local.cwiseAbs();  // to the faces on the centre's side (m)
        room.minCoeff(&k);
        const double side = local[k] >= 0.0 ? 1.0 : -1.0;
        normal = -side * axes.col(k);
        depth = sphere.radius + room[k];
    }
    // Halfway between the sphere's deepest point and the box's surface.
    return Contact::at(sphere.position + (sphere.radius - 0.5 * depth) * normal, normal, depth);
    // ELSE STUB
    // kernelNotImplemented("sphereBox()");
    // return std::nullopt;
    // END SOLUTION
}

}  // namespace gpl
