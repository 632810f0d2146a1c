// Worksheet 2, assignment 2: position Verlet in the previous-position form.
//
// Inputs:  state.x      positions x_n of the N particles (m)
//          state.v      velocities v_n (m/s); only read on the first step
//          state.a      accelerations a_n = a(x_n, v_n) (m/s^2)
//          state.xPrev  positions x_{n-1} one step earlier (m); EMPTY before the first step
//          accel        accel(x, v, a) fills a with the accelerations at (x, v); each call is one
//                       force evaluation
//          h            time step (s), positive and finite
// Outputs: state.x = x_{n+1} = 2 x_n - x_{n-1} + h^2 a_n
//          state.xPrev = x_n
//          state.v = v_{n+1}, derived from positions only (second order)
//          state.a = a(x_{n+1}, v_{n+1}): call accel exactly once per step
//
// The first step has no x_{n-1}: make one up so that the step is still second order.
#include <cstddef>

#include "gpl/integrators.h"

namespace gpl {

void positionVerlet([[maybe_unused]] ParticleState& state, [[maybe_unused]] const AccelerationFunction& accel,
                    [[maybe_unused]] double h) {
    kernelNotImplemented("positionVerlet()");
}

}  // namespace gpl
