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
    notImplemented("integrator()");
}

}  // namespace gpl
