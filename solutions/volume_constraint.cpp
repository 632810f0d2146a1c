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
    // BEGIN SOLUTION
    assert(restVolume > 0.0 && compliance >= 0.0 && h > 0.0);
    const std::array<Vec3, 4> g{(x[3] - x[1]).cross(x[2] - x[1]) / 6.0, (x[2] - x[0]).cross(x[3] - x[0]) / 6.0,
                                (x[3] - x[0]).cross(x[1] - x[0]) / 6.0, (x[1] - x[0]).cross(x[2] - x[0]) / 6.0};
    const double alphaTilde = compliance / (h * h);
    double denominator = alphaTilde;
    for (int i = 0; i < 4; ++i) denominator += w[i] * g[i].squaredNorm();
    if (denominator == 0.0) return out;
    const double C = tetrahedronVolume(x) - restVolume;
    out.dlambda = (-C - alphaTilde * lambda) / denominator;
    for (int i = 0; i < 4; ++i) out.dx[i] = w[i] * out.dlambda * g[i];
    // ELSE STUB
    // kernelNotImplemented("solveVolumeConstraint()");
    // END SOLUTION
    return out;
}

}  // namespace gpl
