// Worksheet 8, hidden tests: graded by instructors and on Gradescope, left out of student releases
// (./lab release drops every file that declares a hidden test; such a file holds hidden tests only).
// Each compares the kernels with themselves under a change the physics does not see: the pair or the
// corners relabelled, the whole scene turned and moved, repeated projections with the summed lambda;
// and a chain of unequal masses at another step against its static closed form.
#include <algorithm>
#include <cmath>
#include <string>

#include "gpl/scenes.h"
#include "gpl/soft_bodies.h"
#include "graded.h"
#include "soft.h"

namespace gpl {
namespace {

using checks::correctionText;
using checks::Pair;
using checks::pairText;
using checks::Random;
using checks::str;
using checks::Tet;
using checks::tetText;

class Worksheet8Hidden : public checks::ContactsTest {};

// 1e-12 of a quantity's size allows any equivalent formula; the mistakes caught are off by percents.
constexpr double kRounding = 1e-12;

double pairScale(const Pair& c) { return 1.0 + c.x1.norm() + c.x2.norm() + c.rest; }

GRADED_TEST(Worksheet8Hidden, DistanceSameForSwappedPair, 2,
            "Swapping the two particles (positions and inverse masses) must swap their moves and keep dlambda: "
            "the constraint |x1 - x2| - rest does not know which particle is first.",
            grading::hidden()) {
    Random rnd(890);
    for (int i = 0; i < 300; ++i) {
        const Pair c = checks::compliantPair(rnd, i);
        Pair s = c;
        std::swap(s.x1, s.x2);
        std::swap(s.w1, s.w2);
        const DistanceCorrection d = checks::solve(c), e = checks::solve(s);
        const std::string what = pairText(c) + correctionText(d) + "\n  swapped:" + correctionText(e);
        ASSERT_GT((d.dx1 - d.dx2).norm(), 0.0) << "the pair is away from its rest distance, yet nothing moved" << what;
        ASSERT_LE((d.dx1 - e.dx2).norm() + (d.dx2 - e.dx1).norm(), kRounding * pairScale(c))
            << "the moves must swap with the particles" << what;
        ASSERT_NEAR(d.dlambda, e.dlambda, kRounding * (std::abs(d.dlambda) + pairScale(c)))
            << "dlambda changed with the particles swapped" << what;
    }
}

GRADED_TEST(Worksheet8Hidden, DistanceSecondProjectionChangesNothing, 2,
            "Projecting the same pair again from where the first projection left it, with lambda summed "
            "(lambda + dlambda), must change nothing: along the line C is linear, so one projection reaches "
            "C + alpha~ lambda = 0, the XPBD balance of the constraint's force and its compliance.",
            grading::hidden()) {
    Random rnd(891);
    for (int i = 0; i < 300; ++i) {
        Pair c = checks::compliantPair(rnd, i);
        c.lambda = 0.0;
        const DistanceCorrection d = checks::solve(c);
        Pair again = c;
        again.x1 += d.dx1;
        again.x2 += d.dx2;
        again.lambda = c.lambda + d.dlambda;
        const DistanceCorrection e = checks::solve(again);
        const std::string what = pairText(c) + correctionText(d) + "\n  second projection:" + correctionText(e);
        ASSERT_GT(std::abs(d.dlambda), 0.0) << "the first projection changed nothing" << what;
        ASSERT_LE(std::abs(e.dlambda), kRounding * (std::abs(d.dlambda) + pairScale(c) / (c.w1 + c.w2)))
            << "the second projection's dlambda must be 0" << what;
    }
}

// The point turned by R about the origin and moved by t.
Vec3 carried(const Vec3& x, const Quat& R, const Vec3& t) { return R * x + t; }

GRADED_TEST(Worksheet8Hidden, DistanceFollowsRigidMotion, 1,
            "Turning and moving the whole pair as one must turn the moves along and keep dlambda (nothing may "
            "depend on the world axes).",
            grading::hidden()) {
    Random rnd(892);
    for (int i = 0; i < 300; ++i) {
        const Pair c = checks::compliantPair(rnd, i);
        const Quat R = rnd.rotation();
        const Vec3 t = rnd.inBox(5.0);
        Pair m = c;
        m.x1 = carried(c.x1, R, t);
        m.x2 = carried(c.x2, R, t);
        const DistanceCorrection d = checks::solve(c), e = checks::solve(m);
        const std::string what = pairText(c) + correctionText(d) + "\n  moved:" + pairText(m) + correctionText(e);
        ASSERT_GT((d.dx1 - d.dx2).norm(), 0.0) << "nothing moved" << what;
        const double tol = kRounding * (pairScale(c) + pairScale(m));
        ASSERT_LE((R * d.dx1 - e.dx1).norm() + (R * d.dx2 - e.dx2).norm(), tol) << "the moves did not turn along" << what;
        ASSERT_NEAR(d.dlambda, e.dlambda, kRounding * std::abs(d.dlambda) + tol / (c.w1 + c.w2))
            << "dlambda changed" << what;
    }
}

GRADED_TEST(Worksheet8Hidden, VolumeSameForRelabelledCorners, 2,
            "Relabelling the corners by an even permutation (x1 x2 x3 -> x2 x3 x1, or x0 x1 -> x1 x0 with x2 x3 -> "
            "x3 x2) keeps the signed volume, so it must only relabel the moves: every corner's gradient is its own "
            "opposite face's.",
            grading::hidden()) {
    Random rnd(893);
    const std::array<std::array<int, 4>, 3> evens{{{0, 2, 3, 1}, {1, 0, 3, 2}, {2, 3, 0, 1}}};
    for (int i = 0; i < 300; ++i) {
        const Tet t = checks::randomTet(rnd);
        const std::array<int, 4>& order = evens[static_cast<std::size_t>(i % 3)];
        Tet r = t;
        for (int j = 0; j < 4; ++j) {
            r.x[j] = t.x[order[j]];
            r.w[j] = t.w[order[j]];
        }
        const VolumeCorrection d = checks::solve(t), e = checks::solve(r);
        const std::string what = tetText(t) + correctionText(d) + "\n  relabelled (" + std::to_string(order[0]) +
                                 std::to_string(order[1]) + std::to_string(order[2]) + std::to_string(order[3]) +
                                 "):" + correctionText(e);
        double moves = 0.0, gap = 0.0;
        for (int j = 0; j < 4; ++j) {
            moves += d.dx[order[j]].norm();
            gap += (e.dx[j] - d.dx[order[j]]).norm();
        }
        ASSERT_GT(moves, 0.0) << "nothing moved" << what;
        ASSERT_LE(gap, 1e-10 * moves + 100.0 * kRounding * checks::tetSize(t))
            << "the moves changed with the corners relabelled" << what;
    }
}

GRADED_TEST(Worksheet8Hidden, VolumeFollowsRigidMotion, 1,
            "Turning and moving the whole tetrahedron as one must turn its moves along and keep dlambda.",
            grading::hidden()) {
    Random rnd(894);
    for (int i = 0; i < 300; ++i) {
        Tet t = checks::randomTet(rnd);
        t.h = 0.01;
        t.compliance = rnd.uniform(0.0, 1.0) * 1e-4;
        const Quat R = rnd.rotation();
        const Vec3 shift = rnd.inBox(5.0);
        Tet m = t;
        for (Vec3& x : m.x) x = carried(x, R, shift);
        const VolumeCorrection d = checks::solve(t), e = checks::solve(m);
        const std::string what = tetText(t) + correctionText(d) + "\n  moved:" + correctionText(e);
        double moves = 0.0, gap = 0.0;
        for (int j = 0; j < 4; ++j) {
            moves += d.dx[j].norm();
            gap += (R * d.dx[j] - e.dx[j]).norm();
        }
        ASSERT_GT(moves, 0.0) << "nothing moved" << what;
        // The moved corners lie up to 10 m out: V rounds against their cube.
        ASSERT_LE(gap, 1e-9 * moves + 1e-9 * checks::tetSize(t)) << "the moves did not turn along" << what;
    }
}

GRADED_TEST(Worksheet8Hidden, VolumeIterationsReachBalance, 2,
            "Projecting a tetrahedron over and over with lambda summed must converge to the XPBD balance "
            "C + alpha~ lambda = 0 (the pressure lambda / h^2 against the compliance), with each step's lambda "
            "carried to the next projection.",
            grading::hidden()) {
    Random rnd(895);
    for (int i = 0; i < 100; ++i) {
        Tet t = checks::randomTet(rnd);
        double sum = 0.0;
        for (int j = 0; j < 4; ++j) sum += t.w[j] * checks::volumeGradient(t.x, j).squaredNorm();
        t.h = 0.01;
        t.compliance = sum * rnd.uniform(0.2, 5.0) * t.h * t.h;  // alpha~ comparable to sum w |g|^2
        const double alphaTilde = t.compliance / (t.h * t.h);
        t.lambda = 0.0;
        const Tet start = t;
        for (int k = 0; k < 40; ++k) {
            const VolumeCorrection d = checks::solve(t);
            t.x = checks::moved(t.x, d);
            t.lambda += d.dlambda;
        }
        const double C0 = tetrahedronVolume(start.x) - start.rest, C = tetrahedronVolume(t.x) - t.rest;
        // Each projection removes the balance's error to first order; the rest shrinks geometrically,
        // far below a millionth of the start's after 40 projections.
        ASSERT_LE(std::abs(C + alphaTilde * t.lambda), 1e-6 * std::abs(C0))
            << "after 40 projections C + alpha~ lambda = " << C + alphaTilde * t.lambda << " m^3 (C = " << C
            << ", lambda = " << t.lambda << ", alpha~ = " << alphaTilde << "); from C = " << C0 << tetText(start);
        ASSERT_LT(std::abs(C), std::abs(C0)) << "the volume error did not shrink" << tetText(start);
    }
}

GRADED_TEST(Worksheet8Hidden, SphereAndBoxFollowRigidMotion, 2,
            "Turning and moving a sphere or a box together with the particle must turn and move the answer along "
            "(the box's orientation is part of the box).",
            grading::hidden()) {
    Random rnd(896);
    int moves = 0;
    for (int i = 0; i < 300; ++i) {
        const Quat R = rnd.rotation();
        const Vec3 shift = rnd.inBox(3.0);
        const double r = rnd.uniform(0.005, 0.1);
        if (i % 2 == 0) {
            const Vec3 centre = rnd.inBox(2.0);
            const double radius = rnd.uniform(0.1, 2.0);
            const Vec3 p = centre + rnd.uniform(0.05, 1.5) * (radius + r) * rnd.direction();
            const Vec3 a = projectParticleSphere(p, r, centre, radius);
            const Vec3 b = projectParticleSphere(carried(p, R, shift), r, carried(centre, R, shift), radius);
            moves += (a - p).norm() > 0.0;
            ASSERT_LE((carried(a, R, shift) - b).norm(), 1e-10 * (1.0 + centre.norm() + radius + shift.norm()))
                << "sphere: the answer " << str(a) << " did not move along (" << str(b) << ")\n  particle at " << str(p)
                << ", r " << r << "; sphere at " << str(centre) << ", radius " << radius;
        } else {
            const checks::Box box = checks::randomBox(rnd);
            Vec3 q;
            for (int k = 0; k < 3; ++k) q[k] = rnd.uniform(-1.0, 1.0) * (box.half[k] + 2.0 * r);
            const Vec3 p = box.world(q);
            checks::Box turned = box;
            turned.centre = carried(box.centre, R, shift);
            turned.orientation = (R * box.orientation).normalized();
            const Vec3 a = projectParticleBox(p, r, box.centre, box.orientation, box.half);
            const Vec3 b = projectParticleBox(carried(p, R, shift), r, turned.centre, turned.orientation, turned.half);
            moves += (a - p).norm() > 0.0;
            ASSERT_LE((carried(a, R, shift) - b).norm(), 1e-10 * (1.0 + box.centre.norm() + box.half.norm() + shift.norm()))
                << "box: the answer " << str(a) << " did not move along (" << str(b) << ")\n  particle at " << str(p)
                << ", r " << r << checks::boxText(box);
        }
    }
    EXPECT_GT(moves, 0) << "no particle was ever pushed out";
}

GRADED_TEST(Worksheet8Hidden, ChainOfUnequalMassesReachesStaticStretch, 2,
            "A hanging XPBD chain of alternately light and heavy particles, with another step and compliance, rests "
            "with each link stretched by alpha T, T the weight of the particles below it: the moves must be "
            "weighted by each particle's own inverse mass, and alpha~ = alpha / h^2 at any h.",
            grading::hidden(), grading::timeLimit(30)) {
    PhysicsEngine& e = engine;
    e.setRequiredStages(kSoftStages);
    e.setTimeStep(0.005);
    e.setConstraintIterations(40);
    SoftBodies& soft = e.softBodies();
    RopeSpec r;
    r.name = "chain";
    r.segments = 8;
    r.start = Vec3(0.5, 2.0, -0.3);
    r.end = r.start - Vec3(0.0, 0.8, 0.0);
    r.compliance = 5e-4;  // m/N
    const std::size_t chain = soft.addRope(r);
    const SoftMesh& m = soft.meshes[chain];
    for (std::uint32_t i = m.first + 1; i < m.first + m.count; ++i) {
        soft.mass[i] = (i - m.first) % 2 == 1 ? 0.05 : 0.2;  // kg
        soft.w[i] = 1.0 / soft.mass[i];
    }
    grading::steps(e, 6000, [](int) {});  // 30 s: the chain's bounce dies out
    if (HasFailure()) return;
    const double g = e.gravity().norm();
    for (int segment = 0; segment < 8; ++segment) {
        const DistanceLink& l = soft.links[m.firstLink + static_cast<std::uint32_t>(segment)];
        double below = 0.0;  // kg: the particles below the link's lower end and that end itself
        for (std::uint32_t i = std::max(l.i, l.j); i < m.first + m.count; ++i) below += soft.mass[i];
        const double tension = below * g, stretch = (soft.x[l.i] - soft.x[l.j]).norm() - l.rest;
        // Within 1 % of alpha T: what the chain's motion keeps after 30 s; the mistakes caught move
        // the rest shape by tens of percents.
        ASSERT_NEAR(stretch, r.compliance * tension, 0.01 * r.compliance * tension)
            << "link " << segment << " from the top stretched by " << stretch << " m; alpha T = " << r.compliance << " m/N x "
            << tension << " N";
    }
}

}  // namespace
}  // namespace gpl
