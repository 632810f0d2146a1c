// Worksheet 6 scenes: boxes that turn. Without gravity and contacts nothing changes a box's angular
// momentum, so what the viewer shows is the torque-free motion of a rigid body alone.
#include "gpl/scenes.h"

namespace gpl {
namespace {

const StageSet kTurning{Stage::Integration, Stage::Rotation};

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

}  // namespace

void addWorksheet6Scenes(SceneRegistry& r) {
    r.add({"spinning-boxes", "F9",
           "Boxes spun about their largest, middle and smallest axes: the middle one flips over and over.", 6, kTurning,
           kDefaultTimeStep, spinningBoxes, Integrator::SemiImplicitEuler, Vec3::Zero(), 7.0});
}

}  // namespace gpl
