// The rotation stage and angular momentum in the engine, stepped with the reference hooks
// (solutions/): a scene turns its bodies only when it declares the stage, static bodies never turn,
// and a state that is no longer finite names integrateRotation().
#include <gtest/gtest.h>

#include <limits>
#include <string>

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
