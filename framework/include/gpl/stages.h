// The stages of a time step, named once, as data. A scene declares the stages it requires; the
// time step runs only those (a falling-sphere scene pays nothing for collisions).
#pragma once

#include <array>
#include <bitset>
#include <initializer_list>
#include <string>

namespace gpl {

enum class Stage {
    ConstantAcceleration,  ///< forces: gravity into every movable body's accumulator (worksheet 1)
    Springs,               ///< forces: Hooke springs (optionally damped) add theirs (worksheet 2)
    Integration,           ///< advance velocities and positions by one time step (worksheets 1, 2)
    Rotation,              ///< advance orientations and angular velocities, integrateRotation() (worksheet 6)
    CollisionDetection,    ///< find the contacts: broad phase, then the kernels of gpl/collision.h (worksheets 3, 5)
    Ropes,                 ///< taut ropes become contacts that pull, ropeContact() (worksheet 4)
    Interpenetration,      ///< move overlapping bodies apart, resolveInterpenetration() (worksheet 3)
    CollisionImpulses,     ///< change velocities at the contacts, applyCollisionImpulse() (worksheet 4)
    Friction,              ///< friction and resting contact: summed, warm-started impulses per contact point (worksheet 7)
    Constraints,           ///< move positions to satisfy rods, chains and the container (worksheet 2)
    ParticleCollisions,    ///< push overlapping spheres apart by moving positions (worksheet 2)
    SoftPredict,           ///< soft bodies: velocities by gravity and wind, predicted positions (worksheet 8)
    SoftContacts,          ///< soft bodies: particles near rigid bodies and near each other, once per step (worksheet 8)
    SoftProject,           ///< soft bodies: sweeps of the constraint and contact kernels over the predictions (worksheet 8)
    SoftVelocities,        ///< soft bodies: velocities from the corrected predictions, which become the positions (worksheet 8)
    FluidPredict,          ///< fluids: velocities by gravity, predicted positions (worksheet 9)
    FluidNeighbours,       ///< fluids: every particle's neighbours, once per step (worksheet 9)
    FluidProject,          ///< fluids: sweeps of the density constraints and the rigid bodies' push (worksheet 9)
    FluidVelocities,       ///< fluids: velocities from the corrected predictions, XSPH, new positions (worksheet 9)
    FluidSph,              ///< fluids: weakly compressible SPH's step in substeps, the comparison (worksheet 9)
    Count
};

constexpr std::size_t kStageCount = static_cast<std::size_t>(Stage::Count);

/// Short name of a stage as shown by the runner and the viewer ("gravity", "integrate").
const char* stageName(Stage stage);

/// A set of stages.
class StageSet {
public:
    StageSet() = default;
    StageSet(std::initializer_list<Stage> stages) {
        for (Stage s : stages) insert(s);
    }
    void insert(Stage s) { bits_.set(index(s)); }
    void erase(Stage s) { bits_.reset(index(s)); }
    bool contains(Stage s) const { return bits_.test(index(s)); }
    /// Names of the stages in the set, comma separated, in stage order.
    std::string names() const;

private:
    static std::size_t index(Stage s) { return static_cast<std::size_t>(s); }
    std::bitset<kStageCount> bits_;
};

}  // namespace gpl
