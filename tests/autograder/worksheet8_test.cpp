// Worksheet 8 autograder: cloth and soft bodies. The kernels are called directly on pairs of particles,
// tetrahedra and rigid shapes drawn from a fixed seed. A distance projection with alpha = 0 must leave
// C = 0, keep the pair's centre of mass, move along the line of the particles and never move a pinned
// one; with a compliance it must change lambda by the XPBD closed form. A volume projection must
// restore the rest volume exactly when one corner moves (V is linear in each corner), to second
// order when all do, keep the centre of mass and move each corner along its gradient (read off V
// itself here); with a compliance, the closed form. A particle inside a sphere or a box must end
// at distance r from it by the shortest way; one that does not touch must stay bit for bit.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include "gpl/scenes.h"
#include "gpl/soft_bodies.h"
#include "graded.h"
#include "soft.h"

namespace gpl {
namespace {

using checks::Box;
using checks::correctionText;
using checks::Pair;
using checks::pairText;
using checks::Random;
using checks::str;
using checks::Tet;
using checks::tetText;

class Worksheet8 : public checks::ContactsTest {};

// Quantities computed in a few operations round to ~1e-16 of their size; 1e-12 of it allows any
// equivalent formula or order of operations, while every mistake tested here is off by percents.
constexpr double kRounding = 1e-12;

// The size of a pair's numbers (m): what its positions and lengths round against.
double pairScale(const Pair& c) { return 1.0 + c.x1.norm() + c.x2.norm() + c.rest; }

// ---- solveDistanceConstraint() ---------------------------------------------------------------------

GRADED_TEST(Worksheet8, DistanceProjectionRestoresRestLength, 3,
            "solveDistanceConstraint() with alpha = 0: after one projection the particles are exactly the rest "
            "distance apart (C = |x1 - x2| - rest = 0). dlambda = -C / (w1 + w2), dx1 = w1 dlambda n, "
            "dx2 = -w2 dlambda n with the unit n = (x1 - x2) / |x1 - x2| (worksheet 8, assignment 1).") {
    Random rnd(801);
    for (int i = 0; i < 300; ++i) {
        const Pair c = checks::randomPair(rnd, i);
        const DistanceCorrection d = checks::solve(c);
        const double after = (c.x1 + d.dx1 - (c.x2 + d.dx2)).norm();
        ASSERT_LE(std::abs(after - c.rest), kRounding * pairScale(c))
            << "after the projection the particles are " << after << " m apart; the rest distance is " << c.rest
            << " m (they were " << (c.x1 - c.x2).norm() << " m apart)" << pairText(c) << correctionText(d);
    }
}

GRADED_TEST(Worksheet8, DistanceMovesAlongTheLine, 2,
            "solveDistanceConstraint(): both particles move along the line through them (grad_1 C = n, "
            "grad_2 C = -n), and a pinned particle (w = 0) does not move at all.") {
    Random rnd(802);
    int moves = 0;
    for (int i = 0; i < 300; ++i) {
        const Pair c = checks::randomPair(rnd, i);
        const DistanceCorrection d = checks::solve(c);
        const Vec3 n = (c.x1 - c.x2).normalized();
        const std::string what = pairText(c) + correctionText(d);
        for (const auto& [dx, w, name] : {std::tuple{d.dx1, c.w1, "x1"}, std::tuple{d.dx2, c.w2, "x2"}}) {
            if (w == 0.0) {
                ASSERT_EQ(dx.norm(), 0.0) << name << " is pinned (w = 0) but moved by " << str(dx) << what;
                continue;
            }
            // Across the line, only rounding of a move as large as the particles' distance.
            ASSERT_LE((dx - dx.dot(n) * n).norm(), kRounding * pairScale(c))
                << name << " moved across the line of the particles (n = " << str(n) << ")" << what;
        }
        moves += (d.dx1 - d.dx2).norm() > 0.0;
    }
    EXPECT_EQ(moves, 300) << "a projection of a pair away from its rest distance must move it: solveDistanceConstraint() "
                             "moved only " << moves << " of 300 pairs";
}

GRADED_TEST(Worksheet8, DistanceKeepsCentreOfMass, 2,
            "solveDistanceConstraint(): a projection is internal to the pair, so m1 dx1 + m2 dx2 = 0: each particle "
            "moves in proportion to its inverse mass, dx1 = w1 dlambda n and dx2 = -w2 dlambda n (the lighter one "
            "moves more).") {
    Random rnd(803);
    for (int i = 0; i < 300; ++i) {
        Pair c = checks::randomPair(rnd, i);
        if (c.w1 == 0.0 || c.w2 == 0.0) continue;
        const DistanceCorrection d = checks::solve(c);
        const double m1 = 1.0 / c.w1, m2 = 1.0 / c.w2;  // kg
        const Vec3 momentum = m1 * d.dx1 + m2 * d.dx2;   // kg m
        const std::string what = "\n  m1 " + formatNumber(m1) + " kg, m2 " + formatNumber(m2) + " kg" + pairText(c) +
                                 correctionText(d);
        ASSERT_GT((d.dx1 - d.dx2).norm(), 0.0) << "the pair is away from its rest distance, yet nothing moved" << what;
        ASSERT_LE(momentum.norm(), kRounding * (m1 + m2) * pairScale(c))
            << "m1 dx1 + m2 dx2 = " << str(momentum) << " kg m; the centre of mass moved" << what;
    }
}

GRADED_TEST(Worksheet8, DistanceComplianceClosedForm, 3,
            "solveDistanceConstraint() with alpha > 0 (XPBD): alpha~ = alpha / h^2, "
            "dlambda = (-C - alpha~ lambda) / (w1 + w2 + alpha~) with the lambda summed so far in the step, "
            "dx1 = w1 dlambda n, dx2 = -w2 dlambda n, n the unit vector from x2 to x1.",
            grading::dependsOn("DistanceProjectionRestoresRestLength")) {
    Random rnd(804);
    for (int i = 0; i < 300; ++i) {
        const Pair c = checks::compliantPair(rnd, i);
        const DistanceCorrection d = checks::solve(c);
        const Vec3 n = (c.x1 - c.x2).normalized();
        const double C = (c.x1 - c.x2).norm() - c.rest, alphaTilde = c.compliance / (c.h * c.h);
        const double dlambda = (-C - alphaTilde * c.lambda) / (c.w1 + c.w2 + alphaTilde);
        const std::string what = "\n  C " + formatNumber(C) + " m, alpha~ " + formatNumber(alphaTilde) + " m/N, expected "
                                 "dlambda " + formatNumber(dlambda) + pairText(c) + correctionText(d);
        ASSERT_NEAR(d.dlambda, dlambda, kRounding * (std::abs(dlambda) + pairScale(c) / (c.w1 + c.w2 + alphaTilde)))
            << "dlambda is not (-C - alpha~ lambda) / (w1 + w2 + alpha~)" << what;
        ASSERT_LE((d.dx1 - c.w1 * dlambda * n).norm(), kRounding * pairScale(c)) << "dx1 is not w1 dlambda n" << what;
        ASSERT_LE((d.dx2 + c.w2 * dlambda * n).norm(), kRounding * pairScale(c)) << "dx2 is not -w2 dlambda n" << what;
    }
}

GRADED_TEST(Worksheet8, DistanceDegenerateInputsMoveNothing, 1,
            "solveDistanceConstraint(): two pinned particles held rigidly (w1 + w2 + alpha~ = 0) and two particles "
            "at the same place (no direction n) move nothing and give no NaN; particles a micrometre apart still "
            "project exactly (check for the two cases before dividing, not with a tolerance).") {
    Random rnd(805);
    for (int i = 0; i < 100; ++i) {
        Pair c = checks::compliantPair(rnd, i);
        if (i % 2 == 0) {
            c.w1 = c.w2 = 0.0;
            c.compliance = 0.0;
        } else {
            c.x2 = c.x1;
        }
        const DistanceCorrection d = checks::solve(c);
        ASSERT_TRUE(d.dx1.norm() == 0.0 && d.dx2.norm() == 0.0 && std::isfinite(d.dlambda))
            << (i % 2 == 0 ? "two pinned particles with alpha = 0" : "two particles at the same place")
            << " must move nothing, with a finite dlambda" << pairText(c) << correctionText(d);
        Pair near = checks::randomPair(rnd, i);
        near.x2 = near.x1 + 1e-6 * rnd.direction();
        const DistanceCorrection e = checks::solve(near);
        const double after = (near.x1 + e.dx1 - (near.x2 + e.dx2)).norm();
        ASSERT_LE(std::abs(after - near.rest), kRounding * pairScale(near))
            << "particles a micrometre apart must still be projected to the rest distance; they end " << after
            << " m apart" << pairText(near) << correctionText(e);
    }
}

// ---- solveVolumeConstraint() -----------------------------------------------------------------------

// V's rounding: its terms are products of three coordinates of up to |x| ~ 5 m.
double volumeScale(const Tet& t) {
    double s = 1.0;
    for (const Vec3& x : t.x) s = std::max(s, x.norm());
    return s * s * s;
}

GRADED_TEST(Worksheet8, VolumeOneFreeCornerRestoredExactly, 3,
            "solveVolumeConstraint() with alpha = 0 and one corner free (the others w = 0): V is linear in each "
            "corner, so one projection restores the rest volume exactly. C = V - V0; the gradient of V at corner i "
            "is the opposite face's cross product over 6, pointing away from that face "
            "(g3 = (x1 - x0) x (x2 - x0) / 6, ...); dlambda = -C / sum w_i |g_i|^2, dx_i = w_i dlambda g_i "
            "(worksheet 8, assignment 2). V is signed: a tetrahedron turned inside out (V < 0) is turned back.") {
    Random rnd(811);
    for (int i = 0; i < 300; ++i) {
        Tet t = checks::randomTet(rnd);
        // Every fifth turned inside out (two corners swapped: V < 0 < V0), as a squashed soft body's can be.
        if (i % 5 == 4) std::swap(t.x[0], t.x[1]);
        // Every sixth a hundred times smaller (edges of about a centimetre, a fine mesh's), or with
        // corners a thousand times heavier: sum w |g|^2 is then tiny, and still no reason to skip.
        if (i % 6 == 1) {
            const Vec3 centre = 0.25 * (t.x[0] + t.x[1] + t.x[2] + t.x[3]);
            for (Vec3& x : t.x) x = centre + 0.01 * (x - centre);
            t.rest *= 1e-6;
        } else if (i % 6 == 3) {
            for (double& w : t.w) w *= 1e-3;
        }
        const int k = i % 4;
        for (int j = 0; j < 4; ++j) t.w[j] = j == k ? t.w[j] : 0.0;
        const VolumeCorrection d = checks::solve(t);
        const std::string what = "\n  corner " + std::to_string(k) + " free" + tetText(t) + correctionText(d);
        for (int j = 0; j < 4; ++j) {
            ASSERT_TRUE(j == k || d.dx[j].norm() == 0.0) << "corner " << j << " is pinned (w = 0) but moved" << what;
        }
        const double after = tetrahedronVolume(checks::moved(t.x, d));
        ASSERT_LE(std::abs(after - t.rest), 100.0 * kRounding * volumeScale(t))
            << "after the projection V = " << after << " m^3; the rest volume is " << t.rest << " m^3" << what;
    }
}

GRADED_TEST(Worksheet8, VolumeAllFreeSecondOrder, 2,
            "solveVolumeConstraint() with alpha = 0 and all corners free: V is cubic in the corners, so one projection "
            "along the exact gradients leaves an error of second order: ten times less initial error leaves a "
            "hundred times less. An error that shrinks only tenfold means the moves are not along dV/dx_i.",
            grading::dependsOn("VolumeOneFreeCornerRestoredExactly")) {
    Random rnd(812);
    for (int i = 0; i < 200; ++i) {
        Tet t = checks::randomTet(rnd);
        const double V = tetrahedronVolume(t.x), sign = i % 2 == 0 ? 1.0 : -1.0;
        double error[2];  // relative volume error after one projection, from 1e-3 and from 1e-4 before
        std::string what;
        for (int e = 0; e < 2; ++e) {
            const double before = e == 0 ? 1e-3 : 1e-4;
            t.rest = V / (1.0 + sign * before);
            const VolumeCorrection d = checks::solve(t);
            error[e] = std::abs(tetrahedronVolume(checks::moved(t.x, d)) - t.rest) / t.rest;
            what += "\n  from a relative error of " + formatNumber(before) + ": " + formatNumber(error[e]) + tetText(t) +
                    correctionText(d);
        }
        // Second order: a ratio of 100, first order (a wrong gradient, or no move): 10. The third-order
        // terms move it by a percent at these errors; 30 lies well between.
        ASSERT_TRUE(error[0] >= 30.0 * error[1] || error[0] <= 1e-13)
            << "the volume error after one projection fell only by " << error[0] / error[1]
            << " when the error before fell tenfold (second order: a hundredfold)" << what;
        ASSERT_LE(error[0], 0.1 * 1e-3) << "one projection must remove most of the volume error" << what;
    }
}

GRADED_TEST(Worksheet8, VolumeKeepsCentreOfMass, 2,
            "solveVolumeConstraint() with all corners free: the gradients of V sum to zero (moving the whole "
            "tetrahedron changes nothing), so sum m_i dx_i = 0 when each corner moves by w_i dlambda g_i. A "
            "gradient from the wrong face or in the wrong order breaks it, and so do moves without w_i.") {
    Random rnd(813);
    for (int i = 0; i < 300; ++i) {
        const Tet t = checks::randomTet(rnd);
        const VolumeCorrection d = checks::solve(t);
        Vec3 momentum = Vec3::Zero();  // kg m
        double mass = 0.0, moves = 0.0;
        for (int j = 0; j < 4; ++j) {
            momentum += d.dx[j] / t.w[j];
            mass += 1.0 / t.w[j];
            moves += d.dx[j].norm();
        }
        const std::string what = tetText(t) + correctionText(d);
        ASSERT_GT(moves, 0.0) << "the tetrahedron is away from its rest volume, yet nothing moved" << what;
        ASSERT_LE(momentum.norm(), 100.0 * kRounding * mass * checks::tetSize(t))
            << "sum m_i dx_i = " << str(momentum) << " kg m; the centre of mass moved" << what;
    }
}

GRADED_TEST(Worksheet8, VolumeMovesAlongGradients, 2,
            "solveVolumeConstraint(): each free corner moves along dV/dx_i, the normal of the opposite face: away "
            "from that face when the volume is too small, towards it when too large. A pinned corner (w = 0) stays, "
            "and a tetrahedron pinned at every corner with alpha = 0 (sum w_i |g_i|^2 + alpha~ = 0) moves nothing and "
            "gives a finite dlambda: check for it before dividing.") {
    Random rnd(814);
    for (int i = 0; i < 300; ++i) {
        Tet t = checks::randomTet(rnd);
        if (i % 3 == 0) t.w[static_cast<std::size_t>(i / 3 % 4)] = 0.0;
        if (i % 10 == 5) {
            t.w = {0.0, 0.0, 0.0, 0.0};
            t.compliance = 0.0;
            const VolumeCorrection held = checks::solve(t);
            bool still = std::isfinite(held.dlambda);
            for (const Vec3& dx : held.dx) still = still && dx.norm() == 0.0;
            ASSERT_TRUE(still) << "a tetrahedron pinned at every corner with alpha = 0 must move nothing, with a "
                               << "finite dlambda" << tetText(t) << correctionText(held);
            continue;
        }
        const VolumeCorrection d = checks::solve(t);
        const double C = tetrahedronVolume(t.x) - t.rest;
        const std::string what = "\n  C " + formatNumber(C) + " m^3" + tetText(t) + correctionText(d);
        for (int j = 0; j < 4; ++j) {
            if (t.w[j] == 0.0) {
                ASSERT_EQ(d.dx[j].norm(), 0.0) << "corner " << j << " is pinned (w = 0) but moved" << what;
                continue;
            }
            const Vec3 g = checks::volumeGradient(t.x, j).normalized();
            const double along = d.dx[j].dot(g);  // m
            ASSERT_LE((d.dx[j] - along * g).norm(), 100.0 * kRounding * checks::tetSize(t))
                << "corner " << j << " moved across dV/dx_" << j << " (unit " << str(g) << ")" << what;
            ASSERT_LT(along * C, 0.0) << "corner " << j << " moved " << along << " m along dV/dx_" << j
                                     << (C < 0.0 ? " (the volume is too small: it must move away from the opposite face)"
                                                 : " (the volume is too large: it must move towards the opposite face)")
                                     << what;
        }
    }
}

GRADED_TEST(Worksheet8, VolumeComplianceClosedForm, 3,
            "solveVolumeConstraint() with alpha > 0 (XPBD): alpha~ = alpha / h^2, "
            "dlambda = (-C - alpha~ lambda) / (sum_i w_i |g_i|^2 + alpha~) with g_i = dV/dx_i (each a cross product "
            "over 6) and the lambda summed so far, dx_i = w_i dlambda g_i.",
            grading::dependsOn("VolumeOneFreeCornerRestoredExactly")) {
    Random rnd(815);
    for (int i = 0; i < 300; ++i) {
        Tet t = checks::randomTet(rnd);
        if (i % 3 == 0) t.w[static_cast<std::size_t>(i / 3 % 4)] = 0.0;
        std::array<Vec3, 4> g;
        double sum = 0.0;
        for (int j = 0; j < 4; ++j) {
            g[j] = checks::volumeGradient(t.x, j);
            sum += t.w[j] * g[j].squaredNorm();
        }
        // alpha~ from a tenth to ten times sum w |g|^2, so that neither term hides the other.
        t.h = rnd.uniform(0.001, 0.02);
        t.compliance = sum * std::exp(rnd.uniform(std::log(0.1), std::log(10.0))) * t.h * t.h;
        const double alphaTilde = t.compliance / (t.h * t.h), C = tetrahedronVolume(t.x) - t.rest;
        t.lambda = rnd.uniform(-1.0, 1.0) * std::abs(C) / (sum + alphaTilde);
        const double dlambda = (-C - alphaTilde * t.lambda) / (sum + alphaTilde);
        const VolumeCorrection d = checks::solve(t);
        const std::string what = "\n  C " + formatNumber(C) + " m^3, alpha~ " + formatNumber(alphaTilde) +
                                 ", expected dlambda " + formatNumber(dlambda) + tetText(t) + correctionText(d);
        const double lambdaScale = (std::abs(C) + volumeScale(t) * kRounding) / (sum + alphaTilde);
        ASSERT_NEAR(d.dlambda, dlambda, 100.0 * kRounding * lambdaScale + 1e-10 * std::abs(dlambda))
            << "dlambda is not (-C - alpha~ lambda) / (sum w_i |g_i|^2 + alpha~)" << what;
        for (int j = 0; j < 4; ++j) {
            const Vec3 expected = t.w[j] * dlambda * g[j];
            ASSERT_LE((d.dx[j] - expected).norm(), 1e-10 * expected.norm() + 100.0 * kRounding * checks::tetSize(t))
                << "dx_" << j << " is not w_" << j << " dlambda g_" << j << " = " << str(expected) << what;
        }
    }
}

// ---- projectParticleSphere() -------------------------------------------------------------------------

struct SphereCase {
    Vec3 p, centre;
    double r, radius;
};

std::string sphereText(const SphereCase& s, const Vec3& answered) {
    return "\n  particle at " + str(s.p) + ", r " + formatNumber(s.r) + " m; sphere at " + str(s.centre) + ", radius " +
           formatNumber(s.radius) + " m (|p - centre| = " + formatNumber((s.p - s.centre).norm()) + ")\n  answered " +
           str(answered);
}

// A sphere of radius 0.1 to 2 m within 3 m of the origin, a particle of radius 0.005 to 0.1 m (0 in a
// draw of five) at `reach` times radius + r from its centre.
SphereCase sphereCase(Random& rnd, int i, double reach) {
    SphereCase s;
    s.centre = rnd.inBox(3.0);
    s.radius = rnd.uniform(0.1, 2.0);
    s.r = i % 5 == 0 ? 0.0 : rnd.uniform(0.005, 0.1);
    s.p = s.centre + reach * (s.radius + s.r) * rnd.direction();
    return s;
}

GRADED_TEST(Worksheet8, SphereInsideMovesToSurface, 2,
            "projectParticleSphere(): a particle whose centre is nearer to the sphere's centre than radius + r moves "
            "along the line from the sphere's centre out to exactly radius + r (its own radius r included) "
            "(worksheet 8, assignment 3).") {
    Random rnd(821);
    for (int i = 0; i < 300; ++i) {
        const SphereCase s = sphereCase(rnd, i, rnd.uniform(0.01, 0.999));
        const Vec3 q = projectParticleSphere(s.p, s.r, s.centre, s.radius);
        const double tol = kRounding * (1.0 + s.centre.norm() + s.radius);
        const Vec3 out = (s.p - s.centre).normalized();
        ASSERT_NEAR((q - s.centre).norm(), s.radius + s.r, tol)
            << "the particle must end radius + r = " << s.radius + s.r << " m from the centre" << sphereText(s, q);
        ASSERT_LE((q - (s.centre + (s.radius + s.r) * out)).norm(), 100.0 * tol)
            << "the particle must move straight out from the sphere's centre, along p - centre" << sphereText(s, q);
    }
}

GRADED_TEST(Worksheet8, SphereMovesOnlyWhatTouches, 1,
            "projectParticleSphere(): a particle radius + r or farther from the centre stays where it is (return p "
            "itself); one inside moves; one exactly at the centre moves straight up (+y) to radius + r.") {
    Random rnd(822);
    for (int i = 0; i < 300; ++i) {
        const bool inside = i % 3 == 0;
        SphereCase s = sphereCase(rnd, i, inside ? rnd.uniform(0.0, 0.99) : rnd.uniform(1.0001, 3.0));
        if (i % 30 == 0) s.p = s.centre;
        const Vec3 q = projectParticleSphere(s.p, s.r, s.centre, s.radius);
        if (!inside) {
            // Where it is, to the rounding of a way back to p through the centre.
            ASSERT_LE((q - s.p).norm(), 4.0 * kRounding * (s.centre.norm() + s.p.norm()))
                << "a particle that does not touch the sphere must stay where it is" << sphereText(s, q);
        } else if (s.p == s.centre) {
            const Vec3 up = s.centre + (s.radius + s.r) * Vec3::UnitY();
            ASSERT_LE((q - up).norm(), kRounding * (1.0 + s.centre.norm() + s.radius))
                << "a particle exactly at the centre moves straight up to " << str(up) << sphereText(s, q);
        } else {
            ASSERT_GT((q - s.p).norm(), 0.0) << "a particle inside the sphere must move" << sphereText(s, q);
        }
    }
}

// ---- projectParticleBox() ------------------------------------------------------------------------------

std::string particleText(const Vec3& p, double r, const Vec3& answered, const Box& b) {
    return "\n  particle at " + str(p) + " (box frame " + str(b.local(p)) + "), r " + formatNumber(r) + " m" +
           checks::boxText(b) + "\n  answered " + str(answered) + " (box frame " + str(b.local(answered)) + ")";
}

double boxScale(const Box& b) { return 1.0 + b.centre.norm() + b.half.norm(); }

GRADED_TEST(Worksheet8, BoxInsideLeavesThroughNearestFace, 3,
            "projectParticleBox(): a particle inside a box leaves through the nearest face, to distance r outside it. "
            "Work in the box's frame, q = R^T (p - centre): the nearest face is along the axis k where "
            "half_k - |q_k| is smallest; q_k becomes sign(q_k) (half_k + r), the other coordinates stay; "
            "p' = centre + R q'.") {
    Random rnd(831);
    for (int i = 0; i < 300; ++i) {
        const Box b = checks::randomBox(rnd);
        const double r = i % 5 == 0 ? 0.0 : rnd.uniform(0.005, 0.1);
        Vec3 q;
        std::array<double, 3> gap;  // m to each axis's nearer face
        for (;;) {
            for (int k = 0; k < 3; ++k) q[k] = rnd.uniform(-0.999, 0.999) * b.half[k];
            for (int k = 0; k < 3; ++k) gap[k] = b.half[k] - std::abs(q[k]);
            std::array<double, 3> sorted = gap;
            std::sort(sorted.begin(), sorted.end());
            if (sorted[1] - sorted[0] > 1e-3) break;  // one face clearly the nearest
        }
        const int k = static_cast<int>(std::min_element(gap.begin(), gap.end()) - gap.begin());
        Vec3 expected = q;
        expected[k] = (q[k] < 0.0 ? -1.0 : 1.0) * (b.half[k] + r);
        const Vec3 p = b.world(q);
        const Vec3 answered = projectParticleBox(p, r, b.centre, b.orientation, b.half);
        ASSERT_LE((answered - b.world(expected)).norm(), 10.0 * kRounding * boxScale(b))
            << "expected " << str(b.world(expected)) << " (box frame " << str(expected) << "): out through the face "
            << (q[k] < 0.0 ? "-" : "+") << "xyz"[k] << ", the nearest" << particleText(p, r, answered, b);
    }
}

GRADED_TEST(Worksheet8, BoxNearFaceMovesOut, 2,
            "projectParticleBox(): a particle outside a box but nearer than r to one of its faces (outside along one "
            "of the box's axes only) moves straight out along that face's normal to distance r; work in the box's "
            "frame, the box may be turned.") {
    Random rnd(832);
    for (int i = 0; i < 300; ++i) {
        const Box b = checks::randomBox(rnd);
        const double r = rnd.uniform(0.005, 0.1);
        const int k = i % 3;
        const double side = i % 2 == 0 ? 1.0 : -1.0;
        Vec3 q;
        for (int j = 0; j < 3; ++j) q[j] = rnd.uniform(-0.999, 0.999) * b.half[j];
        q[k] = side * (b.half[k] + rnd.uniform(0.0, 0.99) * r);
        Vec3 expected = q;
        expected[k] = side * (b.half[k] + r);
        const Vec3 p = b.world(q);
        const Vec3 answered = projectParticleBox(p, r, b.centre, b.orientation, b.half);
        ASSERT_LE((answered - b.world(expected)).norm(), 10.0 * kRounding * boxScale(b))
            << "expected " << str(b.world(expected)) << " (box frame " << str(expected) << ")"
            << particleText(p, r, answered, b);
    }
    // Exactly on a face (an unturned box at the origin: the box frame is the world's, to the bit), as a
    // cloth laid on a box can be: out along the face's normal to r, like any other particle nearer than r.
    for (int i = 0; i < 30; ++i) {
        Box b = checks::randomBox(rnd);
        b.centre = Vec3::Zero();
        b.orientation = Quat::Identity();
        const double r = rnd.uniform(0.005, 0.1);
        const int k = i % 3;
        Vec3 q;
        for (int j = 0; j < 3; ++j) q[j] = rnd.uniform(-0.999, 0.999) * b.half[j];
        q[k] = (i % 2 == 0 ? 1.0 : -1.0) * b.half[k];
        Vec3 expected = q;
        expected[k] = (i % 2 == 0 ? 1.0 : -1.0) * (b.half[k] + r);
        const Vec3 answered = projectParticleBox(q, r, b.centre, b.orientation, b.half);
        ASSERT_LE((answered - expected).norm(), 10.0 * kRounding * boxScale(b))
            << "a particle exactly on the face: expected " << str(expected) << particleText(q, r, answered, b);
    }
}

GRADED_TEST(Worksheet8, BoxNearEdgeOrCornerMovesOut, 2,
            "projectParticleBox(): a particle outside a box nearer than r to an edge or a corner ends at least r from "
            "the box, moved away from the box's nearest point c (along q - c), and by no more than the push out "
            "through the nearest face of the box grown by r. Nothing moves along the axes where the particle lies "
            "within the box's extent.",
            grading::dependsOn("BoxNearFaceMovesOut")) {
    Random rnd(833);
    for (int i = 0; i < 300; ++i) {
        const Box b = checks::randomBox(rnd);
        const double r = rnd.uniform(0.005, 0.1);
        const int inside = i % 4;  // an edge along this axis; 3: a corner
        Vec3 q;
        for (;;) {
            for (int axis = 0; axis < 3; ++axis) {
                const double side = rnd.uniform(0.0, 1.0) < 0.5 ? -1.0 : 1.0;
                q[axis] = axis == inside ? rnd.uniform(-0.999, 0.999) * b.half[axis] : side * (b.half[axis] + rnd.uniform(0.0, r));
            }
            const Vec3 c = checks::nearestOnBox(b, q);
            if ((q - c).norm() < 0.99 * r && (q - c).norm() > 1e-3 * r) break;
        }
        const Vec3 c = checks::nearestOnBox(b, q);
        double grownPush = r;  // m: the least push onto a face of the box grown by r
        for (int axis = 0; axis < 3; ++axis) {
            if (axis != inside) grownPush = std::min(grownPush, b.half[axis] + r - std::abs(q[axis]));
        }
        const Vec3 p = b.world(q);
        const Vec3 answered = projectParticleBox(p, r, b.centre, b.orientation, b.half);
        const Vec3 move = b.local(answered) - q;
        const double tol = 10.0 * kRounding * boxScale(b);
        const std::string what = particleText(p, r, answered, b);
        ASSERT_GE(checks::distanceToBox(b, answered), r - tol)
            << "the particle must end at least r from the box; it is " << checks::distanceToBox(b, answered) << " m"
            << what;
        ASSERT_LE(move.norm(), grownPush + tol)
            << "the move of " << move.norm() << " m is longer than the push onto the grown box's nearest face, "
            << grownPush << " m: not the shortest way out" << what;
        ASSERT_GT(move.dot(q - c), 0.0) << "the particle must move away from the box's nearest point "
                                        << str(b.world(c)) << what;
        if (inside < 3) {
            ASSERT_LE(std::abs(move[inside]), tol)
                << "the particle lies within the box's extent along " << "xyz"[inside] << " and must not move along it"
                << what;
        }
    }
}

GRADED_TEST(Worksheet8, BoxMovesOnlyWhatTouches, 1,
            "projectParticleBox(): a particle farther than r from the box, even a turned box, stays where it is "
            "(return p itself); one nearer moves.") {
    Random rnd(834);
    for (int i = 0; i < 300; ++i) {
        const Box b = checks::randomBox(rnd);
        const double r = rnd.uniform(0.005, 0.1);
        const bool touches = i % 3 == 0;
        Vec3 q;
        for (int j = 0; j < 3; ++j) q[j] = rnd.uniform(-0.999, 0.999) * b.half[j];
        const int k = i % 3;
        const double side = i % 2 == 0 ? 1.0 : -1.0;
        // Beyond the grown box along axis k, or within r of the face.
        q[k] = side * (b.half[k] + (touches ? rnd.uniform(0.0, 0.99) : rnd.uniform(1.001, 5.0)) * r);
        if (!touches && i % 5 == 0) q = q.cwiseProduct(Vec3(2.0, 2.0, 2.0));  // far off a corner
        const Vec3 p = b.world(q);
        const Vec3 answered = projectParticleBox(p, r, b.centre, b.orientation, b.half);
        if (touches) {
            ASSERT_GT((answered - p).norm(), 0.0) << "a particle within r of the box must move" << particleText(p, r, answered, b);
        } else {
            // Where it is, to the rounding of a way back to p through the box's frame.
            ASSERT_LE((answered - p).norm(), 10.0 * kRounding * (boxScale(b) + p.norm()))
                << "a particle farther than r from the box must stay where it is" << particleText(p, r, answered, b);
        }
    }
}

// ---- Whole steps: the soft bodies' stages with the student's kernels -----------------------------------
// The checker's engine holds the particles and constraints; each step runs in the submission's
// engine (predict, soft contacts, project with the student's kernels, soft velocities), and the
// particles' positions and velocities come back for the checks here.

// A rope of `segments` links of 0.1 m hanging straight down from a pinned top, 0.1 kg a particle.
constexpr double kLinkLength = 0.1;       // m
constexpr double kParticleMass = 0.1;     // kg

std::size_t hangingChain(PhysicsEngine& e, int segments, SoftMethod method, double compliance, double stiffness) {
    e.setRequiredStages(kSoftStages);
    RopeSpec r;
    r.name = "chain";
    r.segments = segments;
    r.start = Vec3(0.0, 3.0, 0.0);
    r.end = r.start - Vec3(0.0, kLinkLength * segments, 0.0);
    r.mass = kParticleMass * (segments + 1);
    r.method = method;
    r.compliance = compliance;
    r.stiffness = stiffness;
    return e.softBodies().addRope(r);
}

// The stretch of the mesh's link k (m): its length less its rest length.
double stretchOf(const SoftBodies& soft, std::size_t mesh, int k) {
    const DistanceLink& l = soft.links[soft.meshes[mesh].firstLink + static_cast<std::uint32_t>(k)];
    return (soft.x[l.i] - soft.x[l.j]).norm() - l.rest;
}

GRADED_TEST(Worksheet8, PinnedParticlesNeverMove, 2,
            "A swinging rope pinned at one end and a cloth pinned at two corners: the pinned particles (w = 0) stay "
            "exactly where they are in every step, and the rest hang from them. solveDistanceConstraint() must move "
            "a particle by w dlambda grad C, nothing when w = 0; and simulationTimestep() must run the four soft stages, or "
            "nothing swings.",
            grading::dependsOn("DistanceMovesAlongTheLine"), grading::dependsOn("DistanceProjectionRestoresRestLength"),
            grading::timeLimit(20)) {
    PhysicsEngine& e = engine;
    e.setRequiredStages(kSoftStages);
    e.setConstraintIterations(20);
    SoftBodies& soft = e.softBodies();
    RopeSpec r;
    r.name = "rope";
    r.segments = 10;
    r.start = Vec3(0.0, 3.0, 0.0);
    r.end = Vec3(1.0, 3.0, 0.0);  // horizontal: it swings down
    r.compliance = 1e-5;
    const std::size_t rope = soft.addRope(r);
    ClothSpec c;
    c.name = "cloth";
    c.nx = c.ny = 6;
    c.spacing = 0.1;
    c.origin = Vec3(2.0, 3.0, 0.0);
    c.pinned = {{0, 0}, {5, 0}};
    soft.addCloth(c);
    std::vector<std::size_t> pinned;
    for (std::size_t i = 0; i < soft.x.size(); ++i) {
        if (soft.w[i] == 0.0) pinned.push_back(i);
    }
    ASSERT_EQ(pinned.size(), 3u) << "the rope's top and the cloth's two corners";
    const std::vector<Vec3> start = soft.x;
    // How far a particle may be from its mesh's nearest pin: the way there along the links, at most
    // 1 m (the rope; the cloth's farthest particle is 0.75 m along its edges); the links stretch by
    // alpha T, a fraction of a percent, so a tenth more is far from what holds and far below a fall of metres.
    const double reach = 1.1 * (r.end - r.start).norm();
    const SoftMesh& ropeMesh = soft.meshes[rope];
    double deepestDrop = 0.0;
    grading::steps(e, 300, [&](int k) {
        deepestDrop = std::max(deepestDrop, start[ropeMesh.first].y() - soft.x[ropeMesh.first + ropeMesh.count - 1].y());
        for (const std::size_t i : pinned) {
            ASSERT_TRUE(soft.x[i] == start[i]) << "step " << k << ": pinned particle " << i << " moved from "
                                               << str(start[i]) << " to " << str(soft.x[i]);
        }
        for (std::size_t i = 0; i < soft.x.size(); ++i) {
            double nearest = std::numeric_limits<double>::infinity();
            for (const std::size_t j : pinned) {
                if (soft.meshOf[j] == soft.meshOf[i]) nearest = std::min(nearest, (soft.x[i] - soft.x[j]).norm());
            }
            ASSERT_LE(nearest, reach) << "step " << k << ": particle " << i << " of the "
                                      << (soft.meshOf[i] == rope ? "rope" : "cloth") << " is " << nearest
                                      << " m from its nearest pin: it no longer hangs from it";
        }
    });
    if (HasFailure()) return;
    // And the free particles did swing down: the rope's free end, released level with its pin 1 m
    // away, swings more than half its length below it (a rope that never moved stays level).
    EXPECT_GT(deepestDrop, 0.5 * (r.end - r.start).norm())
        << "the rope's free end came at most " << deepestDrop << " m below its pin in 3 s: it did not swing down";
}

GRADED_TEST(Worksheet8, HangingXpbdChainReachesStaticStretch, 3,
            "A chain of 10 XPBD links (compliance alpha) hanging from a pin comes to rest with each link stretched "
            "by alpha T, T the weight of the particles below it, whatever the number of iterations: "
            "alpha~ = alpha / h^2, and lambda summed over the step's iterations (the term -alpha~ lambda) is what "
            "makes the stretch independent of the iteration count.",
            grading::dependsOn("DistanceComplianceClosedForm"), grading::timeLimit(30)) {
    const double alpha = 1e-3;  // m/N: the top link stretches by 1 % of its length
    for (const int iterations : {20, 100}) {
        PhysicsEngine& e = engine;
        e.clear();
        const std::size_t chain = hangingChain(e, 10, SoftMethod::XPBD, alpha, 1.0);
        e.setConstraintIterations(iterations);
        grading::steps(e, 3000, [](int) {});  // 30 s: the chain's bounce dies out
        if (HasFailure()) return;
        const SoftBodies& soft = e.softBodies();
        const double g = e.gravity().norm();
        for (int j = 0; j < 10; ++j) {
            const double tension = (10 - j) * kParticleMass * g;  // N: the particles below link j
            const double stretch = stretchOf(soft, chain, j);
            // Within 1 % of alpha T: what the chain's motion keeps after 30 s (the sweeps converge
            // from 20 iterations on); a lambda not summed stiffens the chain several times over.
            ASSERT_NEAR(stretch, alpha * tension, 0.01 * alpha * tension)
                << "link " << j << " from the top, " << iterations << " iterations: stretched by " << stretch
                << " m; alpha T = " << alpha << " m/N x " << tension << " N";
        }
    }
}

GRADED_TEST(Worksheet8, PbdChainStiffensWithIterations, 2,
            "PBD (alpha = 0, per-iteration stiffness k < 1): a hanging chain stretches less with more iterations, "
            "its apparent stiffness grows with the iteration count (which XPBD's compliance does not). With "
            "alpha = 0 solveDistanceConstraint() must still restore C = 0 in one projection; the framework scales it.",
            grading::dependsOn("DistanceProjectionRestoresRestLength"), grading::timeLimit(20)) {
    double previous = std::numeric_limits<double>::infinity();
    for (const int iterations : {2, 8, 32}) {
        PhysicsEngine& e = engine;
        e.clear();
        const std::size_t chain = hangingChain(e, 20, SoftMethod::PBD, 0.0, 0.5);
        e.setConstraintIterations(iterations);
        grading::steps(e, 500, [](int) {});  // 5 s
        if (HasFailure()) return;
        const SoftBodies& soft = e.softBodies();
        const SoftMesh& m = soft.meshes[chain];
        const double length = (soft.x[m.first + m.count - 1] - soft.x[m.first]).norm();
        const double stretch = length / (20 * kLinkLength) - 1.0;  // relative
        // Stretched (PBD's k < 1 gives), by less than half: a chain that holds at all; and less than
        // with a quarter of the iterations.
        ASSERT_GT(stretch, 0.0) << iterations << " iterations: the chain is no longer than at rest";
        ASSERT_LT(stretch, 0.5) << iterations << " iterations: the chain stretched by " << stretch * 100
                                << " %: its links do not hold";
        ASSERT_LT(stretch, previous) << iterations << " iterations: stretched by " << stretch * 100
                                     << " %, not less than with a quarter of the iterations (" << previous * 100 << " %)";
        previous = stretch;
    }
}

GRADED_TEST(Worksheet8, SoftCubeKeepsItsVolume, 2,
            "A soft cube (soft edges, incompressible tetrahedra) resting on the floor keeps its volume: every "
            "step's sweeps restore each tetrahedron's rest volume with solveVolumeConstraint(), whose moves must "
            "follow the gradients of V (each the opposite face's cross product over 6, pointing away from it). It must also "
            "fall onto the floor: simulationTimestep() runs the four soft stages.",
            grading::dependsOn("VolumeOneFreeCornerRestoredExactly"), grading::dependsOn("VolumeAllFreeSecondOrder"),
            grading::timeLimit(20)) {
    PhysicsEngine& e = engine;
    e.setRequiredStages(kSoftStages);
    e.setConstraintIterations(10);
    e.add(plane("floor", {0.0, 1.0, 0.0}));
    const double side = 0.4;  // m
    TetMeshSpec cube = makeSoftCube("cube", Vec3(0.0, side / 2.0 + 0.05, 0.0), side, 2);
    cube.edgeCompliance = 1e-3;  // m/N: edges alone would let it sag by a good part of its height
    cube.volumeCompliance = 0.0;
    const std::size_t mesh = e.softBodies().addSoftBody(cube);
    const double h = e.timeStep(), g = e.gravity().norm();
    // The floor pushes the bottom particles up after the sweeps, by at most the g h^2 they fell in the
    // step, which squeezes the bottom layer's tetrahedra: at most g h^2 over the cube's side of its
    // volume; twice that allows the sweeps' remainder.
    const double bound = 2.0 * g * h * h / side;
    double worst = 0.0;
    grading::steps(e, 300, [&](int k) {
        if (k <= 100) return;  // the first second: it lands and settles
        worst = std::max(worst, std::abs(e.softBodies().volumeRatio(mesh) - 1.0));
    });
    if (HasFailure()) return;
    EXPECT_LE(worst, bound) << "the cube's volume over its rest volume strayed from 1 by " << worst
                            << " while it rested on the floor (allowed: 2 g h^2 / side = " << bound << ")";
    double lowest = std::numeric_limits<double>::infinity();
    for (const Vec3& x : e.softBodies().x) lowest = std::min(lowest, x.y());
    EXPECT_GT(lowest, -0.5 * side) << "the cube did not stay above the floor";
    // It fell the 5 cm to the floor: its lowest particle rests on it, its centre one particle radius
    // (1 cm) up, with as much again for the sweeps' remainder (one that never moved stays 5 cm up).
    EXPECT_LT(lowest, 2.0 * cube.radius) << "the cube's lowest particle is " << lowest
                                         << " m above the floor: it never landed";
}

// A cloth of n x n particles 0.05 m apart, level at height y, centred over (cx, cz); XPBD.
ClothSpec levelCloth(const std::string& name, int n, double cx, double y, double cz) {
    ClothSpec c;
    c.name = name;
    c.nx = c.ny = n;
    c.spacing = 0.05;
    const double half = 0.5 * (n - 1) * c.spacing;
    c.origin = Vec3(cx - half, y, cz - half);
    c.radius = 0.01;
    return c;
}

GRADED_TEST(Worksheet8, NoParticleEndsInsideSphereOrBox, 2,
            "Cloth dropped on a ball and on a turned box: at the end of every step no particle lies inside either "
            "(nearer than its radius r): the last sweep pushes every contact out with projectParticleSphere() "
            "and projectParticleBox(), which must reach distance r by the shortest way.",
            grading::dependsOn("SphereInsideMovesToSurface"), grading::dependsOn("BoxInsideLeavesThroughNearestFace"),
            grading::dependsOn("BoxNearFaceMovesOut"), grading::timeLimit(20)) {
    PhysicsEngine& e = engine;
    e.setRequiredStages(kSoftStages);
    e.setConstraintIterations(10);
    // Frictionless bodies: friction moves particles along the surface after the sweeps, which on a
    // curved surface sinks them by the square of the slide; without it the sweeps' last push stands.
    // No floor: a particle caught between two bodies would be pushed by one into the other.
    e.add(sphere("ball", 0.3, 1.0).at({0.0, 0.4, 0.0}).makeStatic().rough(0.0, 0.0));
    const Quat turned = Quat(Eigen::AngleAxisd(0.5, Vec3::UnitY())) * Quat(Eigen::AngleAxisd(0.3, Vec3::UnitX()));
    e.add(box("box", {0.3, 0.2, 0.25}, 1.0).at({1.5, 0.4, 0.0}).rotated(turned).makeStatic().rough(0.0, 0.0));
    SoftBodies& soft = e.softBodies();
    soft.addCloth(levelCloth("on-ball", 14, 0.05, 1.0, -0.03));
    soft.addCloth(levelCloth("on-box", 14, 1.45, 1.0, 0.04));
    const double r = 0.01;  // m, the particles' radius
    double deepest = 0.0;
    int touching = 0;
    grading::steps(e, 200, [&](int k) {  // 2 s: the fall, the landing and the draping
        const double depth = soft.deepestPenetration(e.bodies());
        deepest = std::max(deepest, depth);
        // The last sweep leaves each pushed particle exactly r from the surface; rounding of positions
        // of about a metre is all that may remain.
        ASSERT_LE(depth, 1e-9 * r) << "step " << k << ": a particle lies " << depth << " m inside the ball or the box";
        for (const Vec3& x : soft.x) {
            touching += (x - e.body("ball").position).norm() < 0.3 + 1.5 * r;
        }
    });
    if (HasFailure()) return;
    EXPECT_GT(touching, 0) << "no particle ever came near the ball";
}

GRADED_TEST(Worksheet8, ClothOnSphereGainsNoEnergy, 2,
            "Cloth dropped on a ball with friction: its energy (kinetic and gravitational; its links are rigid) "
            "never exceeds what it started with, and it comes to lie on the ball. A projection that overshoots, or moves "
            "particles the wrong way, feeds energy in. A cloth that never falls (a soft stage left out of "
            "simulationTimestep()) fails too.",
            grading::dependsOn("DistanceComplianceClosedForm"), grading::dependsOn("SphereInsideMovesToSurface"),
            grading::timeLimit(30)) {
    PhysicsEngine& e = engine;
    e.setRequiredStages(kSoftStages);
    e.setConstraintIterations(10);
    e.add(plane("floor", {0.0, 1.0, 0.0}));
    const double R = 0.3;  // m
    e.add(sphere("ball", R, 1.0).at({0.0, 0.5, 0.0}).makeStatic().rough(0.5, 0.4));
    // Every compliance 0: the cloth stores no elastic energy (C^2 / 2 alpha of constraints not yet
    // converged would count energy the step never had), so its kinetic and gravitational energy can only fall.
    ClothSpec c = levelCloth("cloth", 16, 0.0, 1.2, 0.0);
    c.stretchCompliance = c.shearCompliance = c.bendCompliance = 0.0;
    e.softBodies().addCloth(c);
    const double start = e.totalEnergy();  // J, at rest: all of it gravitational
    grading::steps(e, 400, [&](int k) {  // 4 s
        const double now = e.totalEnergy();
        // Dropped from rest, it may trade energy between kinetic and gravitational but never have more
        // than it started with; rounding of sums of a few hundred terms of up to the start's size.
        ASSERT_LE(now, start + 1e-9 * std::abs(start)) << "step " << k << ": the energy rose from " << start
                                                       << " J at the start to " << now << " J";
    });
    if (HasFailure()) return;
    // Draped over the ball: the cloth's centre of mass above the ball's centre (a cloth through it ends
    // on the floor).
    Vec3 centre = Vec3::Zero();
    for (const Vec3& x : e.softBodies().x) centre += x;
    centre /= static_cast<double>(e.softBodies().x.size());
    EXPECT_GT(centre.y(), e.body("ball").position.y()) << "the cloth's centre of mass ended at " << str(centre)
                                                      << ": it does not lie on the ball";
    // And it came down onto it: the ball's top is 0.4 m below the cloth's start, and a draped cloth's
    // centre of mass lies below the top (a cloth that never moved stays at 1.2 m).
    EXPECT_LT(centre.y(), e.body("ball").position.y() + R) << "the cloth's centre of mass ended at " << str(centre)
                                                           << ", above the ball's top: it never fell onto it";
}

}  // namespace
}  // namespace gpl
