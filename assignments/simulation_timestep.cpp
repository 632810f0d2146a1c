// Worksheet 1, assignment 3: the time step.
//
// Inputs:  the engine's bodies and settings; stageActive(stage) tells which stages the scene requires
// Outputs: every stage of one time step run once, in order, each only when its stage is active
//
// Read it top to bottom: one comment and one call per stage.
#include "gpl/engine.h"

namespace gpl {

void PhysicsEngine::simulationTimestep() {
    // Forces: gravity into the acceleration accumulator of every movable body.
    notImplemented("simulationTimestep()");

    // Integrate: advance velocities and positions by one time step.
    if (stageActive(Stage::Integration)) integrator();
}

}  // namespace gpl
