// Interpenetration in the engine: Gauss-Seidel sweeps that find the overlaps among the step's
// near pairs and taut ropes and move each apart with resolveInterpenetration(), until nothing
// overlaps or the sweeps run out. Moving one pair apart can push a body into a third, so every
// sweep looks again (as projectConstraints() does for worksheet 2), and an overlap found that way
// joins contacts(): the impulses that follow answer every contact of the step, the ones the
// sweeps found included (in a resting stack, all of them).
//
// Looking again costs only where something moved: the collision kernels are pure, so a near pair
// found apart stays apart until one of its bodies moves, and is not tested again before that. The
// results are those of testing every pair in every sweep.
#include "gpl/broadphase.h"
#include "gpl/collision.h"
#include "gpl/engine.h"
#include "gpl/response.h"

namespace gpl {

void PhysicsEngine::resolveInterpenetrations() {
    // In a scene with friction, the friction stage corrects positions after its impulses.
    if (stageActive(Stage::Friction)) return;
    start_.clear();
    for (const Body& b : bodies_) start_.push_back(b.position);
    const bool ropes = stageActive(Stage::Ropes);
    pairInContacts_.resize(nearPairs_.size(), 0);
    ropeInContacts_.resize(ropes_.size(), 0);
    // Moves counted so far; per body, the count when it last moved; per near pair, the count when
    // it was last found apart (kOverlapped until then, and again once it overlaps).
    constexpr std::size_t kOverlapped = SIZE_MAX;
    std::size_t moves = 0;
    movedAt_.assign(bodies_.size(), 0);
    apartAt_.assign(nearPairs_.size(), kOverlapped);
    // Detection has just tested every near pair and nothing has moved since: the pairs it found
    // apart stay apart until one of their bodies moves.
    if (stageActive(Stage::CollisionDetection)) {
        for (std::size_t k = 0; k < nearPairs_.size(); ++k) {
            if (!pairInContacts_[k]) apartAt_[k] = 0;
        }
    }
    // Moves the bodies of an overlap apart; a contact not among contacts() yet joins them.
    const auto separate = [this, &moves](const Contact& c, char& inContacts) {
        Body& a = bodies_[c.a];
        Body& b = bodies_[c.b];
        const Vec3 wasA = a.position, wasB = b.position;
        resolveInterpenetration(c, a, b);
        ++moves;
        if (a.position != wasA) movedAt_[c.a] = moves;
        if (b.position != wasB) movedAt_[c.b] = moves;  // a static body never moves
        if (!inContacts) contacts_.push_back(c);
        inContacts = 1;
    };
    for (int sweep = 0; sweep < interpenetrationIterations(); ++sweep) {
        bool overlapping = false;
        for (std::size_t k = 0; k < nearPairs_.size(); ++k) {
            const BodyPair& pair = nearPairs_[k];
            if (apartAt_[k] != kOverlapped && movedAt_[pair.a] <= apartAt_[k] && movedAt_[pair.b] <= apartAt_[k]) {
                continue;  // apart, and neither body has moved since
            }
            const std::optional<Contact> c = collide(bodies_, pair.a, pair.b);
            apartAt_[k] = c ? kOverlapped : moves;
            if (c) separate(*c, pairInContacts_[k]);
            overlapping |= c.has_value();
        }
        for (std::size_t k = 0; ropes && k < ropes_.size(); ++k) {
            const std::optional<Contact> c = ropeContactOf(ropes_[k]);
            if (c) separate(*c, ropeInContacts_[k]);
            overlapping |= c.has_value();
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
