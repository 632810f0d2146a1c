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
    /// Loads the scene by name with the given time step (s), gravity (m/s^2) and integrator (its
    /// id, as gpl::integratorId() spells it).
    virtual void load(const std::string& scene, double timeStep, const std::array<double, 3>& gravity,
                      const std::string& integrator) = 0;
    virtual void step() = 0;
    /// Position (m) and orientation (w, x, y, z) of every body, in the scene's order.
    virtual std::vector<std::array<double, 7>> poses() const = 0;
};

/// The reference world, or nullptr when this build has no solutions (a student release).
std::unique_ptr<ReferenceWorld> makeReferenceWorld();

}  // namespace gplref
