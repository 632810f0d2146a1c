// The accuracy study against theory: the functions ./lab bench accuracy prints are the ones tested
// here. Nothing is timed.
#include "study.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "gpl/integrators.h"

namespace gpl::study {
namespace {

std::vector<Run> sweepOf(const Problem& p, Integrator m) {
    std::vector<Run> runs;
    for (std::size_t n : p.steps) runs.push_back(simulate(p, m, n));
    return runs;
}

void expectOrders(const Problem& p) {
    for (Integrator m : kIntegrators) {
        const Order o = measuredOrder(p, sweepOf(p, m));
        ASSERT_GE(o.points, 3u) << p.id << ", " << integratorName(m) << ": too few runs in the asymptotic window";
        // The design target: measured orders within 0.1 of 1, 1, 2, 2, 4.
        EXPECT_NEAR(o.slope, theoreticalOrder(m), 0.1) << p.id << ", " << integratorName(m);
    }
}

TEST(Study, OrdersOnTheOscillator) { expectOrders(oscillator(2.0 * M_PI)); }
TEST(Study, OrdersOnTheLargeAnglePendulum) { expectOrders(pendulum(2.5)); }
TEST(Study, OrdersOnTheSmallAnglePendulum) { expectOrders(pendulum(0.1)); }

TEST(Study, StabilityLimitsMatchTheory) {
    const Problem p = oscillator(1.0);
    EXPECT_EQ(stabilityLimit(p, Integrator::ExplicitEuler), 0.0) << "explicit Euler has no stable step";
    for (Integrator m : {Integrator::SemiImplicitEuler, Integrator::PositionVerlet, Integrator::VelocityVerlet,
                         Integrator::RungeKutta4}) {
        const double theory = theoreticalStabilityLimit(m);
        // The design target: within 1 % of 2 and 2 sqrt 2.
        EXPECT_NEAR(stabilityLimit(p, m), theory, 0.01 * theory) << integratorName(m);
    }
}

TEST(Study, StabilityLimitOfTheSpringChainFollowsItsFastestMode) {
    const std::vector<double> masses = {1.0, 1000.0, 1.0, 1000.0, 1.0, 1000.0};
    const Problem p = springChain(masses);
    // Same 1 %: the fastest normal mode (from the eigenvalues) limits the step like a single oscillator.
    EXPECT_NEAR(stabilityLimit(p, Integrator::VelocityVerlet), 2.0, 0.02);
    EXPECT_NEAR(stabilityLimit(p, Integrator::RungeKutta4), 2.0 * std::sqrt(2.0), 0.01 * 2.0 * std::sqrt(2.0));
}

TEST(Study, FreeFallEnergyChangePerStep) {
    const Problem p = freeFall();
    const double h = 0.01, g = 9.81;
    const double unit = 0.5 * g * g * h * h;  // J/kg
    const struct {
        Integrator method;
        double expected;  // in units of g^2 h^2 / 2
    } cases[] = {{Integrator::ExplicitEuler, 1.0},
                 {Integrator::SemiImplicitEuler, -1.0},
                 {Integrator::PositionVerlet, 0.0},
                 {Integrator::VelocityVerlet, 0.0},
                 {Integrator::RungeKutta4, 0.0}};
    for (const auto& c : cases) {
        ParticleState s = startState(p.x0, p.v0, p.accel);
        for (int i = 0; i < 10; ++i) {
            const double before = p.energy(s.x, s.v);
            integrate(c.method, s, p.accel, h);
            const double change = p.energy(s.x, s.v) - before;
            // Relative 1e-9 of g^2 h^2 / 2: the energies (~110 J/kg) round at 1e-14 J/kg, 2e-12 of the unit.
            EXPECT_NEAR(change / unit, c.expected, 1e-9) << integratorName(c.method) << ", step " << i + 1;
        }
    }
}

TEST(Study, ForceEvaluationsPerStep) {
    const Problem p = kepler();
    for (Integrator m : kIntegrators) {
        EXPECT_EQ(simulate(p, m, 100).evaluationsPerStep, m == Integrator::RungeKutta4 ? 4.0 : 1.0)
            << integratorName(m);
    }
}

TEST(Study, VerletKeepsEnergyBoundedOverAMillionSteps) {
    const Problem p = oscillator(1.0);
    for (Integrator m : {Integrator::PositionVerlet, Integrator::VelocityVerlet}) {
        const study::Run r = simulateWithStep(p, m, 0.1, 1000000);
        // At h omega = 0.1 the bounded oscillation of Verlet's energy error is ~(h omega)^2 / 4 = 2.5e-3.
        EXPECT_LT(r.energyMax, 1e-2) << integratorName(m);
    }
    EXPECT_FALSE(simulateWithStep(p, Integrator::ExplicitEuler, 0.1, 1000000).finite)
        << "explicit Euler's energy grows by (1 + h^2 omega^2) per step and must overflow";
}

TEST(Study, FloatLosesThePositionFarFromTheOrigin) {
    // At 1e7 m a float's spacing is 1 m: the 1 m oscillation cannot be represented; double's spacing
    // is 2e-9 m and its error stays that of the method (about 1e-5 m at h = 1 ms).
    EXPECT_GT(offsetError(1e7, true), 0.5);
    EXPECT_LT(offsetError(1e7, false), 1e-4);
    EXPECT_LT(offsetError(0.0, true), 1e-4);
}

TEST(Study, BadInputIsRejectedBeforeStepping) {
    const Problem p = oscillator(1.0);
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    for (double h : {nan, inf, 0.0, -0.01}) {
        try {
            simulateWithStep(p, Integrator::RungeKutta4, h, 10);
            ADD_FAILURE() << "h = " << h << " accepted";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find("time step must be a positive finite number"), std::string::npos)
                << e.what();
        }
    }
    Problem bad = p;
    bad.x0[0].y() = inf;
    EXPECT_THROW(simulate(bad, Integrator::VelocityVerlet, 10), std::invalid_argument);
    EXPECT_THROW(simulate(p, Integrator::VelocityVerlet, 0), std::invalid_argument);
    EXPECT_THROW(springChain({1.0, -2.0}), std::invalid_argument);
    EXPECT_THROW(springChain({1.0, nan}), std::invalid_argument);
}

}  // namespace
}  // namespace gpl::study
