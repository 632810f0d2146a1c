// Worksheet 4, assignment 1: a rope as a contact that only pulls.
//
// Inputs:  a, b         the two bodies the rope ties: position (m, world frame)
//          length       the rope's length (m, > 0): the greatest distance between the centres
// Outputs: no contact (std::nullopt) while the rope is slack or just taut (|x_a - x_b| <= length);
//          otherwise a contact with
//            normal     unit vector along the rope from b towards a: (x_a - x_b) / |x_a - x_b|.
//                       Separating a and b along this normal pulls them together, so the
//                       framework's interpenetration and impulse stages answer the rope unchanged.
//            depth      the stretch beyond the length (m), > 0
//            points[0]  the middle of the rope (m, world frame); pointCount = 1
// The framework fills in the indices of the bodies and sets the restitution to 0.
#include <optional>

#include "gpl/collision.h"
#include "gpl/hooks.h"

namespace gpl {

std::optional<Contact> ropeContact([[maybe_unused]] const Body& a, [[maybe_unused]] const Body& b,
                                   [[maybe_unused]] double length) {
    kernelNotImplemented("ropeContact()");
    return std::nullopt;
}

}  // namespace gpl
