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

}  // namespace
}  // namespace gpl
