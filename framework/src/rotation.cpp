// Rotation in the engine (worksheet 6): the stage that turns every movable body with
// integrateRotation(), and angular momentum as a diagnostic.
#include "gpl/rotation.h"

#include "gpl/engine.h"

namespace gpl {

Vec3 angularMomentum(const Body& b) {
    if (b.isStatic()) return Vec3::Zero();
    const Quat& q = b.orientation;
    // R I R^T omega: into the body frame, I, back into the world frame.
    const Vec3 spin = q * (b.inertia * (q.conjugate() * b.angularVelocity));
    return b.position.cross(b.mass * b.velocity) + spin;
}

void PhysicsEngine::rotate() {
    const double h = timeStep();
    for (Body& b : bodies_) {
        if (b.isStatic()) continue;
        integrateRotation(b, h);
        if (!b.orientation.coeffs().allFinite() || !isFinite(b.angularVelocity)) {
            throw SimulationError("body '" + b.name +
                                  "': orientation or angular velocity is no longer finite in step " +
                                  std::to_string(steps_ + 1) + ": check integrateRotation()");
        }
    }
    recordOpenKernels();
}

Vec3 PhysicsEngine::angularMomentum() const {
    Vec3 sum = Vec3::Zero();
    for (const Body& b : bodies_) sum += gpl::angularMomentum(b);
    return sum;
}

}  // namespace gpl
