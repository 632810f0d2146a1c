#include "gpl/scenes.h"

#include <gtest/gtest.h>

#include <limits>
#include <sstream>

#include "gpl/runner.h"

namespace gpl {
namespace {

TEST(Scenes, WorksheetOneScenesExistAndLoad) {
    for (const char* name : {"falling-sphere", "masses", "projectile", "static-and-movable"}) {
        const Scene& s = scenes().find(name);
        EXPECT_EQ(s.worksheet, 1) << name;
        EXPECT_FALSE(s.description.empty()) << name;
        PhysicsEngine e;
        load(e, s);
        EXPECT_FALSE(e.bodies().empty()) << name;
        EXPECT_TRUE(e.requiredStages().contains(Stage::Integration)) << name;
    }
}

TEST(Scenes, MassesSceneSpansFourOrdersOfMagnitude) {
    PhysicsEngine e;
    load(e, scenes().find("masses"));
    double lightest = 1e300, heaviest = 0.0;
    int spheres = 0, boxes = 0;
    for (const Body& b : e.bodies()) {
        lightest = std::min(lightest, b.mass);
        heaviest = std::max(heaviest, b.mass);
        spheres += b.shape == Shape::Sphere;
        boxes += b.shape == Shape::Box;
    }
    EXPECT_GE(heaviest / lightest, 1e4);
    EXPECT_GT(spheres, 0);
    EXPECT_GT(boxes, 0);
}

TEST(Scenes, FoundByKeyCaseInsensitive) {
    EXPECT_EQ(scenes().find("1").name, "falling-sphere");
    EXPECT_EQ(scenes().find("f11").key, "F11");
}

TEST(Scenes, UnknownSceneListsTheKnownOnes) {
    try {
        scenes().find("no-such-scene");
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("no-such-scene"), std::string::npos);
        EXPECT_NE(msg.find("falling-sphere"), std::string::npos);
    }
}

TEST(Scenes, RegistryRejectsDuplicatesAndBadKeys) {
    SceneRegistry r;
    r.add({"a", "1", "first", 1, {}, kDefaultTimeStep, nullptr});
    EXPECT_THROW(r.add({"a", "2", "same name", 1, {}, kDefaultTimeStep, nullptr}), std::invalid_argument);
    EXPECT_THROW(r.add({"b", "1", "same key", 1, {}, kDefaultTimeStep, nullptr}), std::invalid_argument);
    EXPECT_THROW(r.add({"c", "F13", "no such key", 1, {}, kDefaultTimeStep, nullptr}), std::invalid_argument);
}

TEST(Scenes, LaterCourseScenesHaveNoKey) {
    SceneRegistry r;
    EXPECT_NO_THROW(r.add({"one", "", "a course scene without a key", 7, {}, kDefaultTimeStep, nullptr}));
    EXPECT_NO_THROW(r.add({"two", "", "another", 7, {}, kDefaultTimeStep, nullptr}));
    EXPECT_THROW(r.add({"mine", "", "a student scene needs F11 or F12", 0, {}, kDefaultTimeStep, nullptr}),
                 std::invalid_argument);
    EXPECT_EQ(r.find("two").name, "two");
    EXPECT_THROW(r.find(""), std::invalid_argument);  // an empty key names no scene
    for (const char* name : {"incline", "rolling-ball", "box-stack", "corner-landing"}) {
        const Scene& s = scenes().find(name);
        EXPECT_EQ(s.worksheet, 7) << name;
        EXPECT_TRUE(s.stages.contains(Stage::Friction)) << name;
    }
}

TEST(Scenes, F11AndF12AreTheStudentsOwn) {
    SceneRegistry r;
    EXPECT_THROW(r.add({"course", "F11", "a course scene", 1, {}, kDefaultTimeStep, nullptr}), std::invalid_argument);
    EXPECT_THROW(r.add({"mine", "5", "a student scene", 0, {}, kDefaultTimeStep, nullptr}), std::invalid_argument);
    EXPECT_NO_THROW(r.add({"mine", "F12", "a student scene", 0, {}, kDefaultTimeStep, nullptr}));
    for (const Scene& s : scenes().all()) {
        EXPECT_EQ(s.worksheet == 0, s.key == "F11" || s.key == "F12") << s.name;
    }
}

TEST(Scenes, LoadResetsTheEngine) {
    PhysicsEngine e;
    e.setTimeStep(0.5);
    e.setGravity(Vec3::Zero());
    e.add(sphere("left-over", 1.0, 1.0));
    load(e, scenes().find("falling-sphere"));
    EXPECT_EQ(e.timeStep(), kDefaultTimeStep);
    EXPECT_EQ(e.gravity(), standardGravity());
    EXPECT_THROW(e.body("left-over"), std::out_of_range);
    EXPECT_EQ(e.time(), 0.0);
}

TEST(Runner, WritesOneRowPerBodyAndStepPlusWorld) {
    PhysicsEngine e;
    load(e, scenes().find("static-and-movable"));
    std::ostringstream csv;
    writeCsvHeader(csv);
    const RunSummary s = run(e, 10, &csv);
    EXPECT_EQ(s.steps, 10u);
    std::istringstream lines(csv.str());
    std::string line;
    int rows = -1;  // the header
    while (std::getline(lines, line)) ++rows;
    EXPECT_EQ(rows, 11 * static_cast<int>(e.bodies().size() + 1));
    EXPECT_NE(describe(s, e).find("total energy"), std::string::npos);
}

TEST(Runner, ReportsANonFiniteStateInsteadOfThrowing) {
    PhysicsEngine e;
    e.add(sphere("ball", 0.5, 1.0));
    e.setRequiredStages({});  // keeps the reference integrator's assertions (Debug builds) out of it
    e.bodies()[0].velocity.y() = std::numeric_limits<double>::infinity();
    const RunSummary s = run(e, 5, nullptr);
    EXPECT_EQ(s.steps, 0u);
    EXPECT_NE(s.error.find("ball"), std::string::npos);
}

}  // namespace
}  // namespace gpl
