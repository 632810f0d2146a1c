// Worksheet 7 autograder: friction and resting contact. The kernels are called directly on pairs of
// turning bodies drawn from a fixed seed. The prepared point must hold the contact's geometry and the
// inverse effective masses of closed forms (a ball at a lever arm, a push through both centres of
// mass), and the bounce's target only above the resting speed. The impulses get a point prepared
// here and must do what the sums of sequential impulses do: reach the target (stop the approach or
// bounce), keep the normal sum >= 0 while applying its change, stop the slip of two balls or slide
// with mu_d lambda_n against it, stay in the Coulomb cone, never add kinetic energy. Whole scenes
// check the closed forms: a block on an incline stays below atan(mu_s) and slides at
// g (sin - mu_d cos) above it, a sliding ball ends rolling at 5/7 of its speed after 2 v0 / (7 mu g),
// a box and a small stack rest without drift or jitter.
#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "friction.h"
#include "graded.h"

namespace gpl {
namespace {

using checks::pointOf;
using checks::Random;
using checks::str;
using checks::Touch;
using checks::touchText;

class Worksheet7 : public checks::ContactsTest {};

// Quantities computed in a few operations round to ~1e-16 of their size; 1e-12 of it allows any
// equivalent formula or order of operations, while every mistake tested here is off by percents.
constexpr double kRounding = 1e-12;

double speedScale(const Touch& t) {
    double s = 1.0;
    for (const Body* b : {&t.a, &t.b}) {
        s += b->velocity.norm() + b->angularVelocity.norm() * (1.0 + (t.contact.points[0] - b->position).norm());
    }
    return s;
}

double normalVelocity(const Touch& t) { return checks::relativeAt(t.a, t.b, t.contact.points[0]).dot(t.contact.normal); }

// The kernels at the touch's point, prepared in the tests' own way (friction.h: pointOf()).
void normalImpulse(Touch& t) { applyNormalImpulse(pointOf(t), t.a, t.b, t.sum); }
void frictionImpulse(Touch& t) { applyFrictionImpulse(pointOf(t), t.a, t.b, t.sum); }

// Point k of the touch's contact as the student's prepareContactPoint() prepares it.
ContactPoint prepared(const Touch& t, int k = 0) {
    return prepareContactPoint(t.contact, k, t.a, t.b, checks::inverseWorldInertia(t.a),
                               checks::inverseWorldInertia(t.b), t.sum.approach);
}

std::string pointText(const ContactPoint& c) {
    return "\n  prepared: p " + str(c.p) + ", r_a " + str(c.ra) + ", r_b " + str(c.rb) + ", n " + str(c.n.d) + ", t1 " +
           str(c.t1.d) + ", t2 " + str(c.t2.d) + ", K_n " + formatNumber(c.n.K) + ", K_t1 " + formatNumber(c.t1.K) +
           ", K_t2 " + formatNumber(c.t2.K) + ", target " + formatNumber(c.target) + ", mu_s " +
           formatNumber(c.staticFriction) + ", mu_d " + formatNumber(c.friction);
}

// The slip of the material points at the contact: the tangential part of their relative velocity (m/s).
Vec3 slipOf(const Touch& t) {
    const Vec3 u = checks::relativeAt(t.a, t.b, t.contact.points[0]);
    return u - u.dot(t.contact.normal) * t.contact.normal;
}

// A touch whose points approach along the normal (sign -1) or separate (+1) by at least 0.1 m/s.
Touch touchMoving(Random& rnd, int i, double sign) {
    for (;;) {
        Touch t = checks::randomTouch(rnd, i);
        if (normalVelocity(t) * sign < 0.0) {
            t.contact.normal = -t.contact.normal;
            t.tangent = -t.tangent;  // the basis stays right-handed about the new normal
        }
        if (normalVelocity(t) * sign > 0.1) return t;
    }
}

// Two balls touching (friction.h: ballsTouching()) whose points slip by at least 0.1 m/s and also
// move along the normal.
Touch ballsSlipping(Random& rnd, int i) {
    for (;;) {
        Touch t = checks::ballsTouching(rnd, i);
        if (slipOf(t).norm() > 0.1 && std::abs(normalVelocity(t)) > 0.1) return t;
    }
}

// A touch that slips by at least 0.1 m/s.
Touch touchSlipping(Random& rnd, int i) {
    for (;;) {
        Touch t = checks::randomTouch(rnd, i);
        if (slipOf(t).norm() > 0.1) return t;
    }
}

bool changed(const Touch& now, const Touch& before) {
    return now.a.velocity != before.a.velocity || now.b.velocity != before.b.velocity ||
           now.a.angularVelocity != before.a.angularVelocity || now.b.angularVelocity != before.b.angularVelocity;
}

// ---- prepareContactPoint() -------------------------------------------------------------------------

GRADED_TEST(Worksheet7, PreparedPointGeometry, 2,
            "prepareContactPoint() for point k of a contact: p is contact.points[k], r_a = p - x_a and "
            "r_b = p - x_b (from each centre of mass to the point), n the contact's normal, t1 and t2 unit "
            "tangents across n and across each other (tangentBasis(n) gives them), mu_s and mu_d the contact's "
            "(worksheet 7, assignment 2).") {
    Random rnd(731);
    for (int i = 0; i < 300; ++i) {
        Touch t = checks::randomTouch(rnd, i);
        t.contact.pointCount = 1 + i % 4;
        for (int k = 1; k < t.contact.pointCount; ++k) t.contact.points[k] = t.contact.points[0] + rnd.inBox(0.3);
        const int k = i % t.contact.pointCount;
        const Vec3& p = t.contact.points[k];
        const Vec3& n = t.contact.normal;
        const ContactPoint c = prepared(t, k);
        const std::string what = "\n  point " + std::to_string(k) + " of " + std::to_string(t.contact.pointCount) +
                                 pointText(c) + touchText(t);
        const double tol = 100.0 * kRounding * (1.0 + p.norm() + t.a.position.norm() + t.b.position.norm());
        ASSERT_LE((c.p - p).norm(), tol) << "p is not the contact's point " << str(p) << what;
        ASSERT_LE((c.n.d - n).norm(), kRounding) << "n is not the contact's normal " << str(n) << what;
        ASSERT_LE((c.ra - (p - t.a.position)).norm(), tol) << "r_a must be p - x_a = " << str(p - t.a.position) << what;
        ASSERT_LE((c.rb - (p - t.b.position)).norm(), tol) << "r_b must be p - x_b = " << str(p - t.b.position) << what;
        ASSERT_NEAR(c.t1.d.norm(), 1.0, kRounding) << "t1 must be a unit vector" << what;
        ASSERT_NEAR(c.t2.d.norm(), 1.0, kRounding) << "t2 must be a unit vector" << what;
        ASSERT_LE(std::abs(c.t1.d.dot(n)) + std::abs(c.t2.d.dot(n)) + std::abs(c.t1.d.dot(c.t2.d)), 3.0 * kRounding)
            << "t1, t2 and n must be perpendicular to each other" << what;
        ASSERT_EQ(c.staticFriction, t.contact.staticFriction) << "mu_s is the contact's" << what;
        ASSERT_EQ(c.friction, t.contact.friction) << "mu_d is the contact's" << what;
    }
}

GRADED_TEST(Worksheet7, EffectiveMassOfBalls, 3,
            "prepareContactPoint() for two balls (solid, I = 2/5 m R^2) touching at any point: the inverse "
            "effective mass along a unit d is K(d) = 1/m_a + 1/m_b + |r_a x d|^2 / I_a + |r_b x d|^2 / I_b, "
            "for d = n, t1 and t2. K needs the angular terms, each along its own direction.") {
    Random rnd(732);
    for (int i = 0; i < 300; ++i) {
        Touch t = checks::ballsTouching(rnd, i);
        t.contact.points[0] += rnd.inBox(0.5);  // anywhere near: lever arms across the normal too
        const ContactPoint c = prepared(t);
        const auto closed = [&](const Vec3& d) {  // 1/kg
            double K = 0.0;
            for (const Body* ball : {&t.a, &t.b}) {
                if (ball->isStatic()) continue;
                const double I = 0.4 * ball->mass * ball->radius * ball->radius;  // kg m^2
                K += 1.0 / ball->mass + (t.contact.points[0] - ball->position).cross(d).squaredNorm() / I;
            }
            return K;
        };
        for (const auto& [name, K, d] :
             {std::tuple{"K_n", c.n.K, c.n.d}, std::tuple{"K_t1", c.t1.K, c.t1.d}, std::tuple{"K_t2", c.t2.K, c.t2.d}}) {
            const double expected = closed(d);
            ASSERT_NEAR(K, expected, 1e-10 * expected)
                << name << " along " << str(d)
                << ": expected 1/m_a + 1/m_b + |r_a x d|^2 / I_a + |r_b x d|^2 / I_b = " << expected << " 1/kg"
                << pointText(c) << touchText(t);
        }
    }
}

GRADED_TEST(Worksheet7, EffectiveMassThroughCentres, 2,
            "prepareContactPoint() where both centres of mass lie on the normal through the point (a push through "
            "the centres, turning neither body): K_n = 1/m_a + 1/m_b, whatever the shapes and orientations; at a "
            "point at both centres of mass, K is that along the tangents too.") {
    Random rnd(733);
    for (int i = 0; i < 200; ++i) {
        Touch t = checks::randomTouch(rnd, i);
        const Vec3 p = t.contact.points[0], n = t.contact.normal;
        const bool atCentres = i % 4 == 0;
        t.a.position = atCentres ? p : Vec3(p - rnd.uniform(0.1, 2.0) * n);
        t.b.position = atCentres ? p : Vec3(p + rnd.uniform(0.1, 2.0) * n);
        const ContactPoint c = prepared(t);
        const double expected = t.a.invMass + t.b.invMass;  // 1/kg
        ASSERT_NEAR(c.n.K, expected, 1e-10 * expected)
            << "K_n of a push through both centres of mass must be 1/m_a + 1/m_b = " << expected << " 1/kg"
            << pointText(c) << touchText(t);
        if (!atCentres) continue;
        ASSERT_NEAR(c.t1.K, expected, 1e-10 * expected)
            << "K_t1 at the centres of mass must be 1/m_a + 1/m_b = " << expected << " 1/kg" << pointText(c)
            << touchText(t);
        ASSERT_NEAR(c.t2.K, expected, 1e-10 * expected)
            << "K_t2 at the centres of mass must be 1/m_a + 1/m_b = " << expected << " 1/kg" << pointText(c)
            << touchText(t);
    }
}

GRADED_TEST(Worksheet7, EffectiveMassOfTurnedBoxes, 2,
            "prepareContactPoint() for turned boxes and balls at any point: K along n, t1 and t2 is the change of the "
            "relative velocity along that direction per unit impulse along it, with the world inverse inertias "
            "invIa, invIb you are given (the body's own invInertia is in its own frame).") {
    Random rnd(734);
    for (int i = 0; i < 300; ++i) {
        const Touch t = checks::randomTouch(rnd, i);
        const ContactPoint c = prepared(t);
        const Vec3& p = t.contact.points[0];
        for (const auto& [name, K, d] :
             {std::tuple{"K_n", c.n.K, c.n.d}, std::tuple{"K_t1", c.t1.K, c.t1.d}, std::tuple{"K_t2", c.t2.K, c.t2.d}}) {
            const double expected = checks::inverseMassAlong(t.a, t.b, p, d);
            ASSERT_NEAR(K, expected, 1e-10 * expected)
                << name << " along " << str(d) << ": expected " << expected << " 1/kg" << pointText(c) << touchText(t);
        }
    }
}

GRADED_TEST(Worksheet7, PreparedAxesMeasureAndTurnAsThePoint, 2,
            "prepareContactPoint(): each axis n, t1, t2 (unit direction d) holds r_a x d and r_b x d, with which the "
            "sweeps read the velocity of the material points at p along d, d . (v_b - v_a) + (r_b x d) . omega_b - "
            "(r_a x d) . omega_a, and I_a^-1 (r_a x d), I_b^-1 (r_b x d) with the world inverse inertias invIa, invIb you "
            "are given: how much a unit impulse along d at p turns each body (zero for a static body).") {
    Random rnd(738);
    for (int i = 0; i < 300; ++i) {
        const Touch t = checks::randomTouch(rnd, i);
        const ContactPoint c = prepared(t);
        const Vec3& p = t.contact.points[0];
        const Vec3 ra = p - t.a.position, rb = p - t.b.position;
        const Mat3 invIa = checks::inverseWorldInertia(t.a), invIb = checks::inverseWorldInertia(t.b);
        const Vec3 u = checks::relativeAt(t.a, t.b, p);  // m/s
        for (const auto& [name, axis] : {std::pair{"n", &c.n}, std::pair{"t1", &c.t1}, std::pair{"t2", &c.t2}}) {
            const Vec3& d = axis->d;
            const std::string what = std::string("\n  axis ") + name + ": d " + str(d) + ", r_a x d " + str(axis->raXd) +
                                     ", r_b x d " + str(axis->rbXd) + ", I_a^-1 (r_a x d) " + str(axis->invIaRaXd) +
                                     ", I_b^-1 (r_b x d) " + str(axis->invIbRbXd) + pointText(c) + touchText(t);
            ASSERT_NEAR(d.norm(), 1.0, kRounding) << "the axis's direction d must be a unit vector" << what;
            if (axis == &c.n) {
                ASSERT_LE((d - t.contact.normal).norm(), kRounding)
                    << "the normal axis's d must be the contact's normal " << str(t.contact.normal) << what;
            }
            // Rounding of a few products of the lever arms, speeds and inverse inertias, relative to their size.
            const double speed = 1.0 + t.a.velocity.norm() + t.b.velocity.norm() +
                                 (ra.norm() + rb.norm()) * (t.a.angularVelocity.norm() + t.b.angularVelocity.norm());
            const double along = d.dot(t.b.velocity - t.a.velocity) + axis->rbXd.dot(t.b.angularVelocity) -
                                 axis->raXd.dot(t.a.angularVelocity);  // m/s
            ASSERT_NEAR(along, u.dot(d), 1e-10 * speed)
                << "the velocity along d read with the axis, d . (v_b - v_a) + (r_b x d) . omega_b - (r_a x d) . omega_a, "
                   "must be that of the material points at p, u . d = "
                << u.dot(d) << " m/s, not " << along << " m/s: r_a x d must be " << str(ra.cross(d)) << ", r_b x d "
                << str(rb.cross(d)) << what;
            for (const auto& [body, got, expected, scale] :
                 {std::tuple{"a", axis->invIaRaXd, Vec3(invIa * ra.cross(d)), invIa.norm() * ra.norm()},
                  std::tuple{"b", axis->invIbRbXd, Vec3(invIb * rb.cross(d)), invIb.norm() * rb.norm()}}) {
                ASSERT_LE((got - expected).norm(), 1e-10 * (1.0 + scale))
                    << "a unit impulse along d at p turns body " << body << " by I^-1 (r x d) = " << str(expected)
                    << " rad/s (its world inverse inertia, given), not " << str(got) << what;
            }
        }
    }
}

GRADED_TEST(Worksheet7, BounceTargetOnlyAboveRestingSpeed, 2,
            "prepareContactPoint(): a point whose approach when the stage began is faster than kRestingSpeed "
            "(approach < -kRestingSpeed) is to leave at -e approach; a slower one, or one that separates, is resting "
            "contact and is to leave at 0, whatever e. Bouncing at resting speeds makes a box on the floor jitter.") {
    Random rnd(735);
    int bounced = 0, rested = 0;
    for (int i = 0; i < 300; ++i) {
        Touch t = checks::randomTouch(rnd, i);
        t.contact.restitution = rnd.uniform(0.2, 1.0);
        t.sum.approach = i % 3 == 0   ? -rnd.uniform(1.0, 1.2) * kRestingSpeed   // just faster
                         : i % 3 == 1 ? -rnd.uniform(0.0, 0.98) * kRestingSpeed  // slower
                                      : rnd.uniform(-5.0, 2.0);
        const ContactPoint c = prepared(t);
        const bool bounces = t.sum.approach < -kRestingSpeed;
        const double expected = bounces ? -t.contact.restitution * t.sum.approach : 0.0;
        bounced += bounces;
        rested += !bounces;
        ASSERT_NEAR(c.target, expected, kRounding * (1.0 + expected))
            << "the target for an approach of " << t.sum.approach << " m/s (" << (bounces ? "faster" : "not faster")
            << " than kRestingSpeed = " << kRestingSpeed << " m/s) with e = " << t.contact.restitution << pointText(c);
    }
    ASSERT_GT(bounced * rested, 0) << "the test must see both cases";
}

// ---- applyWarmStart() ---------------------------------------------------------------------------------

GRADED_TEST(Worksheet7, WarmStartAppliesLastSums, 2,
            "applyWarmStart(): last step's sums act again at the point, lambda_n n + J_t on b and the opposite on a, "
            "as the sweeps gave them (worksheet 7, assignment 3). Use applyImpulseAtPoint() with that impulse.",
            grading::dependsOn("Worksheet6.ImpulseAtPointOffCentre")) {
    Random rnd(721);
    for (int i = 0; i < 300; ++i) {
        Touch t = checks::randomTouch(rnd, i);
        const Vec3 n = t.contact.normal;
        t.sum.normal = rnd.uniform(0.0, 5.0);
        t.sum.tangent = rnd.uniform(0.0, 1.0) * t.contact.staticFriction * t.sum.normal * rnd.perpendicular(n);
        const Touch before = t;
        applyWarmStart(pointOf(t), t.a, t.b, t.sum);
        const Vec3 j = t.sum.normal * n + t.sum.tangent;  // N s
        const Vec3 p = t.contact.points[0];
        for (const auto& [now, old, sign] : {std::tuple{&t.a, &before.a, -1.0}, std::tuple{&t.b, &before.b, 1.0}}) {
            if (old->isStatic()) continue;
            const Vec3 dv = sign * j / old->mass;
            const Vec3 dw = sign * checks::inverseWorldInertia(*old) * (p - old->position).cross(j);
            const double tol = 100.0 * kRounding * (speedScale(before) + dv.norm() + dw.norm());
            ASSERT_LE((now->velocity - old->velocity - dv).norm(), tol)
                << now->name << "'s velocity changed by " << str(now->velocity - old->velocity) << ", expected "
                << str(dv) << " from the sums lambda_n n + J_t = " << str(j) << touchText(before);
            ASSERT_LE((now->angularVelocity - old->angularVelocity - dw).norm(), tol)
                << now->name << "'s angular velocity changed by " << str(now->angularVelocity - old->angularVelocity)
                << ", expected " << str(dw) << touchText(before);
        }
    }
}

// ---- applyNormalImpulse() ----------------------------------------------------------------------------

GRADED_TEST(Worksheet7, NormalImpulseStopsRestingApproach, 3,
            "applyNormalImpulse() with an empty sum at a point that approaches slowly (a resting contact, target 0): "
            "afterwards the normal velocity of the two material points there is exactly 0, and the sum holds the "
            "impulse given (b's momentum changed by sum.normal n). u needs both bodies' spin, omega x r. A point that "
            "separates gets nothing: the sum never goes below 0 (worksheet 7, assignment 4).",
            grading::dependsOn("Worksheet6.ImpulseAtPointConservesMomenta")) {
    Random rnd(701);
    int changes = 0;
    for (int i = 0; i < 300; ++i) {
        const bool separating = i % 3 == 0;
        Touch t = touchMoving(rnd, i, separating ? 1.0 : -1.0);
        t.sum.approach = -rnd.uniform(0.0, 0.9 * kRestingSpeed);  // resting: no bounce
        const Touch before = t;
        normalImpulse(t);
        if (separating) {
            ASSERT_FALSE(changed(t, before) || t.sum.normal != 0.0)
                << "the point separates and the sum is empty, yet the kernel acted (sum now " << t.sum.normal
                << " N s): a contact never pulls" << touchText(before);
            continue;
        }
        changes += changed(t, before);
        const double tol = 100.0 * kRounding * speedScale(before);
        ASSERT_NEAR(normalVelocity(t), 0.0, tol)
            << "normal velocity at the point after the impulse (it was " << normalVelocity(before)
            << " m/s; a resting contact leaves at 0)" << touchText(before);
        if (!t.b.isStatic()) {
            const Vec3 given = t.b.mass * (t.b.velocity - before.b.velocity);  // N s
            ASSERT_LE((given - t.sum.normal * t.contact.normal).norm(), tol * t.b.mass)
                << "b's momentum changed by " << str(given) << " N s, but the sum says " << t.sum.normal
                << " N s along the normal" << touchText(before);
        }
    }
    EXPECT_GT(changes, 0) << "no approaching point got an impulse: applyNormalImpulse() does nothing yet";
}

GRADED_TEST(Worksheet7, NormalSumClampedNotTheStep, 3,
            "applyNormalImpulse() with a sum from earlier sweeps at a point that now separates: the sum may shrink "
            "(the step is negative) but never below 0. Where lambda_n + step >= 0 the point leaves at normal velocity "
            "0; otherwise the sum becomes 0 and the bodies get -lambda_n back. Clamp the sum, "
            "max(lambda_n + step, 0), and apply the difference; clamping the step at 0 leaves earlier sweeps' excess "
            "in for good.",
            grading::dependsOn("NormalImpulseStopsRestingApproach")) {
    Random rnd(702);
    int shrunk = 0, emptied = 0;
    for (int i = 0; i < 300; ++i) {
        Touch t = touchMoving(rnd, i, 1.0);
        t.sum.approach = -rnd.uniform(0.0, 0.9 * kRestingSpeed);
        const double w = pointOf(t).n.K;  // 1/kg
        const double vn = normalVelocity(t);
        // Earlier sweeps gave 0.3 to 3 times what the separation now takes back.
        t.sum.normal = rnd.uniform(0.3, 3.0) * vn / w;
        const Touch before = t;
        normalImpulse(t);
        const double tol = 100.0 * kRounding * speedScale(before);
        const bool stays = before.sum.normal - vn / w >= 0.0;
        const double expected = stays ? 0.0 : vn - before.sum.normal * w;  // m/s
        shrunk += stays;
        emptied += !stays;
        ASSERT_NEAR(normalVelocity(t), expected, tol)
            << "normal velocity at the point after the kernel; the sum of " << before.sum.normal << " N s "
            << (stays ? "covers the step -u_n / K_n, so the point must leave at 0"
                      : "cannot cover the step -u_n / K_n: it becomes 0 and the bodies get the whole sum back")
            << touchText(before);
        ASSERT_NEAR(t.sum.normal, stays ? before.sum.normal - vn / w : 0.0, tol / w)
            << "the sum after the kernel" << touchText(before);
    }
    ASSERT_GT(shrunk * emptied, 0) << "the test must see both cases";
}

GRADED_TEST(Worksheet7, NormalImpulseReachesTarget, 2,
            "applyNormalImpulse() at an approaching point whose prepared target is not 0 (a collision that bounces): "
            "afterwards the point leaves at exactly point.target, lambda_n' = lambda_n + (target - u_n) / K_n.",
            grading::dependsOn("NormalImpulseStopsRestingApproach")) {
    Random rnd(703);
    for (int i = 0; i < 300; ++i) {
        Touch t = touchMoving(rnd, i, -1.0);
        t.contact.restitution = rnd.uniform(0.2, 1.0);
        t.sum.approach = -rnd.uniform(1.1, 4.0) * kRestingSpeed;  // what the stage measured: it bounces
        const Touch before = t;
        const double target = pointOf(t).target;
        normalImpulse(t);
        ASSERT_NEAR(normalVelocity(t), target, 100.0 * kRounding * speedScale(before))
            << "normal velocity after the impulse; the prepared point's target is " << target << " m/s"
            << touchText(before);
    }
}

GRADED_TEST(Worksheet7, TargetKeptInLaterSweeps, 2,
            "applyNormalImpulse() runs in every sweep and adds to the sum: after the first sweep the point already "
            "leaves at its target, and a second sweep must change nothing (the step is then 0, and the sum keeps "
            "what the first gave).",
            grading::dependsOn("NormalImpulseReachesTarget")) {
    Random rnd(704);
    for (int i = 0; i < 300; ++i) {
        Touch t = touchMoving(rnd, i, -1.0);
        t.contact.restitution = rnd.uniform(0.2, 1.0);
        t.sum.approach = i % 2 == 0 ? -rnd.uniform(1.1, 4.0) * kRestingSpeed : -rnd.uniform(0.0, 0.9) * kRestingSpeed;
        const Touch before = t;
        const double target = pointOf(t).target;
        normalImpulse(t);  // the first sweep
        const double first = t.sum.normal;
        normalImpulse(t);  // the second
        const double tol = 100.0 * kRounding * speedScale(before);
        ASSERT_NEAR(normalVelocity(t), target, tol)
            << "normal velocity after two sweeps; the point must leave at its target, " << target << " m/s"
            << touchText(before);
        ASSERT_NEAR(t.sum.normal, first, tol / pointOf(t).n.K) << "the second sweep changed the sum from " << first
                                                              << " to " << t.sum.normal << " N s" << touchText(before);
    }
}

// ---- applyFrictionImpulse() --------------------------------------------------------------------------

GRADED_TEST(Worksheet7, FrictionStopsSlipOfBalls, 3,
            "applyFrictionImpulse() with a large normal sum (the point sticks) where two balls touch on the line of "
            "their centres (K the same along every tangent): the impulse stops the slip along t1 and along t2, "
            "-(u . t1 / K_t1) t1 - (u . t2 / K_t2) t2, so afterwards the whole slip is 0, the normal velocity is as "
            "it was, and the friction sum holds the impulse given (worksheet 7, assignment 5).",
            grading::dependsOn("Worksheet6.ImpulseAtPointConservesMomenta")) {
    Random rnd(711);
    for (int i = 0; i < 300; ++i) {
        Touch t = ballsSlipping(rnd, i);
        t.sum.normal = 1e6;  // N s: far inside the cone
        const Vec3 slip = slipOf(t);
        const double Kt = pointOf(t).t1.K;  // = K_t2 for balls
        const Touch before = t;
        frictionImpulse(t);
        const double tol = 100.0 * kRounding * speedScale(before);
        ASSERT_LE(slipOf(t).norm(), tol) << "the slip afterwards is " << str(slipOf(t)) << " m/s (it was " << str(slip)
                                         << ")" << touchText(before);
        ASSERT_NEAR(normalVelocity(t), normalVelocity(before), tol)
            << "friction changed the normal velocity at the point" << touchText(before);
        ASSERT_LE((t.sum.tangent + slip / Kt).norm(), tol / Kt)
            << "the friction sum afterwards; expected -u_t / K_t = " << str(Vec3(-slip / Kt)) << " N s"
            << touchText(before);
        const Vec3 given = t.b.mass * (t.b.velocity - before.b.velocity);  // N s
        ASSERT_LE((given - t.sum.tangent).norm(), tol * (1.0 + t.b.mass))
            << "b's momentum changed by " << str(given) << " N s; the friction sum is " << str(t.sum.tangent)
            << touchText(before);
    }
}

GRADED_TEST(Worksheet7, SlidingFrictionIsMuDTimesNormal, 3,
            "applyFrictionImpulse() where stopping the slip would take more than mu_s times the normal sum: the point "
            "slides, and the friction sum becomes mu_d lambda_n against the slip (mu_d, point.friction, not mu_s; "
            "lambda_n, the normal sum, not the speed). The bodies get that impulse at the point.",
            grading::dependsOn("FrictionStopsSlipOfBalls")) {
    Random rnd(712);
    for (int i = 0; i < 300; ++i) {
        Touch t = ballsSlipping(rnd, i);
        const Vec3 slip = slipOf(t);
        const Vec3 dir = slip.normalized();
        const double stop = slip.norm() / pointOf(t).t1.K;  // N s
        t.sum.normal = rnd.uniform(0.05, 0.9) * stop / t.contact.staticFriction;
        const Touch before = t;
        frictionImpulse(t);
        const Vec3 expected = -t.contact.friction * t.sum.normal * dir;
        const double tol = 100.0 * kRounding * (stop + t.sum.normal);
        ASSERT_LE((t.sum.tangent - expected).norm(), tol)
            << "friction sum " << str(t.sum.tangent) << " N s, expected -mu_d lambda_n u_t / |u_t| = " << str(expected)
            << " (stopping the slip would take " << stop
            << " N s > mu_s lambda_n = " << t.contact.staticFriction * t.sum.normal << ")" << touchText(before);
        const Vec3 given = t.b.mass * (t.b.velocity - before.b.velocity);
        ASSERT_LE((given - expected).norm(), tol * (1.0 + t.b.mass))
            << "b's momentum changed by " << str(given) << " N s, the friction sum is " << str(expected)
            << touchText(before);
    }
}

GRADED_TEST(Worksheet7, SlidingSumFromOldSumPlusStep, 2,
            "applyFrictionImpulse() at a sliding point whose friction sum from earlier sweeps points another way than "
            "the slip: the new sum is the old sum plus the impulse that would stop the slip, clamped to mu_d lambda_n "
            "along that total, not along the slip; the bodies get the new sum minus the old.",
            grading::dependsOn("SlidingFrictionIsMuDTimesNormal")) {
    Random rnd(715);
    int tried = 0;
    for (int i = 0; i < 300; ++i) {
        Touch t = ballsSlipping(rnd, i);
        const Vec3 n = t.contact.normal;
        const Vec3 dir = slipOf(t).normalized();
        const double stop = slipOf(t).norm() / pointOf(t).t1.K;  // N s
        const Vec3 oldDir = rnd.perpendicular(n);
        if (oldDir.cross(dir).norm() < 0.3) continue;  // the old sum clearly not along the slip
        ++tried;
        t.sum.tangent = rnd.uniform(0.5, 2.0) * stop * oldDir;
        const Vec3 total = t.sum.tangent - stop * dir;  // N s, before the clamp
        t.sum.normal = total.norm() / (t.contact.staticFriction * rnd.uniform(1.5, 3.0));  // it slides
        const Touch before = t;
        frictionImpulse(t);
        const Vec3 expected = t.contact.friction * t.sum.normal * total.normalized();
        const double tol = 100.0 * kRounding * (stop + before.sum.tangent.norm() + t.sum.normal);
        ASSERT_LE((t.sum.tangent - expected).norm(), tol)
            << "friction sum " << str(t.sum.tangent)
            << " N s, expected mu_d lambda_n along (old sum + step) = " << str(expected)
            << " N s (the step that stops the slip: " << str(Vec3(-stop * dir)) << " N s)" << touchText(before);
        const Vec3 given = t.b.mass * (t.b.velocity - before.b.velocity);
        ASSERT_LE((given - (expected - before.sum.tangent)).norm(), tol * (1.0 + t.b.mass))
            << "b's momentum changed by " << str(given) << " N s; the sum changed by "
            << str(Vec3(expected - before.sum.tangent)) << " N s" << touchText(before);
    }
    EXPECT_GT(tried, 30) << "too few old sums across the slip were drawn";
}

GRADED_TEST(Worksheet7, StaticFrictionHoldsUpToMuS, 2,
            "applyFrictionImpulse(): a point sticks as long as the impulse that stops its slip stays within "
            "mu_s lambda_n (static friction), even when that is more than mu_d lambda_n. Compare with "
            "point.staticFriction to decide, and only a sliding point gets mu_d.",
            grading::dependsOn("FrictionStopsSlipOfBalls")) {
    Random rnd(713);
    for (int i = 0; i < 300; ++i) {
        Touch t = ballsSlipping(rnd, i);
        t.contact.friction = 0.3;
        t.contact.staticFriction = 0.6;
        const double stop = slipOf(t).norm() / pointOf(t).t1.K;  // N s
        t.sum.normal = stop / rnd.uniform(0.35, 0.55);          // mu_d lambda_n < stop < mu_s lambda_n
        const Touch before = t;
        frictionImpulse(t);
        ASSERT_LE(slipOf(t).norm(), 100.0 * kRounding * speedScale(before))
            << "the point must stick: stopping it takes " << stop
            << " N s, within mu_s lambda_n = " << 0.6 * t.sum.normal
            << " N s (though above mu_d lambda_n = " << 0.3 * t.sum.normal << " N s)" << touchText(before);
    }
}

GRADED_TEST(Worksheet7, FrictionSumClampedWithoutSlip, 2,
            "applyFrictionImpulse() at a point that no longer slips, after the normal sum shrank: the friction "
            "sum from earlier sweeps may now lie outside the cone, |J| > mu_s lambda_n, and must be clamped to "
            "mu_d lambda_n (same direction) even though there is no slip to stop; where lambda_n has shrunk to 0 "
            "the cone is a point, and the whole sum goes back to the bodies. Clamp the sum whether or not the point "
            "slips, and whatever lambda_n is.",
            grading::dependsOn("SlidingFrictionIsMuDTimesNormal")) {
    Random rnd(716);
    for (int i = 0; i < 200; ++i) {
        Touch t = checks::randomTouch(rnd, i);
        // Both bodies at rest: the material points at the contact move alike, so nothing slips.
        for (Body* b : {&t.a, &t.b}) {
            b->velocity = Vec3::Zero();
            b->angularVelocity = Vec3::Zero();
        }
        const Vec3 n = t.contact.normal;
        const Vec3 dir = rnd.perpendicular(n);
        // Every fourth point has lost its whole normal sum: its cone is the point 0.
        const bool released = i % 4 == 0;
        t.sum.normal = released ? 0.0 : rnd.uniform(0.1, 5.0);  // N s
        t.sum.tangent = (released ? rnd.uniform(0.1, 2.0) : rnd.uniform(1.2, 3.0) * t.contact.staticFriction * t.sum.normal) *
                        dir;  // N s, outside the cone
        const Touch before = t;
        frictionImpulse(t);
        const Vec3 expected = t.contact.friction * t.sum.normal * dir;  // N s
        const double tol = 100.0 * kRounding * (1.0 + before.sum.tangent.norm());
        ASSERT_LE((t.sum.tangent - expected).norm(), tol)
            << "the friction sum after the kernel is " << str(t.sum.tangent) << " N s; outside the cone it must become "
            << "mu_d lambda_n along its own direction, " << str(expected) << " N s"
            << (released ? " (lambda_n = 0: no normal impulse holds the point, so no friction sum may stay)" : "")
            << touchText(before);
        if (!t.b.isStatic()) {
            const Vec3 given = t.b.mass * (t.b.velocity - before.b.velocity);  // N s
            ASSERT_LE((given - (t.sum.tangent - before.sum.tangent)).norm(), tol * (1.0 + t.b.mass))
                << "b's momentum changed by " << str(given) << " N s; the sum changed by "
                << str(t.sum.tangent - before.sum.tangent) << " N s" << touchText(before);
        }
    }
}

GRADED_TEST(Worksheet7, FrictionSumStaysInCone, 2,
            "applyFrictionImpulse() over many sweeps, the normal sum changing in between: the friction sum stays "
            "perpendicular to the normal and within mu_s lambda_n, and the bodies always hold exactly the sum "
            "(each call applies the new sum minus the old). Clamp the sum, not the step, against lambda_n (not "
            "the speed).",
            grading::dependsOn("SlidingFrictionIsMuDTimesNormal")) {
    Random rnd(714);
    int sliding = 0;
    for (int i = 0; i < 100; ++i) {
        Touch t = touchSlipping(rnd, i);
        if (t.b.isStatic()) continue;
        const Vec3 start = t.b.velocity;
        const Vec3 n = t.contact.normal;
        Vec3 kicks = Vec3::Zero();  // momentum given to b along the tangent plane outside the kernel (N s)
        for (int sweep = 0; sweep < 20; ++sweep) {
            t.sum.normal = rnd.uniform(0.0, 2.0) * t.b.mass;  // N s, growing or shrinking
            const Vec3 kick = rnd.inBox(1.0);                 // m/s: the other contacts' impulses
            t.b.velocity += kick;
            kicks += t.b.mass * (kick - kick.dot(n) * n);
            const Touch before = t;
            frictionImpulse(t);
            const double size = t.sum.tangent.norm();
            sliding += t.sum.normal > 0.0 && std::abs(size - t.contact.friction * t.sum.normal) < 1e-9 * size;
            ASSERT_LE(size, t.contact.staticFriction * t.sum.normal * (1.0 + kRounding) + kRounding)
                << "sweep " << sweep << ": the friction sum " << str(t.sum.tangent)
                << " N s is outside the cone mu_s lambda_n = " << t.contact.staticFriction * t.sum.normal << " N s"
                << touchText(before);
            ASSERT_LE(std::abs(t.sum.tangent.dot(n)), kRounding * (1.0 + size))
                << "sweep " << sweep << ": the friction sum " << str(t.sum.tangent) << " has a part along the normal"
                << touchText(before);
            const Vec3 held = t.b.mass * (t.b.velocity - start) - kicks;  // b's momentum from the kernel
            const Vec3 heldTangent = held - held.dot(n) * n;
            ASSERT_LE((heldTangent - t.sum.tangent).norm(), 1e3 * kRounding * (1.0 + t.b.mass * 20.0))
                << "sweep " << sweep << ": b holds " << str(heldTangent) << " N s of friction from the kernel, the sum says "
                << str(t.sum.tangent) << touchText(before);
        }
    }
    EXPECT_GT(sliding, 0) << "no friction sum ever reached the edge of the cone";
}

GRADED_TEST(Worksheet7, FrictionNeverAddsEnergy, 2,
            "applyFrictionImpulse() from an empty friction sum: friction takes kinetic energy (translation and "
            "rotation) away, or none; it never adds any. Along each tangent the impulse acts against the slip, never "
            "along it, and is no larger than the one that stops it.",
            grading::dependsOn("FrictionStopsSlipOfBalls")) {
    Random rnd(715);
    int changes = 0;
    for (int i = 0; i < 300; ++i) {
        Touch t = touchSlipping(rnd, i);
        const Vec3 dir = slipOf(t).normalized();
        const double stop = slipOf(t).norm() / checks::inverseMassAlong(t.a, t.b, t.contact.points[0], dir);
        t.sum.normal = rnd.uniform(0.1, 4.0) * stop;
        const Touch before = t;
        const double k0 = checks::energyOf(t.a) + checks::energyOf(t.b);
        frictionImpulse(t);
        const double k1 = checks::energyOf(t.a) + checks::energyOf(t.b);
        changes += changed(t, before);
        // Energies of up to ~1e3 J round to ~1e-13 J; 1e-11 of them allows any order of operations.
        ASSERT_LE(k1, k0 + 1e-11 * (1.0 + k0)) << "kinetic energy rose from " << k0 << " J to " << k1 << " J"
                                               << touchText(before);
    }
    EXPECT_GT(changes, 0) << "friction never changed a velocity: applyFrictionImpulse() does nothing yet";
}

// ---- In the engine -----------------------------------------------------------------------------------

// A plane tilted by `slope` (rad) about z (rising along +x) and a box of half extents 0.3 x 0.2 x 0.3 m
// resting on it, both of the coefficients mu_s and mu_d (so the pair's are the same).
void incline(PhysicsEngine& e, double slope, double mus, double mud) {
    e.setRequiredStages(checks::frictionStages());
    const Vec3 normal(-std::sin(slope), std::cos(slope), 0.0);
    e.add(plane("incline", normal).rough(mus, mud));
    const Vec3 up(std::cos(slope), std::sin(slope), 0.0);
    e.add(box("block", {0.3, 0.2, 0.3}, 2.0)
              .at(2.0 * up + 0.2 * normal)
              .rotated(Quat(Eigen::AngleAxisd(slope, Vec3::UnitZ())))
              .rough(mus, mud)
              .bouncy(0.0));
}

GRADED_TEST(Worksheet7, BlockStaysOnGentleIncline, 3,
            "A block at rest on an incline whose slope is below atan(mu_s) stays where it is: static friction holds "
            "it (its speed stays ~0, it moves less than a millimetre in 3 s). The friction stage needs the prepared "
            "point and both impulses, the normal sum for lambda_n and the friction sum within mu_s lambda_n.",
            grading::dependsOn("FrictionStopsSlipOfBalls"), grading::dependsOn("NormalImpulseStopsRestingApproach"),
            grading::dependsOn("EffectiveMassOfTurnedBoxes")) {
    for (const double degrees : {10.0, 20.0, 25.0}) {
        PhysicsEngine& e = engine;
        e.clear();
        const double slope = degrees * M_PI / 180.0;
        incline(e, slope, 0.6, 0.5);  // tan 25 = 0.47 < 0.6
        const Vec3 start = e.body("block").position;
        grading::steps(e, 300, [&](int k) {
            const Body& b = e.body("block");
            // Gravity moves the block by g h^2 = 1 mm in a step before the stages answer; it must not add up.
            ASSERT_LE((b.position - start).norm(), 1e-3)
                << "step " << k << ": the block moved from " << str(start) << " to " << str(b.position) << " on a slope of "
                << degrees << " degrees with mu_s = 0.6 (tan = " << std::tan(slope) << "): static friction must hold it";
        });
        if (HasFailure()) return;
    }
}

GRADED_TEST(Worksheet7, BlockSlidesDownSteepIncline, 3,
            "A block on an incline steeper than atan(mu_s) slides down with the acceleration g (sin theta - mu_d cos "
            "theta): sliding friction mu_d lambda_n, not mu_s lambda_n, against the slip.",
            grading::dependsOn("SlidingFrictionIsMuDTimesNormal"),
            grading::dependsOn("NormalImpulseStopsRestingApproach"), grading::dependsOn("EffectiveMassOfTurnedBoxes")) {
    for (const double degrees : {30.0, 40.0}) {
        PhysicsEngine& e = engine;
        e.clear();
        const double slope = degrees * M_PI / 180.0, mus = 0.5, mud = 0.3;  // tan 30 = 0.58 > 0.5
        incline(e, slope, mus, mud);
        const Vec3 down(-std::cos(slope), -std::sin(slope), 0.0);
        const double g = e.gravity().norm(), h = e.timeStep();
        const double a = g * (std::sin(slope) - mud * std::cos(slope));  // m/s^2
        grading::steps(e, 150, [](int) {});
        const double t = 150 * h, v = e.body("block").velocity.dot(down);
        // Semi-implicit Euler at a constant acceleration is exact, and so is mu_d lambda_n once lambda_n is the
        // weight's normal part; the first steps' settling costs at most one step's change, a h, of the speed a t.
        ASSERT_NEAR(v, a * t, 1.5 * a * h) << "speed down the slope of " << degrees << " degrees after " << t
                                             << " s; expected g (sin - mu_d cos) t with mu_d = " << mud
                                             << (std::abs(v - g * (std::sin(slope) - mus * std::cos(slope)) * t) < a * h
                                                     ? " (this is mu_s, not mu_d)"
                                                     : v > a * t && v < 1.2 * a * t ? " (a little too little friction against the slip: are t1, t2 "
                                                                   "tangentBasis(n)? Assignment 2 says why they must be)"
                                                                 : "");
    }
}

GRADED_TEST(Worksheet7, SlidingBallEndsRolling, 3,
            "A solid ball thrown without spin along a level floor slides; friction mu g slows it and spins it up "
            "until its contact point stops slipping, at t = 2 v0 / (7 mu g), and from then on it rolls at 5/7 v0 "
            "for ever. The friction impulse needs the angular terms of the effective mass, and a rolling ball "
            "(no slip) must get no friction.",
            grading::dependsOn("SlidingFrictionIsMuDTimesNormal"), grading::dependsOn("FrictionStopsSlipOfBalls"),
            grading::dependsOn("EffectiveMassOfBalls")) {
    PhysicsEngine& e = engine;
    e.setRequiredStages(checks::frictionStages());
    const double mu = 0.25, v0 = 4.0, r = 0.3;
    e.add(plane("floor", {0.0, 1.0, 0.0}).rough(mu, mu));
    e.add(sphere("ball", r, 2.0).at({0.0, r, 0.0}).moving({v0, 0.0, 0.0}).rough(mu, mu).bouncy(0.0));
    const double g = e.gravity().norm(), h = e.timeStep();
    const double rolling = 2.0 * v0 / (7.0 * mu * g);  // s
    double rolledAt = -1.0;
    double k0 = kineticEnergy(e.body("ball")), v = v0;
    grading::steps(e, 200, [&](int k) {
        const Body& b = e.body("ball");
        // Sliding friction takes mu g h off the speed each step; rolling, nothing.
        if (rolledAt < 0.0 && std::abs(b.velocity.x() - v) < 0.01 * mu * g * h) rolledAt = k * h;
        v = b.velocity.x();
        const double k1 = kineticEnergy(b);
        // The gravity stage adds g h to the downward speed and the normal sum takes it back: the energy of the
        // ball on the level floor can only fall, to rounding.
        ASSERT_LE(k1, k0 + 1e-9 * k0) << "step " << k << ": kinetic energy rose from " << k0 << " J to " << k1
                                       << " J: friction must never add energy";
        k0 = k1;
    });
    if (HasFailure()) return;
    const Body& b = e.body("ball");
    // The slip falls by 7/2 mu g h per step: it stops within a step of the closed form.
    EXPECT_NEAR(rolledAt, rolling, 1.5 * h) << "the ball stopped slipping at " << rolledAt << " s; expected 2 v0 / (7 mu g) = "
                                            << rolling << " s";
    // After the step where it stops slipping it rolls at the speed reached then, off by at most one step's
    // mu g h from 5/7 v0.
    EXPECT_NEAR(b.velocity.x(), 5.0 / 7.0 * v0, mu * g * h)
        << "speed after 2 s; a ball that stops slipping rolls on at 5/7 v0 = " << 5.0 / 7.0 * v0 << " m/s";
    EXPECT_NEAR(b.angularVelocity.z() * r, -5.0 / 7.0 * v0, mu * g * h) << "omega r after 2 s, rolling without slip";
}

GRADED_TEST(Worksheet7, BoxRestsWithoutJitter, 3,
            "A box set down on the floor (restitution 0.5, turned about the vertical) stays at rest for 5 s: no "
            "bounce at resting speeds (kRestingSpeed), no drift, no spin. Warm starting gives the box last step's "
            "sums first; the normal sum holds it, friction keeps it from creeping.",
            grading::dependsOn("BounceTargetOnlyAboveRestingSpeed"), grading::dependsOn("WarmStartAppliesLastSums"),
            grading::dependsOn("NormalImpulseStopsRestingApproach")) {
    PhysicsEngine& e = engine;
    e.setRequiredStages(checks::frictionStages());
    e.add(plane("floor", {0.0, 1.0, 0.0}));
    const Vec3 half(0.5, 0.2, 0.3);
    e.add(box("box", half, 3.0).at({1.0, half.y(), -0.5}).rotated(Quat(Eigen::AngleAxisd(0.6, Vec3::UnitY()))).bouncy(0.5));
    const Body start = e.body("box");
    const double g = e.gravity().norm(), h = e.timeStep();
    grading::steps(e, 500, [&](int k) {
        const Body& b = e.body("box");
        // Each step gravity adds g h downwards before the stages answer; at rest the stage takes it back to
        // rounding. A bounce, even of e g h, leaves percents of g h.
        ASSERT_LE(b.velocity.norm() + b.angularVelocity.norm() * half.norm(), 1e-3 * g * h)
            << "step " << k << ": the box moves at " << str(b.velocity) << " m/s, turning at " << str(b.angularVelocity)
            << " rad/s: it must rest";
        // Interpenetration lifts the box out of the floor by the g h^2 it sank: within a hundredth of that.
        ASSERT_LE((b.position - start.position).norm(), 1e-2 * g * h * h)
            << "step " << k << ": the box has moved from " << str(start.position) << " to " << str(b.position);
    });
    if (HasFailure()) return;
}

GRADED_TEST(Worksheet7, SmallStackStands, 2,
            "Three boxes stacked on the floor, each a little off the one below, stand still for 5 s: the sums of "
            "normal impulses carry each box's weight down to the floor, and warm starting keeps them from step to "
            "step.",
            grading::dependsOn("BoxRestsWithoutJitter"), grading::dependsOn("NormalSumClampedNotTheStep")) {
    PhysicsEngine& e = engine;
    e.setRequiredStages(checks::frictionStages());
    e.add(plane("floor", {0.0, 1.0, 0.0}));
    const Vec3 half(0.4, 0.25, 0.4);
    for (int i = 0; i < 3; ++i) {
        e.add(box("box" + std::to_string(i + 1), half, 1.0).at({i == 1 ? -0.02 : 0.02, half.y() * (2 * i + 1), 0.0}).bouncy(0.0));
    }
    const std::vector<Body> start = e.bodies();
    double fastest = 0.0;
    grading::steps(e, 500, [&](int k) {
        if (k <= 100) return;  // the first second: the stack settles by a millimetre
        for (const Body& b : e.bodies()) fastest = std::max(fastest, b.velocity.norm());
    });
    if (HasFailure()) return;
    const double g = e.gravity().norm(), h = e.timeStep();
    // At rest the stage takes back gravity's g h each step; a percent of it is what the sweeps leave of it in
    // a stack of three.
    EXPECT_LE(fastest, 1e-2 * g * h) << "the stack still moves in its last 4 s (fastest speed " << fastest << " m/s)";
    for (std::size_t i = 1; i < start.size(); ++i) {
        const Body& b = e.bodies()[i];
        // Settling moves a box by a few tenths of a millimetre; a toppling or sliding stack by centimetres.
        EXPECT_LE((b.position - start[i].position).norm(), 2e-3)
            << b.name << " moved from " << str(start[i].position) << " to " << str(b.position);
    }
}

}  // namespace
}  // namespace gpl
