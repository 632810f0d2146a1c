// Interpenetration in the engine: Gauss-Seidel sweeps that find the overlaps among the step's
// near pairs and taut ropes and move each apart with resolveInterpenetration(), until nothing
// overlaps or the sweeps run out. Moving one pair apart can push a body into a third, so every
// sweep looks again (as projectConstraints() does for worksheet 2), and an overlap found that way
// joins contacts(): the impulses that follow answer every contact of the step, the ones the
// sweeps found included (in a resting stack, all of them).
#include "gpl/collision.h"
#include "gpl/engine.h"
#include "gpl/response.h"

namespace gpl {

void PhysicsEngine::resolveInterpenetrations() {
    start_.clear();
    for (const Body& b : bodies_) start_.push_back(b.position);
    const bool ropes = stageActive(Stage::Ropes);
    pairInContacts_.resize(nearPairs_.size(), 0);
    ropeInContacts_.resize(ropes_.size(), 0);
    // Moves the bodies of an overlap apart; a contact not among contacts() yet joins them.
    const auto separate = [this](const std::optional<Contact>& c, char& inContacts) {
        if (!c) return false;
        resolveInterpenetration(*c, bodies_[c->a], bodies_[c->b]);
        if (!inContacts) contacts_.push_back(*c);
        inContacts = 1;
        return true;
    };
    for (int sweep = 0; sweep < contactIterations_; ++sweep) {
        bool overlapping = false;
        for (std::size_t k = 0; k < nearPairs_.size(); ++k) {
            overlapping |= separate(collide(bodies_, nearPairs_[k].a, nearPairs_[k].b), pairInContacts_[k]);
        }
        for (std::size_t k = 0; ropes && k < ropes_.size(); ++k) {
            overlapping |= separate(ropeContactOf(ropes_[k]), ropeInContacts_[k]);
        }
        if (!overlapping) break;
    }
    recordOpenKernels();
    // Without impulses, contacts are position-based (as in worksheet 2): the velocity follows the
    // correction, so a ball that lands stops instead of pressing on ever faster. With impulses,
    // they own the velocities.
    if (stageActive(Stage::CollisionImpulses)) return;
    for (std::size_t i = 0; i < bodies_.size(); ++i) bodies_[i].velocity += (bodies_[i].position - start_[i]) / timeStep_;
}

}  // namespace gpl
