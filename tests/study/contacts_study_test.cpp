// The contacts study against theory: the functions ./lab bench contacts prints are the ones tested
// here, with the reference hooks. Nothing is timed.
#include <gtest/gtest.h>

#include <cmath>

#include "contacts.h"

namespace gpl::study {
namespace {

constexpr Response kResponses[] = {Response::Positions, Response::Impulses};
constexpr int kPhases = 64;

TEST(ContactsStudy, EveryHookItNeedsIsWrittenInTheReference) { EXPECT_TRUE(openContactHooks().empty()); }

TEST(ContactsStudy, TheRulerMeasuresOverlapFromGeometry) {
    const Body a = sphere("a", 0.5, 1.0);
    const Body b = sphere("b", 0.25, 1.0).at({0.0, 0.6, 0.0});
    EXPECT_DOUBLE_EQ(overlap(a, b), 0.15);
    EXPECT_DOUBLE_EQ(overlap(b, a), 0.15);
    EXPECT_EQ(overlap(a, sphere("far", 0.25, 1.0).at({1.0, 0.0, 0.0})), 0.0);
    const Body tilted = plane("tilted", {1.0, 1.0, 0.0}).at({0.0, -0.2, 0.0});
    // Centre (0, 0, 0) lies 0.2/sqrt(2) in front of the plane.
    EXPECT_NEAR(overlap(a, tilted), 0.5 - 0.2 / std::sqrt(2.0), 1e-15);
    EXPECT_NEAR(overlap(tilted, a), 0.5 - 0.2 / std::sqrt(2.0), 1e-15);
    EXPECT_DOUBLE_EQ(largestOverlap({a, b, tilted}), 0.5 - 0.2 / std::sqrt(2.0));
}

TEST(ContactsStudy, LargestSafeSpeedMatchesTheClosedForm) {
    struct Case {
        double ra, rb, h;
    } cases[] = {{0.01, 0.01, 0.001}, {0.01, 0.1, 0.01}, {0.1, 1.0, 0.05}};
    for (Response r : kResponses) {
        for (const Case& c : cases) {
            const double theory = theoreticalSafeSpeed(c.ra, c.rb, c.h, kPhases);
            // The bisection stops at 1e-9 relative; positions round at 1e-15 relative: 1e-8 is ample.
            EXPECT_NEAR(largestSafeSpeed(r, c.ra, c.rb, c.h, kPhases), theory, 1e-8 * theory)
                << responseName(r) << ", r_a = " << c.ra << ", r_b = " << c.rb << ", h = " << c.h;
            // And the rule of thumb (r_a + r_b)/h: 64 phases put the worst one 1/128 of a step from touching.
            EXPECT_NEAR(theory, (c.ra + c.rb) / c.h, 0.01 * theory);
        }
    }
}

TEST(ContactsStudy, TunnelFractionIsOneMinusReachOverStep) {
    const double ra = 0.05, rb = 0.05, h = 0.01;
    for (Response r : kResponses) {
        for (double stepOverReach : {0.5, 0.99, 1.05, 1.5, 2.0, 3.0, 8.0, 100.0}) {
            const double v = stepOverReach * (ra + rb) / h;
            // One phase may sit within rounding of the boundary and fall either way: 1/64.
            EXPECT_NEAR(tunnelFraction(r, ra, rb, v, h, kPhases), theoreticalTunnelFraction(r, ra, rb, v, h, kPhases),
                        1.0 / kPhases + 1e-12)
                << responseName(r) << ", v h / R = " << stepOverReach;
        }
    }
    // The continuous forms at v h = 1.5 R: 1 - R/(v h) = 1/3 with impulses, twice that with positions.
    const double v = 1.5 * (ra + rb) / h;
    EXPECT_NEAR(theoreticalTunnelFraction(Response::Impulses, ra, rb, v, h, kPhases), 1.0 / 3.0, 1.0 / kPhases);
    EXPECT_NEAR(theoreticalTunnelFraction(Response::Positions, ra, rb, v, h, kPhases), 2.0 / 3.0, 1.0 / kPhases);
}

TEST(ContactsStudy, FastAndSmallBodiesFollowTheRuleAndStayFinite) {
    for (double radius : {0.001, 0.01, 0.1, 1.0}) {
        for (double speed : {1.0, 10.0, 100.0, 1000.0}) {
            const Extreme x = fastSmall(radius, speed, kPhases);
            const std::string where = "r = " + formatNumber(radius) + " m, v = " + formatNumber(speed) + " m/s";
            EXPECT_TRUE(x.finite) << where;
            EXPECT_NEAR(x.sphereFraction, x.theoryFraction, 1.0 / kPhases + 1e-12) << where;  // one boundary phase
            EXPECT_EQ(x.planeFraction, 0.0) << where << ": a plane is a half-space";
            // Restitution 1 and impulses that own the velocities: the speed comes back to rounding (1e-12).
            EXPECT_LE(x.largestEnergyRatio, 1.0 + 1e-12) << where;
        }
    }
}

TEST(ContactsStudy, StageResidualFallsLikeRhoToTheK) {
    for (Response r : kResponses) {
        const double start = r == Response::Positions ? 2e-3 : 1.0;  // m or m/s
        for (double ratio : {1.0, 10.0, 100.0, 1000.0}) {
            for (bool heavyOnTop : {true, false}) {
                const double bottom = heavyOnTop ? 1.0 : ratio, top = heavyOnTop ? ratio : 1.0;
                for (int k : {1, 2, 5, 10, 64, 300}) {
                    const double theory = theoreticalTwoSphereResidual(r, bottom, top, k);
                    // Relative 1e-9 while the residual is far above rounding (1e-12 of the start value:
                    // each sweep rounds positions near 0.5 m at 1e-16 m); below that, only bounded.
                    const double tolerance = std::max(1e-9 * theory, 1e-12 * start);
                    EXPECT_NEAR(twoSphereResidual(r, bottom, top, k), theory, tolerance)
                        << responseName(r) << ", " << bottom << ":" << top << ", " << k << " iterations";
                }
            }
        }
    }
}

TEST(ContactsStudy, ResidualOverlapOnThePileFallsWithIterations) {
    for (Response r : kResponses) {
        double previous = INFINITY;
        for (int k : {1, 2, 4, 8, 16, 32, 64}) {
            const PileRun p = pileWithIterations(r, k);
            EXPECT_LT(p.meanDepth, previous) << responseName(r) << ", " << k << " iterations";
            previous = p.meanDepth;
            EXPECT_GT(p.contactsPerStep, 45.0) << "every ball rests on something";
        }
        // 64 Gauss-Seidel sweeps: at least six orders of magnitude below what detection found.
        const PileRun p = pileWithIterations(r, 64);
        EXPECT_LT(p.meanDepth, 1e-6 * p.foundDepth) << responseName(r);
    }
    // With impulses, enough sweeps leave no contact approaching (the stage stops when none does).
    EXPECT_EQ(pileWithIterations(Response::Impulses, 64).largestApproach, 0.0);
}

TEST(ContactsStudy, OneSphereRestsExactly) {
    for (Response r : kResponses) {
        const Column c = restingColumn(r, 1, 10);
        // Detection finds g h^2 of overlap every step and the stage removes exactly that: rounding only.
        EXPECT_LT(c.jitter, 1e-12) << responseName(r);
        EXPECT_LT(std::abs(c.sink), 1e-12) << responseName(r);
        EXPECT_FALSE(c.passedThrough);
    }
}

TEST(ContactsStudy, TwoSphereColumnJittersByGHSquared) {
    const double gh2 = 9.81 * 0.01 * 0.01;  // m
    for (Response r : kResponses) {
        const Column c = restingColumn(r, 2, 64);
        // The contact vanishes once resolved, and the top sphere falls freely for one step: g h^2
        // exactly, up to rounding and the last sweep's remainder (1e-6 relative).
        EXPECT_NEAR(c.jitter, gh2, 1e-6 * gh2) << responseName(r);
        EXPECT_GT(c.sink, 0.0) << responseName(r);
        EXPECT_LT(c.sink, gh2) << responseName(r);
    }
}

TEST(ContactsStudy, LightOnHeavyRestsLikeEqualMasses) {
    const double gh2 = 9.81 * 0.01 * 0.01;  // m
    for (Response r : kResponses) {
        for (double ratio : {10.0, 100.0, 1000.0}) {
            // rho = 1/(1 + ratio): one sweep settles the pair, so the column only shows the g h^2
            // of a contact that comes and goes (1e-6 relative, as above).
            const Column c = restingColumn(r, {ratio, 1.0}, 10);
            EXPECT_NEAR(c.jitter, gh2, 1e-6 * gh2) << responseName(r) << ", " << ratio << ":1";
            EXPECT_FALSE(c.passedThrough);
        }
    }
}

}  // namespace
}  // namespace gpl::study
