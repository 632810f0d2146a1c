// Interpenetration in the engine: Gauss-Seidel sweeps that find the overlaps among the step's
// near pairs and taut ropes and move each apart with resolveInterpenetration(), until nothing
// overlaps or the sweeps run out. Moving one pair apart can push a body into a third, so every
// sweep looks again (as projectConstraints() does for worksheet 2), and an overlap found that way
// joins contacts(): the impulses that follow answer every contact of the step, the ones the
// sweeps found included (in a resting stack, all of them).
//
// Looking again costs only where something moved: the collision kernels are pure, so a near pair
// found apart stays apart until one of its bodies moves, and is not tested again before that. The
// results are those of testing every pair in every sweep. A large stage moves two halves of its
// pairs at once (OverlapSweeps, overlap_sweeps.cpp), the same to the bit on one thread.
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
    // The near pairs: a large stage without ropes in two halves, at once on the second thread.
    SecondThread* second = threads() > 1 && nearPairs_.size() >= OverlapSweeps::kSplitFrom ? &second_ : nullptr;
    overlapSweeps_.begin(nearPairs_, pairInContacts_, bodies_, !ropes);
    for (int sweep = 0; sweep < contactIterations_; ++sweep) {
        bool overlapping = overlapSweeps_.sweep(bodies_, contacts_, second);
        for (std::size_t k = 0; ropes && k < ropes_.size(); ++k) {
            const std::optional<Contact> c = ropeContactOf(ropes_[k]);
            if (!c) continue;
            overlapping = true;
            Body& a = bodies_[c->a];
            Body& b = bodies_[c->b];
            const Vec3 wasA = a.position, wasB = b.position;
            resolveInterpenetration(*c, a, b);
            if (a.position != wasA) overlapSweeps_.moved(c->a);  // its near pairs are tested again
            if (b.position != wasB) overlapSweeps_.moved(c->b);
            if (!ropeInContacts_[k]) contacts_.push_back(*c);
            ropeInContacts_[k] = 1;
        }
        if (!overlapping) break;
    }
    overlapSweeps_.end(pairInContacts_);
    recordOpenKernels();
    // Without impulses, contacts are position-based (as in worksheet 2): the velocity follows the
    // correction, so a ball that lands stops instead of pressing on ever faster. With impulses,
    // they own the velocities.
    if (stageActive(Stage::CollisionImpulses)) return;
    for (std::size_t i = 0; i < bodies_.size(); ++i) bodies_[i].velocity += (bodies_[i].position - start_[i]) / timeStep_;
}

}  // namespace gpl
