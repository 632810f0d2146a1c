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
    // BEGIN SOLUTION
    const std::size_t n = state.x.size();
    if (state.xPrev.size() != n) {
        // No previous position yet: a Taylor step backwards in time, x_{-1} = x_0 - h v_0 + h^2/2 a_0.
        state.xPrev.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            state.xPrev[i] = state.x[i] - h * state.v[i] + 0.5 * h * h * state.a[i];
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 next = 2.0 * state.x[i] - state.xPrev[i] + h * h * state.a[i];
        // One-sided difference of the last three positions: v_{n+1} + O(h^2).
        state.v[i] = (3.0 * next - 4.0 * state.x[i] + state.xPrev[i]) / (2.0 * h);
        state.xPrev[i] = state.x[i];
        state.x[i] = next;
    }
    accel(state.x, state.v, state.a);
    // ELSE STUB
    // kernelNotImplemented("positionVerlet()");
    // END SOLUTION
}

}  // namespace gpl
