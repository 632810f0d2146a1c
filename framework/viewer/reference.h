// The reference ghost: the same scene stepped by the reference solution. The reference engine is
// the framework and solutions/ compiled once more in a namespace of their own (gpl_reference), so
// it can live in one program beside the student's engine. This header uses standard types only:
// it is the one thing both sides share.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace gplref {

class ReferenceWorld {
public:
    virtual ~ReferenceWorld() = default;
    /// What the viewer may have changed before the first step; the reference takes the same.
    struct Settings {
        double timeStep = 0.01;           ///< s, of one engine step
        std::array<double, 3> gravity{};  ///< m/s^2
        std::string integrator;           ///< its id, as gpl::integratorId() spells it
        int contactIterations = 10;       ///< sweeps over the contacts per step
        int constraintIterations = 4;     ///< projection sweeps per step (rods, soft bodies)
        std::vector<int> disabledStages;  ///< gpl::Stage values switched off
        std::vector<double> restitution;  ///< per body, in the scene's order (0..1)
    };
    /// Loads the scene by name, then applies the settings.
    virtual void load(const std::string& scene, const Settings& settings) = 0;
    virtual void step() = 0;
    /// Position (m) and orientation (w, x, y, z) of every body, in the scene's order.
    virtual std::vector<std::array<double, 7>> poses() const = 0;
    /// Position (m) of every particle of the cloth, ropes and soft bodies, in the scene's order.
    virtual std::vector<std::array<double, 3>> particles() const = 0;
};

/// The reference world, or nullptr when this build has no solutions (a student release).
std::unique_ptr<ReferenceWorld> makeReferenceWorld();

}  // namespace gplref
