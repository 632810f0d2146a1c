// Your own scenes, on the keys F11 and F12. Copy one of the course's scenes
// (framework/src/scenes_worksheet1.cpp) and change it: add bodies, give them velocities, make some
// static. Run it with ./lab run --scene F11 (or press F11 in the viewer).
#include "gpl/scenes.h"

namespace gpl {
namespace {

void myScene(PhysicsEngine& e) {
    e.add(plane("floor", {0.0, 1.0, 0.0}));
    e.add(sphere("my-ball", 0.5, 1.0).at({0.0, 5.0, 0.0}).moving({2.0, 3.0, 0.0}));
}

}  // namespace

void addStudentScenes(SceneRegistry& r) {
    const StageSet stages{Stage::ConstantAcceleration, Stage::Integration};
    r.add({"my-scene", "F11", "Your own scene: edit assignments/student_scenes.cpp.", 0, stages, kDefaultTimeStep,
           myScene});
}

}  // namespace gpl
