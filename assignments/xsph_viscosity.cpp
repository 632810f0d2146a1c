// Worksheet 9, assignment 5: XSPH viscosity, a particle's velocity blended with its neighbours'.
//
// Inputs:  x, v        the particle's position (m) and velocity (m/s)
//          neighbours  the other particles nearer than h (their x_j, v_j and rho_j are read)
//          mass        m (kg, > 0), h the smoothing length (m, > 0)
//          c           how much to blend (dimensionless, 0 <= c <= 1)
// Outputs: v' = v + c sum_j (m / rho_j) (v_j - v) W(|x - x_j|, h), with W the poly6 kernel.
//          A fluid moving as one (every v_j = v) keeps its velocity; each pair's exchange is equal
//          and opposite when the densities are equal.
#include <cassert>

#include "gpl/fluid_kernels.h"
#include "gpl/hooks.h"

namespace gpl {

Vec3 xsphViscosity([[maybe_unused]] const Vec3& x, [[maybe_unused]] const Vec3& v,
                   [[maybe_unused]] const std::vector<FluidNeighbour>& neighbours, [[maybe_unused]] double mass,
                   [[maybe_unused]] double h, [[maybe_unused]] double c) {
    kernelNotImplemented("xsphViscosity()");
    return v;
}

}  // namespace gpl
