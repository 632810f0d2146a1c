// Worksheet 5 scenes: boxes against the floor, balls and each other. Boxes do not turn until
// worksheet 6 and nothing has friction until worksheet 7: a tilted box lands on an edge or a corner
// and stays tilted there, and whatever is pushed sideways slides on.
#include <cmath>
#include <string>

#include "gpl/scenes.h"

namespace gpl {
namespace {

const StageSet kBoxImpulses{Stage::ConstantAcceleration, Stage::Integration, Stage::CollisionDetection,
                            Stage::CollisionImpulses, Stage::Interpenetration};

Quat turn(double radians, const Vec3& axis) { return Quat(Eigen::AngleAxisd(radians, axis.normalized())); }

// Three boxes dropped on a floor, one lying flat, one tilted about one axis (it lands on an edge),
// one about two (it lands on a corner); then a ball thrown at a fourth box resting on the floor.
void fallingBoxes(PhysicsEngine& e) {
    e.add(plane("floor", {0.0, 1.0, 0.0}));
    e.add(box("flat", {0.6, 0.3, 0.4}, 2.0).at({-2.5, 1.5, 0.0}).bouncy(0.4));
    e.add(box("on-an-edge", {0.4, 0.4, 0.4}, 1.0).at({-0.8, 2.0, 0.0}).rotated(turn(0.35, Vec3::UnitZ())).bouncy(0.4));
    e.add(box("on-a-corner", {0.3, 0.5, 0.3}, 1.5)
              .at({0.8, 2.5, 0.0})
              .rotated(turn(0.5, Vec3::UnitX()) * turn(0.4, Vec3::UnitZ()))
              .bouncy(0.4));
    e.add(box("target", {0.4, 0.4, 0.4}, 2.0).at({1.5, 0.4, 2.0}).bouncy(0.4));
    e.add(sphere("ball", 0.25, 1.0).at({4.5, 0.6, 2.0}).moving({-3.0, 3.5, 0.0}).bouncy(0.6));
}

// A stack of five boxes, each turned a little against the one below, and beside it a wall of twelve
// boxes that a heavy ball slides into and through. The wall stands at 45 degrees to the viewer's
// line of sight, its face towards the front right, where the ball comes from: the camera sees the
// ball strike the face, and the bricks knocked out fly off to the back left, clear of the stack.
void stackAndWall(PhysicsEngine& e) {
    e.add(plane("floor", {0.0, 1.0, 0.0}));
    const Vec3 half(0.5, 0.25, 0.4);
    for (int k = 0; k < 5; ++k) {
        e.add(box("stack" + std::to_string(k + 1), half, 1.0)
                  .at({-2.5, half.y() * (2 * k + 1), -0.8})
                  .rotated(turn(0.15 * k, Vec3::UnitY()))
                  .bouncy(0.0));
    }
    const Vec3 centre(0.8, 0.0, -1.0);                       // m, the wall's foot
    const Vec3 along = Vec3(1.0, 0.0, -1.0).normalized();    // the wall's length
    const Vec3 facing = Vec3(1.0, 0.0, 1.0).normalized();    // its face's normal
    const Quat wallTurn = turn(0.25 * M_PI, Vec3::UnitY());  // a brick's x axis along the wall
    const Vec3 brick(0.4, 0.25, 0.2);
    for (int row = 0; row < 4; ++row) {
        for (int col = 0; col < 3; ++col) {
            e.add(box("brick" + std::to_string(3 * row + col + 1), brick, 0.5)
                      .at(centre + brick.x() * 2.0 * (col - 1) * along + Vec3(0.0, brick.y() * (2 * row + 1), 0.0))
                      .rotated(wallTurn)
                      .bouncy(0.2));
        }
    }
    // 3.45 m from the face, a little off the middle brick's centre.
    const Vec3 ball = centre + 0.1 * along + (brick.z() + 0.35 + 3.45) * facing + Vec3(0.0, 0.35, 0.0);
    e.add(sphere("ball", 0.35, 4.0).at(ball).moving(-3.0 * facing).bouncy(0.2));
}

}  // namespace

void addWorksheet5Scenes(SceneRegistry& r) {
    // The ball knocks the target box off along the frictionless floor: the view frames the landings,
    // the throw and the first 4 s.
    r.add({"falling-boxes", "F7", "Boxes land flat, on an edge and on a corner; a ball is thrown at a box.", 5,
           kBoxImpulses, kDefaultTimeStep, fallingBoxes, Integrator::SemiImplicitEuler, Vec3(0.8, 1.2, 0.0), 10.0, 4.0});
    // Without friction (worksheet 7) the bricks the ball knocks over slide on for ever: the view
    // frames the stack, the wall and the first 3 s.
    r.add({"stack-and-wall", "F8", "A stack of five boxes stands; a heavy ball slides into a wall of boxes.", 5,
           kBoxImpulses, kDefaultTimeStep, stackAndWall, Integrator::SemiImplicitEuler, Vec3(0.0, 1.0, 0.0), 10.0, 3.0});
}

}  // namespace gpl
