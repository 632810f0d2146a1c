// Worksheet 6 scenes: boxes that turn. Without gravity and contacts nothing changes a box's angular
// momentum, so what the viewer shows is the torque-free motion of a rigid body alone.
#include "gpl/scenes.h"

namespace gpl {
namespace {

const StageSet kTurning{Stage::Integration, Stage::Rotation};

// A box of half extents 0.15 x 0.4 x 0.8 m: its moments of inertia about x, y and z are the largest,
// the middle one and the smallest, in that order.
Body flatBox(const std::string& name) { return box(name, {0.15, 0.4, 0.8}, 2.0); }

// Spun about its middle axis (y) at 3 rad/s, with a thousandth of that about the others: the tiny
// wobble grows until the box flips over, again and again (the tennis-racket theorem), while its
// angular momentum stays what it was.
void tumblingBox(PhysicsEngine& e) { e.add(flatBox("tumbler").spinning({0.003, 3.0, 0.003})); }

// The same box spun about its largest axis (x, left) and its smallest (z, right), each with the same
// small disturbance: both keep turning about that axis with a slight wobble that never grows.
void spinningBoxes(PhysicsEngine& e) {
    e.add(flatBox("largest-axis").at({-1.5, 0.0, 0.0}).spinning({3.0, 0.03, 0.03}));
    e.add(flatBox("smallest-axis").at({1.5, 0.0, 0.0}).spinning({0.03, 0.03, 3.0}));
}

}  // namespace

void addWorksheet6Scenes(SceneRegistry& r) {
    r.add({"tumbling-box", "F10", "A box spun about its middle axis in zero gravity flips over and over.", 6, kTurning,
           kDefaultTimeStep, tumblingBox, Integrator::SemiImplicitEuler, Vec3::Zero(), 4.0});
    r.add({"spinning-boxes", "F9", "Boxes spun about their largest and smallest axes: they wobble, never flip.", 6,
           kTurning, kDefaultTimeStep, spinningBoxes, Integrator::SemiImplicitEuler, Vec3::Zero(), 6.0});
}

}  // namespace gpl
