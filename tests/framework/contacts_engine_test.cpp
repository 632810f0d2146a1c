// The engine's contact parts that do not depend on what the hooks compute: bad input, ropes,
// settings, and stages a scene does not require.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "gpl/collision.h"
#include "gpl/engine.h"
#include "gpl/scenes.h"

namespace gpl {
namespace {

// The message of the std::invalid_argument that f throws ("" when it throws none).
template <class F>
std::string errorOf(F f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

void expectMentions(const std::string& message, const std::string& a, const std::string& b) {
    EXPECT_NE(message.find(a), std::string::npos) << message;
    EXPECT_NE(message.find(b), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
}

TEST(ContactInput, RestitutionOutsideZeroToOneNamesBodyAndField) {
    for (double e : {-0.1, 1.5, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
        PhysicsEngine engine;
        expectMentions(errorOf([&] { engine.add(sphere("rubber", 0.5, 1.0).bouncy(e)); }), "rubber", "restitution");
        EXPECT_TRUE(engine.bodies().empty());
    }
    PhysicsEngine engine;
    EXPECT_NO_THROW(engine.add(sphere("plastic", 0.5, 1.0).bouncy(0.0)));
    EXPECT_NO_THROW(engine.add(sphere("elastic", 0.5, 1.0).bouncy(1.0)));
}

TEST(ContactInput, BadRadiusAndPlaneNormal) {
    for (double r : {-1.0, 0.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
        expectMentions(errorOf([&] { sphere("marble", r, 1.0); }), "marble", "radius");
        Body b = sphere("marble", 1.0, 1.0);
        b.radius = r;  // set behind the factory's back: the engine still refuses it
        PhysicsEngine engine;
        expectMentions(errorOf([&] { engine.add(b); }), "marble", "radius");
    }
    expectMentions(errorOf([] { plane("floor", Vec3::Zero()); }), "floor", "normal");
    Body p = plane("floor", Vec3::UnitY());
    p.normal = Vec3::Zero();
    PhysicsEngine engine;
    expectMentions(errorOf([&] { engine.add(p); }), "floor", "normal");
}

TEST(ContactInput, DuplicateNamesAreRefused) {
    PhysicsEngine engine;
    engine.add(sphere("twin", 0.5, 1.0));
    expectMentions(errorOf([&] { engine.add(plane("twin", Vec3::UnitY())); }), "twin", "already exists");
    EXPECT_EQ(engine.bodies().size(), 1u);
}

TEST(ContactInput, BadRopes) {
    PhysicsEngine engine;
    engine.add(sphere("anchor", 0.1, 1.0).at({0, 5, 0}).makeStatic());
    engine.add(sphere("hook", 0.1, 1.0).at({0, 6, 0}).makeStatic());
    engine.add(sphere("ball", 0.5, 1.0).at({0, 3, 0}));
    for (double length : {-2.0, 0.0, std::numeric_limits<double>::quiet_NaN()}) {
        expectMentions(errorOf([&] { engine.addRope("anchor", "ball", length); }), "rope 'anchor'-'ball'", "length");
    }
    expectMentions(errorOf([&] { engine.addRope("anchor", "ball", 1.5); }), "rope", "shorter than");
    expectMentions(errorOf([&] { engine.addRope("ball", "ball", 3.0); }), "rope", "two different bodies");
    expectMentions(errorOf([&] { engine.addRope("anchor", "hook", 3.0); }), "rope", "both are static");
    expectMentions(errorOf([&] { engine.addRope("anchor", "nobody", 3.0); }), "nobody", "no body");
    EXPECT_TRUE(engine.ropes().empty());
    EXPECT_EQ(engine.addRope("anchor", "ball"), 0u);  // the current distance, 2 m
    EXPECT_DOUBLE_EQ(engine.ropes()[0].length, 2.0);
    EXPECT_EQ(engine.addRope("hook", "ball", 4.0), 1u);
}

TEST(ContactInput, ContactIterationsAtLeastOne) {
    PhysicsEngine engine;
    EXPECT_EQ(engine.contactIterations(), 10);
    expectMentions(errorOf([&] { engine.setContactIterations(0); }), "contact iterations", "at least 1");
    engine.setContactIterations(3);
    EXPECT_EQ(engine.contactIterations(), 3);
}

TEST(ContactInput, InterpenetrationIterationsFollowTheContactIterationsUnlessSet) {
    PhysicsEngine engine;
    EXPECT_EQ(engine.interpenetrationIterations(), 10);
    engine.setContactIterations(6);
    EXPECT_EQ(engine.interpenetrationIterations(), 6) << "not set: as many as the contact iterations";
    engine.setInterpenetrationIterations(2);
    EXPECT_EQ(engine.interpenetrationIterations(), 2);
    EXPECT_EQ(engine.contactIterations(), 6) << "the impulses' sweeps stay";
    expectMentions(errorOf([&] { engine.setInterpenetrationIterations(-1); }), "interpenetration iterations",
                   "at least 1");
    EXPECT_EQ(engine.interpenetrationIterations(), 2) << "a refused setting changes nothing";
    engine.setInterpenetrationIterations(0);
    EXPECT_EQ(engine.interpenetrationIterations(), 6) << "0: as many as the contact iterations again";
    engine.setInterpenetrationIterations(2);
    load(engine, scenes().find("box-stack"));
    EXPECT_EQ(engine.interpenetrationIterations(), engine.contactIterations()) << "a scene starts from the defaults";
}

TEST(ContactEngine, RemovingABodyTakesItsRopesAlongAndRenumbersTheRest) {
    PhysicsEngine engine;
    engine.add(sphere("a", 0.1, 1.0).at({0, 0, 0}));
    engine.add(sphere("b", 0.1, 1.0).at({1, 0, 0}));
    engine.add(sphere("c", 0.1, 1.0).at({2, 0, 0}));
    engine.addRope("a", "b");
    engine.addRope("b", "c");
    engine.addRope("a", "c");
    engine.remove(1);
    ASSERT_EQ(engine.ropes().size(), 1u);
    EXPECT_EQ(engine.ropes()[0].a, 0u);
    EXPECT_EQ(engine.ropes()[0].b, 1u);
    engine.clear();
    EXPECT_TRUE(engine.ropes().empty());
}

TEST(ContactEngine, RestitutionOfAPairIsTheProduct) {
    EXPECT_DOUBLE_EQ(combineRestitution(0.5, 0.8), 0.4);
    EXPECT_DOUBLE_EQ(combineRestitution(0.7, 1.0), 0.7);  // a plane's default
    EXPECT_DOUBLE_EQ(plane("floor", Vec3::UnitY()).restitution, 1.0);
}

TEST(ContactEngine, CollidePutsTheSphereFirstAndLeavesStaticPairsAlone) {
    // Which kernel collide() picks does not depend on what the kernels compute: with the stubs
    // there is no contact at all, so only the pairs that must never collide are checked here.
    std::vector<Body> bodies = {plane("floor", Vec3::UnitY()), sphere("pillar", 1.0, 1.0).makeStatic()};
    EXPECT_FALSE(collide(bodies, 0, 1));
    EXPECT_FALSE(collide(bodies, 1, 0));
}

TEST(ContactEngine, ScenesWithoutContactStagesFindNoContacts) {
    // A worksheet-1 scene with a floor and falling bodies: no contact stage, so no contacts and the
    // bodies fall through the floor (contacts cost nothing where a scene does not ask for them).
    PhysicsEngine engine;
    load(engine, scenes().find("static-and-movable"));
    EXPECT_FALSE(engine.requiredStages().contains(Stage::CollisionDetection));
    for (int i = 0; i < 300; ++i) engine.step();
    EXPECT_TRUE(engine.contacts().empty());
}

TEST(ContactEngine, ContactScenesDeclareTheirStagesAndViews) {
    int contactScenes = 0;
    for (const Scene& s : scenes().all()) {
        if (s.worksheet != 3 && s.worksheet != 4) continue;
        ++contactScenes;
        EXPECT_TRUE(s.stages.contains(Stage::CollisionDetection)) << s.name;
        EXPECT_TRUE(s.stages.contains(Stage::Interpenetration)) << s.name;
        EXPECT_EQ(s.stages.contains(Stage::CollisionImpulses), s.worksheet == 4) << s.name;
        EXPECT_GT(s.viewDistance, 0.0) << s.name << ": a view hint";
        PhysicsEngine engine;
        load(engine, s);
        EXPECT_EQ(engine.ropes().empty(), !s.stages.contains(Stage::Ropes)) << s.name;
    }
    EXPECT_GE(contactScenes, 6);
}

}  // namespace
}  // namespace gpl
