// Collision impulses in the engine: sequential sweeps of the impulse kernel over the step's contacts
// until no contact approaches or the sweeps run out. Detected contacts come in the order of their
// bodies and the ones interpenetration found after them in the order it found them, so the ball
// that swings into a row of touching balls (Newton's cradle) comes first and its impulse passes
// down the row in one sweep.
//
// The kernel is applyCollisionImpulse() at the centres (worksheet 4), or, in a scene that requires
// the rotation stage, applyContactImpulse() at the contact points (worksheet 6): a scene of
// particles or spheres pays nothing for rotation.
//
// In a scene with friction (worksheet 7) the friction stage answers the contacts instead, with
// summed normal and friction impulses per contact point (friction.cpp); this stage then does nothing.
#include "gpl/collision.h"
#include "gpl/engine.h"
#include "gpl/response.h"
#include "gpl/rotation.h"

namespace gpl {
namespace {

// True when the material points of a and b approach each other at some point of the contact.
bool approachesAtAPoint(const Contact& c, const Body& a, const Body& b) {
    for (int k = 0; k < c.pointCount; ++k) {
        if (normalVelocityAt(c, a, b, c.points[k]) < 0.0) return true;
    }
    return false;
}

}  // namespace

void PhysicsEngine::applyCollisionImpulses() {
    if (stageActive(Stage::Friction)) return;
    const bool turning = stageActive(Stage::Rotation);
    for (int sweep = 0; sweep < contactIterations_; ++sweep) {
        bool approaching = false;
        for (const Contact& c : contacts_) {
            Body& a = bodies_[c.a];
            Body& b = bodies_[c.b];
            if (turning) {
                if (approachesAtAPoint(c, a, b)) approaching = true;
                applyContactImpulse(c, a, b);
            } else {
                if (normalVelocity(c, a, b) < 0.0) approaching = true;
                applyCollisionImpulse(c, a, b);
            }
        }
        if (!approaching) break;
    }
    recordOpenKernels();
}

}  // namespace gpl
