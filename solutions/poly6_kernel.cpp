// Worksheet 9, assignment 1: the poly6 smoothing kernel.
//
// Inputs:  r  the distance between two particles (m, >= 0)
//          h  the smoothing length (m, > 0): how far a particle sees
// Outputs: W(r, h) = 315 / (64 pi h^9) (h^2 - r^2)^3 for r <= h, and 0 beyond (1/m^3).
//          The constant makes W integrate to 1 over the ball of radius h, so that a sum of m W
//          over evenly spread particles is a density.
#include <cassert>

#include "gpl/fluid_kernels.h"
#include "gpl/hooks.h"

namespace gpl {

double poly6Kernel([[maybe_unused]] double r, [[maybe_unused]] double h) {
    // BEGIN SOLUTION
    assert(r >= 0.0 && h > 0.0);
    if (r > h) return 0.0;
    constexpr double pi = 3.14159265358979323846;
    const double h2 = h * h;
    const double q = h2 - r * r;
    return 315.0 / (64.0 * pi * h2 * h2 * h2 * h2 * h) * q * q * q;
    // ELSE STUB
    // kernelNotImplemented("poly6Kernel()");
    // return 0.0;
    // END SOLUTION
}

}  // namespace gpl
