// The rotation stage and angular momentum in the engine, stepped with the reference hooks
// (solutions/): a scene turns its bodies only when it declares the stage, static bodies never turn,
// and a state that is no longer finite names integrateRotation().
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "gpl/engine.h"
#include "gpl/rotation.h"
#include "gpl/scenes.h"

namespace gpl {
namespace {

TEST(RotationEngine, TurnsOnlyWhenTheSceneDeclaresRotation) {
    for (const bool declared : {false, true}) {
        PhysicsEngine e;
        e.setGravity(Vec3::Zero());
        e.setRequiredStages(declared ? StageSet{Stage::Integration, Stage::Rotation} : StageSet{Stage::Integration});
        e.add(box("spinner", {0.2, 0.4, 0.8}, 1.0).spinning({0.3, 2.0, 0.1}));
        e.add(box("wall", {1.0, 1.0, 0.1}, 1.0).at({3.0, 0.0, 0.0}).makeStatic());
        const std::vector<Body> start = e.bodies();
        for (int i = 0; i < 50; ++i) e.step();
        const Body& spinner = e.body("spinner");
        EXPECT_EQ(spinner.orientation.coeffs() != start[0].orientation.coeffs(), declared);
        EXPECT_EQ(e.body("wall").orientation.coeffs(), start[1].orientation.coeffs());
        EXPECT_EQ(e.body("wall").angularVelocity, Vec3::Zero());
    }
}

TEST(RotationEngine, SpheresBounceAlikeWithOrWithoutRotation) {
    // A sphere's contact points lie on the line of the centres along the normal, so the impulse at
    // the point (rotation declared) is worksheet 4's at the centres (not declared): the same bounces.
    std::vector<std::vector<Body>> runs;
    for (const bool declared : {false, true}) {
        PhysicsEngine e;
        StageSet stages{Stage::ConstantAcceleration, Stage::Integration, Stage::CollisionDetection,
                        Stage::Interpenetration, Stage::CollisionImpulses};
        if (declared) stages.insert(Stage::Rotation);
        e.setRequiredStages(stages);
        e.add(plane("floor", {0.0, 1.0, 0.0}));
        e.add(sphere("a", 0.3, 1.0).at({0.0, 1.0, 0.0}).moving({1.0, 0.0, 0.0}).bouncy(0.7));
        e.add(sphere("b", 0.4, 2.0).at({1.5, 2.0, 0.1}).moving({-1.0, 0.0, 0.0}).bouncy(0.9));
        for (int i = 0; i < 300; ++i) e.step();
        runs.push_back(e.bodies());
    }
    for (std::size_t i = 1; i < runs[0].size(); ++i) {
        EXPECT_LE((runs[0][i].position - runs[1][i].position).norm(), 1e-9) << runs[0][i].name;
        EXPECT_LE((runs[0][i].velocity - runs[1][i].velocity).norm(), 1e-9) << runs[0][i].name;
        // r x n of a sphere's contact is zero up to the rounding of the contact point (~1e-16 m).
        EXPECT_LE(runs[1][i].angularVelocity.norm(), 1e-12) << runs[0][i].name << " started to turn";
    }
}

TEST(RotationEngine, BoxDroppedOnACornerStartsTurning) {
    PhysicsEngine e;
    load(e, scenes().find("corner-drop"));
    const Body start = e.body("box");
    double turnedBy = 0.0;  // rad, the most the orientation has turned away from the start
    for (int i = 0; i < 300; ++i) {
        e.step();
        const Body& b = e.body("box");
        turnedBy = std::max(turnedBy, b.orientation.angularDistance(start.orientation));
        // Every impulse of a floor without friction is vertical: the horizontal momentum stays zero.
        ASSERT_LE(std::hypot(b.velocity.x(), b.velocity.z()), 1e-9) << "step " << i + 1;
    }
    EXPECT_GT(turnedBy, 0.3) << "the corner's impulse did not turn the box";
    EXPECT_LT(e.body("box").position.y(), 0.45) << "the box did not come down onto the floor";
}

TEST(RotationEngine, AngularMomentumAboutTheOrigin) {
    PhysicsEngine e;
    e.add(sphere("a", 0.5, 2.0).at({1.0, 0.0, 0.0}).moving({0.0, 3.0, 0.0}));
    e.add(box("b", {0.5, 0.5, 0.5}, 3.0).spinning({0.0, 0.0, 2.0}));
    e.add(box("fixed", {1.0, 1.0, 1.0}, 1.0).at({0.0, 5.0, 0.0}).makeStatic());
    // x × m v = (1, 0, 0) × (0, 6, 0) = (0, 0, 6); the cube's I = m (2 * 0.25) / 3 = 0.5, times 2 rad/s.
    const Vec3 expected(0.0, 0.0, 6.0 + 1.0);
    EXPECT_LE((e.angularMomentum() - expected).norm(), 1e-12 * expected.norm());
    EXPECT_EQ(angularMomentum(e.body("fixed")), Vec3::Zero());
}

TEST(RotationEngine, NonFiniteRotationNamesTheHook) {
    PhysicsEngine e;
    e.setRequiredStages({Stage::Integration, Stage::Rotation});
    e.add(box("box", {0.2, 0.4, 0.8}, 1.0).spinning({1.0, 0.0, 0.0}));
    e.body("box").torque = Vec3(std::numeric_limits<double>::infinity(), 0.0, 0.0);  // N m: a broken force model
    try {
        for (int i = 0; i < 3; ++i) e.step();
        FAIL() << "no SimulationError";
    } catch (const SimulationError& error) {
        const std::string message = error.what();
        EXPECT_NE(message.find("'box'"), std::string::npos) << message;
        EXPECT_NE(message.find("integrateRotation()"), std::string::npos) << message;
    }
}

TEST(RotationEngine, RotationScenesDeclareTheirStagesAndViews) {
    int turning = 0;
    for (const Scene& s : scenes().all()) {
        if (s.worksheet != 6) continue;
        ++turning;
        EXPECT_TRUE(s.stages.contains(Stage::Rotation)) << s.name;
        EXPECT_GT(s.viewDistance, 0.0) << s.name << ": a view hint";
    }
    EXPECT_GE(turning, 1);
}

}  // namespace
}  // namespace gpl
