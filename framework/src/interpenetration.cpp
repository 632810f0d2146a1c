// Interpenetration in the engine: Gauss-Seidel sweeps of resolveInterpenetration() over the
// step's contacts until nothing overlaps or the sweeps run out.
#include "gpl/engine.h"
#include "gpl/response.h"

namespace gpl {

void PhysicsEngine::resolveInterpenetrations() {
    start_.clear();
    for (const Body& b : bodies_) start_.push_back(b.position);
    for (int sweep = 0; sweep < contactIterations_; ++sweep) {
        bool overlapping = false;
        for (const Contact& c : contacts_) {
            Body& a = bodies_[c.a];
            Body& b = bodies_[c.b];
            // The depth now: what the contact had, less what earlier moves in this stage took away
            // along its normal (exact for translations, which are all this stage makes).
            Contact now = c;
            now.depth -= ((b.position - start_[c.b]) - (a.position - start_[c.a])).dot(c.normal);
            if (now.depth <= 0.0) continue;
            overlapping = true;
            resolveInterpenetration(now, a, b);
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
