// The physics engine: bodies, settings, the time step and its hooks, and diagnostics.
//
// Student hooks (bodies in assignments/, reference bodies in solutions/):
//   simulationTimestep()  worksheet 1: one time step, stage by stage
//   integrator()          worksheet 1: advance velocities and positions of all bodies
// Framework-provided stages the hooks call:
//   updateConstantAcceleration()  sets every movable body's acceleration accumulator to gravity
#pragma once

#include <cstddef>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "gpl/body.h"
#include "gpl/stages.h"

namespace gpl {

/// Default time step of the engine (s): 100 steps per simulated second. A scene may override it.
constexpr double kDefaultTimeStep = 0.01;
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

    // ---- Bodies -------------------------------------------------------------------------------
    /// Adds a body after validating it (throws std::invalid_argument with the reason); returns its index.
    std::size_t add(Body body);
    std::vector<Body>& bodies() { return bodies_; }
    const std::vector<Body>& bodies() const { return bodies_; }
    /// The body with this name; throws std::out_of_range when there is none.
    Body& body(const std::string& name);
    const Body& body(const std::string& name) const;
    /// Removes the body at this index (throws std::out_of_range when there is none).
    void remove(std::size_t index);
    /// Removes every body and resets time and the step counter.
    void clear();

    /// The whole dynamic state: bodies, time and step counter (for history and replays).
    struct State {
        std::vector<Body> bodies;
        double time = 0.0;
        std::size_t steps = 0;
    };
    State state() const { return {bodies_, time_, steps_}; }
    void restore(const State& s);

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

    // ---- Time stepping ------------------------------------------------------------------------
    /// One time step: runs simulationTimestep(), advances the clock and checks that every body is
    /// still finite (throws SimulationError naming the body and the step otherwise).
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

    // ---- Hooks not implemented yet ------------------------------------------------------------
    /// Called by a stub: records the hook and prints "not implemented: <hook>" once per process.
    void notImplemented(const std::string& hook);
    /// Hooks whose stubs have run in this engine (empty once the student has filled them in).
    const std::set<std::string>& missingHooks() const { return missing_; }

    // ---- Diagnostics (world) --------------------------------------------------------------------
    double kineticEnergy() const;    ///< J
    double potentialEnergy() const;  ///< J, gravitational, zero at the origin
    double totalEnergy() const;      ///< J
    Vec3 linearMomentum() const;     ///< kg m/s
    /// True when every body's position and velocity are finite.
    bool allFinite() const;

private:
    std::vector<Body> bodies_;
    Vec3 gravity_ = standardGravity();
    double timeStep_ = kDefaultTimeStep;
    StageSet required_{Stage::ConstantAcceleration, Stage::Integration};
    StageSet disabled_;
    double time_ = 0.0;
    std::size_t steps_ = 0;
    std::set<std::string> missing_;
};

}  // namespace gpl
