// The contact solvers' test scenes (framework/src/scenes_stacking.cpp): each is registered as a
// worksheet-7 scene with the friction stages, starts with its bodies exactly touching (overlap-
// recovery: overlapping, as it says) and steps a second without leaving finite numbers; the
// friction the scenes state matches the closed forms they cite. Whether the stacks stand is the
// contact solver's to test, not this file's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "gpl/collision.h"
#include "gpl/engine.h"
#include "gpl/scenes.h"

namespace gpl {
namespace {

std::vector<std::string> stackingSceneNames() {
    SceneRegistry r;
    addStackingScenes(r);
    std::vector<std::string> names;
    for (const Scene& s : r.all()) names.push_back(s.name);
    return names;
}

// The deepest overlap of any two bodies now (m), by the collision kernels.
double deepestOverlap(const PhysicsEngine& e) {
    double deepest = 0.0;
    for (std::size_t i = 0; i < e.bodies().size(); ++i) {
        for (std::size_t j = i + 1; j < e.bodies().size(); ++j) {
            if (const std::optional<Contact> c = collide(e.bodies(), i, j)) deepest = std::max(deepest, c->depth);
        }
    }
    return deepest;
}

TEST(StackingScenes, AllTheSolversTestScenesAreThere) {
    const std::vector<std::string> names = stackingSceneNames();
    for (const char* name : {"stack-10", "stack-10-offset", "stack-20", "stack-20-offset", "pyramid-10", "sphere-pyramid",
                             "sphere-pyramid-slippery", "sphere-tetrahedron", "sphere-tetrahedron-slippery", "arch",
                             "card-house", "mass-ratio", "friction-ramp", "overlap-recovery", "confined", "dominoes"}) {
        EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
    }
    for (const std::string& name : names) {
        const Scene& s = scenes().find(name);
        EXPECT_EQ(s.worksheet, 7) << name;
        EXPECT_TRUE(s.key.empty()) << name;
        EXPECT_TRUE(s.stages.contains(Stage::Friction) && s.stages.contains(Stage::Rotation)) << name;
        EXPECT_FALSE(s.description.empty()) << name;
        EXPECT_GT(s.viewDistance, 0.0) << name << ": a view hint";
    }
}

TEST(StackingScenes, BodiesStartTouchingAndStayFiniteForASecond) {
    for (const std::string& name : stackingSceneNames()) {
        PhysicsEngine e;
        load(e, scenes().find(name));
        if (name == "overlap-recovery") {
            EXPECT_GT(deepestOverlap(e), 0.1) << name << ": its cubes start a quarter of a side into each other";
        } else {
            EXPECT_LE(deepestOverlap(e), 1e-9) << name;
        }
        for (int i = 0; i < 100; ++i) ASSERT_NO_THROW(e.step()) << name << ", step " << i;
        EXPECT_TRUE(e.allFinite()) << name;
    }
}

TEST(StackingScenes, SpherePyramidsStraddleTheLeastFrictionOfTheirStatics) {
    // A lower sphere of the 3-sphere pyramid stays only for mu >= tan 15 deg; of the tetrahedron for
    // mu >= tan(asin(1/sqrt 3) / 2). The rough scenes are above, the slippery ones below.
    const double pyramid = std::tan(15.0 * M_PI / 180.0), tetrahedron = std::tan(0.5 * std::asin(1.0 / std::sqrt(3.0)));
    EXPECT_NEAR(pyramid, 0.268, 5e-4);
    EXPECT_NEAR(tetrahedron, 0.318, 5e-4);
    const auto pairMu = [](const std::string& scene) {
        PhysicsEngine e;
        load(e, scenes().find(scene));
        const Body& top = e.bodies().back();
        const Body& lower = e.bodies()[e.bodies().size() - 2];
        return combineFriction(top.staticFriction, lower.staticFriction);
    };
    EXPECT_GT(pairMu("sphere-pyramid"), pyramid);
    EXPECT_LT(pairMu("sphere-pyramid-slippery"), pyramid);
    EXPECT_GT(pairMu("sphere-tetrahedron"), tetrahedron);
    EXPECT_LT(pairMu("sphere-tetrahedron-slippery"), tetrahedron);
}

TEST(StackingScenes, RampBoxesStraddleTheSlopesAngle) {
    // On a 30 degree slope a box stays when its pair's coefficient is above tan 30 = 0.577: two of
    // the five are, three are not.
    PhysicsEngine e;
    load(e, scenes().find("friction-ramp"));
    int above = 0, below = 0;
    const Body& slope = e.body("slope");
    for (const Body& b : e.bodies()) {
        if (b.isStatic()) continue;
        EXPECT_NEAR(slope.normal.dot(b.position), b.halfExtents.y(), 1e-12) << b.name << " rests on the slope";
        (combineFriction(b.staticFriction, slope.staticFriction) > std::tan(M_PI / 6.0) ? above : below) += 1;
    }
    EXPECT_EQ(above, 2);
    EXPECT_EQ(below, 3);
}

}  // namespace
}  // namespace gpl
