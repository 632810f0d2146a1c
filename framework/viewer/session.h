// What the viewer shows and changes, without any GL: the engine on a scene, time control
// (pause, step, step back, speed, substeps), interaction (select, drag, shoot, add, remove,
// gravity; bodies, the particles of cloth, ropes and soft bodies, and a fluid's particles), energy
// plots and the reference ghost. Keys and mouse map onto these calls.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "camera.h"
#include "clock.h"
#include "fluid_shapes.h"
#include "gpl/scenes.h"
#include "history.h"
#include "picking.h"
#include "reference.h"
#include "scene_shapes.h"
#include "soft_shapes.h"

namespace gpl::viewer {

/// Energies over the last samples, one per viewer tick (J).
struct EnergySeries {
    static constexpr std::size_t kCapacity = 600;
    std::deque<float> kinetic, potential, total;
    double initialTotal = 0.0;  ///< J, at the last reset
    void clear() { kinetic.clear(), potential.clear(), total.clear(); }
    void push(double k, double p);
};

class Session {
public:
    static constexpr std::size_t kHistoryBytes = 256u << 20;  ///< memory for the step-back history
    static constexpr int kMaxStepsPerFrame = 64;              ///< beyond this, time is dropped
    static constexpr double kMinSpeed = 1.0 / 64.0;           ///< simulated seconds per real second
    static constexpr double kMaxSpeed = 8.0;

    explicit Session(const Scene& scene);

    // ---- Scene ---------------------------------------------------------------------------------
    /// Loads the scene afresh with its own time step and gravity (keeps speed, substeps, pause).
    void load(const Scene& scene);
    void reset() { load(*scene_); }
    const Scene& scene() const { return *scene_; }
    /// The space the scene fills when it starts (sceneBounds()): walls are drawn within it, so
    /// they stay put while bodies move, are shot or are added.
    const Bounds& bounds() const { return bounds_; }
    PhysicsEngine& engine() { return engine_; }
    const PhysicsEngine& engine() const { return engine_; }

    // ---- Time ----------------------------------------------------------------------------------
    /// Advances by one frame of realSeconds (times the speed) in whole ticks unless paused.
    void frame(double realSeconds);
    void togglePause() { paused_ = !paused_; }
    void setPaused(bool p) { paused_ = p; }
    bool paused() const { return paused_; }
    void stepOnce();  ///< one tick, also while paused
    bool stepBack();  ///< restores the state before the last tick; false when the history is empty
    void faster() { setSpeed(speed_ * 2.0); }
    void slower() { setSpeed(speed_ / 2.0); }
    void setSpeed(double s);  ///< clamped to kMinSpeed .. kMaxSpeed
    double speed() const { return speed_; }
    /// One tick is `tick` seconds, split into `substeps` engine steps.
    void setTick(double tick);
    double tick() const { return tick_; }
    void setSubsteps(int n);
    int substeps() const { return substeps_; }
    const History& history() const { return history_; }
    const FixedStepClock& clock() const { return clock_; }

    // ---- Interaction ---------------------------------------------------------------------------
    void setIntegrator(Integrator kind);
    /// The friction stage's contact solver (friction.h); it forgets last step's impulses.
    void setContactSolver(ContactSolver solver);
    /// Switches a stage the scene requires on or off (the panel's stage list).
    void setStageEnabled(Stage stage, bool on);
    /// Sweeps over the contacts per step, clamped to 1 .. kMaxContactIterations.
    void setContactIterations(int n);
    static constexpr int kMaxContactIterations = 100;
    /// Projection sweeps per step of the soft bodies' constraints (and of rods), the engine's
    /// constraintIterations(), clamped to 1 .. kMaxConstraintIterations.
    void setConstraintIterations(int n);
    static constexpr int kMaxConstraintIterations = 200;
    /// The fluid's density-constraint sweeps per PBF step (FluidParameters::iterations), clamped
    /// to 1 .. kMaxFluidIterations.
    void setFluidIterations(int n);
    static constexpr int kMaxFluidIterations = 100;
    /// Sets a body's coefficient of restitution, clamped to 0 .. 1; it acts from the next step on.
    /// Like every edit, a step back to a state before it undoes it.
    void setRestitution(std::size_t index, double e);
    void toggleGravity();
    void setGravity(const Vec3& g);  ///< m/s^2; throws std::invalid_argument when not finite
    bool gravityOn() const { return engine_.gravity() != Vec3::Zero(); }
    /// Selects a body (and no particle).
    void select(std::optional<std::size_t> index) { selected_ = index, selectedParticle_.reset(), selectedFluid_.reset(); }
    std::optional<std::size_t> selected() const { return selected_; }
    const Body* selectedBody() const { return selected_ ? &engine_.bodies()[*selected_] : nullptr; }
    /// Selects a particle of the soft bodies (and no body).
    void selectParticle(std::optional<std::uint32_t> particle) {
        selectedParticle_ = particle, selected_.reset(), selectedFluid_.reset();
    }
    std::optional<std::uint32_t> selectedParticle() const { return selectedParticle_; }
    /// Selects a particle of the fluid (and no body or soft particle).
    void selectFluidParticle(std::optional<std::uint32_t> particle) {
        selectedFluid_ = particle, selected_.reset(), selectedParticle_.reset();
    }
    std::optional<std::uint32_t> selectedFluidParticle() const { return selectedFluid_; }
    /// What a ray from the camera hits first: a body, a particle of the soft bodies or of the fluid
    /// (a fluid's tank walls are not drawn and not picked).
    struct Picked {
        std::optional<std::size_t> body;
        std::optional<std::uint32_t> particle;
        std::optional<std::uint32_t> fluidParticle;
    };
    Picked pickAt(const Ray& ray) const;
    /// Picks the body or particle under the ray and selects it (or clears the selection when
    /// none); returns the body picked.
    std::optional<std::size_t> pickAndSelect(const Ray& ray);
    /// Starts dragging what is under the ray, and selects it. A body: a spring pulls it toward the
    /// cursor, which moves on the plane through the grab point facing the camera. A particle: it is
    /// held (pinned) while dragged, each step moving it and its predicted position a share of the
    /// way to the cursor (on the plane through it facing the camera), so its neighbours follow; let
    /// go, it keeps the velocity of its last step (a particle pinned by the scene stays pinned
    /// where it is left). A fluid's particle: each step it moves the same share of the way (kept
    /// inside the fluid's container) and its neighbours make way; let go, it keeps the velocity of its
    /// last step. Static bodies cannot be dragged.
    bool beginDrag(const Ray& ray, const Vec3& viewDirection);
    void dragTo(const Ray& ray);
    void endDrag() { drag_.reset(); }
    bool dragging() const { return drag_.has_value(); }
    std::optional<Vec3> dragTarget() const { return drag_ ? std::optional<Vec3>(drag_->target) : std::nullopt; }
    /// Per second, the share of the way to the cursor a dragged particle moves: 1 - exp(-rate h) per step.
    static constexpr double kParticleDragRate = 20.0;
    void shoot(const Ray& from, double speed);  ///< a 1 kg sphere from the camera (m/s)
    void addBox(const Vec3& at);                ///< a 1 m box dropped at a point
    bool removeSelected();
    /// Edits (add, remove, drag, step back, settings or restitution changed after the start) stop
    /// the reference ghost; a reset starts it again. Before the first step the ghost starts over
    /// with the changed settings instead.
    bool edited() const { return edited_; }

    // ---- Diagnostics ---------------------------------------------------------------------------
    const EnergySeries& energies() const { return energies_; }
    /// The last error (a non-finite state, an exception from a hook); the session pauses on one.
    const std::string& error() const { return error_; }

    // ---- Reference ghost -----------------------------------------------------------------------
    bool ghostAvailable() const { return reference_ != nullptr; }
    void setGhost(bool on);
    bool ghostWanted() const { return ghostOn_ && reference_; }
    /// Shown: wanted, and the scene not edited since the last reset.
    bool ghostOn() const { return ghostWanted() && !edited_; }
    /// Ghost poses: position (m) and orientation (w, x, y, z) per body, in the scene's order.
    const std::vector<std::array<double, 7>>& ghostPoses() const { return ghostPoses_; }
    /// The ghost's particles (m), in the scene's order.
    const std::vector<Vec3>& ghostParticles() const { return ghostParticles_; }
    /// Largest distance between a body or particle and its ghost (m), and the body's or the
    /// particle's name ("flag#12").
    double ghostDifference(std::string* name = nullptr) const;

private:
    void tickOnce();
    /// One engine step; a dragged particle moved toward the cursor and held through it.
    void stepEngine();
    void takeGhostState();
    void restartGhost();
    void settingsChanged();
    std::string uniqueName(const std::string& stem) const;

    struct Drag {
        std::size_t index;                      ///< the body's, or the particle's when `particle`
        Vec3 target;                            ///< m, where the cursor is in the world
        Vec3 planePoint;                        ///< m
        Vec3 planeNormal;                       ///< unit
        bool particle = false;                  ///< a soft particle
        bool fluid = false;                     ///< a fluid particle
        Vec3 particleVelocity = Vec3::Zero();  ///< m/s, of its last step
    };

    const Scene* scene_;
    PhysicsEngine engine_;
    Bounds bounds_;
    History history_{kHistoryBytes};
    FixedStepClock clock_;
    EnergySeries energies_;
    std::optional<std::size_t> selected_;
    std::optional<std::uint32_t> selectedParticle_;
    std::optional<std::uint32_t> selectedFluid_;
    std::optional<Drag> drag_;
    std::unique_ptr<gplref::ReferenceWorld> reference_;
    std::vector<std::array<double, 7>> ghostPoses_;
    std::vector<Vec3> ghostParticles_;
    std::string error_;
    double tick_ = kDefaultTimeStep;  ///< s
    double speed_ = 1.0;
    int substeps_ = 1;
    int shots_ = 0;
    bool paused_ = false;
    bool edited_ = false;
    bool ghostOn_ = false;
};

}  // namespace gpl::viewer
