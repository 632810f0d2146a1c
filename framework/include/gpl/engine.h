// The physics engine: bodies, settings, the time step and its hooks, and diagnostics.
//
// Student hooks (bodies in assignments/, reference bodies in solutions/):
//   simulationTimestep()  worksheet 1: one time step, stage by stage
//   integrator()          worksheet 1: semi-implicit Euler for all bodies
//   positionVerlet(), velocityVerlet()  worksheet 2: kernels in gpl/integrators.h
// Framework-provided stages the hooks call:
//   updateConstantAcceleration()  sets every movable body's acceleration accumulator to gravity
//   applySpringForces()           adds the springs' accelerations to the accumulators
//   integrate()                   one step with the chosen integrator (integrator() for semi-implicit Euler)
//   projectConstraints()          moves positions onto rods, chains, the container; separates spheres
//   detectCollisions()            broad phase, then the collision kernels (worksheet 3): contacts()
//   addRopeContacts()             every taut rope becomes a contact (worksheet 4)
//   applyCollisionImpulses()      sweeps of applyCollisionImpulse() over contacts() (worksheet 4)
//   resolveInterpenetrations()    sweeps of resolveInterpenetration() over contacts() (worksheet 3)
//   rotate()                      integrateRotation() for every movable body (worksheet 6)
//   solveContacts()               summed normal and friction impulses, warm started (worksheet 7)
//   predictParticles()            soft bodies: v += h (g + wind / m), p = x + h v (worksheet 8)
//   findParticleContacts()        soft bodies: particles near rigid bodies and near each other (worksheet 8)
//   projectParticles()            soft bodies: sweeps of solveDistanceConstraint(), solveVolumeConstraint()
//                                 and the contact kernels over the predictions (worksheet 8)
//   updateParticleVelocities()    soft bodies: v = (p - x) / h, x = p (worksheet 8)
//   predictFluid()                fluids: v += h g, p = x + h v (worksheet 9)
//   findFluidNeighbours()         fluids: every particle's neighbours, once per step (worksheet 9)
//   projectFluid()                fluids: sweeps of fluidDensity(), densityConstraintLambda(),
//                                 densityCorrection() and the rigid bodies' push (worksheet 9)
//   updateFluidVelocities()       fluids: v = (p - x) / h, xsphViscosity(), x = p (worksheet 9)
//   stepSph()                     fluids: weakly compressible SPH's step, the comparison (worksheet 9)
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "gpl/body.h"
#include "gpl/constraints.h"
#include "gpl/contact.h"
#include "gpl/fluids.h"
#include "gpl/forces.h"
#include "gpl/friction.h"
#include "gpl/integrators.h"
#include "gpl/owned.h"
#include "gpl/second_thread.h"
#include "gpl/soft_bodies.h"
#include "gpl/stages.h"

namespace gpl {

// The contact stages' own state, each in its own header: the engine holds it (Owned, owned.h), and a
// file that includes engine.h (every hook file) compiles none of it.
class BroadPhase;     // broadphase.h
struct BodyPair;      // broadphase.h
class FrictionStage;  // friction_stage.h

/// Default time step of the engine (s): 100 steps per simulated second. A scene may override it.
constexpr double kDefaultTimeStep = 0.01;
/// Margin of the contact stages' broad phase, as a fraction of each body's size: pairs this near
/// are watched for overlaps while interpenetration moves bodies apart.
constexpr double kContactMargin = 0.1;
/// Time steps ahead along its velocity that a body's box reaches when the broad phase keeps its
/// pairs for the next steps (BroadPhase::findPairs()): a body that moves steadily stays inside.
constexpr double kPairsAhead = 3.0;
/// Standard gravity (m/s^2), pointing down the y axis.
inline Vec3 standardGravity() { return Vec3(0.0, -9.81, 0.0); }

/// Thrown when the simulation reaches a state it cannot continue from (a NaN, an infinity).
class SimulationError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class PhysicsEngine {
public:
    PhysicsEngine();
    ~PhysicsEngine();
    /// A copy has its own contact stages, copied, and no second thread until it needs one.
    PhysicsEngine(const PhysicsEngine&);
    PhysicsEngine& operator=(const PhysicsEngine&);
    PhysicsEngine(PhysicsEngine&&);
    PhysicsEngine& operator=(PhysicsEngine&&);

    // ---- Bodies -------------------------------------------------------------------------------
    /// Adds a body after validating it (throws std::invalid_argument with the reason); returns its index.
    std::size_t add(Body body);
    std::vector<Body>& bodies() { return bodies_; }
    const std::vector<Body>& bodies() const { return bodies_; }
    /// The body with this name; throws std::out_of_range when there is none.
    Body& body(const std::string& name);
    const Body& body(const std::string& name) const;
    /// Removes the body at this index with the springs and constraints attached to it (throws
    /// std::out_of_range when there is none).
    void remove(std::size_t index);
    /// Removes every body, spring, constraint and rope, the container, the soft bodies and the
    /// fluid's particles, and resets time and the step counter.
    void clear();

    /// The whole dynamic state: bodies, time, step counter, position Verlet's previous positions,
    /// the soft bodies' particles: positions, velocities and inverse masses (a dragged particle is
    /// pinned while held), and the fluid's particles' positions and velocities (for history and
    /// replays).
    struct State {
        std::vector<Body> bodies;
        double time = 0.0;
        std::size_t steps = 0;
        std::vector<Vec3> previousPositions;
        std::vector<Vec3> particlePositions;   ///< SoftBodies::x (m)
        std::vector<Vec3> particleVelocities;  ///< SoftBodies::v (m/s)
        std::vector<double> particleInverseMasses;  ///< SoftBodies::w (1/kg)
        std::vector<Vec3> fluidPositions;      ///< Fluids::x (m)
        std::vector<Vec3> fluidVelocities;     ///< Fluids::v (m/s)
    };
    State state() const;
    /// Restores a state taken from this engine with the same bodies, springs, constraints and soft
    /// bodies.
    void restore(const State& s);

    // ---- Soft bodies (worksheet 8): cloth, ropes of particles, tetrahedral soft bodies ------------
    SoftBodies& softBodies() { return soft_; }
    const SoftBodies& softBodies() const { return soft_; }

    // ---- Fluids (worksheet 9): particles of one rest density, PBF or WCSPH ------------------------
    Fluids& fluids() { return fluids_; }
    const Fluids& fluids() const { return fluids_; }

    // ---- Springs and constraints (worksheet 2); bodies by name, checked, index returned -------------
    /// A Hooke spring between two bodies (one may be static: an anchor). restLength < 0 means the
    /// bodies' current distance. Throws std::invalid_argument on a bad body, a non-positive or
    /// non-finite stiffness, a negative damping or rest length, or two static ends.
    std::size_t addSpring(const std::string& a, const std::string& b, double stiffness, double damping = 0.0,
                          double restLength = -1.0);
    /// Holds two bodies at a fixed distance, their current one; same checks as addSpring().
    std::size_t addDistanceConstraint(const std::string& a, const std::string& b);
    /// Keeps every movable sphere inside a sphere of this centre and radius (m).
    void setContainer(const Vec3& centre, double radius);
    const std::vector<Spring>& springs() const { return springs_; }
    const std::vector<DistanceConstraint>& distanceConstraints() const { return distances_; }
    const std::optional<Container>& container() const { return container_; }

    // ---- Ropes and contacts (worksheets 3, 4) -----------------------------------------------------
    /// A rope between two bodies that keeps them at most `length` m apart (their current distance
    /// when omitted) and only pulls. Throws std::invalid_argument on a bad body, two static ends, or
    /// a length that is not a positive finite number or is shorter than the bodies' distance now.
    std::size_t addRope(const std::string& a, const std::string& b);
    std::size_t addRope(const std::string& a, const std::string& b, double length);
    const std::vector<Rope>& ropes() const { return ropes_; }
    /// The contacts of the last step: found by detectCollisions() and addRopeContacts(), and those
    /// that resolveInterpenetrations() created and resolved.
    const std::vector<Contact>& contacts() const { return contacts_; }
    /// Sweeps per step of each contact stage (>= 1; throws std::invalid_argument otherwise): the
    /// impulses' over contacts(), interpenetration's over the near pairs and ropes. A sweep that
    /// finds nothing to do ends the stage early.
    int contactIterations() const { return contactIterations_; }
    void setContactIterations(int iterations);
    /// Sweeps per step of interpenetration alone: as many as contactIterations() unless set (0, the
    /// default, restores that). A scene may want fewer, as a solver runs fewer position iterations
    /// than velocity iterations: the friction stage keeps the gaps the impulses have closed, so
    /// overlaps shrink over the steps instead of within one. Throws std::invalid_argument below 0.
    int interpenetrationIterations() const {
        return interpenetrationIterations_ > 0 ? interpenetrationIterations_ : contactIterations_;
    }
    void setInterpenetrationIterations(int iterations);
    /// Threads the broad phase, the friction stage, the soft bodies and the fluid may use: 1, or 2
    /// (the default on a machine with two cores or more), which they use only for scenes large
    /// enough to gain (the second thread is made then, and kept by the engine); the results are the
    /// same to the bit either way. Throws std::invalid_argument below 1.
    int threads() const;
    void setThreads(int threads);

    /// The friction stage's contact solver (friction.h); changing it forgets last step's impulses.
    ContactSolver contactSolver() const { return contactSolver_; }
    void setContactSolver(ContactSolver solver);

    // ---- Settings (per engine, never global) ------------------------------------------------------
    const Vec3& gravity() const { return gravity_; }
    void setGravity(const Vec3& g);  ///< throws std::invalid_argument when not finite
    double timeStep() const { return timeStep_; }
    void setTimeStep(double h);  ///< s; throws std::invalid_argument unless finite and > 0
    /// Stages the loaded scene requires; the step runs only stages that are required and enabled.
    const StageSet& requiredStages() const { return required_; }
    void setRequiredStages(const StageSet& stages) { required_ = stages; }
    void setStageEnabled(Stage stage, bool on);
    bool stageEnabled(Stage stage) const { return !disabled_.contains(stage); }
    /// True when the stage is required by the scene and not switched off by the user.
    bool stageActive(Stage stage) const { return required_.contains(stage) && stageEnabled(stage); }
    /// The integrator integrate() uses; changing it forgets position Verlet's previous positions.
    Integrator integratorKind() const { return integratorKind_; }
    void setIntegratorKind(Integrator kind);
    /// Gauss-Seidel sweeps of projectConstraints() per step (>= 1; throws std::invalid_argument otherwise).
    int constraintIterations() const { return constraintIterations_; }
    void setConstraintIterations(int iterations);

    // ---- Time stepping ------------------------------------------------------------------------
    /// One time step: empties the contacts (and the acceleration accumulators when the gravity
    /// stage, which sets them, is not active), runs simulationTimestep(), advances the clock and
    /// checks that every body and particle is still finite (throws SimulationError naming the body,
    /// or the particle's mesh and index, and the step otherwise).
    void step();
    double time() const { return time_; }  ///< simulated time (s)
    std::size_t stepCount() const { return steps_; }

    // ---- Hooks (worksheet 1) ------------------------------------------------------------------
    /// Student hook: one time step, one call per stage, each skipped unless stageActive().
    void simulationTimestep();
    /// Student hook: advances the velocity and the position of every movable body by timeStep().
    void integrator();
    /// Framework: sets the acceleration accumulator of every movable body to gravity(); static
    /// bodies keep a zero accumulator. Called once per step, it replaces (never adds to) the old value.
    void updateConstantAcceleration();

    // ---- Framework stages (worksheet 2) ----------------------------------------------------------
    /// Adds every spring's force divided by the mass to the two bodies' acceleration accumulators.
    void applySpringForces();
    /// Advances all bodies by timeStep() with integratorKind(): semi-implicit Euler is the
    /// worksheet-1 hook integrator(); the others are the kernels of gpl/integrators.h, started
    /// from the accumulators and evaluating accelerations() at intermediate states.
    void integrate();
    /// Moves positions, constraintIterations() times in turn: overlapping spheres apart (stage
    /// ParticleCollisions), then distance constraints and the container (stage Constraints). Each
    /// body's velocity gains its displacement divided by h, so the motion follows the correction.
    void projectConstraints();
    /// The engine's force model at any state of all bodies (index as bodies()): gravity and springs
    /// where their stages are active, divided by the mass; zero for static bodies (m/s^2).
    void accelerations(const std::vector<Vec3>& x, const std::vector<Vec3>& v, std::vector<Vec3>& a) const;

    // ---- Framework stages (worksheets 3, 4): one source file each --------------------------------
    /// Adds a contact for every pair of bodies that overlap: pairs from the broad phase, decided by
    /// the collision kernels of gpl/collision.h, in the order of the pairs (collision.cpp).
    void detectCollisions();
    /// Adds a contact for every taut rope, from ropeContact() (collision.cpp).
    void addRopeContacts();
    /// Sweeps the impulse kernel over contacts() until none approaches (impulses.cpp): in scenes that
    /// require the rotation stage applyContactImpulse() at the contact points (worksheet 6), in the
    /// others applyCollisionImpulse() at the centres (worksheet 4).
    void applyCollisionImpulses();
    /// Sweeps over the near pairs of detectCollisions() and the taut ropes, moving every overlap it
    /// finds apart with resolveInterpenetration(), until none overlaps; overlaps its moves create
    /// join contacts(). Without the impulse stage the velocities follow the displacements, as in
    /// projectConstraints() (interpenetration.cpp).
    void resolveInterpenetrations();

    // ---- Framework stage (worksheet 6) -------------------------------------------------------------
    /// Advances the orientation and angular velocity of every movable body by timeStep() with
    /// integrateRotation(); throws SimulationError naming the body when either is no longer finite
    /// (rotation.cpp).
    void rotate();

    // ---- Framework stage (worksheet 7) -------------------------------------------------------------
    /// Friction and resting contact (friction.cpp): measures every contact point's approach and
    /// prepares the point once with prepareContactPoint(), warm starts it with applyWarmStart() from
    /// last step's sums (same pair of bodies in either order, each point paired one to one with the
    /// nearest of last step's points where the bodies carry them now, within kWarmStartDistance), then sweeps
    /// contactIterations() times over contacts() with applyNormalImpulse() and
    /// applyFrictionImpulse() at every prepared point; then every body ends the step
    /// where its new velocity takes it (moved by h times the change of its velocity, turned by h times
    /// the change of its angular velocity), and overlap deeper than kContactSlop is reduced by split
    /// impulses, in positions only (split_impulses.h). It keeps the sums for the next step. That
    /// is sequential impulses, the default of contactSolver(); the baseline (baumgarte.h) and the
    /// soft step (soft_step.h) answer the same contacts their own ways. In a scene that requires
    /// it, applyCollisionImpulses() and resolveInterpenetrations() leave the contacts to it.
    void solveContacts();

    // ---- Framework stages (worksheet 8): the soft bodies' step (soft_bodies.h) -----------------------
    /// Stage SoftPredict: softBodies().predict() with timeStep(), gravity() and time().
    void predictParticles();
    /// Stage SoftContacts: softBodies().findContacts() against bodies(), once per step.
    void findParticleContacts();
    /// Stage SoftProject: softBodies().project() with constraintIterations() sweeps against bodies().
    void projectParticles();
    /// Stage SoftVelocities: softBodies().updateVelocities() with timeStep().
    void updateParticleVelocities();

    // ---- Framework stages (worksheet 9): the fluids' step (fluids.h) ---------------------------------
    /// Stage FluidPredict: fluids().predict() with timeStep() and gravity().
    void predictFluid();
    /// Stage FluidNeighbours: fluids().findNeighbours(), once per step.
    void findFluidNeighbours();
    /// Stage FluidProject: fluids().project() against bodies().
    void projectFluid();
    /// Stage FluidVelocities: fluids().updateVelocities() with timeStep().
    void updateFluidVelocities();
    /// Stage FluidSph: fluids().stepSph() with timeStep() and gravity() against bodies().
    void stepSph();

    // ---- Hooks not implemented yet ------------------------------------------------------------
    /// Called by a stub: records the hook and prints "not implemented: <hook>" once per process.
    void notImplemented(const std::string& hook);
    /// Hooks whose stubs have run in this engine (empty once the student has filled them in).
    const std::set<std::string>& missingHooks() const { return missing_; }

    // ---- Diagnostics (world) --------------------------------------------------------------------
    double kineticEnergy() const;    ///< J, the bodies' and the particles'
    /// J: the springs' plus, while the gravity stage is active, the gravitational (zero at the origin);
    /// plus the particles' gravitational and their XPBD constraints' elastic energy.
    double potentialEnergy() const;
    double totalEnergy() const;      ///< J
    Vec3 linearMomentum() const;     ///< kg m/s
    /// kg m^2/s, about the origin: the sum of every body's x × m v + R I R^T omega (rotation.cpp).
    Vec3 angularMomentum() const;
    /// True when every body's and particle's position and velocity are finite.
    bool allFinite() const;

private:
    /// The grader's copy of an engine in another process (tests/grading/engine_access.h).
    friend struct EngineAccess;

    std::vector<Body> bodies_;
    Vec3 gravity_ = standardGravity();
    double timeStep_ = kDefaultTimeStep;
    StageSet required_{Stage::ConstantAcceleration, Stage::Integration};
    StageSet disabled_;
    double time_ = 0.0;
    std::size_t steps_ = 0;
    std::set<std::string> missing_;
    std::vector<Spring> springs_;
    std::vector<DistanceConstraint> distances_;
    std::optional<Container> container_;
    Integrator integratorKind_ = Integrator::SemiImplicitEuler;
    int constraintIterations_ = 4;
    std::vector<Vec3> previousPositions_;  ///< position Verlet's x_{n-1} per body (m); empty: not started
    std::vector<Rope> ropes_;
    std::vector<Contact> contacts_;     ///< this step's, emptied when a step begins
    std::vector<BodyPair> nearPairs_;  ///< this step's broad-phase pairs with kContactMargin, likewise
    std::vector<char> pairInContacts_;  ///< per near pair: its contact is in contacts_ (0 or 1)
    std::vector<char> ropeInContacts_;  ///< per rope: its contact is in contacts_ (0 or 1)
    std::vector<std::size_t> movedAt_;  ///< interpenetration's, per body: moves counted when it last moved
    std::vector<std::size_t> apartAt_;  ///< interpenetration's, per near pair: moves counted when last found apart
    int contactIterations_ = 10;
    int interpenetrationIterations_ = 0;  ///< 0: as many as contactIterations_
    Owned<BroadPhase> broadPhase_;  ///< the contact stages' broad phase (broadphase.h)
    std::vector<Vec3> start_;  ///< positions when a position stage began (m); kept to reuse its memory
    SecondThread second_;  ///< the second thread of the broad phase, collision detection and the friction stage
    Owned<FrictionStage> friction_;  ///< the friction stage's memory and buffers (friction_stage.h)
    ContactSolver contactSolver_ = ContactSolver::SequentialImpulses;
    SoftBodies soft_;                      ///< worksheet 8's particles, meshes and constraints
    Fluids fluids_;                        ///< worksheet 9's fluid particles

    std::size_t bodyIndex(const std::string& name) const;
    /// Copies the kernel hooks whose stubs ran into missingHooks().
    void recordOpenKernels();
    /// The rope's contact from ropeContact(), with the framework's fields set; none while slack.
    std::optional<Contact> ropeContactOf(const Rope& rope) const;
    /// step() before simulationTimestep(): empties the contacts (and the accumulators when gravity is off).
    void beginStep();
    /// step() after simulationTimestep(): advances the clock and checks that every body and particle is finite.
    void endStep();
    /// e plus the energy of every spring, added one by one (J).
    double plusSpringEnergies(double e) const;
    /// e plus the soft bodies' particles' gravitational and elastic energy and the fluid's gravitational
    /// energy (J); e itself without either.
    double plusSoftEnergies(double e) const;
};

}  // namespace gpl
