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
    kernelNotImplemented("sphereSphere()");
    return std::nullopt;
}

}  // namespace gpl
