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
    // BEGIN SOLUTION
    if (body.isStatic()) return Mat3::Zero();
    const Mat3 r = body.orientation.toRotationMatrix();
    return r * body.invInertia * r.transpose();
    // ELSE STUB
    // kernelNotImplemented("worldInverseInertia()");
    // return Mat3::Zero();
    // END SOLUTION
}

}  // namespace gpl
