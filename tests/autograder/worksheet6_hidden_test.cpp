// Worksheet 6, hidden tests: graded by instructors and on Gradescope, left out of student releases
// (./lab release drops every file that declares a hidden test; such a file holds hidden tests only).
#include <cmath>
#include <string>
#include <utility>

#include "contacts.h"
#include "gpl/response.h"
#include "gpl/rotation.h"
#include "graded.h"
#include "turning.h"

namespace gpl {
namespace {

using checks::Random;
using checks::str;
using checks::turning;

class Worksheet6Hidden : public checks::ContactsTest {};

// The body turned by R about the origin and moved by t, with its velocities turned along: a rigid
// motion of the whole scene, seen from another fixed frame.
Body carried(Body b, const Quat& R, const Vec3& t) {
    b.position = R * b.position + t;
    b.velocity = R * b.velocity;
    b.angularVelocity = R * b.angularVelocity;
    b.torque = R * b.torque;
    b.orientation = (R * b.orientation).normalized();
    return b;
}

// Velocities of two outcomes agree (m/s, rad/s); rounding of the largest speeds involved.
double velocityGap(const Body& x, const Body& y) {
    return (x.velocity - y.velocity).norm() + (x.angularVelocity - y.angularVelocity).norm();
}
double speeds(const Body& b) { return 1.0 + b.velocity.norm() + b.angularVelocity.norm(); }

GRADED_TEST(Worksheet6Hidden, RotationSameInATurnedWorld, 2,
            "integrateRotation() must not depend on the frame the world is described in: turning the whole scene by "
            "R turns the new orientation and angular velocity by R too. Keep every world quantity (omega, tau, L) in "
            "the world frame and the body-frame inertia between R and R^T.",
            grading::dependsOn("Worksheet6.TorqueFreeKeepsAngularMomentum"), grading::hidden()) {
    Random rnd(651);
    int changes = 0;
    for (int i = 0; i < 200; ++i) {
        Body b = checks::turningBody(rnd, "body", i);
        b.torque = rnd.inBox(2.0);  // N m
        const Quat R = rnd.rotation();
        Body c = carried(b, R, rnd.inBox(50.0));
        const Body before = b;
        grading::rotationSteps(b, 0.01, 20, [](int) {});
        grading::rotationSteps(c, 0.01, 20, [](int) {});
        changes += b.orientation.coeffs() != before.orientation.coeffs();
        // 20 steps, each rounding to ~1e-16; turned vectors and quaternions add a few ulps.
        const double tol = 1e-12 * speeds(before);
        ASSERT_LE((c.angularVelocity - R * b.angularVelocity).norm(), tol)
            << "in the turned world the angular velocity became " << str(c.angularVelocity) << ", expected "
            << str(R * b.angularVelocity) << " (this world's, turned)\n  " << turning(before);
        ASSERT_LE(checks::angleBetween(c.orientation, R * b.orientation), 1e-12)
            << "in the turned world the orientation became " << checks::str(c.orientation) << ", expected "
            << checks::str(Quat(R * b.orientation)) << "\n  " << turning(before);
    }
    EXPECT_GT(changes, 0) << "integrateRotation() never turned a body";
}

// Two movable bodies and a contact at `points` points that all approach.
struct Collision {
    Body a, b;
    Contact contact;
};

Collision approaching(Random& rnd, int i) {
    for (;;) {
        Collision c{checks::turningBody(rnd, "a", i), checks::turningBody(rnd, "b", i + 1), {}};
        c.contact.normal = rnd.direction();
        c.contact.restitution = rnd.uniform(0.0, 1.0);
        c.contact.pointCount = 1 + i % 4;
        const Vec3 middle = 0.5 * (c.a.position + c.b.position);
        bool ok = true;
        for (int k = 0; k < c.contact.pointCount; ++k) {
            c.contact.points[k] = middle + rnd.inBox(1.0);
            const Vec3& p = c.contact.points[k];
            ok = ok && (checks::pointVelocity(c.b, p) - checks::pointVelocity(c.a, p)).dot(c.contact.normal) < -0.1;
        }
        if (ok) return c;
    }
}

std::string text(const Collision& c) {
    return "\n  a: " + turning(c.a) + "\n  b: " + turning(c.b) + "\n  normal " + str(c.contact.normal) + ", " +
           std::to_string(c.contact.pointCount) + " point(s), the first at " + str(c.contact.points[0]);
}

GRADED_TEST(Worksheet6Hidden, ContactImpulseSameForSwappedPair, 2,
            "applyContactImpulse() must treat the two bodies alike: with a and b swapped and the normal reversed the "
            "bodies leave with the same velocities. Use r_a and r_b of each body, and the relative velocity of b's "
            "point minus a's along n.",
            grading::dependsOn("Worksheet6.ContactImpulseConservesMomenta"), grading::hidden()) {
    Random rnd(652);
    int changes = 0;
    for (int i = 0; i < 200; ++i) {
        Collision c = approaching(rnd, i);
        Collision s{c.b, c.a, c.contact};
        s.contact.normal = -c.contact.normal;
        const Collision before = c;
        applyContactImpulse(c.contact, c.a, c.b);
        applyContactImpulse(s.contact, s.a, s.b);
        changes += c.a.velocity != before.a.velocity;
        const double tol = 1e-11 * (speeds(before.a) + speeds(before.b));
        ASSERT_LE(velocityGap(c.a, s.b) + velocityGap(c.b, s.a), tol)
            << "swapped, a leaves with " << str(s.b.velocity) << " and " << str(s.b.angularVelocity)
            << " rad/s, unswapped with " << str(c.a.velocity) << " and " << str(c.a.angularVelocity) << " rad/s"
            << text(before);
    }
    EXPECT_GT(changes, 0) << "the impulse never changed a velocity";
}

GRADED_TEST(Worksheet6Hidden, ContactImpulseFollowsRigidMotion, 2,
            "applyContactImpulse() seen from a turned and moved frame: turning and moving the whole configuration "
            "(bodies, points, normal) must turn the velocities afterwards the same way. Measure lever arms from the "
            "centres (p - x), never from the origin, and turn the inertia into the world with the orientation.",
            grading::dependsOn("Worksheet6.ContactImpulseConservesMomenta"), grading::hidden()) {
    Random rnd(653);
    for (int i = 0; i < 200; ++i) {
        Collision c = approaching(rnd, i);
        const Quat R = rnd.rotation();
        const Vec3 t = rnd.inBox(50.0);
        Collision m{carried(c.a, R, t), carried(c.b, R, t), c.contact};
        m.contact.normal = R * c.contact.normal;
        for (int k = 0; k < c.contact.pointCount; ++k) m.contact.points[k] = R * c.contact.points[k] + t;
        const Collision before = c;
        applyContactImpulse(c.contact, c.a, c.b);
        applyContactImpulse(m.contact, m.a, m.b);
        // Positions up to ~60 m after the move: lever arms lose ~1e-14 m to rounding.
        const double tol = 1e-11 * (speeds(before.a) + speeds(before.b));
        const Body back[] = {carried(c.a, R, t), carried(c.b, R, t)};
        ASSERT_LE(velocityGap(m.a, back[0]) + velocityGap(m.b, back[1]), tol)
            << "in the moved frame the velocities differ from this frame's, turned: a " << str(m.a.velocity)
            << " against " << str(back[0].velocity) << ", b " << str(m.b.velocity) << " against "
            << str(back[1].velocity) << text(before);
    }
}

}  // namespace
}  // namespace gpl
