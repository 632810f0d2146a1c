// Worksheet 6, assignment 1: the inverse inertia tensor in the world frame.
//
// Inputs:  body   orientation q (unit quaternion, body to world; R its rotation matrix) and
//                 invInertia I^-1 (1/(kg m^2), 3x3, symmetric, in the body frame); isStatic()
// Outputs: the inverse inertia tensor in the world frame, R I^-1 R^T (1/(kg m^2), 3x3, symmetric):
//          what turns a world angular momentum L into the world angular velocity omega = R I^-1 R^T L.
//          The zero matrix for a static body (it never turns).
#include "gpl/hooks.h"
#include "gpl/rotation.h"

namespace gpl {

Mat3 worldInverseInertia([[maybe_unused]] const Body& body) {
    kernelNotImplemented("worldInverseInertia()");
    return Mat3::Zero();
}

}  // namespace gpl
