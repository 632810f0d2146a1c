// Engine tests that step with the reference hooks (solutions/): an instructor's tree only; a student
// release builds the other framework tests against its stubs.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "gpl/constraints.h"
#include "gpl/engine.h"
#include "gpl/forces.h"
#include "gpl/scenes.h"

namespace gpl {
namespace {

TEST(Engine, StateRoundTripsAndBodiesCanBeRemoved) {
    PhysicsEngine e;
    e.add(sphere("a", 0.5, 1.0).at({0.0, 5.0, 0.0}));
    e.add(sphere("b", 0.5, 1.0).at({2.0, 5.0, 0.0}));
    const PhysicsEngine::State start = e.state();
    for (int i = 0; i < 10; ++i) e.step();
    ASSERT_NE(e.body("a").position, start.bodies[0].position);
    e.restore(start);
    EXPECT_EQ(e.body("a").position, start.bodies[0].position);
    EXPECT_EQ(e.stepCount(), 0u);
    EXPECT_EQ(e.time(), 0.0);
    e.remove(0);
    EXPECT_EQ(e.bodies().size(), 1u);
    EXPECT_EQ(e.bodies()[0].name, "b");
    EXPECT_THROW(e.remove(5), std::out_of_range);
}

TEST(Engine, RestoreReplaysPositionVerletExactly) {
    PhysicsEngine e;
    e.setIntegratorKind(Integrator::PositionVerlet);
    e.add(box("anchor", {0.1, 0.1, 0.1}, 1.0).makeStatic());
    e.add(sphere("bob", 0.2, 1.0).at({1.0, 0.0, 0.0}));
    e.addSpring("anchor", "bob", 40.0, 0.0, 0.5);
    for (int i = 0; i < 5; ++i) e.step();
    const PhysicsEngine::State mid = e.state();
    for (int i = 0; i < 5; ++i) e.step();
    const Vec3 first = e.body("bob").position;
    e.restore(mid);
    for (int i = 0; i < 5; ++i) e.step();
    EXPECT_EQ(e.body("bob").position, first) << "the previous positions come back with the state";
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
