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
    // BEGIN SOLUTION
    const std::size_t n = state.x.size();
    for (std::size_t i = 0; i < n; ++i) {
        state.x[i] += h * state.v[i] + 0.5 * h * h * state.a[i];
        state.v[i] += 0.5 * h * state.a[i];  // first half kick, with a_n
    }
    accel(state.x, state.v, state.a);
    // Second half kick, with a_{n+1}.
    for (std::size_t i = 0; i < n; ++i) state.v[i] += 0.5 * h * state.a[i];
    // ELSE STUB
    // kernelNotImplemented("velocityVerlet()");
    // END SOLUTION
}

}  // namespace gpl
