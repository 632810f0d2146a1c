// Contacts: where two bodies touch (or a rope is taut), found anew every time step.
//
// One type serves every pair of shapes and every later worksheet: the normal and the depth say how
// to separate the bodies, the points (world coordinates) say where the impulse acts, so that the
// angular part of the impulse (worksheet 6) and friction (worksheet 7) need no other type. A box
// resting on a floor touches it at four points; a sphere touches anything at one.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

#include "gpl/math.h"

namespace gpl {

/// Most points one contact has: the four corners of a box face on a plane.
constexpr int kMaxContactPoints = 4;

struct Contact {
    std::size_t a = 0;            ///< index of the first body in the engine (set by the framework)
    std::size_t b = 0;            ///< index of the second body (set by the framework)
    Vec3 normal = Vec3::UnitY();  ///< unit vector from the first body towards the second, world frame
    double depth = 0.0;           ///< penetration along the normal (m); > 0 when the bodies overlap
    std::array<Vec3, kMaxContactPoints> points{};  ///< where the bodies touch, world frame (m)
    int pointCount = 0;                            ///< points in use, 1..kMaxContactPoints
    double restitution = 0.0;  ///< combined coefficient of restitution of the pair, 0..1 (set by the framework)
    double friction = 0.0;     ///< combined sliding friction mu_d of the pair (set by the framework, worksheet 7)
    double staticFriction = 0.0;  ///< combined static friction mu_s of the pair, >= friction (likewise)

    /// A contact at one point.
    static Contact at(const Vec3& point, const Vec3& normal, double depth) {
        Contact c;
        c.normal = normal;
        c.depth = depth;
        c.points[0] = point;
        c.pointCount = 1;
        return c;
    }
};

/// The rule that combines the restitution of two bodies (each 0..1) into the pair's: their
/// product. A plastic body (0) never bounces, two elastic ones (1) keep all their energy, and a
/// rigid floor of restitution 1 lets every ball bounce with its own coefficient.
inline double combineRestitution(double ea, double eb) { return ea * eb; }

/// The rule that combines the friction coefficients of two bodies (static with static, sliding with
/// sliding) into the pair's: their geometric mean sqrt(mu_a mu_b). Two bodies of the same material
/// keep their coefficient, a frictionless body (0) makes the pair frictionless, and the order of
/// mu_s >= mu_d survives the combination. Equal coefficients skip the square root, which would give
/// them back to the bit (sqrt(x x) = x in floating point while x x neither overflows nor underflows).
inline double combineFriction(double mua, double mub) { return mua == mub ? mua : std::sqrt(mua * mub); }

/// A rope between two bodies: at most `length` apart, it only pulls (a slack rope does nothing).
/// A taut rope becomes a contact (ropeContact()) whose normal points along the rope from the second
/// body to the first, and whose depth is the excess length: pushing the bodies apart along such a
/// normal pulls them together, so the same interpenetration and impulse kernels answer it.
struct Rope {
    std::size_t a = 0;    ///< index of the first body
    std::size_t b = 0;    ///< index of the second body
    double length = 0.0;  ///< greatest distance between the two centres (m), > 0
};

}  // namespace gpl
