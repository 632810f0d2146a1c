// Worksheet 8, assignment 2: a tetrahedron's volume with a compliance (XPBD).
//
// Inputs:  x           the four corners' predicted positions x0 .. x3 (m)
//          w           their inverse masses (1/kg, >= 0)
//          restVolume  V0 (m^3, > 0)
//          compliance  alpha (1/(N m), >= 0), h the time step (s), lambda as in assignment 1
// Outputs: with V = (x1 - x0) x (x2 - x0) . (x3 - x0) / 6 (tetrahedronVolume()), C = V - V0 and the
//          gradients of V, each the opposite face's cross product over 6, pointing away from that face:
//            g0 = (x3 - x1) x (x2 - x1) / 6     g1 = (x2 - x0) x (x3 - x0) / 6
//            g2 = (x3 - x0) x (x1 - x0) / 6     g3 = (x1 - x0) x (x2 - x0) / 6
//          and alpha~ = alpha / h^2,
//            dlambda = (-C - alpha~ lambda) / (sum_i w_i |g_i|^2 + alpha~),   dx_i = w_i dlambda g_i
//          Nothing moves when the denominator is 0.
#include <cassert>

#include "gpl/hooks.h"
#include "gpl/soft_constraints.h"

namespace gpl {

VolumeCorrection solveVolumeConstraint([[maybe_unused]] const std::array<Vec3, 4>& x,
                                       [[maybe_unused]] const std::array<double, 4>& w,
                                       [[maybe_unused]] double restVolume, [[maybe_unused]] double compliance,
                                       [[maybe_unused]] double h, [[maybe_unused]] double lambda) {
    VolumeCorrection out;
    kernelNotImplemented("solveVolumeConstraint()");
    return out;
}

}  // namespace gpl
