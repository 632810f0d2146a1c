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
    // The same about every axis (a sphere, a cube): R (c 1) R^T = c 1 in every frame, returned as it
    // is, exactly; the product would round it to a matrix slightly different about each axis.
    const Mat3& inv = body.invInertia;
    if (inv(0, 1) == 0.0 && inv(0, 2) == 0.0 && inv(1, 2) == 0.0 && inv(1, 0) == 0.0 && inv(2, 0) == 0.0 &&
        inv(2, 1) == 0.0 && inv(0, 0) == inv(1, 1) && inv(0, 0) == inv(2, 2))
        return inv;
    const Mat3 R = body.orientation.toRotationMatrix();
    return R * body.invInertia * R.transpose();
    // ELSE STUB
    // kernelNotImplemented("worldInverseInertia()");
    // return Mat3::Zero();
    // END SOLUTION
}

}  // namespace gpl
