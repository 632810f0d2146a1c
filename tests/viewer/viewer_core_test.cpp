// The viewer's GL-free parts: camera, fixed-step clock, history, picking, the shapes drawn besides
// the bodies (walls, ropes, contact normals), what is drawn of cloth, ropes, soft bodies and fluids,
// and the session that keys and mouse drive.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "camera.h"
#include "clock.h"
#include "fluid_shapes.h"
#include "history.h"
#include "picking.h"
#include "scene_shapes.h"
#include "session.h"
#include "soft_shapes.h"

namespace gpl::viewer {
namespace {

TEST(Camera, RayThroughTheCentreIsTheViewDirection) {
    Camera c;
    const Ray r = c.rayThrough(640, 360, 1280, 720);
    EXPECT_TRUE(r.direction.isApprox(c.forward(), 1e-12));
    EXPECT_TRUE(r.origin.isApprox(c.eye(), 1e-12));
}

TEST(Camera, ProjectInvertsRayThrough) {
    Camera c;
    c.orbit(120, -40);
    for (const auto& [x, y] : {std::pair{10.0, 20.0}, {640.0, 360.0}, {1200.0, 700.0}}) {
        const Ray r = c.rayThrough(x, y, 1280, 720);
        double px = 0, py = 0;
        ASSERT_TRUE(c.project(r.origin + 7.0 * r.direction, 1280, 720, px, py));
        EXPECT_NEAR(px, x, 1e-6);
        EXPECT_NEAR(py, y, 1e-6);
    }
    double px, py;
    EXPECT_FALSE(c.project(c.eye() - c.forward(), 1280, 720, px, py)) << "a point behind the eye";
}

TEST(Camera, OrbitKeepsTheTargetAndDistancePanMovesBoth) {
    Camera c;
    const Vec3 target = c.target();
    const double d = c.distance();
    c.orbit(200, 50);
    EXPECT_EQ(c.target(), target);
    EXPECT_NEAR((c.eye() - c.target()).norm(), d, 1e-9);
    const Vec3 eye = c.eye();
    c.pan(100, 0, 720);
    EXPECT_NEAR((c.target() - target).dot(c.forward()), 0.0, 1e-9) << "pan moves across the view";
    EXPECT_GT((c.eye() - eye).norm(), 0.1);
    c.zoom(3);
    EXPECT_LT(c.distance(), d);
    for (int i = 0; i < 200; ++i) c.zoom(5);
    EXPECT_GE(c.distance(), 0.5);
}

TEST(Camera, FlyMovesAlongTheViewAndLookTurnsAboutTheEye) {
    Camera c;
    c.setFlying(true);
    const Vec3 eye = c.eye();
    c.move(Vec3(0.0, 0.0, 2.0));
    EXPECT_TRUE((c.eye() - eye).isApprox(2.0 * c.forward(), 1e-9));
    const Vec3 before = c.eye();
    c.look(80, 30);
    EXPECT_TRUE(c.eye().isApprox(before, 1e-9));
}

TEST(Camera, FrameShowsEveryBody) {
    const std::vector<Body> bodies = {sphere("a", 0.5, 1.0).at({-30.0, 2.0, 5.0}),
                                      box("b", {1.0, 1.0, 1.0}, 1.0).at({25.0, 40.0, -10.0}),
                                      plane("p", Vec3::UnitY())};
    Camera c;
    c.frame(bodies);
    for (const Body& b : bodies) {
        if (b.shape == Shape::Plane) continue;
        double x, y;
        ASSERT_TRUE(c.project(b.position, 1280, 720, x, y)) << b.name;
        EXPECT_TRUE(x > 0 && x < 1280 && y > 0 && y < 720) << b.name << " at " << x << ", " << y;
    }
}

TEST(Clock, BanksTimeWithoutLosingAny) {
    FixedStepClock clock;
    const double h = 0.01;
    int steps = 0;
    double real = 0.0;
    for (double frame : {0.016, 0.033, 0.004, 0.1, 0.0071}) {
        steps += clock.advance(frame, 1.0, h, 64);
        real += frame;
    }
    // Every second of real time is either stepped or still banked (to rounding).
    EXPECT_NEAR(steps * h + clock.banked(), real, 1e-12);
    EXPECT_LT(clock.banked(), h);
    EXPECT_EQ(clock.dropped(), 0.0);
}

TEST(Clock, SpeedScalesAndTheCapDropsInsteadOfSpiralling) {
    FixedStepClock clock;
    EXPECT_EQ(clock.advance(0.1, 0.5, 0.01, 64), 5);
    clock.reset();
    EXPECT_EQ(clock.advance(2.0, 1.0, 0.01, 64), 64);
    EXPECT_NEAR(clock.dropped(), 2.0 - 0.64, 1e-9);
    EXPECT_EQ(clock.advance(-1.0, 1.0, 0.01, 64), 0);
    EXPECT_EQ(clock.advance(0.1, 1.0, 0.0, 64), 0);
}

TEST(History, KeepsTheNewestWithinItsBudget) {
    PhysicsEngine e;
    for (int i = 0; i < 10; ++i) e.add(sphere("s" + std::to_string(i), 0.5, 1.0));
    const std::size_t one = History::bytesOf(e.state());
    History h(5 * one);
    for (int i = 0; i < 8; ++i) {
        e.step();
        h.push(e.state());
    }
    EXPECT_EQ(h.size(), 5u);
    EXPECT_LE(h.bytes(), h.budget());
    PhysicsEngine::State s;
    ASSERT_TRUE(h.pop(s));
    EXPECT_EQ(s.steps, 8u) << "the newest comes out first";
    while (h.pop(s)) {
    }
    EXPECT_EQ(s.steps, 4u) << "the oldest kept is the fifth newest";
    EXPECT_EQ(h.bytes(), 0u);
    History tiny(one / 2);
    tiny.push(e.state());
    EXPECT_EQ(tiny.size(), 0u) << "a state larger than the budget is not kept";
}

TEST(Picking, SpheresAndBoxesButNotPlanes) {
    const Ray down{Vec3(0.0, 10.0, 0.0), Vec3(0.0, -1.0, 0.0)};
    EXPECT_NEAR(*intersect(sphere("s", 1.0, 1.0).at({0.0, 2.0, 0.0}), down), 7.0, 1e-12);
    EXPECT_FALSE(intersect(sphere("s", 1.0, 1.0).at({3.0, 2.0, 0.0}), down));
    EXPECT_NEAR(*intersect(box("b", {1.0, 2.0, 1.0}, 1.0).at({0.0, 2.0, 0.0}), down), 6.0, 1e-12);
    // Turned 45 degrees about z, the box's corner points up: sqrt(2) above its centre.
    const Body turned = box("t", {1.0, 1.0, 1.0}, 1.0).rotated(Quat(Eigen::AngleAxisd(M_PI / 4, Vec3::UnitZ())));
    EXPECT_NEAR(*intersect(turned, down), 10.0 - std::sqrt(2.0), 1e-9);
    EXPECT_FALSE(intersect(plane("p", Vec3::UnitY()), down));
    const std::vector<Body> bodies = {sphere("far", 1.0, 1.0).at({0.0, 0.0, 0.0}),
                                      sphere("near", 1.0, 1.0).at({0.0, 5.0, 0.0})};
    EXPECT_EQ(pick(bodies, down)->index, 1u);
    EXPECT_FALSE(pick(bodies, Ray{Vec3(0.0, 10.0, 0.0), Vec3(0.0, 1.0, 0.0)}));
}

class SessionTest : public ::testing::Test {
protected:
    Session session{scenes().find("static-and-movable")};
    const Body& ball() { return session.engine().body("ball"); }
};

TEST_F(SessionTest, PauseStepAndStepBack) {
    session.frame(0.1);
    EXPECT_EQ(session.engine().stepCount(), 10u);
    session.togglePause();
    session.frame(1.0);
    EXPECT_EQ(session.engine().stepCount(), 10u) << "paused";
    const PhysicsEngine::State before = session.engine().state();
    session.stepOnce();
    EXPECT_EQ(session.engine().stepCount(), 11u);
    ASSERT_TRUE(session.stepBack());
    EXPECT_EQ(session.engine().stepCount(), 10u);
    EXPECT_EQ(ball().position, before.bodies[3].position);
    EXPECT_EQ(ball().velocity, before.bodies[3].velocity);
    for (int i = 0; i < 10; ++i) ASSERT_TRUE(session.stepBack());
    EXPECT_EQ(session.engine().stepCount(), 0u);
    EXPECT_FALSE(session.stepBack()) << "nothing before the start";
}

TEST_F(SessionTest, SpeedAndSubsteps) {
    session.setSpeed(0.25);
    session.frame(0.4);
    EXPECT_EQ(session.engine().stepCount(), 10u) << "a quarter of 0.4 s in 0.01 s ticks";
    session.setSpeed(1000.0);
    EXPECT_EQ(session.speed(), 8.0);
    session.setSpeed(1.0);
    session.setSubsteps(4);
    EXPECT_DOUBLE_EQ(session.engine().timeStep(), session.tick() / 4);
    const double t = session.engine().time();
    session.stepOnce();
    EXPECT_NEAR(session.engine().time() - t, session.tick(), 1e-12) << "a tick is the same time, in four steps";
    EXPECT_THROW(session.setTick(-1.0), std::invalid_argument);
}

TEST_F(SessionTest, GravityShootAddRemove) {
    session.toggleGravity();
    EXPECT_FALSE(session.gravityOn());
    const Vec3 v = ball().velocity;
    session.stepOnce();
    EXPECT_EQ(ball().velocity, v) << "no gravity, no change";
    session.toggleGravity();
    EXPECT_TRUE(session.gravityOn());

    const std::size_t n = session.engine().bodies().size();
    session.shoot(Ray{Vec3(0.0, 2.0, 20.0), Vec3(0.0, 0.0, -1.0)}, 20.0);
    ASSERT_EQ(session.engine().bodies().size(), n + 1);
    EXPECT_TRUE(session.engine().bodies().back().velocity.isApprox(Vec3(0.0, 0.0, -20.0)));
    session.addBox(Vec3(0.0, 3.0, 0.0));
    EXPECT_EQ(session.engine().bodies().size(), n + 2);
    EXPECT_TRUE(session.edited());
    EXPECT_FALSE(session.removeSelected()) << "nothing selected";
    session.select(session.engine().bodies().size() - 1);
    EXPECT_TRUE(session.removeSelected());
    EXPECT_EQ(session.engine().bodies().size(), n + 1);
    session.reset();
    EXPECT_EQ(session.engine().bodies().size(), n);
    EXPECT_FALSE(session.edited());
}

TEST_F(SessionTest, DragPullsTheBodyToTheCursorAndStaticBodiesStay) {
    const Vec3 eye(0.0, 8.0, 20.0);
    const Ray atBall{eye, (ball().position - eye).normalized()};
    ASSERT_TRUE(session.beginDrag(atBall, Vec3(0.0, 0.0, -1.0)));
    EXPECT_EQ(session.selectedBody()->name, "ball");
    const Vec3 start = ball().position;
    const Vec3 goal = ball().position + Vec3(3.0, 2.0, 0.0);
    session.dragTo(Ray{eye, (goal - eye).normalized()});
    const Vec3 target = session.dragTarget().value();
    EXPECT_GT((target - start).norm(), 2.0) << "the cursor's point moved with the cursor";
    for (int i = 0; i < 200; ++i) session.stepOnce();
    // The spring holds the ball at the cursor's point against gravity (sag g / omega^2 = 7 cm).
    EXPECT_LT((ball().position - target).norm(), 0.1);
    session.endDrag();
    EXPECT_FALSE(session.dragging());

    const Body& shelf = session.engine().body("shelf");
    const Ray atShelf{eye, (shelf.position - eye).normalized()};
    EXPECT_FALSE(session.beginDrag(atShelf, Vec3(0.0, 0.0, -1.0))) << "static bodies cannot be dragged";
    EXPECT_EQ(session.pickAndSelect(atShelf).value(), 1u);
}

TEST_F(SessionTest, ANonFiniteStatePausesWithAMessage) {
    session.engine().bodies()[3].velocity.x() = std::numeric_limits<double>::infinity();
    session.engine().setRequiredStages({});  // the reference integrator's Debug assertions stay out of it
    session.stepOnce();
    EXPECT_TRUE(session.paused());
    EXPECT_NE(session.error().find("ball"), std::string::npos) << session.error();
}

TEST_F(SessionTest, GhostStepsTheReferenceInLockStep) {
    ASSERT_TRUE(session.ghostAvailable()) << "this build has solutions/";
    session.setGhost(true);
    for (int i = 0; i < 50; ++i) session.stepOnce();
    ASSERT_EQ(session.ghostPoses().size(), session.engine().bodies().size());
    // These tests link the reference hooks, so the ghost must agree to the last bit.
    EXPECT_EQ(session.ghostDifference(), 0.0);
    session.addBox(Vec3::Zero());
    EXPECT_FALSE(session.ghostOn()) << "an edit stops the comparison";
    session.reset();
    EXPECT_TRUE(session.ghostOn());
}

TEST(SessionEdits, RemovingABodyForgetsTheHistoryBeforeIt) {
    // Newton's cradle: the ropes after a removed ball are numbered anew; a step back into a state
    // that still holds the ball would tie ropes to the wrong bodies.
    Session s{scenes().find("newtons-cradle")};
    for (int i = 0; i < 5; ++i) s.stepOnce();
    s.select(s.engine().bodies().size() / 2);
    ASSERT_TRUE(s.removeSelected());
    EXPECT_FALSE(s.stepBack()) << "nothing to step back into";
    s.stepOnce();
    ASSERT_TRUE(s.stepBack());
    for (const Rope& r : s.engine().ropes()) {
        EXPECT_TRUE(s.engine().bodies()[r.a].isStatic()) << "each rope hangs from an anchor";
        EXPECT_FALSE(s.engine().bodies()[r.b].isStatic());
    }
}

TEST(SessionContacts, StagesIterationsAndRestitutionGoThroughTheSessionAndTheGhost) {
    Session s{scenes().find("bouncing-balls")};
    ASSERT_TRUE(s.ghostAvailable());
    s.setGhost(true);
    // Before the first step the ghost starts over with every change, so it still agrees.
    s.setContactIterations(3);
    EXPECT_EQ(s.engine().contactIterations(), 3);
    s.setContactIterations(0);
    EXPECT_EQ(s.engine().contactIterations(), 1) << "clamped";
    s.setContactIterations(1000);
    EXPECT_EQ(s.engine().contactIterations(), Session::kMaxContactIterations);
    const std::size_t ball = 5;  // e=0.9
    s.setRestitution(ball, 0.0);
    EXPECT_EQ(s.engine().bodies()[ball].restitution, 0.0);
    s.setRestitution(ball, 1.7);
    EXPECT_EQ(s.engine().bodies()[ball].restitution, 1.0) << "clamped";
    s.setRestitution(ball, 0.2);
    s.setStageEnabled(Stage::Interpenetration, false);
    EXPECT_FALSE(s.engine().stageActive(Stage::Interpenetration));
    for (int i = 0; i < 150; ++i) s.stepOnce();
    EXPECT_TRUE(s.ghostOn());
    EXPECT_EQ(s.ghostDifference(), 0.0) << "the reference took the same settings";
    EXPECT_FALSE(s.engine().contacts().empty()) << "balls resting on the floor";
    // After the start an edit stops the comparison, as other edits do.
    s.setRestitution(ball, 0.9);
    EXPECT_FALSE(s.ghostOn());
    // A step back to a state before the edit undoes it, as it does every edit.
    s.stepOnce();
    ASSERT_TRUE(s.stepBack());
    ASSERT_TRUE(s.stepBack());
    EXPECT_EQ(s.engine().bodies()[ball].restitution, 0.2);
    s.setStageEnabled(Stage::Interpenetration, true);
    s.reset();
    EXPECT_EQ(s.engine().bodies()[ball].restitution, 0.9) << "a reset loads the scene's own";
}

TEST(SessionContacts, ARestitutionOfZeroStopsTheBounce) {
    Session bouncy{scenes().find("bouncing-balls")}, plastic{scenes().find("bouncing-balls")};
    plastic.setRestitution(5, 0.0);
    for (int i = 0; i < 150; ++i) bouncy.stepOnce(), plastic.stepOnce();  // 1.5 s: after the first bounce
    EXPECT_GT(bouncy.engine().bodies()[5].position.y(), 1.0);
    EXPECT_LT(plastic.engine().bodies()[5].position.y(), 0.31);
}

TEST(SceneShapes, TheBoxOfPlanesHasFourWallsAroundAFloor) {
    Session s{scenes().find("balls-in-a-box")};
    const auto& bodies = s.engine().bodies();
    EXPECT_TRUE(isGround(bodies[0]));
    const auto walls = wallPatches(bodies, s.bounds());
    ASSERT_EQ(walls.size(), 4u);
    for (const PlanePatch& w : walls) {
        Bounds extent;
        for (const Vec3& p : w.corners) extent.extend(p);
        EXPECT_NEAR(extent.min().y(), 0.0, 1e-9) << "from the floor";
        EXPECT_GT(extent.max().y(), 5.0) << "up to where the balls start";
        // Across the wall: from one neighbouring wall to the other, 4 m.
        const Vec3 size = extent.diagonal();
        EXPECT_NEAR(std::max(size.x(), size.z()), 4.0, 1e-9);
        EXPECT_NEAR(std::min(size.x(), size.z()), 0.0, 1e-9) << "flat";
        // Counter-clockwise seen from the free side: the polygon's normal is the wall's.
        const Vec3 n = (w.corners[1] - w.corners[0]).cross(w.corners[2] - w.corners[1]);
        EXPECT_GT(n.dot(w.normal), 0.0);
    }
    const auto floor = enclosedGround(bodies);
    ASSERT_TRUE(floor);
    Bounds extent;
    for (const Vec3& p : floor->corners) extent.extend(p);
    EXPECT_TRUE(extent.min().isApprox(Vec3(-2.0, 0.0, -2.0), 1e-9));
    EXPECT_TRUE(extent.max().isApprox(Vec3(2.0, 0.0, 2.0), 1e-9));
}

TEST(SceneShapes, TheBilliardTableHasLowCushionsAroundTheCloth) {
    Session s{scenes().find("billiards")};
    const auto walls = wallPatches(s.engine().bodies(), s.bounds());
    ASSERT_EQ(walls.size(), 4u);
    for (const PlanePatch& w : walls) {
        for (const Vec3& p : w.corners) {
            EXPECT_GE(p.y(), -1e-12);
            EXPECT_LT(p.y(), 0.1) << "a cushion a few ball radii high, not a wall";
            EXPECT_LE(std::abs(p.x()), 1.27 + 1e-9);
            EXPECT_LE(std::abs(p.z()), 0.635 + 1e-9);
        }
    }
    const auto cloth = enclosedGround(s.engine().bodies());
    ASSERT_TRUE(cloth);
    EXPECT_EQ(cloth->corners.size(), 4u);
}

TEST(SceneShapes, TheValleysSlopesMeetAtTheBottomAndNothingEnclosesAnOpenFloor) {
    Session s{scenes().find("valley")};
    const auto& bodies = s.engine().bodies();
    EXPECT_FALSE(isGround(bodies[0])) << "tilted by 30 degrees";
    const auto walls = wallPatches(bodies, s.bounds());
    ASSERT_EQ(walls.size(), 4u);
    for (const Vec3& p : walls[0].corners) EXPECT_LE(p.x(), 1e-9) << "the left slope stops at the bottom";
    for (const Vec3& p : walls[1].corners) EXPECT_GE(p.x(), -1e-9) << "the right slope starts there";
    for (const Vec3& p : walls[2].corners) {
        EXPECT_GE(p.y(), 1.0 + std::abs(p.x()) * std::tan(M_PI / 6.0) - 1e-9) << "the back wall stands on the slopes";
    }
    EXPECT_FALSE(enclosedGround(bodies)) << "no ground";
    Session heap{scenes().find("heap")};
    EXPECT_TRUE(wallPatches(heap.engine().bodies(), heap.bounds()).empty());
    EXPECT_FALSE(enclosedGround(heap.engine().bodies())) << "a floor open on every side";
}

TEST(SceneShapes, TheInclinesSlopeIsDrawnWhereverTheBoxSlidesUntilItIsOnTheFloor) {
    Session s{scenes().find("incline")};
    const auto walls = wallPatches(s.engine().bodies(), s.bounds());
    ASSERT_EQ(walls.size(), 1u) << "the slope; the floor is the ground";
    Bounds slope;
    for (const Vec3& p : walls[0].corners) slope.extend(p);
    EXPECT_NEAR(slope.min().y(), 0.0, 1e-9) << "from the floor";
    // Over the scene's view time the sliding box is always over the drawn slope (seen from above)
    // or on the floor, where it ends.
    const double half = 0.3;  // m, the box's half length along the slope
    const int steps = static_cast<int>(std::lround(s.scene().viewSeconds / s.tick()));
    for (int i = 0; i <= steps; ++i) {
        const Body& box = s.engine().body("slides");
        const Vec3& x = box.position;
        const bool onFloor = x.y() < box.halfExtents.norm();  // a corner or more on the floor
        EXPECT_TRUE(onFloor || (x.x() >= slope.min().x() - half && x.x() <= slope.max().x() &&
                                x.z() >= slope.min().z() && x.z() <= slope.max().z()))
            << "at t = " << s.engine().time() << " s the box is at (" << x.transpose() << ")";
        if (i < steps) s.stepOnce();
    }
    EXPECT_LT(s.engine().body("slides").position.y(), 0.3) << "lying on the floor at the end of the view time";
}

TEST(SceneShapes, ARopeIsTautWhenItPulledOrIsAtItsFullLength) {
    const std::vector<Body> bodies = {sphere("a", 0.1, 1.0), sphere("b", 0.1, 1.0).at({3.0, 0.0, 0.0})};
    EXPECT_TRUE(ropeTaut(Rope{0, 1, 3.0}, bodies, {}));
    EXPECT_TRUE(ropeTaut(Rope{0, 1, 3.001}, bodies, {})) << "a hair of slack counts as taut";
    EXPECT_FALSE(ropeTaut(Rope{0, 1, 3.1}, bodies, {}));
    Contact pulled = Contact::at(Vec3(1.5, 0.0, 0.0), Vec3(-1.0, 0.0, 0.0), 0.01);  // from b towards a
    pulled.a = 0, pulled.b = 1;
    EXPECT_TRUE(ropeTaut(Rope{0, 1, 3.1}, bodies, {pulled})) << "it pulled in the last step";
    Contact touching = pulled;
    touching.normal = Vec3(1.0, 0.0, 0.0);  // from a towards b: the two bodies touch, the rope did nothing
    EXPECT_FALSE(ropeTaut(Rope{0, 1, 3.1}, bodies, {touching}));
}

TEST(SceneShapes, ASlackRopeSagsAndIsAsLongAsTheRope) {
    const Vec3 a(0.0, 2.0, 0.0), b(3.0, 2.0, 0.0), down(0.0, -1.0, 0.0);
    const auto straight = ropeCurve(a, b, 3.0, down, 8);
    ASSERT_EQ(straight.size(), 9u);
    for (const Vec3& p : straight) EXPECT_NEAR(p.y(), 2.0, 1e-12) << "at its full length";
    for (double length : {3.2, 5.0, 30.0}) {
        const auto slack = ropeCurve(a, b, length, down, 400);
        double arc = 0.0;
        for (std::size_t i = 1; i < slack.size(); ++i) arc += (slack[i] - slack[i - 1]).norm();
        EXPECT_NEAR(arc, length, 1e-3 * length);
        EXPECT_LT(slack[200].y(), 2.0) << "it sags down";
        EXPECT_TRUE(slack.front().isApprox(a) && slack.back().isApprox(b));
    }
    const auto hanging = ropeCurve(a, a, 2.0, down, 2);
    EXPECT_NEAR(hanging[1].y(), 1.0, 1e-12) << "both ends at one point: it hangs down, doubled";
}

TEST(SceneShapes, ANormalIsAsLongAsMostOfTheSmallerBody) {
    const std::vector<Body> bodies = {plane("floor", Vec3::UnitY()), sphere("big", 1.0, 1.0),
                                      sphere("small", 0.25, 1.0)};
    Contact c;
    c.a = 1, c.b = 0;
    EXPECT_DOUBLE_EQ(normalLength(c, bodies), 0.8);
    c.b = 2;
    EXPECT_DOUBLE_EQ(normalLength(c, bodies), 0.2);
}

// ---- Cloth, ropes and soft bodies (worksheet 8) ---------------------------------------------------

// A cloth of nx x ny particles 0.1 m apart, spanned by u and v from origin.
SoftBodies flatCloth(int nx, int ny, const Vec3& origin, const Vec3& u, const Vec3& v) {
    SoftBodies soft;
    ClothSpec c;
    c.nx = nx, c.ny = ny, c.spacing = 0.1, c.origin = origin, c.u = u, c.v = v;
    soft.addCloth(c);
    return soft;
}

TEST(SoftShapes, AFlatClothsNormalsAllPointAlongItsNormal) {
    // Triangles counter-clockwise seen from the side u x v points to: every particle's normal, on
    // the edges and corners too, is u x v, to rounding.
    const Vec3 u = Vec3(1.0, 2.0, 2.0) / 3.0, v = Vec3(2.0, 1.0, -2.0) / 3.0;
    ASSERT_NEAR(u.dot(v), 0.0, 1e-15);
    for (const auto& [uu, vv] : {std::pair{Vec3(Vec3::UnitX()), Vec3(Vec3::UnitZ())}, std::pair{u, v}}) {
        const SoftBodies soft = flatCloth(7, 5, Vec3(0.3, 1.0, -0.2), uu, vv);
        std::vector<Vec3> n;
        surfaceNormals(soft.x, soft.meshes[0], n);
        ASSERT_EQ(n.size(), 35u);
        for (std::size_t k = 0; k < n.size(); ++k) {
            // 1e-12: unit vectors from sums of exact products, to rounding.
            EXPECT_LT((n[k] - uu.cross(vv)).norm(), 1e-12) << "particle " << k << ": " << n[k].transpose();
        }
    }
}

TEST(SoftShapes, ASoftCubesNormalsPointOutOfItsFaces) {
    SoftBodies soft;
    const Vec3 centre(0.2, 1.0, -0.3);
    const double half = 0.25;
    soft.addSoftBody(makeSoftCube("cube", centre, 2.0 * half, 4));
    const SoftMesh& m = soft.meshes[0];
    std::vector<Vec3> n;
    surfaceNormals(soft.x, m, n);
    int inside = 0, onFaces = 0;
    for (std::uint32_t k = 0; k < m.count; ++k) {
        const Vec3 d = soft.x[m.first + k] - centre;
        // Which faces the particle lies on (a coordinate at +-half: one inside a face, two on an edge).
        int faces = 0, axis = 0;
        for (int a = 0; a < 3; ++a) {
            if (std::abs(std::abs(d[a]) - half) < 1e-12) ++faces, axis = a;
        }
        if (faces == 0) {
            EXPECT_EQ(n[k], Vec3::Zero()) << "an inner particle is on no surface triangle";
            ++inside;
            continue;
        }
        EXPECT_GT(n[k].dot(d), 0.0) << "outward at " << d.transpose();
        if (faces == 1) {
            // Every triangle around it lies in the face: its normal is the face's, to rounding.
            const Vec3 face = std::copysign(1.0, d[axis]) * Vec3::Unit(axis);
            EXPECT_LT((n[k] - face).norm(), 1e-12) << "at " << d.transpose() << ": " << n[k].transpose();
            ++onFaces;
        }
    }
    EXPECT_EQ(inside, 3 * 3 * 3);
    EXPECT_EQ(onFaces, 6 * 3 * 3);
}

TEST(SoftShapes, ARopesTubeIsARingOfItsRadiusAroundEverySegment) {
    const std::vector<Vec3> chain = {Vec3(0.0, 2.0, 0.0), Vec3(0.1, 1.9, 0.0), Vec3(0.1, 1.8, 0.1),
                                     Vec3(0.0, 1.8, 0.1), Vec3(0.0, 1.8, 0.1 + 1e-9)};
    const double radius = 0.02;
    const int sides = 8;
    const TriangleMesh tube = ropeTube(chain, radius, sides);
    ASSERT_EQ(tube.vertices.size(), 4u * 2 * sides) << "two rings per segment";
    ASSERT_EQ(tube.indices.size(), 4u * sides * 6);
    for (std::size_t k = 0; k < tube.vertices.size(); ++k) {
        const std::size_t segment = k / (2 * sides);
        const Vec3 axis = (chain[segment + 1] - chain[segment]).normalized();
        const Vec3& end = k % (2 * sides) < std::size_t(sides) ? chain[segment] : chain[segment + 1];
        EXPECT_NEAR(tube.normals[k].norm(), 1.0, 1e-12);
        EXPECT_NEAR(tube.normals[k].dot(axis), 0.0, 1e-9) << "across the segment";
        EXPECT_LT((tube.vertices[k] - (end + radius * tube.normals[k])).norm(), 1e-12) << "on the ring";
    }
    // Counter-clockwise seen from outside: each triangle faces the way its corners' normals do.
    for (std::size_t t = 0; t < tube.indices.size(); t += 3) {
        const Vec3 &a = tube.vertices[tube.indices[t]], &b = tube.vertices[tube.indices[t + 1]],
                   &c = tube.vertices[tube.indices[t + 2]];
        EXPECT_GT((b - a).cross(c - a).dot(tube.normals[tube.indices[t]]), 0.0) << "triangle " << t / 3;
    }
}

TEST(SoftShapes, ARayPicksTheCornerNearestWhereItFirstCrossesACloth) {
    SoftBodies soft = flatCloth(6, 6, Vec3(0.0, 1.0, 0.0), Vec3::UnitX(), Vec3::UnitZ());
    ClothSpec upper;
    upper.name = "upper", upper.nx = 6, upper.ny = 6, upper.spacing = 0.1, upper.origin = Vec3(0.0, 2.0, 0.0);
    soft.addCloth(upper);
    // Straight down at (0.23, 0.31): the upper cloth first, 3 m below the eye; its corner (2, 3).
    const auto down = pickParticle(soft, Ray{Vec3(0.23, 5.0, 0.31), -Vec3::UnitY()});
    ASSERT_TRUE(down);
    EXPECT_EQ(particleName(soft, down->particle), "upper#20");  // j nx + i = 3 * 6 + 2
    EXPECT_NEAR(down->distance, 3.0, 1e-12);
    // From below, the lower cloth's back: the same corner of it.
    const auto up = pickParticle(soft, Ray{Vec3(0.23, -1.0, 0.31), Vec3::UnitY()});
    ASSERT_TRUE(up);
    EXPECT_EQ(particleName(soft, up->particle), "cloth#20");
    EXPECT_NEAR(up->distance, 2.0, 1e-12);
    EXPECT_FALSE(pickParticle(soft, Ray{Vec3(0.6, 5.0, 0.31), -Vec3::UnitY()})) << "beside the cloths";
    // Past the corner (0.5, 0.5) by half the 1 cm radius, level with the cloths: the corner's sphere.
    const auto corner = pickParticle(soft, Ray{Vec3(0.505, 2.0, 5.0), -Vec3::UnitZ()});
    ASSERT_TRUE(corner);
    EXPECT_EQ(particleName(soft, corner->particle), "upper#35");
    EXPECT_FALSE(pickParticle(soft, Ray{Vec3(0.23, 5.0, 0.31), Vec3::UnitY()})) << "away from them";
}

TEST(SoftShapes, ARayPicksARopesParticleWithinItsBead) {
    SoftBodies soft;
    RopeSpec r;
    r.segments = 10, r.start = Vec3(0.0, 2.0, 0.0), r.end = Vec3(1.0, 2.0, 0.0), r.radius = 0.01;
    soft.addRope(r);
    const double bead = ropeDrawRadius(soft, 0);
    // A fifth of a segment, more than the contact radius (1e-12: the segments' lengths summed, to rounding).
    EXPECT_NEAR(bead / (0.2 * 0.1), 1.0, 1e-12);
    const auto hit = pickParticle(soft, Ray{Vec3(0.3 + 0.9 * bead, 2.0, 5.0), -Vec3::UnitZ()});
    ASSERT_TRUE(hit);
    EXPECT_EQ(particleName(soft, hit->particle), "rope#3");
    EXPECT_FALSE(pickParticle(soft, Ray{Vec3(0.35, 2.0, 5.0), -Vec3::UnitZ()})) << "between two beads";
    EXPECT_EQ(particleByName(soft, "rope#3"), hit->particle);
    EXPECT_FALSE(particleByName(soft, "rope#11")) << "11 particles: 0..10";
    EXPECT_FALSE(particleByName(soft, "rope"));
    EXPECT_FALSE(particleByName(soft, "cord#3"));
    EXPECT_FALSE(particleByName(soft, "rope#99999999999999999999")) << "no number a mesh could hold";
    EXPECT_FALSE(particleByName(soft, "rope#-1"));
}

TEST(SoftShapes, AMeshIsFramedAsItsParticlesSpheres) {
    SoftBodies soft = flatCloth(3, 3, Vec3(-0.1, 4.0, -0.1), Vec3::UnitX(), Vec3::UnitZ());
    Camera c;
    c.lookAt(Vec3(0.0, 4.0, 0.0), 5.0);
    std::vector<PixelBox> boxes;
    ASSERT_TRUE(movingMeshes(c, soft, 1280, 720, boxes));
    ASSERT_EQ(boxes.size(), 1u);
    double x = 0, y = 0;
    ASSERT_TRUE(c.project(Vec3(0.0, 4.0, 0.0), 1280, 720, x, y));
    EXPECT_TRUE(boxes[0].left < x && x < boxes[0].right && boxes[0].top < y && y < boxes[0].bottom)
        << "the cloth around the view's centre";
    EXPECT_LT(boxes[0].right - boxes[0].left, 200.0) << "20 cm at 5 m";
    for (double& w : soft.w) w = 0.0;
    boxes.clear();
    EXPECT_TRUE(movingMeshes(c, soft, 1280, 720, boxes));
    EXPECT_TRUE(boxes.empty()) << "a mesh pinned everywhere does not move";
}

TEST(SessionSoft, ARayPicksAClothInFrontOfABodyAndTheBodyInFrontOfACloth) {
    Session s{scenes().find("cloth-on-sphere")};
    const Ray fromAbove{Vec3(0.01, 5.0, 0.02), -Vec3::UnitY()};
    const Session::Picked top = s.pickAt(fromAbove);
    ASSERT_TRUE(top.particle);
    EXPECT_FALSE(top.body);
    s.pickAndSelect(fromAbove);
    EXPECT_EQ(s.selectedParticle(), top.particle);
    EXPECT_FALSE(s.selected());
    const Session::Picked bottom = s.pickAt(Ray{Vec3(0.01, 0.4, 3.0), -Vec3::UnitZ()});
    EXPECT_TRUE(bottom.body) << "the ball, below the cloth";
    EXPECT_FALSE(bottom.particle);
}

TEST(SessionSoft, ADraggedParticleIsHeldOnItsWayToTheCursorAndLeftWithItsVelocity) {
    Session s{scenes().find("flag")};
    SoftBodies& soft = s.engine().softBodies();
    const std::uint32_t tip = *particleByName(soft, "flag#29");  // the free corner at the top
    const Vec3 eye = soft.x[tip] + Vec3(0.0, 0.0, 3.0);
    ASSERT_TRUE(s.beginDrag(Ray{eye, (soft.x[tip] - eye).normalized()}, -Vec3::UnitZ()));
    ASSERT_EQ(s.selectedParticle(), tip);
    EXPECT_FALSE(s.selected());
    const Vec3 goal = soft.x[tip] + Vec3(0.3, 0.4, 0.0);
    s.dragTo(Ray{eye, (goal - eye).normalized()});
    ASSERT_LT((*s.dragTarget() - goal).norm(), 1e-12) << "on the plane through the particle";
    const double w = soft.w[tip], h = s.engine().timeStep();
    // Held through each step, the particle is where the drag put it, a share 1 - exp(-rate h) of
    // the way closer: after n steps exp(-rate h n) of the 0.5 m is left (1e-12 relative to the 0.5 m:
    // n moves, each exact to rounding).
    const int n = 40;
    for (int i = 0; i < n; ++i) s.stepOnce();
    const double left = 0.5 * std::exp(-Session::kParticleDragRate * h * n);
    EXPECT_NEAR((soft.x[tip] - goal).norm(), left, 0.5 * 1e-12);
    EXPECT_EQ(soft.w[tip], w) << "pinned only while a step runs: the state between steps keeps its mass";
    const Vec3 velocity = soft.v[tip];
    // The velocity of its last step: that step's move over h (1e-9 relative: the move, exact to
    // 1e-12 of 0.5 m, is a few cm).
    const double speed = left * (std::exp(Session::kParticleDragRate * h) - 1.0) / h;
    EXPECT_NEAR(velocity.norm() / speed, 1.0, 1e-9);
    EXPECT_TRUE(s.edited()) << "a drag stops the ghost's comparison";
    s.endDrag();
    EXPECT_FALSE(s.dragging());
    EXPECT_EQ(soft.v[tip], velocity) << "let go with the velocity of its last step";
    // A step back while dragging restores the state the history kept, with the particle free.
    ASSERT_TRUE(s.beginDrag(Ray{eye, (soft.x[tip] - eye).normalized()}, -Vec3::UnitZ()));
    s.stepOnce();
    ASSERT_TRUE(s.stepBack());
    EXPECT_FALSE(s.dragging());
    EXPECT_EQ(soft.w[tip], w);
    const std::uint32_t pin = *particleByName(soft, "flag#0");
    EXPECT_EQ(soft.w[pin], 0.0) << "the pinned corner stays pinned";
}

TEST(SessionSoft, StepBackRestoresTheParticles) {
    Session s{scenes().find("soft-cube")};
    for (int i = 0; i < 5; ++i) s.stepOnce();
    const std::vector<Vec3> x = s.engine().softBodies().x, v = s.engine().softBodies().v;
    for (int i = 0; i < 5; ++i) s.stepOnce();
    EXPECT_NE(s.engine().softBodies().x, x);
    for (int i = 0; i < 5; ++i) ASSERT_TRUE(s.stepBack());
    EXPECT_EQ(s.engine().softBodies().x, x);
    EXPECT_EQ(s.engine().softBodies().v, v);
    // The history counts the particles' memory against its budget.
    const PhysicsEngine::State state = s.engine().state();
    PhysicsEngine::State bodiesOnly = state;
    bodiesOnly.particlePositions = std::vector<Vec3>();
    bodiesOnly.particleVelocities = std::vector<Vec3>();
    bodiesOnly.particleInverseMasses = std::vector<double>();
    EXPECT_GE(History::bytesOf(state) - History::bytesOf(bodiesOnly), x.size() * (2 * sizeof(Vec3) + sizeof(double)));
}

TEST(SessionSoft, TheIterationsGoThroughTheSessionAndTheGhost) {
    Session s{scenes().find("rope-pbd-xpbd")};
    ASSERT_TRUE(s.ghostAvailable());
    s.setGhost(true);
    s.setConstraintIterations(3);
    EXPECT_EQ(s.engine().constraintIterations(), 3);
    s.setConstraintIterations(0);
    EXPECT_EQ(s.engine().constraintIterations(), 1) << "clamped";
    s.setConstraintIterations(100000);
    EXPECT_EQ(s.engine().constraintIterations(), Session::kMaxConstraintIterations);
    s.setConstraintIterations(3);
    for (int i = 0; i < 100; ++i) s.stepOnce();
    ASSERT_EQ(s.ghostParticles().size(), s.engine().softBodies().x.size());
    EXPECT_TRUE(s.ghostOn());
    // These tests link the reference hooks: with the same iterations the ghost agrees to the bit.
    EXPECT_EQ(s.ghostDifference(), 0.0);
    Session other{scenes().find("rope-pbd-xpbd")};
    for (int i = 0; i < 100; ++i) other.stepOnce();
    EXPECT_NE(other.engine().softBodies().x, s.engine().softBodies().x) << "3 sweeps are not the scene's own";
}

// ---- Fluids (worksheet 9) -----------------------------------------------------------------------

// Relative luminance's weights (Rec. 709), for "lighter" and "darker".
double luma(const std::uint8_t c[4]) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

TEST(FluidShapes, TheDensityMapIsWhiteAtZeroBlueBelowRedAboveAndClamped) {
    std::uint8_t zero[4], low[4], high[4], beyond[4], nan[4];
    divergingColour(0.0, zero);
    EXPECT_EQ(zero[0], zero[1]);
    EXPECT_EQ(zero[1], zero[2]) << "grey at the centre";
    EXPECT_GT(luma(zero), 230.0) << "and nearly white";
    divergingColour(-1.0, low);
    divergingColour(1.0, high);
    EXPECT_GT(low[2], low[0] + 100) << "blue below";
    EXPECT_GT(high[0], high[2] + 100) << "red above";
    divergingColour(7.0, beyond);
    EXPECT_TRUE(std::equal(beyond, beyond + 4, high)) << "clamped";
    divergingColour(std::nan(""), nan);
    EXPECT_TRUE(std::equal(nan, nan + 4, zero)) << "an undefined error shows as none";
    // Either side darker with every step away from the centre.
    for (double t = 0.0; t < 1.0; t += 0.125) {
        std::uint8_t a[4], b[4];
        divergingColour(t, a), divergingColour(t + 0.125, b);
        EXPECT_GT(luma(a), luma(b)) << "above, at " << t;
        divergingColour(-t, a), divergingColour(-t - 0.125, b);
        EXPECT_GT(luma(a), luma(b)) << "below, at " << t;
    }
}

TEST(FluidShapes, TheSpeedMapGrowsLighterFromZeroToItsRange) {
    for (double t = 0.0; t < 1.0; t += 0.0625) {
        std::uint8_t a[4], b[4];
        sequentialColour(t, a), sequentialColour(t + 0.0625, b);
        EXPECT_LT(luma(a), luma(b)) << "at " << t;
    }
    std::uint8_t below[4], zero[4];
    sequentialColour(-1.0, below), sequentialColour(0.0, zero);
    EXPECT_TRUE(std::equal(below, below + 4, zero)) << "clamped";
}

// A block of water, 4 x 3 x 2 particles 2.5 cm apart, in a tank with room above.
Fluids smallBlock() {
    Fluids f;
    FluidParameters p;
    p.spacing = 0.025;
    p.smoothingLength = 0.05;
    f.setParameters(p);
    f.setContainer({Vec3::Zero(), Vec3(0.1, 0.2, 0.05)});
    f.addBlock(Vec3::Zero(), Vec3(0.1, 0.075, 0.05));
    return f;
}

TEST(FluidShapes, ParticlesAreColouredByTheirDensityErrorOrSpeed) {
    Fluids f = smallBlock();
    ASSERT_EQ(f.size(), 24u);
    f.density[0] = 1010.0;  // 1 % compressed
    f.density[1] = 900.0;   // 10 % short: beyond the range
    f.v[2] = Vec3(0.0, -1.0, 0.0);
    std::vector<std::uint8_t> c;
    fluidColours(f, FluidColouring::DensityError, 0.02, c);
    ASSERT_EQ(c.size(), 4 * f.size());
    std::uint8_t expected[4];
    divergingColour(0.5, expected);  // 1 % of a 2 % range (to rounding of 1010 / 1000 - 1)
    EXPECT_TRUE(std::equal(expected, expected + 4, &c[0]));
    divergingColour(-1.0, expected);
    EXPECT_TRUE(std::equal(expected, expected + 4, &c[4]));
    divergingColour(0.0, expected);
    EXPECT_TRUE(std::equal(expected, expected + 4, &c[8])) << "at rest density whatever its speed";
    fluidColours(f, FluidColouring::Speed, 2.0, c);
    sequentialColour(0.5, expected);
    EXPECT_TRUE(std::equal(expected, expected + 4, &c[8]));
    sequentialColour(0.0, expected);
    EXPECT_TRUE(std::equal(expected, expected + 4, &c[0])) << "at rest whatever its density";
    f.density.clear();
    EXPECT_EQ(densityErrorOf(f, 0), 0.0) << "before any density is computed";
}

TEST(FluidShapes, TheTanksWallsFloorAndLidAreToldFromOtherBodies) {
    for (const char* name : {"dam-break", "drop-into-pool", "pour-onto-sphere", "tank-slosh"}) {
        PhysicsEngine e;
        load(e, scenes().find(name));
        ASSERT_TRUE(e.fluids().container()) << name;
        std::size_t walls = 0;
        for (const Body& b : e.bodies()) walls += isTankWall(b, *e.fluids().container()) ? 1 : 0;
        EXPECT_EQ(walls, 6u) << name << ": four walls, a floor and a lid";
    }
    PhysicsEngine e;
    load(e, scenes().find("pour-onto-sphere"));
    EXPECT_FALSE(isTankWall(e.body("ball"), *e.fluids().container())) << "a sphere inside the tank";
    const FluidBox tank = *e.fluids().container();
    Body inside = box("inside", Vec3::Constant(0.05), 1.0).at(Vec3(0.0, 0.1, 0.0)).makeStatic();
    EXPECT_FALSE(isTankWall(inside, tank));
    Body away = box("away", Vec3::Constant(0.05), 1.0).at(Vec3(3.0, 0.1, 0.0)).makeStatic();
    EXPECT_FALSE(isTankWall(away, tank)) << "outside, not touching";
    Body moving = box("moving", Vec3::Constant(0.05), 1.0).at(Vec3(0.0, -0.05, 0.0));
    EXPECT_FALSE(isTankWall(moving, tank)) << "under the floor but free to move";
}

TEST(FluidShapes, ARayPicksTheNearestParticleItEnters) {
    const Fluids f = smallBlock();
    // Particle (i, j, k) = (1, 2, 0) is at (0.0375, 0.0625, 0.0125); index i + 4 (j + 3 k).
    const auto front = pickFluidParticle(f, Ray{Vec3(0.0375, 0.0625, 5.0), -Vec3::UnitZ()});
    ASSERT_TRUE(front);
    EXPECT_DOUBLE_EQ(f.x[front->particle].z(), 0.0375) << "the nearer of the two in line";
    EXPECT_NEAR(front->distance, 5.0 - 0.0375 - f.radius(), 1e-12);
    const auto back = pickFluidParticle(f, Ray{Vec3(0.0375, 0.0625, -5.0), Vec3::UnitZ()});
    ASSERT_TRUE(back);
    EXPECT_EQ(back->particle, 1u + 4u * 2u) << "from behind, the one at z = 0.0125";
    EXPECT_FALSE(pickFluidParticle(f, Ray{Vec3(0.0375, 0.3, 5.0), -Vec3::UnitZ()})) << "above the block";
    EXPECT_FALSE(pickFluidParticle(f, Ray{Vec3(0.0375, 0.0625, 5.0), Vec3::UnitZ()})) << "away from it";
}

TEST(FluidShapes, TheBenchmarksFillKeepsOutOfTheBallAndStaysInTheContainer) {
    PhysicsEngine e;
    load(e, scenes().find("pour-onto-sphere"));
    Fluids& f = e.fluids();
    ASSERT_EQ(fillContainer(f, e.bodies(), 20000), 20000u);
    const Body& ball = e.body("ball");
    const FluidBox tank = *f.container();
    double lowest = 1.0;
    for (const Vec3& q : f.x) {
        ASSERT_TRUE(tank.contains(q));
        ASSERT_GE((q - ball.position).norm(), ball.radius + f.radius()) << "no particle inside the ball";
        lowest = std::min(lowest, q.y());
    }
    EXPECT_EQ(lowest, tank.lower.y() + f.radius()) << "from the floor up";
    // 24 x 40 x 24 lattice points in the 0.6 x 1 x 0.6 m tank, less those in the ball.
    const std::size_t all = fillContainer(f, e.bodies(), 100000);
    EXPECT_LT(all, 24u * 40u * 24u);
    EXPECT_GT(all, 24u * 40u * 24u - 1000u) << "a ball of 0.12 m and half a spacing around it hold about 620 lattice points";
    Fluids none;
    EXPECT_EQ(fillContainer(none, e.bodies(), 10), 0u) << "no container, nothing to fill";
}

// For every pixel of a width x height view, the particle whose sprite is in front there: of the
// sprites (discs of spriteWidth() about each particle's projection) that hold the pixel's centre,
// the one of the nearest centre, as the depth test decides. -1 where there is none.
std::vector<long> frontSprites(const Camera& camera, const Fluids& f, int width, int height) {
    const double pixelsPerMetre = 0.5 * height / std::tan(Camera::kFieldOfViewY * 3.14159265358979323846 / 360.0);
    std::vector<long> front(static_cast<std::size_t>(width) * height, -1);
    std::vector<double> nearest(front.size(), HUGE_VAL);
    for (std::size_t i = 0; i < f.size(); ++i) {
        double x, y;
        if (!camera.project(f.x[i], width, height, x, y)) continue;
        const double depth = (f.x[i] - camera.eye()).dot(camera.forward());
        const double half = 0.5 * spriteWidth(f.radius(), depth, pixelsPerMetre);
        for (int py = std::max(0, int(y - half) - 1); py < std::min(height, int(y + half) + 2); ++py) {
            for (int px = std::max(0, int(x - half) - 1); px < std::min(width, int(x + half) + 2); ++px) {
                const double dx = px + 0.5 - x, dy = py + 0.5 - y;
                const std::size_t at = static_cast<std::size_t>(py) * width + px;
                if (dx * dx + dy * dy <= half * half && depth < nearest[at]) nearest[at] = depth, front[at] = long(i);
            }
        }
    }
    return front;
}

TEST(FluidShapes, OnlySpritesHiddenBehindNearerOnesAreLeftOut) {
    PhysicsEngine e;
    load(e, scenes().find("pour-onto-sphere"));
    Fluids& f = e.fluids();
    ASSERT_EQ(fillContainer(f, e.bodies(), 20000), 20000u);
    const int width = 920, height = 720;  // the default window's view beside the panel
    Camera camera;
    const Vec3 centre = 0.5 * (f.container()->lower + f.container()->upper);
    for (const double turn : {0.0, 140.0}) {  // pixels of orbit: head-on to the tank's front, and askew
        camera.lookAt(centre, 1.9);           // the tank fills most of the view's height
        camera.orbit(turn, 0.0);
        std::vector<std::uint32_t> order(f.size());
        for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
        const auto depth = [&](std::uint32_t i) { return (f.x[i] - camera.eye()).dot(camera.forward()); };
        std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return depth(a) < depth(b); });
        SpriteDepths work;
        std::vector<std::uint32_t> visible;
        visibleSprites(camera, f, width, height, order, work, visible);
        // Every particle in front somewhere is kept: leaving out the others changes no pixel.
        std::vector<bool> kept(f.size(), false);
        for (std::uint32_t i : visible) kept[i] = true;
        std::size_t seen = 0;
        std::vector<bool> counted(f.size(), false);
        for (long i : frontSprites(camera, f, width, height)) {
            if (i < 0 || counted[i]) continue;
            counted[i] = true, ++seen;
            EXPECT_TRUE(kept[i]) << "particle " << i << " shows at some pixel but is left out (turn " << turn << ")";
        }
        // The kept ones in the order given, and most of a block of fluid left out: it shows its outer layers.
        EXPECT_TRUE(std::is_sorted(visible.begin(), visible.end(),
                                   [&](std::uint32_t a, std::uint32_t b) { return depth(a) < depth(b); }));
        EXPECT_LT(visible.size(), f.size() / 2) << "turn " << turn;
        EXPECT_GE(visible.size(), seen);
    }
    // Out of the view: nothing drawn, so nothing kept.
    camera.lookAt(centre + Vec3(50.0, 0.0, 0.0), 1.9);
    SpriteDepths work;
    std::vector<std::uint32_t> all(f.size()), visible;
    for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    visibleSprites(camera, f, width, height, all, work, visible);
    EXPECT_TRUE(visible.empty());
}

TEST(SessionFluid, AParticleIsPickedThroughTheTanksFrontWallAndDraggedTheFluidMakingWay) {
    Session s{scenes().find("dam-break")};
    const Fluids& f = s.engine().fluids();
    // The column's particle nearest the front wall (z = a = 0.25) at mid height, seen from the front.
    std::uint32_t target = 0;
    for (std::uint32_t i = 0; i < f.size(); ++i) {
        const Vec3 d = f.x[i] - Vec3(0.1375, 0.2375, 0.2375);
        if (d.norm() < (f.x[target] - Vec3(0.1375, 0.2375, 0.2375)).norm()) target = i;
    }
    const Vec3 eye(0.1375, 0.2375, 3.0);
    const Ray ray{eye, (f.x[target] - eye).normalized()};
    const Session::Picked hit = s.pickAt(ray);
    ASSERT_TRUE(hit.fluidParticle) << "the wall in front is not picked";
    EXPECT_EQ(*hit.fluidParticle, target);
    EXPECT_FALSE(hit.body);
    ASSERT_TRUE(s.beginDrag(ray, -Vec3::UnitZ()));
    EXPECT_EQ(s.selectedFluidParticle(), target);
    EXPECT_FALSE(s.selected());
    // Pulled 0.3 m right, into the empty tank: after n steps it is exp(-rate h n) of the way short.
    const Vec3 goal = f.x[target] + Vec3(0.3, 0.0, 0.0);
    s.dragTo(Ray{eye, (goal - eye).normalized()});
    const int n = 40;
    for (int i = 0; i < n; ++i) s.stepOnce();
    const double left = 0.3 * std::exp(-Session::kParticleDragRate * s.engine().timeStep() * n);
    // The goal moves nowhere; each step puts the particle exactly its share closer (1e-9 relative
    // to the 0.3 m: rounding of n moves).
    EXPECT_NEAR((f.x[target] - goal).norm(), left, 0.3 * 1e-9);
    EXPECT_TRUE(s.edited());
    s.endDrag();
    ASSERT_TRUE(s.stepBack());
    EXPECT_FALSE(s.dragging());
    EXPECT_EQ(s.selectedFluidParticle(), target) << "the selection stays";
    s.reset();
    EXPECT_FALSE(s.selectedFluidParticle());
}

TEST(SessionFluid, TheIterationsGoThroughTheSession) {
    Session s{scenes().find("tank-slosh")};
    s.setFluidIterations(9);
    EXPECT_EQ(s.engine().fluids().parameters().iterations, 9);
    s.setFluidIterations(0);
    EXPECT_EQ(s.engine().fluids().parameters().iterations, 1) << "clamped";
    s.setFluidIterations(100000);
    EXPECT_EQ(s.engine().fluids().parameters().iterations, Session::kMaxFluidIterations);
    EXPECT_STREQ(fluidMethodName(s.engine()), "PBF");
    Session sph{scenes().find("dam-break-sph")};
    EXPECT_STREQ(fluidMethodName(sph.engine()), "WCSPH");
}

TEST(EnergySeries, KeepsTheLastSamples) {
    EnergySeries s;
    for (std::size_t i = 0; i < EnergySeries::kCapacity + 10; ++i) s.push(double(i), 1.0);
    EXPECT_EQ(s.total.size(), EnergySeries::kCapacity);
    EXPECT_EQ(s.kinetic.front(), 10.0f);
    EXPECT_EQ(s.total.back(), float(EnergySeries::kCapacity + 10));
}

}  // namespace
}  // namespace gpl::viewer
