// Worksheet 4 scenes: contacts answered by impulses with restitution, and ropes.
#include <cmath>
#include <random>
#include <string>

#include "gpl/scenes.h"

namespace gpl {
namespace {

const StageSet kImpulses{Stage::ConstantAcceleration, Stage::Integration, Stage::CollisionDetection,
                         Stage::CollisionImpulses, Stage::Interpenetration};
const StageSet kRopes{Stage::ConstantAcceleration, Stage::Integration,       Stage::CollisionDetection,
                      Stage::Ropes,                Stage::CollisionImpulses, Stage::Interpenetration};

// Five balls dropped from 4 m onto a floor of restitution 1: each rebounds with its own
// coefficient, to e^2 of the height before.
void bouncingBalls(PhysicsEngine& e) {
    e.add(plane("floor", {0.0, 1.0, 0.0}));
    const double restitution[] = {0.0, 0.3, 0.5, 0.7, 0.9};
    for (int i = 0; i < 5; ++i) {
        e.add(sphere("e=" + formatNumber(restitution[i]), 0.3, 1.0)
                  .at({1.2 * (i - 2), 4.0, 0.0})
                  .bouncy(restitution[i]));
    }
}

// A billiard table (2.54 m by 1.27 m of cloth, cushions as four planes) and a break: the cue ball
// at 8 m/s into a triangle of fifteen. The cloth has restitution 0 (the balls roll on it without
// hopping), the cushions 1, the balls 0.95: a pair of balls 0.9025 by the product rule, a ball and
// a cushion 0.95. No friction yet (worksheet 7), so the balls slide on for ever.
void billiards(PhysicsEngine& e) {
    const double r = 0.028575, m = 0.17;  // m, kg: pool balls
    const double halfLength = 1.27, halfWidth = 0.635;
    e.add(plane("cloth", {0.0, 1.0, 0.0}).bouncy(0.0));
    e.add(plane("cushion-head", {1.0, 0.0, 0.0}).at({-halfLength, 0.0, 0.0}));
    e.add(plane("cushion-foot", {-1.0, 0.0, 0.0}).at({halfLength, 0.0, 0.0}));
    e.add(plane("cushion-left", {0.0, 0.0, 1.0}).at({0.0, 0.0, -halfWidth}));
    e.add(plane("cushion-right", {0.0, 0.0, -1.0}).at({0.0, 0.0, halfWidth}));
    e.add(sphere("cue", r, m).at({-0.635, r, 0.0}).moving({8.0, 0.0, 0.0}).bouncy(0.95));
    // The rack: rows of 1..5 balls, touching, apex on the foot spot; a hair of space (0.1 mm)
    // between neighbours, so that the break, not the rack, starts the contacts.
    const double gap = 2.0 * r + 1e-4;
    int n = 1;
    for (int row = 0; row < 5; ++row) {
        for (int k = 0; k <= row; ++k, ++n) {
            const Vec3 at(0.635 + row * gap * std::sqrt(3.0) / 2.0, r, (k - row / 2.0) * gap);
            e.add(sphere("ball" + std::to_string(n), r, m).at(at).bouncy(0.95));
        }
    }
}

// Newton's cradle: five steel balls of restitution 1, each hanging on a 2 m rope from its own
// anchor, side by side and just touching. The first is lifted to 40 degrees and let go.
void newtonsCradle(PhysicsEngine& e) {
    const double r = 0.25, length = 2.0, top = 4.0;
    const double lift = 40.0 * M_PI / 180.0;
    for (int i = 0; i < 5; ++i) {
        const double x = 2.0 * r * (i - 2);
        const std::string anchor = "anchor" + std::to_string(i + 1), ball = "ball" + std::to_string(i + 1);
        e.add(sphere(anchor, 0.03, 1.0).at({x, top, 0.0}).makeStatic());
        Vec3 at(x, top - length, 0.0);
        if (i == 0) at = Vec3(x - length * std::sin(lift), top - length * std::cos(lift), 0.0);
        e.add(sphere(ball, r, 1.0).at(at).bouncy(1.0));
        e.addRope(anchor, ball, length);
    }
}

// Two balls tied by a 3 m rope: one thrown up and sideways, one resting on the floor. The rope goes
// slack and taut again; each time it is taut it jerks the other ball along.
void ballsOnARope(PhysicsEngine& e) {
    e.add(plane("floor", {0.0, 1.0, 0.0}).bouncy(0.5));
    e.add(sphere("thrown", 0.25, 1.0).at({-1.0, 0.25, 0.0}).moving({3.0, 9.0, 0.0}).bouncy(0.5));
    e.add(sphere("tied", 0.25, 2.0).at({0.5, 0.25, 0.0}).bouncy(0.5));
    e.addRope("thrown", "tied", 3.0);
}

// The heap the performance benchmark compares with other engines: 1000 spheres (0.5 m, 1 kg,
// restitution 0) on a jittered 10 x 10 x 10 lattice of spacing 1.2 m, dropped on a plane.
void heap(PhysicsEngine& e) {
    e.add(plane("ground", {0.0, 1.0, 0.0}));
    std::mt19937 random(1);  // fixed seed: the same heap every time
    const auto jitter = [&random] { return 0.1 * (static_cast<double>(random()) / 4294967296.0 - 0.5); };  // m
    int n = 0;
    for (int y = 0; y < 10; ++y) {
        for (int z = 0; z < 10; ++z) {
            for (int x = 0; x < 10; ++x, ++n) {
                const Vec3 at(1.2 * (x - 4.5) + jitter(), 1.0 + 1.2 * y + jitter(), 1.2 * (z - 4.5) + jitter());
                e.add(sphere("sphere" + std::to_string(n), 0.5, 1.0).at(at).bouncy(0.0));
            }
        }
    }
}

}  // namespace

void addWorksheet4Scenes(SceneRegistry& r) {
    r.add({"bouncing-balls", "F2", "Five balls of restitution 0 to 0.9 bounce on a floor: heights fall like e^2.", 4,
           kImpulses, kDefaultTimeStep, bouncingBalls, Integrator::SemiImplicitEuler, Vec3(0.0, 2.4, 0.0), 10.5});
    r.add({"billiards", "F3", "A billiard break on a table of planes: impulses between balls and cushions.", 4,
           kImpulses, 0.002, billiards, Integrator::SemiImplicitEuler, Vec3(0.0, 0.5, 0.3), 3.0});
    r.add({"newtons-cradle", "F4", "Newton's cradle: five balls on ropes pass one impulse along the row.", 4, kRopes,
           0.0025, newtonsCradle, Integrator::SemiImplicitEuler, Vec3(0.0, 2.6, 0.0), 6.0});
    r.add({"balls-on-a-rope", "F5", "Two balls tied by a rope: thrown, it goes slack and jerks taut.", 4, kRopes,
           kDefaultTimeStep, ballsOnARope, Integrator::SemiImplicitEuler, Vec3(5.4, 1.9, 0.0), 14.5});
    // Without friction (worksheet 7) the heap, once down, spreads for ever at some 10 m/s: its view
    // frames the drop and the first 2 s.
    r.add({"heap", "F6", "1000 spheres dropped on a plane: without friction their heap spreads out into one layer.", 4,
           kImpulses, kDefaultTimeStep, heap, Integrator::SemiImplicitEuler, Vec3(0.0, 5.7, 0.0), 38.0, 2.0});
}

}  // namespace gpl
