// Worksheet 9, assignment 2: the density at a particle.
//
// Inputs:  x           the particle's position (m)
//          neighbours  the other particles nearer than h (their positions x_j are read)
//          mass        every particle's mass m (kg, > 0)
//          h           the smoothing length (m, > 0)
// Outputs: rho_i = sum over j of m W(|x - x_j|, h), with W = poly6Kernel(), over the neighbours and
//          over the particle itself (its term is m W(0, h)) (kg/m^3).
#include <cassert>

#include "gpl/fluid_kernels.h"
#include "gpl/hooks.h"

namespace gpl {

double fluidDensity([[maybe_unused]] const Vec3& x, [[maybe_unused]] const std::vector<FluidNeighbour>& neighbours,
                    [[maybe_unused]] double mass, [[maybe_unused]] double h) {
    // BEGIN SOLUTION
    assert(mass > 0.0 && h > 0.0);
    double rho = mass * poly6Kernel(0.0, h);  // the particle itself
    for (const FluidNeighbour& j : neighbours) rho += mass * poly6Kernel((x - j.x).norm(), h);
    return rho;
    // ELSE STUB
    // kernelNotImplemented("fluidDensity()");
    // return 0.0;
    // END SOLUTION
}

}  // namespace gpl
