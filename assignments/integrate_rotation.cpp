// Worksheet 6, assignment 2: one time step of rotation.
//
// Inputs:  body   orientation q (unit quaternion, body to world), angularVelocity omega (rad/s, world
//                 frame), inertia I and invInertia I^-1 (kg m^2 and 1/(kg m^2), body frame), torque tau
//                 (N m, world frame, about the centre of mass; constant over the step), isStatic()
//          h      time step (s), > 0
// Outputs: body.orientation and body.angularVelocity at t + h. With I_world(q) = R I R^T (R the
//          rotation matrix of q) and turn(q, w, dt) = (q + dt/2 (0, w) q) / |...| (one step of the
//          quaternion derivative dq/dt = 1/2 (0, omega) q, world omega on the left, back to unit length):
//            L      = I_world(q) omega + h tau       world angular momentum after the torque (N m s)
//            q_half = turn(q, I_world(q)^-1 L, h/2)  the orientation half a step on
//            q'     = turn(q, I_world(q_half)^-1 L, h)   a whole step with the midpoint's omega
//            omega' = I_world(q')^-1 L               the angular velocity in the new orientation
//          Without torque L stays exactly what it was. Static bodies are left as they are.
#include "gpl/hooks.h"
#include "gpl/rotation.h"

namespace gpl {

void integrateRotation([[maybe_unused]] Body& body, [[maybe_unused]] double h) {
    kernelNotImplemented("integrateRotation()");
}

}  // namespace gpl
