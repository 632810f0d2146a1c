// The friction stage's other contact solvers with the reference hooks in the engine's whole step.
// The soft step (soft_step.h) against closed forms: static friction holds a block on a gentle
// incline, sliding friction gives the acceleration g (sin theta - mu_d cos theta) on a steep one, a
// thrown ball rolls at 5/7 of its speed, restitution returns e times the approach, and a column of
// boxes keeps its contacts' overlap to millimetres. The baseline (baumgarte.h) against what its
// bias is: a box started in the floor leaves it with the bias's speed, where sequential impulses'
// split impulses move it out and leave it at rest.
#include <gtest/gtest.h>

#include <cmath>

#include "gpl/baumgarte.h"
#include "gpl/engine.h"
#include "gpl/scenes.h"

namespace gpl {
namespace {

// An engine with the friction stage's stages, solved by the soft step.
PhysicsEngine softEngine() {
    PhysicsEngine e;
    e.setRequiredStages(kFrictionStages);
    e.setContactSolver(ContactSolver::SoftStep);
    return e;
}

// A 2 kg block resting on an incline of this slope (rad), both of friction mus, mud.
void incline(PhysicsEngine& e, double slope, double mus, double mud) {
    const Vec3 normal(-std::sin(slope), std::cos(slope), 0.0);
    e.add(plane("incline", normal).rough(mus, mud).bouncy(0.0));
    const Vec3 up(std::cos(slope), std::sin(slope), 0.0);
    e.add(box("block", {0.3, 0.2, 0.3}, 2.0)
              .at(2.0 * up + 0.2 * normal)
              .rotated(Quat(Eigen::AngleAxisd(slope, Vec3::UnitZ())))
              .rough(mus, mud)
              .bouncy(0.0));
}

TEST(SoftStep, StaticFrictionHoldsABlockBelowAtanMu) {
    for (const double degrees : {10.0, 25.0}) {  // tan 25 deg = 0.47 < mu_s = 0.6
        PhysicsEngine e = softEngine();
        incline(e, degrees * M_PI / 180.0, 0.6, 0.5);
        const Vec3 start = e.body("block").position;
        for (int s = 0; s < 300; ++s) e.step();
        // The soft contact settles into the slope by a fraction of a millimetre; it must not creep.
        EXPECT_LT((e.body("block").position - start).norm(), 1e-3) << degrees << " degrees";
        EXPECT_LT(e.body("block").velocity.norm(), 1e-4) << degrees << " degrees";
    }
}

TEST(SoftStep, SlidingFrictionGivesTheClosedFormAcceleration) {
    for (const double degrees : {30.0, 40.0}) {  // tan 30 deg = 0.58 > mu_s = 0.5
        PhysicsEngine e = softEngine();
        const double slope = degrees * M_PI / 180.0, mud = 0.3;
        incline(e, slope, 0.5, mud);
        const Vec3 down(-std::cos(slope), -std::sin(slope), 0.0);
        const double a = e.gravity().norm() * (std::sin(slope) - mud * std::cos(slope));  // m/s^2
        for (int s = 0; s < 150; ++s) e.step();
        const double t = 150 * e.timeStep();
        // Sliding at a constant acceleration is exact once the normal impulse carries the weight's
        // normal part; the first steps' settling costs at most a step's change of speed, a h.
        EXPECT_NEAR(e.body("block").velocity.dot(down), a * t, 1.5 * a * e.timeStep()) << degrees << " degrees";
    }
}

TEST(SoftStep, AThrownBallEndsRollingAtFiveSeventhsOfItsSpeed) {
    // A solid ball thrown without spin: friction at the floor slows it and spins it up until the
    // contact point sticks, at v = 5/7 v0, whatever mu is.
    PhysicsEngine e = softEngine();
    e.add(plane("floor", Vec3::UnitY()).rough(0.3, 0.3).bouncy(0.0));
    e.add(sphere("ball", 0.3, 1.0).at({0.0, 0.3, 0.0}).moving({4.0, 0.0, 0.0}).rough(0.3, 0.3).bouncy(0.0));
    for (int s = 0; s < 200; ++s) e.step();
    const Body& ball = e.body("ball");
    EXPECT_NEAR(ball.velocity.x(), 4.0 * 5.0 / 7.0, 0.005 * 4.0 * 5.0 / 7.0);  // 0.5 %: a step's slip at most
    // It rolls: omega r = v, on a radius within a millimetre of r (the soft contact lets the ball a
    // fraction of a millimetre into the floor, and it rolls on what is left).
    EXPECT_NEAR(-ball.angularVelocity.z() * ball.radius, ball.velocity.x(), 1e-3 / ball.radius * ball.velocity.x());
}

TEST(SoftStep, ABallLeavesTheFloorWithRestitutionTimesItsApproach) {
    PhysicsEngine e = softEngine();
    e.add(plane("floor", Vec3::UnitY()).rough(0.0, 0.0).bouncy(1.0));
    e.add(sphere("ball", 0.2, 1.0).at({0.0, 1.2, 0.0}).rough(0.0, 0.0).bouncy(0.7));
    double approach = 0.0;
    for (int s = 0; s < 200; ++s) {
        const double before = e.body("ball").velocity.y();
        e.step();
        if (before < 0.0 && e.body("ball").velocity.y() > 0.0) {
            approach = before + e.gravity().y() * e.timeStep();  // what the step's gravity added before the floor answered
            break;
        }
    }
    ASSERT_LT(approach, -1.0) << "the ball never bounced";
    // The bounce answers the approach measured after the integration stage; the substeps' share of
    // gravity after it changes the leaving speed by at most g h.
    EXPECT_NEAR(e.body("ball").velocity.y(), -0.7 * approach, std::abs(e.gravity().y()) * e.timeStep());
}

TEST(SoftStep, ATenCubeColumnOverlapsByLessThanTwoMillimetresAtItsBase) {
    // The contact spring, a quarter of the substeps' rate, yields under the weight above it: the
    // bottom face of ten carries nine cubes, a spring of 100 Hz at h = 0.01 s over four substeps
    // lets it in by about a millimetre.
    PhysicsEngine e;
    load(e, scenes().find("stack-10"));
    ASSERT_EQ(e.contactSolver(), ContactSolver::SoftStep);
    for (int s = 0; s < 300; ++s) e.step();
    double deepest = 0.0;
    for (const Contact& c : e.contacts()) deepest = std::max(deepest, c.depth);
    EXPECT_LT(deepest, 2e-3);
    EXPECT_GT(deepest, 0.0) << "a soft contact carrying weight overlaps";
}

// A 1 kg box started 2 cm into a floor of restitution 0, solved by `solver`; its velocity after one step.
Vec3 afterOneStepInTheFloor(ContactSolver solver) {
    PhysicsEngine e;
    e.setRequiredStages(kFrictionStages);
    e.setContactSolver(solver);
    e.add(plane("floor", Vec3::UnitY()).rough(0.5, 0.5).bouncy(0.0));
    e.add(box("box", Vec3::Constant(0.25), 1.0).at({0.0, 0.25 - 0.02, 0.0}).rough(0.5, 0.5).bouncy(0.0));
    e.step();
    return e.body("box").velocity;
}

TEST(Baumgarte, TheBiasThatPushesABoxOutOfTheFloorStaysInItsVelocity) {
    // The overlap after integration is 2 cm + g h^2; the bias asks for kBias (d - slop) / h upwards.
    const double h = kDefaultTimeStep, d = 0.02 + 9.81 * h * h;
    const double bias = BaumgarteImpulses::kBias * (d - kContactSlop) / h;  // m/s
    // Every corner asks for the same speed, so the box leaves with it (ten sweeps over four corners
    // that each turn the box converge to 1e-4 of it).
    EXPECT_NEAR(afterOneStepInTheFloor(ContactSolver::Baumgarte).y(), bias, 1e-4 * bias);
    // Sequential impulses correct the same overlap in positions alone: the box is left at rest (as
    // near as the same ten sweeps come, a ten-thousandth of that speed).
    EXPECT_NEAR(afterOneStepInTheFloor(ContactSolver::SequentialImpulses).y(), 0.0, 1e-4 * bias);
}

}  // namespace
}  // namespace gpl
