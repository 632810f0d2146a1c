// Cloth and soft bodies (worksheet 8): position-based constraints on particles as pure kernels.
// Positions, inverse masses and the constraint's parameters in; corrections out. A particle of
// inverse mass 0 is pinned and never moves.
//
// Student hooks (bodies in assignments/, reference bodies in solutions/):
//   solveDistanceConstraint()  XPBD: two particles held at a rest distance, with a compliance
//   solveVolumeConstraint()    XPBD: a tetrahedron held at its rest volume, with a compliance
//   projectParticleSphere()    a particle pushed out of a rigid sphere
//   projectParticleBox()       a particle pushed out of a rigid box
// Framework (soft_bodies.cpp): the particles, their meshes and constraints, and the step that
// calls these kernels (SoftBodies in soft_bodies.h).
//
// XPBD in one line: for a constraint C(x) = 0 with compliance alpha (the inverse of a stiffness,
// m/N for a distance), alpha~ = alpha / h^2, and the multiplier lambda summed over the step's
// iterations (it starts at 0 each step), one projection changes lambda by
//     dlambda = (-C - alpha~ lambda) / (sum_i w_i |grad_i C|^2 + alpha~)
// and moves each particle by dx_i = w_i grad_i C dlambda. With alpha = 0 this is PBD's projection
// (worksheet 2's rod for a distance).
#pragma once

#include <array>

#include "gpl/math.h"

namespace gpl {

/// What one projection of a distance constraint does.
struct DistanceCorrection {
    Vec3 dx1 = Vec3::Zero();  ///< move of the first particle (m)
    Vec3 dx2 = Vec3::Zero();  ///< move of the second particle (m)
    double dlambda = 0.0;     ///< change of the constraint's multiplier (the framework adds it to lambda)
};

/// Student hook (worksheet 8, assignment 1). C = |x1 - x2| - rest; grad_1 C = n = (x1 - x2) / |x1 - x2|,
/// grad_2 C = -n. w1, w2: inverse masses (1/kg, >= 0); rest (m, >= 0); compliance alpha (m/N, >= 0);
/// h: the time step (s, > 0); lambda: the multiplier summed so far in this step.
/// Returns no move when both particles are pinned (w1 + w2 + alpha~ = 0) or they coincide.
DistanceCorrection solveDistanceConstraint(const Vec3& x1, const Vec3& x2, double w1, double w2, double rest,
                                           double compliance, double h, double lambda);

/// What one projection of a volume constraint does.
struct VolumeCorrection {
    std::array<Vec3, 4> dx{Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};  ///< moves (m)
    double dlambda = 0.0;  ///< change of the multiplier
};

/// Signed volume of the tetrahedron x0 x1 x2 x3 (m^3): (x1 - x0) x (x2 - x0) . (x3 - x0) / 6,
/// positive when x3 lies on the side of the triangle x0 x1 x2 that its normal (x1 - x0) x (x2 - x0)
/// points to.
double tetrahedronVolume(const std::array<Vec3, 4>& x);

/// Student hook (worksheet 8, assignment 2). C = V(x) - restVolume with V = tetrahedronVolume();
/// w: inverse masses; restVolume (m^3, > 0); compliance alpha (1/(N m), >= 0); h (s); lambda as
/// above. Returns no move when no particle can move (sum w_i |grad_i C|^2 + alpha~ = 0).
VolumeCorrection solveVolumeConstraint(const std::array<Vec3, 4>& x, const std::array<double, 4>& w,
                                       double restVolume, double compliance, double h, double lambda);

/// Student hook (worksheet 8, assignment 3). A particle of radius r (m) at p against a rigid sphere
/// of this centre and radius: when the particle's centre is nearer to the sphere's centre than
/// radius + r, it moves along the line from the centre to distance radius + r; otherwise it stays.
/// A particle exactly at the centre moves up (+y).
Vec3 projectParticleSphere(const Vec3& p, double r, const Vec3& centre, double radius);

/// Student hook (worksheet 8, assignment 3). A particle of radius r at p against a rigid box (centre,
/// orientation body to world, half extents, m): a particle nearer to the box than r moves out to
/// distance r from it by the shortest way: from a point outside the box, away from its nearest
/// point on the box; from inside, out through the nearest face. A particle r or farther from the
/// box stays.
Vec3 projectParticleBox(const Vec3& p, double r, const Vec3& centre, const Quat& orientation, const Vec3& half);

}  // namespace gpl
