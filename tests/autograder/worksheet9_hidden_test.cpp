// Worksheet 9, hidden tests: graded by instructors and on Gradescope, left out of student releases
// (./lab release drops every file that declares a hidden test; such a file holds hidden tests only).
// The same laws as the graded tests on other inputs: other smoothing lengths and spacings, a lattice
// turned and moved, clouds under rigid motions with their neighbours relabelled, a flow seen from a
// moving frame.
#include <cmath>
#include <string>
#include <vector>

#include "fluid.h"
#include "graded.h"

namespace gpl {
namespace {

using checks::Cloud;
using checks::Fluid;
using checks::fluidText;
using checks::kFluidPi;
using checks::neighboursText;
using checks::Random;
using checks::str;

class Worksheet9Hidden : public checks::ContactsTest {};

// 1e-12 of a quantity's size allows any equivalent formula; the mistakes caught are off by percents.
constexpr double kRounding = 1e-12;

GRADED_TEST(Worksheet9Hidden, Poly6AtOtherLengths, 2,
            "poly6Kernel() at smoothing lengths from millimetres to metres: it integrates to 1, has W(0, h) = "
            "315 / (64 pi h^3) and scales as W(r, a h) = W(r / a, h) / a^3.",
            grading::hidden()) {
    constexpr int N = 20;  // lattice spacings per h
    const std::vector<long> shells = checks::latticeShells(N);
    for (const double h : {0.007, 3.3}) {
        const double s = h / N;
        double sum = 0.0;
        for (std::size_t n = 0; n < shells.size(); ++n) {
            if (shells[n] == 0) continue;
            sum += static_cast<double>(shells[n]) * poly6Kernel(std::sqrt(static_cast<double>(n)) * s, h) * s * s * s;
        }
        // The lattice sum's error, about (s / h)^5 (the kernel's third derivative jumps at h).
        ASSERT_NEAR(sum, 1.0, std::pow(s / h, 5))
            << "the integral of W over the ball of radius h = " << h << " m is " << sum;
        const double W0 = 315.0 / (64.0 * kFluidPi * h * h * h);
        ASSERT_NEAR(poly6Kernel(0.0, h), W0, kRounding * W0) << "W(0, h) with h = " << h << " m";
        for (const double a : {0.05, 40.0}) {
            for (int k = 0; k < 10; ++k) {
                const double r = a * h * k / 10.0;
                const double stretched = poly6Kernel(r, a * h), expected = poly6Kernel(r / a, h) / (a * a * a);
                ASSERT_NEAR(stretched, expected, kRounding * W0 / (a * a * a))
                    << "W(" << r << ", " << a * h << ") = " << stretched << ", but W(" << r / a << ", " << h << ") / "
                    << a << "^3 = " << expected;
            }
        }
    }
}

GRADED_TEST(Worksheet9Hidden, SpikyGradientTurnsWithSpace, 1,
            "spikyGradient() of a turned r is the turned gradient, grad W(R r) = R grad W(r), at smoothing lengths "
            "from a centimetre to metres.",
            grading::hidden()) {
    Random rnd(990);
    for (const double h : {0.011, 5.0}) {
        for (int i = 0; i < 100; ++i) {
            const Vec3 r = h * rnd.uniform(0.02, 0.98) * rnd.direction();
            const Quat R = checks::randomRotation(rnd);
            const Vec3 g = spikyGradient(r, h), turned = spikyGradient(R * r, h);
            ASSERT_GT(g.norm(), 0.0) << "spikyGradient(" << str(r) << ", " << h << ") must not be zero";
            ASSERT_LE((turned - R * g).norm(), kRounding * g.norm())
                << "spikyGradient(" << str(R * r) << ", " << h << ") = " << str(turned) << "; the turned gradient of "
                << str(r) << " is " << str(R * g);
        }
    }
}

GRADED_TEST(Worksheet9Hidden, DensityOfTurnedLattice, 2,
            "fluidDensity() inside a fluid at rest whose lattice is turned and moved, its neighbours in any order, at "
            "other spacings, ratios h / s and rest densities: rho0 within the lattice sum's error.",
            grading::hidden()) {
    Random rnd(991);
    for (const auto& [s, ratio, rho0] : {std::tuple{0.02, 2.5, 700.0}, std::tuple{0.3, 3.5, 1200.0}}) {
        Fluid f;
        f.s = s;
        f.h = ratio * s;
        f.rho0 = rho0;
        const Vec3 x = rnd.inBox(5.0);
        const std::vector<FluidNeighbour> neighbours =
            checks::relabelled(checks::latticeNeighbours(x, f.s, f.h, checks::randomRotation(rnd)));
        const double rho = fluidDensity(x, neighbours, f.mass(), f.h);
        // The lattice sum differs from W's integral by about (s / h)^5.
        ASSERT_NEAR(rho / f.rho0, 1.0, std::pow(f.s / f.h, 5))
            << "the density inside the turned lattice is " << rho << " kg/m^3" << fluidText(f)
            << neighboursText(x, neighbours);
    }
}

GRADED_TEST(Worksheet9Hidden, LambdaSameUnderRigidMotionAndRelabelling, 2,
            "densityConstraintLambda() depends on the distances between the particles only: the same for the fluid "
            "turned and moved and for its neighbours in another order.",
            grading::hidden()) {
    Random rnd(992);
    Fluid f;
    f.h = 0.03;
    f.s = 0.012;
    for (int i = 0; i < 30; ++i) {
        const Vec3 x = rnd.inBox(1.0);
        const std::vector<FluidNeighbour> neighbours = checks::randomNeighbours(rnd, x, f, 30);
        const double density = f.rho0 * rnd.uniform(0.9, 1.1), eps = 10.0;
        const double lambda = densityConstraintLambda(x, neighbours, density, f.rho0, f.mass(), f.h, eps);
        const Quat R = checks::randomRotation(rnd);
        const Vec3 t = rnd.inBox(3.0);
        const double moved = densityConstraintLambda(R * x + t, checks::relabelled(checks::carried(neighbours, R, t)),
                                                     density, f.rho0, f.mass(), f.h, eps);
        const std::string what = "\n  density " + formatNumber(density) + ", eps " + formatNumber(eps) + fluidText(f) +
                                 neighboursText(x, neighbours);
        ASSERT_TRUE(std::isfinite(lambda) && lambda != 0.0)
            << "lambda = " << lambda << " away from rest density" << what;
        ASSERT_NEAR(moved, lambda, 1e-10 * std::abs(lambda))
            << "lambda " << lambda << " becomes " << moved << " with the fluid turned, moved and relabelled" << what;
    }
}

GRADED_TEST(Worksheet9Hidden, CorrectionTurnsWithTheCloud, 2,
            "densityCorrection() for a cloud turned and moved, each particle's neighbours in another order: every move "
            "is the turned move, and the moves still sum to zero at another smoothing length with s_corr of n = 3.",
            grading::hidden()) {
    Random rnd(993);
    Fluid f;
    f.s = 0.15;
    f.h = 0.3;
    TensileCorrection tensile;
    tensile.k = 0.05;
    tensile.dq = 0.25 * f.h;
    tensile.n = 3;
    const Cloud cloud = checks::randomCloud(rnd, rnd.inBox(2.0), f, 50);
    const Quat R = checks::randomRotation(rnd);
    const Vec3 t = rnd.inBox(3.0);
    Vec3 total = Vec3::Zero();
    double size = 0.0;
    for (std::size_t i = 0; i < cloud.particles.size(); ++i) {
        const FluidNeighbour& p = cloud.particles[i];
        const Vec3 dp = densityCorrection(p.x, p.lambda, cloud.neighbours[i], f.rho0, f.mass(), f.h, tensile);
        const Vec3 turned =
            densityCorrection(R * p.x + t, p.lambda, checks::relabelled(checks::carried(cloud.neighbours[i], R, t)),
                              f.rho0, f.mass(), f.h, tensile);
        ASSERT_LE((turned - R * dp).norm(), 1e-10 * dp.norm())
            << "dp " << str(dp) << " turned is " << str(R * dp) << ", but the turned cloud gives " << str(turned)
            << fluidText(f) << neighboursText(p.x, cloud.neighbours[i]);
        total += dp;
        size += dp.norm();
    }
    ASSERT_GT(size, 0.0) << "no particle moved";
    // Each move sums a few dozen terms; their rounding is 1e-14 of the moves, the mistakes' a share.
    ASSERT_LE(total.norm(), 1e-10 * size)
        << "the moves sum to " << str(total) << " m; they must sum to 0" << fluidText(f);
}

GRADED_TEST(Worksheet9Hidden, XsphSameInMovingAndTurnedFrames, 2,
            "xsphViscosity() blends velocity differences only: adding one velocity u to every particle adds u to v', "
            "and turning the whole fluid turns v'.",
            grading::hidden()) {
    Random rnd(994);
    const Fluid f;
    for (int i = 0; i < 30; ++i) {
        const Vec3 x = rnd.inBox(1.0), v = rnd.inBox(2.0), u = rnd.inBox(3.0);
        const std::vector<FluidNeighbour> neighbours = checks::randomNeighbours(rnd, x, f, 25);
        const double c = rnd.uniform(0.05, 1.0);
        const Vec3 blended = xsphViscosity(x, v, neighbours, f.mass(), f.h, c);
        std::vector<FluidNeighbour> moving = neighbours;
        for (FluidNeighbour& j : moving) j.v += u;
        const Vec3 inMoving = xsphViscosity(x, v + u, moving, f.mass(), f.h, c);
        const std::string what = "\n  v " + str(v) + ", c " + formatNumber(c) + ", answered v' " + str(blended) +
                                 fluidText(f) + neighboursText(x, neighbours);
        const double scale = v.norm() + u.norm() + 2.0;  // m/s: the velocities' size
        ASSERT_GT((blended - v).norm(), 0.0) << "neighbours of other velocities must change v" << what;
        ASSERT_LE((inMoving - (blended + u)).norm(), kRounding * scale)
            << "with u = " << str(u) << " added to every velocity, v' is " << str(inMoving) << "; must be v' + u"
            << what;
        const Quat R = checks::randomRotation(rnd);
        const Vec3 t = rnd.inBox(3.0);
        const Vec3 turned =
            xsphViscosity(R * x + t, R * v, checks::relabelled(checks::carried(neighbours, R, t)), f.mass(), f.h, c);
        ASSERT_LE((turned - R * blended).norm(), 1e-10 * scale)
            << "the turned fluid gives v' = " << str(turned) << "; the turned v' is " << str(R * blended) << what;
    }
}

}  // namespace
}  // namespace gpl
