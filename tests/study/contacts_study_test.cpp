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
        std::vector<PileRun> runs;
        for (int k : {1, 2, 4, 8, 16, 32, 64}) {
            runs.push_back(pileWithIterations(r, k));
            EXPECT_GT(runs.back().contactsPerStep, 45.0) << "every ball rests on something";
            // Interpenetration looks again in every sweep and hands the overlaps its moves create
            // to contacts(): no pair overlaps after the step that is not among them.
            EXPECT_EQ(runs.back().largestAnyPair, runs.back().largestDepth) << responseName(r) << ", " << k;
            // The pile is chaotic: each compiler's rounding makes a pile of its own, whose mean overlap
            // falls with the sweeps but may come out a little above the last one at a single doubling;
            // four times the sweeps leave less.
            if (runs.size() > 2) {
                EXPECT_LT(runs.back().meanDepth, runs[runs.size() - 3].meanDepth)
                    << responseName(r) << ", " << k << " iterations";
            }
        }
        // Every sweep takes overlap away; a moving pile has no closed form, and tall stacks in it
        // converge slowly (rho near 1), so ask for a factor 30 over 64 sweeps (the reference gives
        // more than 100).
        EXPECT_LT(runs.back().meanDepth, runs.front().meanDepth / 30.0) << responseName(r);
        if (r == Response::Impulses) {
            EXPECT_LT(runs.back().meanApproach, runs.front().meanApproach / 30.0);
        }
    }
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

TEST(ContactsStudy, OneSweepColumnSinksByTriangularNumbers) {
    for (int n = 2; n <= 8; ++n) {
        const Column c = restingColumn(Response::Positions, n, 1);
        const double theory = theoreticalOneSweepSink(n);
        // A tall column approaches its steady state slowly (one sweep lifts one contact a step):
        // by 5 s its mean is within 1e-6 of it and what still moves is below 1e-3 of the sink.
        EXPECT_NEAR(c.sink, theory, 1e-6 * theory) << n << " spheres";
        EXPECT_LT(c.jitter, 1e-3 * theory) << n << " spheres";
    }
}

TEST(ContactsStudy, ColumnSinkFallsWithSweeps) {
    for (Response r : kResponses) {
        double previous = INFINITY;
        for (int k : {1, 2, 4, 8, 16, 32, 64}) {
            const Column c = restingColumn(r, 6, k);
            EXPECT_FALSE(c.passedThrough) << responseName(r) << ", " << k << " iterations";
            EXPECT_LT(c.sink, previous) << responseName(r) << ", " << k << " iterations";
            previous = c.sink;
        }
    }
}

TEST(ContactsStudy, TwoSphereStackSettlesAtTheSteadyOverlap) {
    struct Case {
        double bottom, top;  // kg
        int iterations;
    } cases[] = {{1, 1, 1}, {1, 1, 2}, {1, 1, 4}, {1, 1, 10}, {1, 10, 10}, {1, 100, 10}, {1, 10, 30}};
    for (Response r : kResponses) {
        for (const Case& c : cases) {
            const Column column = restingColumn(r, {c.bottom, c.top}, c.iterations);
            const std::string where = std::string(responseName(r)) + ", " + formatNumber(c.bottom) + ":" +
                                      formatNumber(c.top) + ", " + std::to_string(c.iterations) + " iterations";
            const double sink = theoreticalStackSink(r, c.bottom, c.top, c.iterations);
            // The steady state is reached within 5 s in every case here; 1e-4 relative covers the
            // rest of the approach and rounding (1e-15 m at 0.5 m).
            EXPECT_NEAR(column.sink, sink, 1e-4 * sink + 1e-14) << where;
            EXPECT_LT(column.jitter, 1e-4 * sink + 1e-14) << where << ": a steady state does not move";
            if (r == Response::Impulses) {
                const double speed = theoreticalStackSpeed(r, c.bottom, c.top, c.iterations);
                EXPECT_NEAR(column.largestSpeed, speed, 1e-4 * speed + 1e-14) << where;
            }
        }
    }
    // Light on heavy: one sweep all but settles the pair, nothing is left to sink.
    for (Response r : kResponses) {
        EXPECT_LT(restingColumn(r, {1000.0, 1.0}, 10).sink, 1e-12) << responseName(r);
    }
}

}  // namespace
}  // namespace gpl::study
