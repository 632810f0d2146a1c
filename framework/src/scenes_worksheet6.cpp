// Worksheet 6 scenes: boxes that turn. Without gravity and contacts nothing changes a box's angular
// momentum, so spinning-boxes shows the torque-free motion of a rigid body alone; corner-drop shows
// the impulse at a contact point turning a box (worksheet 5's box contacts).
#include "gpl/scenes.h"

namespace gpl {
namespace {

const StageSet kTurning{Stage::Integration, Stage::Rotation};
const StageSet kLanding{Stage::ConstantAcceleration, Stage::Integration,      Stage::Rotation,
                        Stage::CollisionDetection,   Stage::Interpenetration, Stage::CollisionImpulses};

// Three boxes of half extents 0.15 x 0.4 x 0.8 m (moments of inertia about x, y and z: the largest,
// the middle one and the smallest), each spun at 3 rad/s about one of its axes with a hundredth of
// that about the others. About the largest axis (left) and the smallest (right) the wobble stays
// small; about the middle one (centre) it grows until the box flips over, again and again (the
// tennis-racket theorem), while every box keeps its angular momentum.
void spinningBoxes(PhysicsEngine& e) {
    const Vec3 half(0.15, 0.4, 0.8);
    e.add(box("largest-axis", half, 2.0).at({-2.2, 0.0, 0.0}).spinning({3.0, 0.03, 0.03}));
    e.add(box("middle-axis", half, 2.0).spinning({0.03, 3.0, 0.03}));
    e.add(box("smallest-axis", half, 2.0).at({2.2, 0.0, 0.0}).spinning({0.03, 0.03, 3.0}));
}

// A box dropped from 1 m above the floor, tilted so that one corner lands first: the impulse at that
// corner sets it turning, it falls onto an edge and a face and bounces on. Without friction
// (worksheet 7) it spins and slides on the floor for ever; its horizontal momentum stays zero.
void cornerDrop(PhysicsEngine& e) {
    e.add(plane("floor", {0.0, 1.0, 0.0}));
    const Quat tilt = Quat(Eigen::AngleAxisd(0.5, Vec3::UnitX())) * Quat(Eigen::AngleAxisd(0.4, Vec3::UnitZ()));
    e.add(box("box", {0.2, 0.3, 0.4}, 2.0).at({0.0, 1.5, 0.0}).rotated(tilt).bouncy(0.5));
}

}  // namespace

void addWorksheet6Scenes(SceneRegistry& r) {
    r.add({"spinning-boxes", "F9",
           "Boxes spun about their largest, middle and smallest axes: the middle one flips over and over.", 6, kTurning,
           kDefaultTimeStep, spinningBoxes, Integrator::SemiImplicitEuler, Vec3::Zero(), 7.0});
    // Without friction (worksheet 7) the box slides and spins on for ever: the view frames the
    // landing and the first 4 s.
    r.add({"corner-drop", "F10", "A box dropped on a corner: the impulse at the corner sets it turning.", 6, kLanding,
           kDefaultTimeStep, cornerDrop, Integrator::SemiImplicitEuler, Vec3(0.0, 1.1, 0.0), 5.5, 4.0});
}

}  // namespace gpl
