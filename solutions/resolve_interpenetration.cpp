// Worksheet 3, assignment 3: move two overlapping bodies apart.
//
// Inputs:  contact      normal (unit, from a towards b) and depth (m, > 0 when overlapping)
//          a, b         position (m) and invMass (1/kg; 0 for a static body)
// Outputs: a.position and b.position moved along the normal until the overlap is gone: together
//          they move `depth` apart, each by a share proportional to its inverse mass, so that the
//          lighter body moves more, a static body never moves and the centre of mass of two free
//          bodies stays where it was. Nothing moves when both are static or the depth is <= 0.
// Only positions change: velocities are the impulses' business (worksheet 4).
#include "gpl/hooks.h"
#include "gpl/response.h"

namespace gpl {

void resolveInterpenetration([[maybe_unused]] const Contact& contact, [[maybe_unused]] Body& a,
                             [[maybe_unused]] Body& b) {
    // BEGIN SOLUTION
    const double w = a.invMass + b.invMass;
    if (w == 0.0 || contact.depth <= 0.0) return;
    const Vec3 correction = (contact.depth / w) * contact.normal;  // m per unit inverse mass (kg m)
    a.position -= a.invMass * correction;
    b.position += b.invMass * correction;
    // ELSE STUB
    // kernelNotImplemented("resolveInterpenetration()");
    // END SOLUTION
}

}  // namespace gpl
