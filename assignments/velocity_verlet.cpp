// Worksheet 2, assignment 3: velocity Verlet.
//
// Inputs:  state.x   positions x_n of the N particles (m)
//          state.v   velocities v_n (m/s)
//          state.a   accelerations a_n = a(x_n, v_n) (m/s^2)
//          accel     accel(x, v, a) fills a with the accelerations at (x, v); each call is one
//                    force evaluation
//          h         time step (s), positive and finite
// Outputs: state.x = x_{n+1} = x_n + h v_n + h^2/2 a_n
//          state.v = v_{n+1} = v_n + h/2 (a_n + a_{n+1})
//          state.a = a_{n+1}: call accel exactly once per step, at the new positions
//          state.xPrev is not used
//
// Velocity-dependent forces (damping) see the half-step velocity v_n + h/2 a_n.
#include <cstddef>

#include "gpl/integrators.h"

namespace gpl {

void velocityVerlet([[maybe_unused]] ParticleState& state, [[maybe_unused]] const AccelerationFunction& accel,
                    [[maybe_unused]] double h) {
    kernelNotImplemented("velocityVerlet()");
}

}  // namespace gpl
