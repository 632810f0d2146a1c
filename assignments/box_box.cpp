// Worksheet 5, assignment 4: box against box, by separating axes.
//
// Inputs:  a, b         two boxes: position of the centre (m, world frame), orientation (unit
//                       quaternion, box frame to world frame), halfExtents (m, > 0, box axes)
// Outputs: no contact (std::nullopt) when some axis separates the boxes or they only touch (their
//          shadows on some axis overlap by 0 or less); otherwise a contact along the axis of least
//          overlap among the 15 candidates (the 3 + 3 face normals, the 9 cross products of an edge
//          of a with an edge of b; a face axis is kept unless an edge axis overlaps clearly less)
//            normal     that axis as a unit vector from a towards b
//            depth      the overlap of the two shadows on it (m), > 0
//            points     face axis: the face of the other box that faces the axis's face (the
//                       reference face), cut to the sides of the reference face, its corners and
//                       cuts that lie behind the reference face, each moved halfway to it; at most
//                       four (the deepest and three that span the rest). Edge axis: one point
//                       halfway between the closest points of the two edges.
//            pointCount 1..4
// The framework fills in the indices of the bodies and the restitution.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "gpl/collision.h"
#include "gpl/hooks.h"

namespace gpl {

// Helpers of your own may go here, in an anonymous namespace: namespace { ... }

std::optional<Contact> boxBox([[maybe_unused]] const Body& a, [[maybe_unused]] const Body& b) {
    kernelNotImplemented("boxBox()");
    return std::nullopt;
}

}  // namespace gpl
