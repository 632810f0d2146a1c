// The cloth study against theory: the functions ./lab bench cloth prints are the ones tested here,
// with the reference hooks, on the study's own hanging cloth (12 x 12 particles). Nothing is timed.
#include "cloth_study.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gpl::study {
namespace {

// The study's hanging cloth (cloth_main.cpp): 12 x 12 particles, 1 m square, 1 kg.
constexpr int kN = 12;
constexpr double kSide = 1.0, kMass = 1.0;

const ClothMethod kPbd{"PBD k=1", SoftMethod::PBD, 1.0, 0.0};
const ClothMethod kRigidXpbd{"XPBD a=0", SoftMethod::XPBD, 1.0, 0.0};
const ClothMethod kSoftXpbd{"XPBD soft", SoftMethod::XPBD, 1.0, kSoftCompliance};

Settled hang(const ClothMethod& m, double h, int iterations) {
    return settleHanging(hangingClothSpec(kN, kSide, kMass, m), h, iterations);
}

TEST(ClothStudy, ChainTheoryIsTensionTimesCompliance) {
    // 12 x 12 particles of 1/144 kg: the top link holds 11 of them, 11/144 x 9.81 N, and stretches by
    // that times 0.02 m/N over a rest length of 1/11 m.
    const ChainStretch c = chainStretch(kN, kSide, kMass, 0.02);
    EXPECT_NEAR(c.largest, 11.0 / 144.0 * 9.81 * 0.02 * 11.0, 1e-12);
    // The mean vertical link holds n/2 = 6 particles; the horizontal half of the links none.
    EXPECT_NEAR(c.mean, 0.5 * 6.0 / 144.0 * 9.81 * 0.02 * 11.0, 1e-12);
}

TEST(ClothStudy, XpbdSettledStretchIsTheMaterialsWhateverTheIterations) {
    const ChainStretch theory = chainStretch(kN, kSide, kMass, kSoftCompliance);
    for (int n : {16, 32, 64}) {
        const Settled s = hang(kSoftXpbd, 1.0 / 60.0, n);
        ASSERT_TRUE(s.finite) << n << " iterations";
        // The shear and bend links, 100 times softer than the stretch links, carry about 3 % of the
        // weight (two shear diagonals per column and row at half the vertical stiffness each, and the
        // bend links across two rows): 5 % leaves room for them and for the averaged sway.
        EXPECT_NEAR(s.largest, theory.largest, 0.05 * theory.largest) << n << " iterations";
    }
}

TEST(ClothStudy, XpbdSettledStretchIsTheMaterialsWhateverTheTimeStep) {
    const ChainStretch theory = chainStretch(kN, kSide, kMass, kSoftCompliance);
    for (int perSecond : {60, 120, 240}) {
        const Settled s = hang(kSoftXpbd, 1.0 / perSecond, 16);
        ASSERT_TRUE(s.finite) << "h = 1/" << perSecond;
        // As above: the softer links' share of the weight.
        EXPECT_NEAR(s.largest, theory.largest, 0.05 * theory.largest) << "h = 1/" << perSecond;
    }
}

TEST(ClothStudy, PbdStretchFallsWithTheIterations) {
    double previous = hang(kPbd, 1.0 / 60.0, 1).largest;
    for (int n : {2, 4, 8, 16, 32}) {
        const double now = hang(kPbd, 1.0 / 60.0, n).largest;
        // PBD leaves each Gauss-Seidel mode of factor t with t^n / (1 - t^n) of its load as stretch;
        // doubling n multiplies that by t^n / (1 + t^n) < 1/2. 0.6 allows for the sway left in the
        // average.
        EXPECT_LT(now, 0.6 * previous) << n << " iterations";
        previous = now;
    }
}

TEST(ClothStudy, PbdStretchFallsAsTheTimeStepSquared) {
    // With alpha = 0 the Gauss-Seidel sweeps do not depend on h, and the multipliers at rest are h^2
    // times the tensions: at a fixed iteration count PBD's settled stretch goes as h^2, halving h
    // quarters it. 5 % allows for the sway left in the average.
    double previous = hang(kPbd, 1.0 / 30.0, 16).largest;
    for (int perSecond : {60, 120, 240}) {
        const double now = hang(kPbd, 1.0 / perSecond, 16).largest;
        EXPECT_NEAR(now / previous, 0.25, 0.05 * 0.25) << "h = 1/" << perSecond;
        previous = now;
    }
}

TEST(ClothStudy, XpbdWithComplianceZeroIsPbdWithStiffnessOne) {
    // alpha = 0 makes XPBD's projection PBD's with stiffness 1, whose per-iteration share
    // 1 - (1 - 1)^(1/n) is 1: the same arithmetic, the same figures.
    for (int n : {1, 4}) {
        const Settled pbd = hang(kPbd, 1.0 / 60.0, n);
        const Settled xpbd = hang(kRigidXpbd, 1.0 / 60.0, n);
        EXPECT_DOUBLE_EQ(xpbd.largest, pbd.largest) << n << " iterations";
        EXPECT_DOUBLE_EQ(xpbd.mean, pbd.mean) << n << " iterations";
    }
}

TEST(ClothStudy, ClothDroppedOnTheSphereEndsNoStepInsideIt) {
    // The study's drop beside Bullet, 64 x 64 particles, friction 0.5: the sweeps end with every
    // contact pushed out and friction moving particles only along the plane of their last push, and
    // a particle the links pull into the sphere from beyond its contacts is pushed out after the
    // sweeps, so no particle ends a step deeper than the rounding of a push (a millionth of its
    // radius).
    const SphereDrop d;
    const DropRun run = dropOnSphere(d);
    ASSERT_TRUE(run.finite);
    EXPECT_LE(run.deepest, 1e-6 * d.radius);
}

TEST(ClothStudy, TheMeasuresReadPositions) {
    SphereDrop d;
    d.sphereRadius = 0.5;
    d.radius = 0.01;
    // A particle 0.5 m from the centre lies its own radius inside the sphere; one 1 m away, not at all.
    EXPECT_NEAR(penetration({Vec3(0.0, 0.5, 0.0), Vec3(1.0, 0.0, 0.0)}, d), 0.01, 1e-15);
    EXPECT_EQ(penetration({Vec3(0.0, 2.0, 0.0)}, d), 0.0);
    DistanceLink a, b;
    a.i = 0, a.j = 1, a.rest = 1.0;
    b.i = 1, b.j = 2, b.rest = 2.0;
    double largest = 0.0, mean = 0.0;
    linkStretch({Vec3::Zero(), Vec3(1.1, 0.0, 0.0), Vec3(3.1, 0.0, 0.0)}, {a, b}, largest, mean);
    EXPECT_NEAR(largest, 0.1, 1e-12);
    EXPECT_NEAR(mean, 0.05, 1e-12);
    EXPECT_EQ(median({3.0, 1.0, 2.0}), 2.0);
}

#ifdef GPL_BARE_XPBD  // bench/instructor/bare_xpbd.cpp, in an instructor's tree
TEST(ClothStudy, BareXpbdSweepsMoveTheClothAsTheProjectionDoes) {
    // The soft hanging cloth (pinned top row, compliant links) half a second into its fall, stretched,
    // then predicted: the bare sweeps and the engine's projection start from the same positions.
    const double h = 1.0 / 60.0;
    const int iterations = 10;
    SoftBodies soft;
    soft.setThreads(1);
    soft.addCloth(hangingClothSpec(kN, kSide, kMass, kSoftXpbd));
    const Vec3 g(0.0, -9.81, 0.0);
    for (int s = 0; s < 30; ++s) {
        soft.predict(h, g, s * h);
        soft.project(h, iterations, {});
        soft.updateVelocities(h);
    }
    soft.predict(h, g, 30 * h);
    std::vector<Vec3> bare = soft.p, fewer = soft.p;
    std::vector<DistanceLink> links = soft.links, fewerLinks = soft.links;
    bareXpbdSweeps(bare, soft.w, links, h, iterations);
    bareXpbdSweeps(fewer, soft.w, fewerLinks, h, iterations - 1);
    soft.project(h, iterations, {});
    // The same arithmetic in the same order: equal to rounding (1e-12 of the spacing); one sweep
    // fewer leaves the stretched cloth's particles that far apart, which shows the check can fail.
    const double tolerance = 1e-12 * kSide / (kN - 1);
    int fewerApart = 0;
    for (std::size_t i = 0; i < bare.size(); ++i) {
        EXPECT_LE((bare[i] - soft.p[i]).norm(), tolerance) << "particle " << i;
        if ((fewer[i] - soft.p[i]).norm() > tolerance) ++fewerApart;
    }
    // Every particle but the pinned top row moves in the tenth sweep.
    EXPECT_EQ(fewerApart, kN * (kN - 1));
    for (std::size_t k = 0; k < links.size(); ++k) {
        EXPECT_NEAR(links[k].lambda, soft.links[k].lambda, 1e-12 * std::abs(soft.links[k].lambda)) << "link " << k;
    }
}
#endif

}  // namespace
}  // namespace gpl::study
