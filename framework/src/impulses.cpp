// Collision impulses in the engine: sequential sweeps of applyCollisionImpulse() over the step's
// contacts until no contact approaches or the sweeps run out. Detected contacts come in the order
// of their bodies and the ones interpenetration found after them in the order it found them, so
// the ball that swings into a row of touching balls (Newton's cradle) comes first and its
// impulse passes down the row in one sweep.
#include "gpl/collision.h"
#include "gpl/engine.h"
#include "gpl/response.h"

namespace gpl {

void PhysicsEngine::applyCollisionImpulses() {
    for (int sweep = 0; sweep < contactIterations_; ++sweep) {
        bool approaching = false;
        for (const Contact& c : contacts_) {
            Body& a = bodies_[c.a];
            Body& b = bodies_[c.b];
            if (normalVelocity(c, a, b) < 0.0) approaching = true;
            applyCollisionImpulse(c, a, b);
        }
        if (!approaching) break;
    }
    recordOpenKernels();
}

}  // namespace gpl
