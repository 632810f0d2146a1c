// Worksheet 7 scenes: friction and resting contact. The keys ran out with worksheet 6: these scenes
// are reached by name (./lab viewer incline) or from the viewer's scene menu.
#include <cmath>

#include "gpl/scenes.h"

namespace gpl {
namespace {

// The slope of the incline: 25 degrees, tan = 0.466.
constexpr double kSlope = 25.0 * M_PI / 180.0;

// Two boxes at rest on a slope of 25 degrees (tan 25 = 0.47). With the incline's coefficients 1 and
// the combination sqrt(mu_a mu_b), the left box's pair has mu_s = 0.7, mu_d = 0.6 (above tan 25: it
// stays) and the right box's mu_s = 0.3, mu_d = 0.2 (below: it slides down at
// g (sin 25 - 0.2 cos 25) = 2.37 m/s^2). They start 12 m up the slope: the sliding box is on it for
// 3.1 s (the worksheet reads its speed at 3 s), then slides onto the floor at the slope's foot,
// whose friction stops it.
void incline(PhysicsEngine& e) {
    const Vec3 normal(-std::sin(kSlope), std::cos(kSlope), 0.0);  // the slope rises along +x
    const Vec3 upSlope(std::cos(kSlope), std::sin(kSlope), 0.0);
    const Vec3 across = Vec3::UnitZ();
    e.add(plane("incline", normal).rough(1.0, 1.0));
    const Quat tilt(Eigen::AngleAxisd(kSlope, Vec3::UnitZ()));
    const Vec3 half(0.3, 0.2, 0.3);
    const Vec3 start = 12.0 * upSlope + half.y() * normal;  // m, resting on the slope 12 m up
    e.add(box("stays", half, 2.0).at(start - 0.6 * across).rotated(tilt).rough(0.49, 0.36));
    e.add(box("slides", half, 2.0).at(start + 0.6 * across).rotated(tilt).rough(0.09, 0.04));
    e.add(plane("floor", Vec3::UnitY()).rough(1.0, 1.0));
}

// A ball and a box thrown along the floor at 4 m/s without spin (mu = 0.3 with the floor). Friction
// at the ball's contact point slows its centre and spins it up until the point no longer slides:
// from then on it rolls at 5/7 of 4 m/s, 2.86 m/s, for ever. The box slides to a stop after
// v^2 / (2 mu g) = 2.7 m.
void rollingBall(PhysicsEngine& e) {
    e.add(plane("floor", {0.0, 1.0, 0.0}).rough(0.3, 0.3));
    e.add(sphere("ball", 0.3, 1.0).at({-4.0, 0.3, -0.6}).moving({4.0, 0.0, 0.0}).rough(0.3, 0.3).bouncy(0.0));
    e.add(box("box", {0.25, 0.25, 0.25}, 1.0).at({-4.0, 0.25, 0.6}).moving({4.0, 0.0, 0.0}).rough(0.3, 0.3).bouncy(0.0));
}

// Five boxes stacked on the floor, each a little off the one below: the stack stands still, without
// drift or jitter, held by the normal impulses that the sweeps sum up and warm starting carries from
// step to step.
void boxStack(PhysicsEngine& e) {
    e.add(plane("floor", {0.0, 1.0, 0.0}));
    const Vec3 half(0.4, 0.25, 0.4);
    for (int i = 0; i < 5; ++i) {
        const double offset = (i % 2 == 0 ? 0.02 : -0.02);  // m
        e.add(box("box" + std::to_string(i + 1), half, 1.0).at({offset, half.y() * (2 * i + 1), 0.0}).bouncy(0.0));
    }
}

// Worksheet 6's corner drop with friction (mu = 0.5) and resting contact: the box of half extents
// 0.2 x 0.3 x 0.4 m, tilted about x and z, lands on a corner with restitution 0.5, tumbles and comes
// to rest on a face. Without the friction stage it rocks for ever: each step the impulse of
// worksheet 4 bounces a resting corner by e g h, which this stage's restitution leaves to impacts.
void cornerLanding(PhysicsEngine& e) {
    e.add(plane("floor", {0.0, 1.0, 0.0}));
    const Quat tilt = Quat(Eigen::AngleAxisd(0.5, Vec3::UnitX())) * Quat(Eigen::AngleAxisd(0.4, Vec3::UnitZ()));
    e.add(box("box", {0.2, 0.3, 0.4}, 2.0).at({0.0, 1.5, 0.0}).rotated(tilt).bouncy(0.5));
}

}  // namespace

void addWorksheet7Scenes(SceneRegistry& r) {
    // The view frames the slope from the boxes to its foot, and the sliding box until it lies on the
    // floor.
    r.add({"incline", "", "Two boxes on a slope of 25 degrees: the one with mu_s above tan 25 stays, the other slides.",
           7, kFrictionStages, kDefaultTimeStep, incline, Integrator::SemiImplicitEuler, Vec3(4.5, 2.3, 0.0), 15.0,
           3.5});
    r.add({"rolling-ball", "", "A ball and a box thrown along the floor: the ball ends rolling at 5/7 of its speed.", 7,
           kFrictionStages, kDefaultTimeStep, rollingBall, Integrator::SemiImplicitEuler, Vec3(-0.3, 0.5, 0.0), 10.0, 2.5});
    r.add({"box-stack", "", "Five boxes stacked on the floor: they rest still, without drift or jitter.", 7, kFrictionStages,
           kDefaultTimeStep, boxStack, Integrator::SemiImplicitEuler, Vec3(0.0, 1.5, 0.0), 8.0, 10.0});
    r.add({"corner-landing", "", "Worksheet 6's corner drop with friction: the box tumbles and comes to rest on a face.", 7,
           kFrictionStages, kDefaultTimeStep, cornerLanding, Integrator::SemiImplicitEuler, Vec3(0.0, 1.1, 0.0), 5.5,
           4.0});
}

}  // namespace gpl
