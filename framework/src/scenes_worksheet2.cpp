// Worksheet 2 scenes: pendulum, chain, springs and a container of balls, stepped by Verlet.
#include <cmath>
#include <string>

#include "gpl/scenes.h"

namespace gpl {
namespace {

const StageSet kConstrained{Stage::ConstantAcceleration, Stage::Integration, Stage::Constraints};
const StageSet kSprings{Stage::ConstantAcceleration, Stage::Springs, Stage::Integration};
const StageSet kContainer{Stage::ConstantAcceleration, Stage::Integration, Stage::Constraints,
                          Stage::ParticleCollisions};

// A 1 kg bob on a 2 m rod, released from rest at 60 degrees: small-angle period 2.84 s, the true
// one 7 % longer (2 pi sqrt(L/g) times 1.073 at this amplitude).
void pendulum(PhysicsEngine& e) {
    const Vec3 pivot(0.0, 5.0, 0.0);
    const double length = 2.0;
    const double angle = M_PI / 3.0;
    e.add(sphere("pivot", 0.05, 1.0).at(pivot).makeStatic());
    e.add(sphere("bob", 0.2, 1.0).at(pivot + length * Vec3(std::sin(angle), -std::cos(angle), 0.0)));
    e.addDistanceConstraint("pivot", "bob");
}

// Twelve 0.1 kg links of 0.4 m hanging from a pivot, released horizontally.
void chain(PhysicsEngine& e) {
    const Vec3 pivot(0.0, 6.0, 0.0);
    e.add(sphere("pivot", 0.05, 1.0).at(pivot).makeStatic());
    std::string previous = "pivot";
    for (int i = 1; i <= 12; ++i) {
        const std::string name = "link" + std::to_string(i);
        e.add(sphere(name, 0.08, 0.1).at(pivot + Vec3(0.4 * i, 0.0, 0.0)));
        e.addDistanceConstraint(previous, name);
        previous = name;
    }
}

// Three spring-mass systems side by side: undamped (omega = sqrt(k/m) = 6.3 rad/s, period 1 s),
// damped, and two bodies in series (body-body spring).
void springOscillator(PhysicsEngine& e) {
    const double k = 40.0;  // N/m
    for (int i = 0; i < 3; ++i) {
        const std::string anchor = "anchor" + std::to_string(i + 1);
        e.add(sphere(anchor, 0.05, 1.0).at({3.0 * (i - 1), 8.0, 0.0}).makeStatic());
    }
    // Rest length 1 m; the weight stretches it by m g / k = 0.25 m, and each starts 0.5 m lower still.
    e.add(sphere("undamped", 0.25, 1.0).at({-3.0, 6.25, 0.0}));
    e.addSpring("anchor1", "undamped", k, 0.0, 1.0);
    e.add(sphere("damped", 0.25, 1.0).at({0.0, 6.25, 0.0}));
    e.addSpring("anchor2", "damped", k, 0.8, 1.0);
    e.add(sphere("upper", 0.2, 1.0).at({3.0, 6.5, 0.0}));
    e.add(sphere("lower", 0.2, 1.0).at({3.0, 5.0, 0.0}));
    e.addSpring("anchor3", "upper", k, 0.0, 1.0);
    e.addSpring("upper", "lower", k, 0.0, 1.0);
}

// 300 balls dropped into a round container (a circle in the z = 0 plane): the Verlet sandbox.
void container(PhysicsEngine& e) {
    const Vec3 centre(0.0, 5.0, 0.0);
    const double radius = 5.0;    // m
    const double ball = 0.15;     // m
    const double spacing = 0.34;  // m between starting centres: no overlaps at the start
    e.setContainer(centre, radius);
    int count = 0;
    for (int row = 0; count < 300; ++row) {
        const double y = centre.y() + radius - 0.3 - spacing * row;
        for (int col = -15; col <= 15 && count < 300; ++col) {
            const Vec3 p(spacing * col, y, 0.0);
            if ((p - centre).norm() > radius - ball - 0.05) continue;
            // Small sideways velocities, alternating, so the heap does not settle in a perfect lattice.
            const double vx = (count % 2 == 0 ? 0.3 : -0.3) * (1.0 + 0.1 * (count % 7));
            e.add(sphere("ball" + std::to_string(count), ball, 0.1).at(p).moving({vx, 0.0, 0.0}));
            ++count;
        }
    }
}

}  // namespace

void addWorksheet2Scenes(SceneRegistry& r) {
    r.add({"pendulum", "5", "A rod pendulum released at 60 degrees; the rod is a distance constraint.", 2, kConstrained,
           kDefaultTimeStep, pendulum, Integrator::PositionVerlet, Vec3(0.0, 4.0, 0.0), 7.0});
    r.add({"chain", "6", "A chain of twelve links released horizontally from a pivot.", 2, kConstrained,
           kDefaultTimeStep, chain, Integrator::PositionVerlet, Vec3(0.0, 3.5, 0.0), 11.0});
    r.add({"spring-oscillator", "7", "Springs: undamped, damped, and two bodies in series.", 2, kSprings,
           kDefaultTimeStep, springOscillator, Integrator::VelocityVerlet, Vec3(0.0, 5.8, 0.0), 10.0});
    r.add({"container", "8", "300 balls dropped into a round container; contacts resolved by moving positions.", 2,
           kContainer, kDefaultTimeStep, container, Integrator::PositionVerlet, Vec3(0.0, 6.8, 0.0), 17.0});
}

}  // namespace gpl
