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

    // Forces: springs add theirs (worksheet 2).
    if (stageActive(Stage::Springs)) applySpringForces();

    // Integrate: advance velocities and positions by one time step with the chosen integrator
    // (integrator() for semi-implicit Euler).
    if (stageActive(Stage::Integration)) integrate();

    // Rotate: advance orientations and angular velocities by one time step (worksheet 6).
    if (stageActive(Stage::Rotation)) rotate();

    // Contacts: pairs that overlap, from the broad phase and the collision kernels (worksheet 3).
    if (stageActive(Stage::CollisionDetection)) detectCollisions();

    // Ropes: every taut rope joins the contacts as one that pulls (worksheet 4).
    if (stageActive(Stage::Ropes)) addRopeContacts();

    // Interpenetration: overlapping bodies move apart, shared by mass (worksheet 3); overlaps
    // this creates join the contacts.
    if (stageActive(Stage::Interpenetration)) resolveInterpenetrations();

    // Impulses: velocities at the contacts change so that the bodies separate (worksheet 4).
    if (stageActive(Stage::CollisionImpulses)) applyCollisionImpulses();

    // Friction: summed normal and friction impulses at every contact point, started from last
    // step's; in a scene with friction this stage, not the one above, answers the contacts (worksheet 7).
    if (stageActive(Stage::Friction)) solveContacts();

    // Constraints: move positions onto rods, chains and the container, and spheres apart (worksheet 2).
    if (stageActive(Stage::Constraints) || stageActive(Stage::ParticleCollisions)) projectConstraints();

    // Soft bodies, predict: velocities by gravity and wind, predicted positions p = x + h v (worksheet 8).
    if (stageActive(Stage::SoftPredict)) predictParticles();

    // Soft contacts: which particles lie near the rigid bodies and near each other, once per step.
    if (stageActive(Stage::SoftContacts)) findParticleContacts();

    // Project: sweeps of the distance and volume constraints, then the contacts, over the predictions.
    if (stageActive(Stage::SoftProject)) projectParticles();

    // Soft velocities: v = (p - x) / h, and the corrected predictions become the positions.
    if (stageActive(Stage::SoftVelocities)) updateParticleVelocities();

    // Fluid, predict: velocities by gravity, predicted positions p = x + h v (worksheet 9).
    if (stageActive(Stage::FluidPredict)) predictFluid();

    // Neighbours: every fluid particle's neighbours nearer than the smoothing length, once per step.
    if (stageActive(Stage::FluidNeighbours)) findFluidNeighbours();

    // Fluid project: sweeps of densities, multipliers and moves, then the rigid bodies' push.
    if (stageActive(Stage::FluidProject)) projectFluid();

    // Fluid velocities: v = (p - x) / h, XSPH viscosity, and the predictions become the positions.
    if (stageActive(Stage::FluidVelocities)) updateFluidVelocities();

    // SPH: weakly compressible SPH's whole step in substeps, the framework's comparison (worksheet 9).
    if (stageActive(Stage::FluidSph)) stepSph();
}

}  // namespace gpl
