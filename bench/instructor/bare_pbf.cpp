// The fluids study's bare PBF iteration (fluids_study.h): in the instructors' tree only. Written
// out, it is a model answer of worksheet 9's hooks, and a student release (tools/release.py) and the
// Gradescope bundle leave this folder out; bench/CMakeLists.txt builds it where it exists.
#include <algorithm>
#include <cmath>

#include "fluids_study.h"

namespace gpl::study {

double barePbfIteration(const ParticleGrid& grid, const std::vector<Vec3>& x, double mass, double restDensity, double h,
                        double epsilon, const TensileCorrection& tensile, std::vector<double>& lambda,
                        std::vector<Vec3>& moved) {
    constexpr double pi = 3.14159265358979323846;
    const double h2 = h * h;
    const double poly6 = 315.0 / (64.0 * pi * std::pow(h, 9));  // W = poly6 (h^2 - r^2)^3
    const double spiky = -45.0 / (pi * std::pow(h, 6));         // grad W = spiky (h - r)^2 r / |r|
    const double share = mass / restDensity;
    const auto gradient = [&](const Vec3& r) -> Vec3 {
        const double length = r.norm();
        if (length == 0.0 || length > h) return Vec3::Zero();
        return (spiky * (h - length) * (h - length) / length) * r;
    };
    const std::uint32_t* list = grid.list().data();
    lambda.resize(x.size());
    moved.resize(x.size());
    // Pass 1: each density and, from it, each multiplier.
    for (std::size_t i = 0; i < x.size(); ++i) {
        const std::uint32_t first = grid.start(i), last = first + grid.count(i);
        double sum = h2 * h2 * h2;  // the particle itself
        Vec3 gradI = Vec3::Zero();
        double squares = 0.0;
        for (std::uint32_t k = first; k < last; ++k) {
            const Vec3 r = x[i] - x[list[k]];
            const double q = h2 - r.squaredNorm();
            if (q > 0.0) sum += q * q * q;
            const Vec3 gradJ = -share * gradient(r);
            squares += gradJ.squaredNorm();
            gradI -= gradJ;
        }
        const double density = mass * poly6 * sum;
        const double C = std::max(density, restDensity) / restDensity - 1.0;
        lambda[i] = -C / (squares + gradI.squaredNorm() + epsilon);
    }
    // Pass 2: each move, with s_corr; pass 3 (in the same loop: the moves go to `moved`): each particle moved.
    const double wdq = tensile.k > 0.0 ? poly6 * std::pow(h2 - tensile.dq * tensile.dq, 3) : 1.0;
    double total = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        const std::uint32_t first = grid.start(i), last = first + grid.count(i);
        Vec3 dp = Vec3::Zero();
        for (std::uint32_t k = first; k < last; ++k) {
            const std::uint32_t j = list[k];
            const Vec3 r = x[i] - x[j];
            double sCorr = 0.0;
            if (tensile.k > 0.0) {
                const double q = std::max(h2 - r.squaredNorm(), 0.0);
                const double ratio = poly6 * q * q * q / wdq;
                double power = 1.0;
                for (int e = 0; e < tensile.n; ++e) power *= ratio;
                sCorr = -tensile.k * power;
            }
            dp += (lambda[i] + lambda[j] + sCorr) * gradient(r);
        }
        moved[i] = x[i] + share * dp;
        total += moved[i].sum();
    }
    return total;
}

}  // namespace gpl::study
