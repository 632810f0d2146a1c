// Worksheet 9, assignment 1: the gradient of the spiky smoothing kernel.
//
// Inputs:  r  the vector from neighbour j to particle i, r = x_i - x_j (m)
//          h  the smoothing length (m, > 0)
// Outputs: the gradient of W_spiky(|r|, h) = 15 / (pi h^6) (h - |r|)^3 with respect to x_i:
//            grad W(r, h) = -45 / (pi h^6) (h - |r|)^2 r / |r|     for 0 < |r| <= h,
//          the zero vector at r = 0 (no direction) and beyond h (1/m^4). It points from i towards j:
//          the kernel falls as the two part. Unlike poly6's, its slope does not vanish as |r| -> 0,
//          so that close particles push each other apart.
#include <cassert>

#include "gpl/fluid_kernels.h"
#include "gpl/hooks.h"

namespace gpl {

Vec3 spikyGradient([[maybe_unused]] const Vec3& r, [[maybe_unused]] double h) {
    kernelNotImplemented("spikyGradient()");
    return Vec3::Zero();
}

}  // namespace gpl
