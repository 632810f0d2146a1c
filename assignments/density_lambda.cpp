// Worksheet 9, assignment 3: the multiplier of a particle's density constraint (position-based fluids).
//
// Inputs:  x            the particle's predicted position (m)
//          neighbours   the other particles nearer than h (their predicted positions x_j are read)
//          density      rho_i, the density at the particle (fluidDensity()) (kg/m^3)
//          restDensity  rho0 (kg/m^3, > 0), mass m (kg, > 0), h the smoothing length (m, > 0)
//          epsilon      the relaxation eps (1/m^2, > 0)
// Outputs: with C = rho_i / rho0 - 1 and the gradients of C with respect to each particle,
//            grad_j C = -(m / rho0) grad W(x - x_j)          for each neighbour j
//            grad_i C =  (m / rho0) sum_j grad W(x - x_j)     for the particle itself
//          (W the spiky kernel, spikyGradient()),
//            lambda = -C / (sum_k |grad_k C|^2 + eps)
//          summed over the neighbours and the particle itself.
#include <cassert>

#include "gpl/fluid_kernels.h"
#include "gpl/hooks.h"

namespace gpl {

double densityConstraintLambda([[maybe_unused]] const Vec3& x,
                               [[maybe_unused]] const std::vector<FluidNeighbour>& neighbours,
                               [[maybe_unused]] double density, [[maybe_unused]] double restDensity,
                               [[maybe_unused]] double mass, [[maybe_unused]] double h,
                               [[maybe_unused]] double epsilon) {
    kernelNotImplemented("densityConstraintLambda()");
    return 0.0;
}

}  // namespace gpl
