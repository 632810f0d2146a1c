// Worksheet 3 scenes: contacts found and answered by moving positions (no impulses yet), so the
// velocity follows the correction and every landing is plastic.
#include <cmath>
#include <random>
#include <string>

#include "gpl/scenes.h"

namespace gpl {
namespace {

const StageSet kPositional{Stage::ConstantAcceleration, Stage::Integration, Stage::CollisionDetection,
                           Stage::Interpenetration};

// A box of planes (a floor and four walls, 4 m by 4 m, open at the top) with 45 balls dropped
// into it from a loose lattice, each with a small sideways velocity.
void ballsInABox(PhysicsEngine& e) {
    const double half = 2.0;  // m, half the box's inner width
    e.add(plane("floor", {0.0, 1.0, 0.0}));
    e.add(plane("wall-left", {1.0, 0.0, 0.0}).at({-half, 0.0, 0.0}));
    e.add(plane("wall-right", {-1.0, 0.0, 0.0}).at({half, 0.0, 0.0}));
    e.add(plane("wall-back", {0.0, 0.0, 1.0}).at({0.0, 0.0, -half}));
    e.add(plane("wall-front", {0.0, 0.0, -1.0}).at({0.0, 0.0, half}));
    std::mt19937 random(3);  // fixed seed: the same scene every time
    const auto jitter = [&random] { return static_cast<double>(random()) / 4294967296.0 - 0.5; };  // -0.5..0.5
    int n = 0;
    for (int layer = 0; layer < 5; ++layer) {
        for (int row = 0; row < 3; ++row) {
            for (int col = 0; col < 3; ++col, ++n) {
                const double radius = 0.25 + 0.1 * ((n * 7) % 4) / 3.0;  // 0.25 .. 0.35 m
                const Vec3 at(1.1 * (col - 1) + 0.1 * jitter(), 1.0 + 1.1 * layer, 1.1 * (row - 1) + 0.1 * jitter());
                const double mass = std::pow(radius / 0.25, 3);  // kg: one density, 1 kg at 0.25 m
                e.add(sphere("ball" + std::to_string(n), radius, mass)
                          .at(at)
                          .moving({2.0 * jitter(), 0.0, 2.0 * jitter()}));
            }
        }
    }
}

// Two planes tilted by 30 degrees towards each other form a valley (offset from the origin);
// twenty balls fall onto the slopes, slide down without friction and gather at the bottom.
void valley(PhysicsEngine& e) {
    const double tilt = M_PI / 6.0;
    e.add(plane("left-slope", {std::sin(tilt), std::cos(tilt), 0.0}).at({0.0, 1.0, 0.0}));
    e.add(plane("right-slope", {-std::sin(tilt), std::cos(tilt), 0.0}).at({0.0, 1.0, 0.0}));
    e.add(plane("back", {0.0, 0.0, 1.0}).at({0.0, 0.0, -1.0}));
    e.add(plane("front", {0.0, 0.0, -1.0}).at({0.0, 0.0, 1.0}));
    for (int i = 0; i < 20; ++i) {
        const double x = -3.8 + 0.4 * i;
        e.add(sphere("ball" + std::to_string(i), 0.3, 1.0).at({x, 5.0 + 0.5 * (i % 3), 0.3 * ((i % 3) - 1)}));
    }
}

}  // namespace

void addWorksheet3Scenes(SceneRegistry& r) {
    r.add({"balls-in-a-box", "9", "45 balls dropped into a box of five planes; overlaps resolved by moving positions.",
           3, kPositional, kDefaultTimeStep, ballsInABox, Integrator::SemiImplicitEuler, Vec3(0.0, 3.0, 0.0), 13.0});
    r.add({"valley", "F1", "Balls slide down two tilted planes into the valley between them.", 3, kPositional,
           kDefaultTimeStep, valley, Integrator::SemiImplicitEuler, Vec3(0.0, 4.5, 0.0), 10.5});
}

}  // namespace gpl
