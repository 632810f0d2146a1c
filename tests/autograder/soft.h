// What the worksheet-8 autograders share: random pairs of particles and tetrahedra from a fixed seed,
// the closed forms the kernels are compared with (written here once, in the tests' own way), rigid
// boxes for the particles to meet, and messages that show every input.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "contacts.h"
#include "gpl/soft_constraints.h"

namespace gpl::checks {

// ---- A distance constraint ----------------------------------------------------------------------

/// The inputs of one call of solveDistanceConstraint().
struct Pair {
    Vec3 x1 = Vec3::Zero(), x2 = Vec3::UnitX();
    double w1 = 1.0, w2 = 1.0;  ///< 1/kg
    double rest = 1.0;          ///< m
    double compliance = 0.0;    ///< m/N
    double h = 0.01;            ///< s
    double lambda = 0.0;
};

inline std::string pairText(const Pair& c) {
    return "\n  x1 " + str(c.x1) + ", x2 " + str(c.x2) + ", w1 " + formatNumber(c.w1) + ", w2 " + formatNumber(c.w2) +
           " 1/kg, rest " + formatNumber(c.rest) + " m, alpha " + formatNumber(c.compliance) + " m/N, h " +
           formatNumber(c.h) + " s, lambda " + formatNumber(c.lambda);
}

inline std::string correctionText(const DistanceCorrection& d) {
    return "\n  answered: dx1 " + str(d.dx1) + ", dx2 " + str(d.dx2) + ", dlambda " + formatNumber(d.dlambda);
}

inline DistanceCorrection solve(const Pair& c) {
    return solveDistanceConstraint(c.x1, c.x2, c.w1, c.w2, c.rest, c.compliance, c.h, c.lambda);
}

/// Two particles up to 2 m from the origin, 0.1 to 2 m apart, held at 0.3 to 1.7 times their distance;
/// inverse masses from 0.1 to 10 1/kg, one of them pinned in one draw of four (never both); alpha = 0.
inline Pair randomPair(Random& rnd, int i) {
    Pair c;
    c.x1 = rnd.inBox(2.0);
    c.x2 = c.x1 + rnd.uniform(0.1, 2.0) * rnd.direction();
    c.w1 = std::exp(rnd.uniform(std::log(0.1), std::log(10.0)));
    c.w2 = std::exp(rnd.uniform(std::log(0.1), std::log(10.0)));
    if (i % 4 == 1) c.w1 = 0.0;
    if (i % 8 == 3) c.w2 = 0.0;
    c.rest = rnd.uniform(0.3, 1.7) * (c.x1 - c.x2).norm();
    return c;
}

/// The same pair with a compliance of 1e-7 to 1e-2 m/N, a step of 1 to 20 ms and a summed lambda of
/// either sign, as large as a projection's own change.
inline Pair compliantPair(Random& rnd, int i) {
    Pair c = randomPair(rnd, i);
    c.compliance = std::exp(rnd.uniform(std::log(1e-7), std::log(1e-2)));
    c.h = rnd.uniform(0.001, 0.02);
    const double alphaTilde = c.compliance / (c.h * c.h);
    c.lambda = rnd.uniform(-1.0, 1.0) * (c.x1 - c.x2).norm() / (c.w1 + c.w2 + alphaTilde);
    return c;
}

// ---- A volume constraint ------------------------------------------------------------------------

/// The inputs of one call of solveVolumeConstraint().
struct Tet {
    std::array<Vec3, 4> x{};
    std::array<double, 4> w{1.0, 1.0, 1.0, 1.0};  ///< 1/kg
    double rest = 1.0;                             ///< m^3
    double compliance = 0.0;                       ///< 1/(N m)
    double h = 0.01;                               ///< s
    double lambda = 0.0;
};

inline std::string tetText(const Tet& t) {
    std::string s = "\n  corners";
    for (const Vec3& c : t.x) s += " " + str(c);
    s += "\n  w";
    for (const double w : t.w) s += " " + formatNumber(w);
    return s + " 1/kg, V " + formatNumber(tetrahedronVolume(t.x)) + " m^3, V0 " + formatNumber(t.rest) +
           " m^3, alpha " + formatNumber(t.compliance) + " 1/(N m), h " + formatNumber(t.h) + " s, lambda " +
           formatNumber(t.lambda);
}

inline std::string correctionText(const VolumeCorrection& d) {
    std::string s = "\n  answered: dx";
    for (const Vec3& c : d.dx) s += " " + str(c);
    return s + ", dlambda " + formatNumber(d.dlambda);
}

inline VolumeCorrection solve(const Tet& t) {
    return solveVolumeConstraint(t.x, t.w, t.rest, t.compliance, t.h, t.lambda);
}

/// The corners moved by a correction.
inline std::array<Vec3, 4> moved(const std::array<Vec3, 4>& x, const VolumeCorrection& d) {
    return {x[0] + d.dx[0], x[1] + d.dx[1], x[2] + d.dx[2], x[3] + d.dx[3]};
}

/// The gradient of V with respect to corner i, read off V itself: V is linear in each corner, so a
/// central difference of any step is exact (to rounding) whatever formula gave V.
inline Vec3 volumeGradient(const std::array<Vec3, 4>& x, int i) {
    Vec3 g;
    for (int k = 0; k < 3; ++k) {
        std::array<Vec3, 4> plus = x, minus = x;
        plus[i][k] += 1.0;
        minus[i][k] -= 1.0;
        g[k] = (tetrahedronVolume(plus) - tetrahedronVolume(minus)) / 2.0;
    }
    return g;
}

/// A well-shaped tetrahedron of edges about 0.2 to 2 m anywhere within 3 m of the origin, turned
/// at random, of positive volume; inverse masses from 0.1 to 10 1/kg, all free; its rest volume
/// 0.5 to 1.5 times its volume; alpha = 0.
inline Tet randomTet(Random& rnd) {
    const std::array<Vec3, 4> regular{Vec3(1.0, 1.0, 1.0), Vec3(-1.0, 1.0, -1.0), Vec3(1.0, -1.0, -1.0),
                                      Vec3(-1.0, -1.0, 1.0)};  // edge 2 sqrt 2, volume +8/3
    for (;;) {
        Tet t;
        const double size = rnd.uniform(0.07, 0.7);
        const Quat R = rnd.rotation();
        const Vec3 at = rnd.inBox(3.0);
        for (int i = 0; i < 4; ++i) t.x[i] = at + R * (size * (regular[i] + rnd.inBox(0.4)));
        // Kept when at least a fifth of the regular one's volume (none of the flat or turned-over ones).
        if (tetrahedronVolume(t.x) < 0.2 * 8.0 / 3.0 * size * size * size) continue;
        for (double& w : t.w) w = std::exp(rnd.uniform(std::log(0.1), std::log(10.0)));
        t.rest = rnd.uniform(0.5, 1.5) * tetrahedronVolume(t.x);
        return t;
    }
}

/// The tetrahedron's size: its longest edge (m).
inline double tetSize(const Tet& t) {
    double L = 0.0;
    for (int i = 0; i < 4; ++i) {
        for (int j = i + 1; j < 4; ++j) L = std::max(L, (t.x[i] - t.x[j]).norm());
    }
    return L;
}

// ---- Rigid shapes -------------------------------------------------------------------------------

/// A rigid box for projectParticleBox(): centre, orientation (box to world), half extents (m).
struct Box {
    Vec3 centre = Vec3::Zero();
    Quat orientation = Quat::Identity();
    Vec3 half = Vec3::Ones();
    Vec3 local(const Vec3& p) const { return orientation.conjugate() * (p - centre); }
    Vec3 world(const Vec3& q) const { return centre + orientation * q; }
};

inline std::string boxText(const Box& b) {
    const Quat& q = b.orientation;
    return "\n  box centre " + str(b.centre) + ", half extents " + str(b.half) + ", orientation (w, x, y, z) (" +
           formatNumber(q.w()) + ", " + formatNumber(q.x()) + ", " + formatNumber(q.y()) + ", " + formatNumber(q.z()) +
           ")";
}

/// A box of half extents 0.1 to 1 m, turned at random, within 3 m of the origin.
inline Box randomBox(Random& rnd) {
    Box b;
    b.centre = rnd.inBox(3.0);
    b.orientation = rnd.rotation();
    b.half = Vec3(rnd.uniform(0.1, 1.0), rnd.uniform(0.1, 1.0), rnd.uniform(0.1, 1.0));
    return b;
}

/// The point of the box nearest to q (box frame).
inline Vec3 nearestOnBox(const Box& b, const Vec3& q) { return q.cwiseMax(-b.half).cwiseMin(b.half); }

/// Distance (m) from a world point to the box: 0 inside.
inline double distanceToBox(const Box& b, const Vec3& p) {
    const Vec3 q = b.local(p);
    return (q - nearestOnBox(b, q)).norm();
}

}  // namespace gpl::checks
