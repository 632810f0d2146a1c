// Worksheet 8, assignment 3: a particle pushed out of a rigid sphere.
//
// Inputs:  p       the particle's predicted position (m)
//          r       its radius (m, >= 0)
//          centre  the rigid sphere's centre (m), radius its radius (m, > 0)
// Outputs: with d = p - centre: when |d| < radius + r the particle moves along d to distance
//          radius + r from the centre,
//            p' = centre + (radius + r) d / |d|
//          (straight up, +y, when d = 0); otherwise p' = p.
#include <cassert>

#include "gpl/hooks.h"
#include "gpl/soft_constraints.h"

namespace gpl {

Vec3 projectParticleSphere([[maybe_unused]] const Vec3& p, [[maybe_unused]] double r,
                           [[maybe_unused]] const Vec3& centre, [[maybe_unused]] double radius) {
    // BEGIN SOLUTION
    assert(r >= 0.0 && radius > 0.0);
    const Vec3 d = p - centre;
    const double distance = d.norm();
    const double reach = radius + r;
    if (distance >= reach) return p;
    const Vec3 outward = distance > 0.0 ? Vec3(d / distance) : Vec3::UnitY();
    return centre + reach * outward;
    // ELSE STUB
    // kernelNotImplemented("projectParticleSphere()");
    // return p;
    // END SOLUTION
}

}  // namespace gpl
