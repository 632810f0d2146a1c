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
    // The energy of the movable bodies before and after the update, summed in this loop rather than
    // by two more passes of totalEnergy(): m (|v|^2 / 2 - g.x) per body, the translational kinetic
    // and the gravitational energy (this update leaves rotation alone; static bodies have none; the
    // springs' only count where this check is off). A NaN fails it too, and step() names any body
    // that is no longer finite.
    const Vec3 g = stageActive(Stage::ConstantAcceleration) ? gravity() : Vec3::Zero();
    [[maybe_unused]] double energyBefore = 0.0, energyAfter = 0.0;  // read by the assertion alone
    for (Body& b : bodies()) {
        if (b.isStatic()) continue;
        energyBefore += b.mass * (0.5 * b.velocity.squaredNorm() - g.dot(b.position));
        // Semi-implicit (symplectic) Euler: the new velocity moves the body.
        b.velocity += h * b.acceleration;
        b.position += h * b.velocity;
        energyAfter += b.mass * (0.5 * b.velocity.squaredNorm() - g.dot(b.position));
    }
    // Under gravity alone this update removes m g^2 h^2 / 2 per body and step; it never adds energy.
    // (With springs its energy oscillates about the true value instead: worksheet 2.) The tolerance
    // covers rounding in the energy sums (a few ulps of the total).
    assert(stageActive(Stage::Springs) || energyAfter <= energyBefore + 1e-12 * (std::abs(energyBefore) + 1.0));
    // ELSE STUB
    // notImplemented("integrator()");
    // END SOLUTION
}

}  // namespace gpl
