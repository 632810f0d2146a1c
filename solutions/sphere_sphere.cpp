// Worksheet 3, assignment 1: sphere against sphere.
//
// Inputs:  a, b         two spheres: position (m, world frame) and radius (m, > 0)
// Outputs: no contact (std::nullopt) when the spheres are apart or exactly touching; otherwise a
//          contact with
//            normal     unit vector from a's centre towards b's centre
//            depth      overlap along the normal (m): r_a + r_b - |x_b - x_a| > 0
//            points[0]  one point (m, world frame) on the line of centres, inside both spheres:
//                       the middle of the stretch of that line inside both, which is halfway
//                       between the two surfaces unless one sphere lies within the other;
//                       pointCount = 1 (Contact::at(point, normal, depth) fills all three)
// Concentric spheres have no line of centres: use the normal (0, 1, 0), depth r_a + r_b.
// The framework fills in the indices of the bodies and the restitution.
#include <algorithm>
#include <optional>

#include "gpl/collision.h"
#include "gpl/hooks.h"

namespace gpl {

std::optional<Contact> sphereSphere([[maybe_unused]] const Body& a, [[maybe_unused]] const Body& b) {
    // BEGIN SOLUTION
    const Vec3 d = b.position - a.position;
    const double distance = d.norm();
    const double depth = a.radius + b.radius - distance;
    if (depth <= 0.0) return std::nullopt;  // apart, or touching at one point: nothing to answer
    const Vec3 normal = distance > 0.0 ? Vec3(d / distance) : Vec3::UnitY();
    // The stretch of the line of centres inside both spheres, measured from a's centre along the
    // normal, and its middle: a.radius - depth / 2 while neither sphere lies within the other.
    const double from = std::max(-a.radius, distance - b.radius), to = std::min(a.radius, distance + b.radius);
    return Contact::at(a.position + (0.5 * (from + to)) * normal, normal, depth);
    // ELSE STUB
    // kernelNotImplemented("sphereSphere()");
    // return std::nullopt;
    // END SOLUTION
}

}  // namespace gpl
