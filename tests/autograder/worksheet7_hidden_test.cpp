// Worksheet 7, hidden tests: graded by instructors and on Gradescope, left out of student releases
// (./lab release drops every file that declares a hidden test; such a file holds hidden tests only).
#include <cmath>
#include <string>

#include "friction.h"
#include "graded.h"

namespace gpl {
namespace {

using checks::Random;
using checks::str;
using checks::Touch;
using checks::touchText;

class Worksheet7Hidden : public checks::ContactsTest {};

// Velocities of two outcomes agree (m/s, rad/s); rounding of the largest speeds involved.
double velocityGap(const Body& x, const Body& y) {
    return (x.velocity - y.velocity).norm() + (x.angularVelocity - y.angularVelocity).norm();
}
double speeds(const Body& b) { return 1.0 + b.velocity.norm() + b.angularVelocity.norm(); }

// Both impulses at the touch's point, prepared in the tests' own way.
void both(Touch& t) {
    const ContactPoint point = checks::pointOf(t);
    applyNormalImpulse(point, t.a, t.b, t.sum);
    applyFrictionImpulse(point, t.a, t.b, t.sum);
}

// The touch's point as the student's prepareContactPoint() prepares it.
ContactPoint prepared(const Touch& t) {
    return prepareContactPoint(t.contact, 0, t.a, t.b, checks::inverseWorldInertia(t.a),
                               checks::inverseWorldInertia(t.b), t.sum.approach);
}

GRADED_TEST(Worksheet7Hidden, PreparedPointSameForSwappedPair, 2,
            "Swapping the two bodies (and reversing the normal) must not change what prepareContactPoint() finds: "
            "the lever arms swap, K_n and the target stay, and so does K_t1 + K_t2 (the same for any tangent basis).",
            grading::hidden()) {
    Random rnd(790);
    for (int i = 0; i < 300; ++i) {
        Touch t = checks::randomTouch(rnd, i);
        t.sum.approach = rnd.uniform(-3.0, 1.0);
        Touch s = t;
        std::swap(s.a, s.b);
        s.contact.normal = -t.contact.normal;
        const ContactPoint c = prepared(t), d = prepared(s);
        ASSERT_GT(c.n.K, 0.0) << "K_n of a pair with a body that can move must be positive" << touchText(t);
        const double tol = 1e-10 * (1.0 + c.n.K + c.t1.K + c.t2.K);
        ASSERT_LE((c.ra - d.rb).norm() + (c.rb - d.ra).norm(), 1e-10 * (1.0 + c.ra.norm() + c.rb.norm()))
            << "the lever arms must swap" << touchText(t);
        ASSERT_NEAR(c.n.K, d.n.K, tol) << "K_n changed with the pair swapped" << touchText(t);
        ASSERT_NEAR(c.t1.K + c.t2.K, d.t1.K + d.t2.K, tol) << "K_t1 + K_t2 changed with the pair swapped" << touchText(t);
        ASSERT_NEAR(c.target, d.target, 1e-12 * (1.0 + c.target)) << "the target changed" << touchText(t);
    }
}

GRADED_TEST(Worksheet7Hidden, ImpulsesSameForSwappedPair, 2,
            "Swapping the two bodies (and reversing the normal, the tangents along) must not change what the normal "
            "and friction kernels do: both bodies end with the same velocities, and the sums are the same "
            "(the friction sum reversed, as it acts on the other body).",
            grading::hidden()) {
    Random rnd(791);
    int changes = 0;
    for (int i = 0; i < 300; ++i) {
        Touch t = checks::randomTouch(rnd, i);
        t.sum.approach = -rnd.uniform(0.0, 2.0 * kRestingSpeed);
        t.sum.normal = rnd.uniform(0.0, 3.0);
        Touch s = t;
        std::swap(s.a, s.b);
        s.contact.normal = -t.contact.normal;
        const Touch before = t;
        both(t);
        both(s);
        changes += velocityGap(t.b, before.b) > 0.0;
        const double tol = 1e-10 * (speeds(before.a) + speeds(before.b));
        ASSERT_LE(velocityGap(t.a, s.b) + velocityGap(t.b, s.a), tol)
            << "swapping a and b changed the outcome:\n  a: " << str(t.a.velocity) << " / " << str(s.b.velocity)
            << "\n  b: " << str(t.b.velocity) << " / " << str(s.a.velocity) << touchText(before);
        ASSERT_NEAR(t.sum.normal, s.sum.normal, 1e-10 * (1.0 + t.sum.normal)) << touchText(before);
        ASSERT_LE((t.sum.tangent + s.sum.tangent).norm(), 1e-10 * (1.0 + t.sum.tangent.norm())) << touchText(before);
    }
    EXPECT_GT(changes, 0) << "the kernels never changed a velocity: they do nothing yet";
}

// The body turned by R about the origin and moved by d, with its velocities turned along.
Body carried(Body b, const Quat& R, const Vec3& d) {
    b.position = R * b.position + d;
    b.velocity = R * b.velocity;
    b.angularVelocity = R * b.angularVelocity;
    b.orientation = (R * b.orientation).normalized();
    return b;
}

GRADED_TEST(Worksheet7Hidden, ImpulsesFollowRigidMotion, 2,
            "Turning and moving the whole contact as one must turn and move the outcome of the normal and friction "
            "kernels along (nothing may depend on the world axes, e.g. a tangent built from a fixed axis).",
            grading::hidden()) {
    Random rnd(792);
    int changes = 0;
    for (int i = 0; i < 300; ++i) {
        Touch t = checks::randomTouch(rnd, i);
        t.sum.approach = -rnd.uniform(0.0, 2.0 * kRestingSpeed);
        t.sum.normal = rnd.uniform(0.0, 3.0);
        const Quat R = rnd.rotation();
        const Vec3 d = rnd.inBox(10.0);
        Touch m = t;
        m.a = carried(t.a, R, d);
        m.b = carried(t.b, R, d);
        m.contact.normal = R * t.contact.normal;
        m.contact.points[0] = R * t.contact.points[0] + d;
        m.tangent = R * t.tangent;
        const Touch before = t;
        both(t);
        both(m);
        changes += velocityGap(t.b, before.b) > 0.0;
        const double tol = 1e-10 * (speeds(before.a) + speeds(before.b));
        ASSERT_LE(velocityGap(carried(t.a, R, d), m.a) + velocityGap(carried(t.b, R, d), m.b), tol)
            << "the moved scene's outcome is not the original's moved along" << touchText(before);
        ASSERT_LE((R * t.sum.tangent - m.sum.tangent).norm(), 1e-10 * (1.0 + t.sum.tangent.norm())) << touchText(before);
    }
    EXPECT_GT(changes, 0) << "the kernels never changed a velocity: they do nothing yet";
}

GRADED_TEST(Worksheet7Hidden, BallRollsDownIncline, 2,
            "Rolling down a slope of theta with tan(theta) < 7/2 mu_s, a solid ball does not slip, its centre "
            "accelerating at 5/7 g sin(theta) (static friction: no energy lost).",
            grading::hidden()) {
    PhysicsEngine& e = engine;
    e.setRequiredStages(checks::frictionStages());
    const double slope = 20.0 * M_PI / 180.0, r = 0.25;  // tan 20 = 0.36 < 7/2 mu_s = 1.75
    const Vec3 normal(-std::sin(slope), std::cos(slope), 0.0);
    e.add(plane("incline", normal).rough(0.5, 0.4));
    e.add(sphere("ball", r, 1.5).at(3.0 * Vec3(std::cos(slope), std::sin(slope), 0.0) + r * normal).rough(0.5, 0.4).bouncy(0.0));
    const double g = e.gravity().norm(), h = e.timeStep();
    const Vec3 down(-std::cos(slope), -std::sin(slope), 0.0);
    grading::steps(e, 100, [](int) {});
    const double a = 5.0 / 7.0 * g * std::sin(slope), t = 100 * h;
    // Semi-implicit Euler at a constant acceleration is exact; the first step's settling costs one step's a h.
    EXPECT_NEAR(e.body("ball").velocity.dot(down), a * t, 1.5 * a * h)
        << "speed down the slope after " << t << " s; a rolling solid ball accelerates at 5/7 g sin(theta)";
}

}  // namespace
}  // namespace gpl
