// Worksheet 8, assignment 1: a distance constraint with a compliance (XPBD).
//
// Inputs:  x1, x2      the two particles' predicted positions (m)
//          w1, w2      their inverse masses (1/kg, >= 0; 0 is pinned)
//          rest        the rest distance (m, >= 0)
//          compliance  alpha (m/N, >= 0): 0 is a rod, larger is stretchier
//          h           the time step (s, > 0)
//          lambda      the multiplier this constraint has summed in this step's earlier iterations
// Outputs: with d = |x1 - x2|, n = (x1 - x2) / d, C = d - rest and alpha~ = alpha / h^2,
//            dlambda = (-C - alpha~ lambda) / (w1 + w2 + alpha~)
//            dx1 = w1 dlambda n,   dx2 = -w2 dlambda n
//          Nothing moves when w1 + w2 + alpha~ = 0 (two pinned particles held rigidly) or d = 0
//          (no direction to push along).
#include <cassert>
#include <cmath>

#include "gpl/hooks.h"
#include "gpl/soft_constraints.h"

namespace gpl {

DistanceCorrection solveDistanceConstraint([[maybe_unused]] const Vec3& x1, [[maybe_unused]] const Vec3& x2,
                                           [[maybe_unused]] double w1, [[maybe_unused]] double w2,
                                           [[maybe_unused]] double rest, [[maybe_unused]] double compliance,
                                           [[maybe_unused]] double h, [[maybe_unused]] double lambda) {
    DistanceCorrection out;
    // BEGIN SOLUTION
    assert(w1 >= 0.0 && w2 >= 0.0 && compliance >= 0.0 && h > 0.0);
    const Vec3 d = x1 - x2;
    const double length = d.norm();
    const double alphaTilde = compliance / (h * h);
    const double denominator = w1 + w2 + alphaTilde;
    if (length == 0.0 || denominator == 0.0) return out;
    const Vec3 n = d / length;  // grad_1 C; grad_2 C = -n
    const double C = length - rest;
    out.dlambda = (-C - alphaTilde * lambda) / denominator;
    out.dx1 = w1 * out.dlambda * n;
    out.dx2 = -w2 * out.dlambda * n;
    // ELSE STUB
    // kernelNotImplemented("solveDistanceConstraint()");
    // END SOLUTION
    return out;
}

}  // namespace gpl
