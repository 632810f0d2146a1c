// The engine's worksheet-2 parts: integrator choice, springs, constraints, the scenes.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "gpl/constraints.h"
#include "gpl/engine.h"
#include "gpl/forces.h"
#include "gpl/scenes.h"

namespace gpl {
namespace {

TEST(Integrators, NamesAndIdsRoundTrip) {
    for (Integrator m : kIntegrators) {
        EXPECT_EQ(integratorFromId(integratorId(m)), m);
        EXPECT_EQ(integratorFromId(integratorName(m)), m);
    }
    try {
        integratorFromId("leapfrog");
        ADD_FAILURE() << "unknown integrator accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("position-verlet"), std::string::npos) << e.what();
    }
}

TEST(Kernels, SpringForceIsHookeWithDamping) {
    // Stretched by 0.5 m along x, k = 10 N/m: 5 N pulling a back towards b.
    EXPECT_TRUE(
        springForce({1.5, 0, 0}, {0, 0, 0}, Vec3::Zero(), Vec3::Zero(), 10.0, 1.0, 0.0).isApprox(Vec3(-5.0, 0.0, 0.0)));
    // Damping opposes the relative velocity along the spring only: 2 N s/m * 3 m/s; sideways motion ignored.
    EXPECT_TRUE(springForce({1.0, 0, 0}, {0, 0, 0}, {3.0, 7.0, 0.0}, Vec3::Zero(), 10.0, 1.0, 2.0)
                    .isApprox(Vec3(-6.0, 0.0, 0.0)));
    EXPECT_EQ(springForce(Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), 10.0, 1.0, 0.0), Vec3::Zero());
    EXPECT_DOUBLE_EQ(springEnergy({0, 2.0, 0}, Vec3::Zero(), 10.0, 1.0), 5.0);
}

TEST(Kernels, DistanceProjectionSharesByInverseMass) {
    Vec3 a(0, 0, 0), b(3, 0, 0);
    projectDistance(a, b, 1.0, 0.5, 1.5);  // 1.5 m too long; a moves 1 m, b 0.5 m
    EXPECT_TRUE(a.isApprox(Vec3(1.0, 0, 0)));
    EXPECT_TRUE(b.isApprox(Vec3(2.5, 0, 0)));
    Vec3 pivot(0, 0, 0), bob(0, -3, 0);
    projectDistance(pivot, bob, 0.0, 1.0, 2.0);
    EXPECT_EQ(pivot, Vec3::Zero());
    EXPECT_TRUE(bob.isApprox(Vec3(0, -2, 0)));
}

TEST(Kernels, ContainerAndSphereSeparation) {
    Vec3 x(0, 10, 0);
    keepInside(x, 0.5, Container{Vec3::Zero(), 5.0});
    EXPECT_TRUE(x.isApprox(Vec3(0, 4.5, 0)));
    Vec3 inside(1, 1, 0);
    keepInside(inside, 0.5, Container{Vec3::Zero(), 5.0});
    EXPECT_EQ(inside, Vec3(1, 1, 0));
    Vec3 a(0, 0, 0), b(0.6, 0, 0);
    separateSpheres(a, b, 0.5, 0.5, 1.0, 1.0);
    EXPECT_NEAR((a - b).norm(), 1.0, 1e-12);
    EXPECT_NEAR(a.x(), -0.2, 1e-12);
}

TEST(Engine, IntegratorIsChosenPerSceneAndAtRunTime) {
    PhysicsEngine e;
    EXPECT_EQ(e.integratorKind(), Integrator::SemiImplicitEuler);
    load(e, scenes().find("pendulum"));
    EXPECT_EQ(e.integratorKind(), Integrator::PositionVerlet);
    // The same spring scene with every integrator: all run and only the chosen one moves it differently.
    std::vector<Vec3> ends;
    for (Integrator m : kIntegrators) {
        load(e, scenes().find("spring-oscillator"));
        e.setIntegratorKind(m);
        for (int i = 0; i < 200; ++i) e.step();
        ends.push_back(e.body("undamped").position);
    }
    for (std::size_t i = 1; i < ends.size(); ++i) {
        // 2 s of a 1 s-period oscillator: the methods differ by at least their O(h) error (1e-4 m).
        EXPECT_NE(ends[i], ends[0]);
        // Explicit Euler's amplitude grows by exp(n (h omega)^2 / 2) = 1.5 over these 200 steps: 0.25 m.
        EXPECT_LT((ends[i] - ends[0]).norm(), 0.5) << integratorName(kIntegrators[i]) << " strays far";
    }
}

TEST(Engine, SpringsAndConstraintsAreCheckedWhenAdded) {
    PhysicsEngine e;
    e.add(sphere("a", 0.1, 1.0));
    e.add(sphere("b", 0.1, 1.0).at({1, 0, 0}));
    e.add(sphere("wall", 0.1, 1.0).at({2, 0, 0}).makeStatic());
    e.add(sphere("wall2", 0.1, 1.0).at({3, 0, 0}).makeStatic());
    EXPECT_THROW(e.addSpring("a", "nobody", 10.0), std::invalid_argument);
    EXPECT_THROW(e.addSpring("a", "a", 10.0), std::invalid_argument);
    EXPECT_THROW(e.addSpring("wall", "wall2", 10.0), std::invalid_argument);
    EXPECT_THROW(e.addSpring("a", "b", 0.0), std::invalid_argument);
    EXPECT_THROW(e.addSpring("a", "b", std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
    EXPECT_THROW(e.addSpring("a", "b", 10.0, -1.0), std::invalid_argument);
    EXPECT_THROW(e.setContainer(Vec3::Zero(), 0.0), std::invalid_argument);
    EXPECT_THROW(e.setConstraintIterations(0), std::invalid_argument);
    EXPECT_EQ(e.addSpring("a", "b", 10.0), 0u);
    EXPECT_DOUBLE_EQ(e.springs()[0].restLength, 1.0);
    EXPECT_EQ(e.addDistanceConstraint("b", "wall"), 0u);
}

TEST(Engine, PendulumRodKeepsItsLength) {
    PhysicsEngine e;
    load(e, scenes().find("pendulum"));
    const double length = e.distanceConstraints()[0].length;
    double lowest = e.body("bob").position.y();
    for (int i = 0; i < 300; ++i) {
        e.step();
        // Projection against a static pivot is exact up to rounding.
        EXPECT_NEAR((e.body("bob").position - e.body("pivot").position).norm(), length, 1e-9 * length);
        lowest = std::min(lowest, e.body("bob").position.y());
    }
    EXPECT_LT(lowest, 3.01) << "the bob should swing through the bottom (y = 3 m)";
}

TEST(Engine, ContainerKeepsEveryBallInsideAndApart) {
    PhysicsEngine e;
    load(e, scenes().find("container"));
    ASSERT_GE(e.bodies().size(), 200u);
    for (int i = 0; i < 300; ++i) e.step();
    const Container& c = *e.container();
    double worstOverlap = 0.0;
    for (std::size_t i = 0; i < e.bodies().size(); ++i) {
        const Body& a = e.bodies()[i];
        // The container is projected last in each sweep: inside up to rounding.
        EXPECT_LE((a.position - c.centre).norm() + a.radius, c.radius * (1.0 + 1e-12)) << a.name;
        for (std::size_t j = i + 1; j < e.bodies().size(); ++j) {
            const Body& b = e.bodies()[j];
            worstOverlap = std::max(worstOverlap, a.radius + b.radius - (a.position - b.position).norm());
        }
    }
    // Four Gauss-Seidel sweeps leave small overlaps in a heap of 300: below a fifth of a radius.
    EXPECT_LT(worstOverlap, 0.2 * e.bodies()[0].radius);
    EXPECT_LT(e.body("ball0").position.y(), 9.5) << "the balls should have fallen";
}

TEST(Engine, UndampedSpringConservesEnergyWithVerlet) {
    PhysicsEngine e;
    load(e, scenes().find("spring-oscillator"));
    e.setStageEnabled(Stage::Springs, true);
    const double e0 = e.totalEnergy();
    // The damped spring loses energy; check the scene's energy never rises by more than Verlet's
    // bounded oscillation (h omega = 0.06: relative (h omega)^2 ~ 4e-3 of the oscillating part).
    double highest = e0;
    for (int i = 0; i < 1000; ++i) {
        e.step();
        highest = std::max(highest, e.totalEnergy());
    }
    EXPECT_LT(highest - e0, 1e-2 * std::abs(e0));
    EXPECT_LT(e.totalEnergy(), e0) << "the damped spring should have taken energy out";
}

}  // namespace
}  // namespace gpl
