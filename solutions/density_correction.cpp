// Worksheet 9, assignment 4: a particle's move from the density constraints (position-based fluids).
//
// Inputs:  x            the particle's predicted position (m)
//          lambda       its multiplier lambda_i (densityConstraintLambda())
//          neighbours   the other particles nearer than h (their x_j and lambda_j are read)
//          restDensity  rho0 (kg/m^3, > 0), mass m (kg, > 0), h the smoothing length (m, > 0)
//          tensile      k, dq and n of the tensile correction
// Outputs: with W the poly6 kernel and grad W the spiky kernel's gradient,
//            s_corr_j = -k (W(|x - x_j|, h) / W(dq, h))^n
//            dp = (m / rho0) sum_j (lambda_i + lambda_j + s_corr_j) grad W(x - x_j)
//          Each pair's term is the same with i and j swapped but of opposite sign, so that the moves
//          of a cloud of particles sum to zero: no momentum is made.
#include <cassert>
#include <cmath>

#include "gpl/fluid_kernels.h"
#include "gpl/hooks.h"

namespace gpl {

Vec3 densityCorrection([[maybe_unused]] const Vec3& x, [[maybe_unused]] double lambda,
                       [[maybe_unused]] const std::vector<FluidNeighbour>& neighbours,
                       [[maybe_unused]] double restDensity, [[maybe_unused]] double mass, [[maybe_unused]] double h,
                       [[maybe_unused]] const TensileCorrection& tensile) {
    Vec3 dp = Vec3::Zero();
    // BEGIN SOLUTION
    assert(restDensity > 0.0 && mass > 0.0 && h > 0.0 && tensile.k >= 0.0);
    const double Wdq = tensile.k > 0.0 ? poly6Kernel(tensile.dq, h) : 1.0;
    for (const FluidNeighbour& j : neighbours) {
        const Vec3 r = x - j.x;
        double sCorr = 0.0;  // -k (W / W(dq))^n; n is a small whole number: n products, not std::pow
        if (tensile.k > 0.0) {
            const double ratio = poly6Kernel(r.norm(), h) / Wdq;
            double power = 1.0;
            for (int e = 0; e < tensile.n; ++e) power *= ratio;
            sCorr = -tensile.k * power;
        }
        dp += (lambda + j.lambda + sCorr) * spikyGradient(r, h);
    }
    dp *= mass / restDensity;
    // ELSE STUB
    // kernelNotImplemented("densityCorrection()");
    // END SOLUTION
    return dp;
}

}  // namespace gpl
