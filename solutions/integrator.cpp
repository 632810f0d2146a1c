// Worksheet 1, assignment 3: the integrator.
//
// Inputs:  bodies()     position x (m), velocity v (m/s), acceleration accumulator a (m/s^2),
//                       isStatic() for bodies that never move
//          timeStep()   h (s)
// Outputs: v and x of every movable body advanced from t to t + h; static bodies untouched
//
// Helpers you may use: isFinite(vector), totalEnergy() (J), and per body kineticEnergy(body) and
// potentialEnergy(body, gravity) (J), assert() from <cassert>.
#include <cassert>
#include <cmath>

#include "gpl/engine.h"

namespace gpl {

void PhysicsEngine::integrator() {
    // BEGIN SOLUTION
    const double h = timeStep();
    [[maybe_unused]] const double energyBefore = totalEnergy();  // J, read by the assertion alone
    for (Body& b : bodies()) {
        if (b.isStatic()) continue;
        // Semi-implicit (symplectic) Euler: the new velocity moves the body.
        b.velocity += h * b.acceleration;
        b.position += h * b.velocity;
        assert(isFinite(b.position) && isFinite(b.velocity));
    }
    // Under gravity alone this update removes m g^2 h^2 / 2 per body and step; it never adds energy.
    // (With springs its energy oscillates about the true value instead: worksheet 2.) The tolerance
    // covers rounding in the energy sums (a few ulps of the total).
    [[maybe_unused]] const double energyAfter = totalEnergy();
    assert(stageActive(Stage::Springs) || energyAfter <= energyBefore + 1e-12 * (std::abs(energyBefore) + 1.0));
    // ELSE STUB
    // notImplemented("integrator()");
    // END SOLUTION
}

}  // namespace gpl
