// Worksheet 6 autograder: rotation. The kernels are called directly on turning boxes and spheres
// drawn from a fixed seed and compared with the closed forms of rigid-body mechanics: the world
// inertia tensor R I R^T, angular momentum kept without torque and grown by tau t with it, the
// orientation of a body turning at a constant rate, impulses that keep linear and angular momentum
// and set the normal velocity at the contact point to -e times its old value. A whole scene checks
// boxes spun about each of their axes in the engine.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "contacts.h"
#include "gpl/response.h"
#include "gpl/rotation.h"
#include "gpl/scenes.h"
#include "graded.h"
#include "turning.h"

namespace gpl {
namespace {

using checks::Random;
using checks::str;
using checks::turning;

class Worksheet6 : public checks::ContactsTest {};

// Quantities computed in a few operations round to ~1e-16 of their size; 1e-12 of it allows any
// equivalent formula or order of operations, while every mistake tested here is off by percents.
constexpr double kRounding = 1e-12;

// A box with distinct moments of inertia (about x the largest, then y, then z).
Body asymmetricBox(const std::string& name) { return box(name, {0.15, 0.4, 0.8}, 2.0); }

// ---- worldInverseInertia() ---------------------------------------------------------------------------

GRADED_TEST(Worksheet6, WorldInertiaOfTurnedBox, 2,
            "worldInverseInertia(): a box turned by 90 degrees about z has its x and y axes swapped in the world, "
            "so the diagonal entries of its inverse inertia for x and y swap too; unturned, it is invInertia itself, "
            "and a static body's is zero. Rotate the body-frame tensor into the world: R I^-1 R^T "
            "(worksheet 6, assignment 1).") {
    const Body b = asymmetricBox("box");
    const Vec3 d = b.invInertia.diagonal();  // 1/(kg m^2), about the body's x, y, z
    const double tol = kRounding * d.maxCoeff();
    const Mat3 unturned = worldInverseInertia(b);
    ASSERT_LE((unturned - b.invInertia).norm(), tol) << "unturned box: got\n"
                                                     << unturned << "\nexpected\n"
                                                     << b.invInertia;
    const struct {
        Vec3 axis;
        Vec3 expected;  // the diagonal after a quarter turn about the axis
    } turns[] = {{Vec3::UnitZ(), {d.y(), d.x(), d.z()}},
                 {Vec3::UnitX(), {d.x(), d.z(), d.y()}},
                 {Vec3::UnitY(), {d.z(), d.y(), d.x()}}};
    for (const auto& t : turns) {
        Body turned = b;
        turned.rotated(Quat(Eigen::AngleAxisd(M_PI / 2.0, t.axis)));
        const Mat3 w = worldInverseInertia(turned);
        const Mat3 expected = t.expected.asDiagonal();
        ASSERT_LE((w - expected).norm(), tol)
            << "box turned by 90 degrees about " << str(t.axis) << ": got\n"
            << w << "\nexpected\n"
            << expected << ((w - b.invInertia).norm() < tol ? "\n(this is the body-frame tensor, not turned)" : "");
    }
    Body fixed = b;
    fixed.rotated(Quat(Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, 3.0).normalized()))).makeStatic();
    ASSERT_TRUE(worldInverseInertia(fixed).isZero(0.0))
        << "a static body never turns: its inverse inertia is zero, got\n"
        << worldInverseInertia(fixed);
}

GRADED_TEST(Worksheet6, WorldInertiaIsRotatedTensor, 3,
            "worldInverseInertia() for any orientation: the result is symmetric, is the inverse of the world inertia "
            "tensor R I R^T, and turns each world axis R e_i of the box by 1/I_i. Use the rotation matrix R of the "
            "orientation as R I^-1 R^T (not R^T I^-1 R, not the body-frame tensor), also for a box of two equal "
            "moments (a square cross-section), which only a body of three equal moments may skip.") {
    Random rnd(601);
    for (int i = 0; i < 300; ++i) {
        // Every fifth a box of square cross-section: I_x = I_y != I_z.
        const double side = rnd.uniform(0.1, 0.5);
        const Body b = i % 5 == 4 ? box("square", {side, side, 2.5 * side}, rnd.uniform(0.5, 5.0)).rotated(rnd.rotation())
                                  : checks::turningBody(rnd, "body", i);
        const Mat3 w = worldInverseInertia(b);
        const double scale = b.invInertia.diagonal().maxCoeff();  // 1/(kg m^2)
        ASSERT_LE((w - w.transpose()).norm(), kRounding * scale) << "not symmetric:\n" << w << "\n  " << turning(b);
        const Mat3 r = b.orientation.toRotationMatrix();
        // The inverse of R I R^T, for a tensor whose moments differ by up to ~100 times: rounding of
        // 1e-16 grows by that condition number at most.
        const Mat3 product = w * checks::worldInertia(b);
        ASSERT_LE((product - Mat3::Identity()).norm(), 100.0 * kRounding)
            << "times the world inertia R I R^T it gives\n"
            << product << "\ninstead of the identity\n  " << turning(b);
        for (int k = 0; k < 3; ++k) {
            const Vec3 axis = r.col(k);  // the body's k-th axis in the world
            const Vec3 expected = b.invInertia(k, k) * axis;
            ASSERT_LE((w * axis - expected).norm(), kRounding * scale)
                << "the body's axis " << k << " in the world, " << str(axis) << ", must be scaled by 1/I_" << k << " = "
                << b.invInertia(k, k) << ", got " << str(w * axis) << "\n  " << turning(b);
        }
    }
}

// ---- integrateRotation() -----------------------------------------------------------------------------

GRADED_TEST(Worksheet6, RotationAboutPrincipalAxisKeepsOmega, 2,
            "integrateRotation(): a sphere, and a box turning about one of its own axes, turn at a constant angular "
            "velocity for ever (no torque, no wobble). Keep the world angular momentum L = R I R^T omega and "
            "compute omega from it in the new orientation (worksheet 6, assignment 2).") {
    Random rnd(602);
    for (int i = 0; i < 40; ++i) {
        Body b = i % 2 == 0 ? sphere("sphere", rnd.uniform(0.1, 1.0), rnd.uniform(0.1, 10.0)) : asymmetricBox("box");
        b.rotated(rnd.rotation());
        // The largest and the smallest axis: about the middle one, the slightest rounding grows (the
        // tennis-racket theorem).
        const Vec3 axis = i % 2 == 0 ? rnd.direction() : Vec3(b.orientation * Vec3::Unit(i % 4 == 1 ? 0 : 2));
        b.spinning(rnd.uniform(0.5, 5.0) * axis);
        const Vec3 w0 = b.angularVelocity;
        const Quat q0 = b.orientation;
        double turned = 0.0;  // rad, after 0.1 s: at least 0.05 rad, far from a whole turn back to the start
        grading::rotationSteps(b, 0.01, 500, [&](int k) {
            if (k == 10) turned = checks::angleBetween(b.orientation, q0);
            // Rounding of ~1e-16 per step, 500 steps.
            EXPECT_LE((b.angularVelocity - w0).norm(), 500.0 * kRounding * w0.norm())
                << "step " << k << ": angular velocity " << str(b.angularVelocity) << ", it started as " << str(w0)
                << " about a principal axis of " << b.name << " (orientation at the start " << checks::str(q0) << ")";
        });
        if (HasFailure()) return;
        ASSERT_GT(turned, 1e-3)
            << b.name << " turning at " << str(w0) << " rad/s for 0.1 s has not turned: integrateRotation() must change "
            << "the orientation";
    }
}

// A torque-free asymmetric box turning about no axis of its own: its angular velocity wanders, its
// angular momentum must not.
Body tumbling(Random& rnd) {
    Body b = asymmetricBox("box").rotated(rnd.rotation());
    const double speed = rnd.uniform(1.0, 4.0);  // rad/s
    b.spinning(speed * rnd.direction());
    return b;
}

GRADED_TEST(
    Worksheet6, TorqueFreeKeepsAngularMomentum, 3,
    "integrateRotation() without torque: the world angular momentum L = R I R^T omega of a box turning about no "
    "axis of its own must stay exactly what it was, though omega changes. Holding omega fixed, or stepping "
    "Euler's equations explicitly, lets L drift: compute L first, turn the orientation, then omega = "
    "(R' I R'^T)^-1 L with the new orientation.") {
    Random rnd(603);
    for (int i = 0; i < 20; ++i) {
        Body b = tumbling(rnd);
        const Body start = b;
        const Vec3 l0 = checks::worldInertia(b) * b.angularVelocity;
        Vec3 w = b.angularVelocity;
        double turnedOmega = 0.0;  // how far omega's direction moved (rad)
        grading::rotationSteps(b, 0.01, 1000, [&](int k) {
            const Vec3 l = checks::worldInertia(b) * b.angularVelocity;
            // Rounding of ~1e-16 per step over 1000 steps, times 10 for the products of the inertia
            // tensor; a drifting method is off by percents within a hundred steps.
            EXPECT_LE((l - l0).norm(), 1e-11 * l0.norm())
                << "step " << k << ": angular momentum " << str(l) << ", it started as " << str(l0)
                << " (relative change " << (l - l0).norm() / l0.norm() << ")\n  at the start: " << turning(start);
            turnedOmega = std::max(
                turnedOmega, std::acos(std::clamp(b.angularVelocity.normalized().dot(w.normalized()), -1.0, 1.0)));
        });
        if (HasFailure()) return;
        ASSERT_GT(turnedOmega, 0.05) << "omega never changed direction: the box does not turn as it should\n  "
                                     << turning(start);
    }
}

GRADED_TEST(Worksheet6, TorqueFreeEnergyBounded, 2,
            "integrateRotation() without torque: the kinetic energy 1/2 omega . L of a tumbling box must stay within "
            "(h |omega|)^2 of what it was over 1000 steps (|omega| the fastest the box can turn, |L| / I_min). One "
            "explicit step of the orientation with the old omega "
            "gains energy every step; take omega at the midpoint orientation q_half for the whole step.",
            grading::dependsOn("TorqueFreeKeepsAngularMomentum")) {
    Random rnd(604);
    const double h = 0.01;
    for (int i = 0; i < 20; ++i) {
        Body b = tumbling(rnd);
        const Body start = b;
        const double e0 = checks::energyOf(b);
        // The midpoint rule errs by ~(h |omega|)^3 per step in the orientation, and the energy, a function of it
        // on a bounded orbit, by ~(h |omega|)^2 relative at most (measured: 3e-5 at h |omega| = 0.03); a step
        // with the old omega gains percents in these 10 s. |omega| = |I_world^-1 L| reaches at most |L| / I_min.
        const double fastest = (checks::worldInertia(b) * b.angularVelocity).norm() / b.inertia.diagonal().minCoeff();
        const double hw = h * fastest;
        grading::rotationSteps(b, h, 1000, [&](int k) {
            const double e = checks::energyOf(b);
            EXPECT_LE(std::abs(e - e0), hw * hw * e0)
                << "step " << k << ": kinetic energy " << e << " J, it started at " << e0
                << " J\n  at the start: " << turning(start);
        });
        if (HasFailure()) return;
    }
}

GRADED_TEST(Worksheet6, OrientationStaysUnit, 2,
            "integrateRotation(): the orientation must stay a unit quaternion step after step (only a unit "
            "quaternion is a rotation). Normalise it after every update: q / |q|.") {
    Random rnd(605);
    for (int i = 0; i < 10; ++i) {
        Body b = i % 2 == 0 ? tumbling(rnd) : sphere("ball", 0.5, 1.0).rotated(rnd.rotation());
        b.spinning(rnd.uniform(5.0, 20.0) * rnd.direction());
        double turned = 0.0;  // rad
        Quat q = b.orientation;  // the step's start
        grading::rotationSteps(b, 0.01, 2000, [&](int k) {
            turned += checks::angleBetween(q, b.orientation);
            q = b.orientation;
            // A unit quaternion normalised anew each step: a few ulps.
            EXPECT_NEAR(b.orientation.norm(), 1.0, kRounding)
                << "step " << k << ": |q| = " << b.orientation.norm() << ", q = " << checks::str(b.orientation)
                << " for " << b.name << " turning at " << str(b.angularVelocity) << " rad/s";
        });
        if (HasFailure()) return;
        ASSERT_GT(turned, 1.0) << b.name << " turning at 5 rad/s or more for 20 s never turned: integrateRotation() "
                               << "must change the orientation";
    }
}

GRADED_TEST(Worksheet6, ConstantTorqueGrowsAngularMomentum, 2,
            "integrateRotation() with a constant torque tau (world frame): the angular momentum grows exactly like "
            "L(t) = L(0) + tau t, whatever the body does. Add h tau to L = R I R^T omega each step, before the turn "
            "(a body at rest under a torque turns in the first step already, as (3) turns with that L), and leave a "
            "static body untouched.") {
    Random rnd(606);
    const double h = 0.01;
    for (int i = 0; i < 20; ++i) {
        Body b = i % 2 == 0 ? tumbling(rnd) : sphere("ball", rnd.uniform(0.1, 1.0), rnd.uniform(0.1, 10.0));
        b.rotated(rnd.rotation()).spinning(rnd.inBox(3.0));
        b.torque = rnd.uniform(0.1, 2.0) * rnd.direction();  // N m
        const Body start = b;
        const Vec3 l0 = checks::worldInertia(b) * b.angularVelocity;
        grading::rotationSteps(b, h, 300, [&](int k) {
            const Vec3 expected = l0 + b.torque * (k * h);
            const Vec3 l = checks::worldInertia(b) * b.angularVelocity;
            // Rounding per step as above, over momenta up to |L(0)| + |tau| t.
            EXPECT_LE((l - expected).norm(), 1e-11 * (l0.norm() + start.torque.norm() * k * h))
                << "step " << k << ": angular momentum " << str(l) << ", expected L(0) + tau t = " << str(expected)
                << "\n  torque " << str(start.torque) << " N m; at the start: " << turning(start);
        });
        if (HasFailure()) return;
    }
    // (3) turns with the momentum after the step's torque: a box at rest under a torque about one of its
    // axes turns about that axis at |omega_k| = k h tau / I in step k, by turn()'s 2 atan(h |omega_k| / 2).
    for (int axis = 0; axis < 3; ++axis) {
        Body b = asymmetricBox("box").rotated(rnd.rotation());
        const double inertia = b.inertia(axis, axis);  // kg m^2, about the axis
        const double tau = 10.0 * inertia;             // N m: 10 rad/s^2
        b.torque = tau * (b.orientation * Vec3::Unit(axis));
        const Body start = b;
        const int n = 10;
        double expected = 0.0;  // rad
        for (int k = 1; k <= n; ++k) expected += 2.0 * std::atan(0.5 * h * (k * h * tau / inertia));
        grading::rotationSteps(b, h, n, [](int) {});
        const double turned = checks::angleBetween(start.orientation, b.orientation);
        // h |omega| stays below 0.01: other turns (the exponential, rotation matrices) differ from turn()'s by
        // (h |omega|)^2 / 12 < 1e-5 of the angle. Turning with the momentum before the torque turns 18 % less.
        ASSERT_NEAR(turned, expected, 1e-4 * expected)
            << "a box at rest under a torque of " << tau << " N m about its axis " << axis << " (I = " << inertia
            << " kg m^2) turned by " << turned << " rad in " << n << " steps of " << h << " s; expected " << expected
            << " rad (each step's turn uses L after adding h tau)\n  at the start: " << turning(start);
    }
    Body fixed = asymmetricBox("fixed").rotated(rnd.rotation()).makeStatic();
    fixed.torque = Vec3(1.0, 2.0, 3.0);
    const Body before = fixed;
    integrateRotation(fixed, h);
    ASSERT_TRUE(fixed.orientation.coeffs() == before.orientation.coeffs() && fixed.angularVelocity == Vec3::Zero())
        << "a static body must stay as it is, yet its orientation became " << checks::str(fixed.orientation)
        << " and its angular velocity " << str(fixed.angularVelocity);
}

GRADED_TEST(Worksheet6, OrientationConvergesToClosedForm, 3,
            "integrateRotation() at a constant angular velocity omega (a sphere, or a box about one of its axes): "
            "after t seconds the orientation is the turn by |omega| t about omega, applied after the start: "
            "q(t) = exp(t/2 (0, omega)) q(0). Halving h must at least halve the error. Check the factor 1/2 in "
            "dq/dt = 1/2 (0, omega) q and the order of the product (world omega on the left).") {
    Random rnd(607);
    for (int i = 0; i < 12; ++i) {
        Body b0 = i % 2 == 0 ? sphere("sphere", 0.5, 2.0) : asymmetricBox("box");
        b0.rotated(rnd.rotation());
        const Vec3 axis = i % 2 == 0 ? rnd.direction() : Vec3(b0.orientation * Vec3::Unit(i % 4 == 1 ? 0 : 2));
        const double speed = rnd.uniform(1.0, 3.0), t = 1.0;  // rad/s, s
        b0.spinning(speed * axis);
        const Quat exact = Quat(Eigen::AngleAxisd(speed * t, axis)) * b0.orientation;
        std::vector<double> errors;
        std::string table;
        for (const int steps : {10, 20, 40, 80}) {
            Body b = b0;
            grading::rotationSteps(b, t / steps, steps, [](int) {});
            errors.push_back(checks::angleBetween(b.orientation, exact));
            table += "\n    h = " + formatNumber(t / steps) + " s: off by " + formatNumber(errors.back()) + " rad";
        }
        for (std::size_t k = 1; k < errors.size(); ++k) {
            // First order or better: halving h at least halves the error (0.55 allows a first-order
            // method's higher terms); a wrong rate or order converges to another orientation and stalls.
            ASSERT_LE(errors[k], 0.55 * errors[k - 1] + 1e-13)
                << b0.name << " turning at " << speed << " rad/s about " << str(axis) << " from "
                << checks::str(b0.orientation) << "; its orientation after " << t << " s against the closed form "
                << checks::str(exact) << ":" << table;
        }
        ASSERT_LE(errors.back(), 0.05) << "still far from the closed form:" << table;
    }
}

// ---- applyImpulseAtPoint() ---------------------------------------------------------------------------

// Two turning bodies; with `walls`, a or b is static in every tenth pair (a static body takes any
// momentum: only pairs of movable bodies keep theirs).
struct Pair {
    Body a, b;
};

Pair randomPair(Random& rnd, int i, bool walls) {
    Pair p{checks::turningBody(rnd, "a", i), checks::turningBody(rnd, "b", i + 1)};
    if (walls && i % 10 == 3) p.a.makeStatic();
    if (walls && i % 10 == 7) p.b.makeStatic();
    return p;
}

std::string pairText(const Pair& p) { return "\n  a: " + turning(p.a) + "\n  b: " + turning(p.b); }

// Momentum and angular momentum of the pair are both exact to rounding of the largest term.
double momentumScale(const Pair& p, const Vec3& about) {
    double s = 0.0;
    for (const Body* b : {&p.a, &p.b}) {
        if (b->isStatic()) continue;
        s += b->mass * b->velocity.norm() * (1.0 + (b->position - about).norm()) +
             (checks::worldInertia(*b) * b->angularVelocity).norm();
    }
    return s;
}

GRADED_TEST(Worksheet6, ImpulseAtPointConservesMomenta, 3,
            "applyImpulseAtPoint(): J acts on b at the point and -J on a, so linear momentum m_a v_a + m_b v_b and "
            "angular momentum about any fixed point stay the same: v += J/m and omega += I_world^-1 (r x J) with "
            "r = p - x of that body, for b; the opposite for a (worksheet 6, assignment 3).",
            grading::dependsOn("WorldInertiaIsRotatedTensor")) {
    Random rnd(611);
    int changes = 0;
    for (int i = 0; i < 300; ++i) {
        Pair p = randomPair(rnd, i, false);
        const Pair before = p;
        const Vec3 point = rnd.inBox(5.0), impulse = rnd.uniform(0.1, 10.0) * rnd.direction();
        applyImpulseAtPoint(p.a, p.b, point, impulse);
        changes += p.a.angularVelocity != before.a.angularVelocity || p.b.angularVelocity != before.b.angularVelocity;
        const Vec3 p0 = linearMomentum(before.a) + linearMomentum(before.b);
        const Vec3 p1 = linearMomentum(p.a) + linearMomentum(p.b);
        const double scale = momentumScale(before, Vec3::Zero()) + impulse.norm() * (1.0 + point.norm());
        ASSERT_LE((p1 - p0).norm(), kRounding * scale)
            << "momentum " << str(p1) << " after the impulse " << str(impulse) << " at " << str(point) << ", "
            << str(p0) << " before" << pairText(before);
        for (const Vec3& about : {Vec3(Vec3::Zero()), rnd.inBox(10.0)}) {
            const Vec3 l0 = checks::momentAbout(before.a, about) + checks::momentAbout(before.b, about);
            const Vec3 l1 = checks::momentAbout(p.a, about) + checks::momentAbout(p.b, about);
            ASSERT_LE((l1 - l0).norm(),
                      kRounding * (momentumScale(before, about) + impulse.norm() * (1.0 + (point - about).norm())))
                << "angular momentum about " << str(about) << ": " << str(l1) << " after the impulse " << str(impulse)
                << " at " << str(point) << ", " << str(l0) << " before" << pairText(before);
        }
    }
    EXPECT_GT(changes, 0) << "no impulse ever turned a body: applyImpulseAtPoint() changes no angular velocity yet";
}

GRADED_TEST(Worksheet6, ImpulseAtPointOffCentre, 2,
            "applyImpulseAtPoint(): an impulse J at the point p changes b's velocity by J / m_b and its angular "
            "velocity by I_world^-1 (r x J) with r = p - x_b (from the centre to the point, in that order); "
            "through the centre it turns nothing.",
            grading::dependsOn("WorldInertiaIsRotatedTensor")) {
    Random rnd(612);
    for (int i = 0; i < 300; ++i) {
        Pair p = randomPair(rnd, i, true);
        p.a.makeStatic();  // a wall: b alone takes the impulse
        if (p.b.isStatic()) continue;
        const Pair before = p;
        const bool centre = i % 5 == 0;
        const Vec3 point = centre ? p.b.position : Vec3(p.b.position + rnd.uniform(0.1, 1.0) * rnd.direction());
        const Vec3 impulse = rnd.uniform(0.1, 10.0) * rnd.direction();
        applyImpulseAtPoint(p.a, p.b, point, impulse);
        const Vec3 dv = impulse / before.b.mass;
        const Vec3 dw = checks::worldInertia(before.b).inverse() * (point - before.b.position).cross(impulse);
        const double scale = 1.0 + before.b.velocity.norm() + before.b.angularVelocity.norm() + dv.norm() + dw.norm();
        ASSERT_LE((p.b.velocity - before.b.velocity - dv).norm(), kRounding * scale)
            << "velocity change " << str(p.b.velocity - before.b.velocity) << ", expected J/m = " << str(dv)
            << " for the impulse " << str(impulse) << " at " << str(point) << pairText(before);
        ASSERT_LE((p.b.angularVelocity - before.b.angularVelocity - dw).norm(), 100.0 * kRounding * scale)
            << "angular velocity change " << str(p.b.angularVelocity - before.b.angularVelocity)
            << ", expected I_world^-1 (r x J) = " << str(dw) << " for the impulse " << str(impulse) << " at "
            << str(point) << (centre ? " (the centre: no turn)" : "") << pairText(before);
        ASSERT_TRUE(p.a.velocity == Vec3::Zero() && p.a.angularVelocity == Vec3::Zero())
            << "the static body moved: " << turning(p.a);
    }
}

// ---- applyContactImpulse() ---------------------------------------------------------------------------

// Two turning bodies and a contact of `points` points where, for sign -1, every point approaches
// (+1: every point separates). Normal and points are random: the kernel's physics does not depend
// on where the collision kernels put them.
struct Collision {
    Pair p;
    Contact contact;
};

std::string collisionText(const Collision& c) {
    std::string s = pairText(c.p) + "\n  normal " + str(c.contact.normal) + ", restitution " +
                    formatNumber(c.contact.restitution) + ", points";
    for (int k = 0; k < c.contact.pointCount; ++k) s += " " + str(c.contact.points[k]);
    return s;
}

double normalAt(const Collision& c, const Vec3& point) {
    return (checks::pointVelocity(c.p.b, point) - checks::pointVelocity(c.p.a, point)).dot(c.contact.normal);
}

Collision randomCollision(Random& rnd, int i, int points, double restitution, double sign = -1.0, bool walls = true) {
    for (;;) {
        Collision c{randomPair(rnd, i, walls), {}};
        if (c.p.a.isStatic() && c.p.b.isStatic()) continue;
        c.contact.normal = rnd.direction();
        c.contact.restitution = restitution;
        c.contact.pointCount = points;
        c.contact.depth = 0.01;
        const Vec3 middle = 0.5 * (c.p.a.position + c.p.b.position);
        for (int k = 0; k < points; ++k) c.contact.points[k] = middle + rnd.inBox(1.0);
        bool ok = true;
        for (int k = 0; k < points; ++k) {
            const double vn = normalAt(c, c.contact.points[k]);
            ok = ok && vn * sign > 0.1;  // clearly approaching (separating): tells most
        }
        if (ok) return c;
    }
}

double speedScale(const Collision& c) {
    double s = 1.0;
    for (const Body* b : {&c.p.a, &c.p.b}) {
        s += b->velocity.norm() + b->angularVelocity.norm() * (1.0 + (c.contact.points[0] - b->position).norm());
    }
    return s;
}

double restitutionFor(Random& rnd, int i) { return i % 7 == 0 ? 0.0 : i % 7 == 1 ? 1.0 : rnd.uniform(0.0, 1.0); }

GRADED_TEST(Worksheet6, ContactImpulseReversesNormalVelocityAtPoint, 3,
            "applyContactImpulse() at one point: afterwards the normal velocity of the two material points there, "
            "(v_b + omega_b x r_b - v_a - omega_a x r_a) . n, must be exactly -e times what it was. The effective mass "
            "needs the angular terms n . ((I_a^-1 (r_a x n)) x r_a + (I_b^-1 (r_b x n)) x r_b) besides 1/m_a + 1/m_b "
            "(worksheet 6, assignment 4).",
            grading::dependsOn("ImpulseAtPointConservesMomenta"), grading::dependsOn("ImpulseAtPointOffCentre")) {
    Random rnd(621);
    for (int i = 0; i < 300; ++i) {
        Collision c = randomCollision(rnd, i, 1, restitutionFor(rnd, i));
        const Collision before = c;
        const Vec3 point = c.contact.points[0];
        const double vn = normalAt(c, point), e = c.contact.restitution;
        applyContactImpulse(c.contact, c.p.a, c.p.b);
        const double after = normalAt(c, point);
        ASSERT_NEAR(after, -e * vn, 100.0 * kRounding * speedScale(before))
            << "normal velocity at the point after the impulse; it was " << vn << " m/s, so with e = " << e
            << " it must become " << -e * vn << " m/s" << collisionText(before);
    }
}

GRADED_TEST(Worksheet6, ContactImpulseSkipsOnlySeparatingPoints, 2,
            "applyContactImpulse() over several points: a point whose material points separate (v_rel >= 0) gets "
            "nothing, and the loop goes on to the next point (continue, not break); a point after it that approaches "
            "still gets its impulse.",
            grading::dependsOn("ContactImpulseReversesNormalVelocityAtPoint")) {
    Random rnd(625);
    int tried = 0;
    for (int i = 0; i < 300; ++i) {
        Collision c = randomCollision(rnd, i, 1, restitutionFor(rnd, i));
        const Vec3 approaching = c.contact.points[0];
        // A first point where the two material points separate: the bodies turn, so the normal
        // velocity differs from point to point.
        bool found = false;
        for (int k = 0; k < 50 && !found; ++k) {
            const Vec3 p = approaching + rnd.inBox(1.0);
            c.contact.points[0] = p;
            found = normalAt(c, p) > 0.05 * speedScale(c);
        }
        if (!found) continue;
        ++tried;
        c.contact.points[1] = approaching;
        c.contact.pointCount = 2;
        const Collision before = c;
        const double vn = normalAt(c, approaching), e = c.contact.restitution;
        applyContactImpulse(c.contact, c.p.a, c.p.b);
        // The separating point changed nothing, so the second point's velocity answers its own impulse alone.
        ASSERT_NEAR(normalAt(c, approaching), -e * vn, 100.0 * kRounding * speedScale(before))
            << "normal velocity at the second point, which approached at " << vn << " m/s after a first point that "
            << "separates; with e = " << e << " it must become " << -e * vn << " m/s" << collisionText(before);
    }
    EXPECT_GT(tried, 30) << "too few configurations with a separating first point were drawn";
}

GRADED_TEST(Worksheet6, ContactImpulseConservesMomenta, 3,
            "applyContactImpulse(): at every point an impulse j n on b and -j n on a, both at that point, so linear "
            "momentum and angular momentum about any fixed point stay the same. Apply each point's impulse at the "
            "point (applyImpulseAtPoint()), not at the centres.",
            grading::dependsOn("ImpulseAtPointConservesMomenta")) {
    Random rnd(622);
    int changes = 0;
    for (int i = 0; i < 300; ++i) {
        Collision c = randomCollision(rnd, i, 1 + i % 4, restitutionFor(rnd, i), -1.0, false);
        const Collision before = c;
        applyContactImpulse(c.contact, c.p.a, c.p.b);
        changes += c.p.a.velocity != before.p.a.velocity || c.p.b.velocity != before.p.b.velocity;
        const Vec3 p0 = linearMomentum(before.p.a) + linearMomentum(before.p.b);
        const Vec3 p1 = linearMomentum(c.p.a) + linearMomentum(c.p.b);
        // Impulses of the size of the momenta: rounding of both.
        const Vec3 about = rnd.inBox(10.0);
        ASSERT_LE((p1 - p0).norm(), 10.0 * kRounding * momentumScale(before.p, Vec3::Zero()))
            << "momentum " << str(p1) << " after the impulse, " << str(p0) << " before" << collisionText(before);
        for (const Vec3& o : {Vec3(Vec3::Zero()), about}) {
            const Vec3 l0 = checks::momentAbout(before.p.a, o) + checks::momentAbout(before.p.b, o);
            const Vec3 l1 = checks::momentAbout(c.p.a, o) + checks::momentAbout(c.p.b, o);
            ASSERT_LE((l1 - l0).norm(), 10.0 * kRounding * momentumScale(before.p, o))
                << "angular momentum about " << str(o) << ": " << str(l1) << " after the impulse, " << str(l0)
                << " before" << collisionText(before);
        }
    }
    EXPECT_GT(changes, 0) << "the impulse never changed a velocity: applyContactImpulse() does nothing yet";
}

GRADED_TEST(Worksheet6, ContactImpulseThroughCentresIsLinear, 2,
            "applyContactImpulse() with the point on the line through both centres along the normal: r x n = 0, so "
            "nothing turns and the velocities change exactly as worksheet 4's linear impulse "
            "j = -(1 + e) v_rel / (1/m_a + 1/m_b) says.",
            grading::dependsOn("ImpulseAtPointConservesMomenta")) {
    Random rnd(623);
    for (int i = 0; i < 300; ++i) {
        Collision c = randomCollision(rnd, i, 1, restitutionFor(rnd, i));
        const Vec3 n = c.contact.normal;
        c.p.b.position = c.p.a.position + rnd.uniform(0.2, 2.0) * n;
        c.contact.points[0] = c.p.a.position + rnd.uniform(0.0, 1.0) * (c.p.b.position - c.p.a.position);
        const double vn = (c.p.b.velocity - c.p.a.velocity).dot(n);  // the centres' = the points'
        if (vn > -0.1) continue;
        const Collision before = c;
        applyContactImpulse(c.contact, c.p.a, c.p.b);
        const double j = -(1.0 + c.contact.restitution) * vn / (c.p.a.invMass + c.p.b.invMass);
        const double tol = 10.0 * kRounding * speedScale(before);
        for (const auto& [now, old] : {std::pair{&c.p.a, &before.p.a}, std::pair{&c.p.b, &before.p.b}}) {
            const double sign = now == &c.p.a ? -1.0 : 1.0;
            const Vec3 expected = old->velocity + sign * j * old->invMass * n;
            ASSERT_LE((now->velocity - expected).norm(), tol)
                << now->name << "'s velocity " << str(now->velocity) << ", expected " << str(expected)
                << collisionText(before);
            ASSERT_LE((now->angularVelocity - old->angularVelocity).norm(), tol)
                << now->name << "'s angular velocity changed to " << str(now->angularVelocity)
                << ", though the impulse goes through both centres" << collisionText(before);
        }
    }
}

GRADED_TEST(Worksheet6, ContactImpulseNeverAddsEnergy, 2,
            "applyContactImpulse(): with e <= 1 no collision gains kinetic energy (translation and rotation), and with "
            "e = 1 at one point it keeps it exactly. Too large an impulse (an effective mass without its angular "
            "terms, or a wrong sign in them) overshoots and adds energy.",
            grading::dependsOn("ImpulseAtPointConservesMomenta")) {
    Random rnd(624);
    for (int i = 0; i < 300; ++i) {
        const int points = i % 2 == 0 ? 1 : 1 + i % 4;
        const double e = i % 4 == 0 ? 1.0 : rnd.uniform(0.0, 1.0);
        Collision c = randomCollision(rnd, i, points, e);
        const Collision before = c;
        const double k0 = checks::energyOf(c.p.a) + checks::energyOf(c.p.b);
        applyContactImpulse(c.contact, c.p.a, c.p.b);
        const double k1 = checks::energyOf(c.p.a) + checks::energyOf(c.p.b);
        // Energies of up to ~1e3 J round to ~1e-13 J; 1e-11 of them allows any order of operations.
        ASSERT_LE(k1, k0 + 1e-11 * (1.0 + k0))
            << "kinetic energy rose from " << k0 << " J to " << k1 << " J" << collisionText(before);
        if (e == 1.0 && points == 1) {
            ASSERT_NEAR(k1, k0, 1e-11 * (1.0 + k0))
                << "an elastic collision at one point keeps the kinetic energy" << collisionText(before);
        }
    }
}

GRADED_TEST(Worksheet6, ContactImpulseNothingWhenSeparating, 2,
            "applyContactImpulse(): a point where the material points already move apart along the normal gets no "
            "impulse (a contact never pulls): skip it. Use the velocities of the points, v + omega x r, not those "
            "of the centres.") {
    Random rnd(625);
    int changes = 0;
    for (int i = 0; i < 300; ++i) {
        const bool separating = i % 3 != 0;
        Collision c = randomCollision(rnd, i, 1 + i % 4, restitutionFor(rnd, i), separating ? 1.0 : -1.0);
        const Collision before = c;
        applyContactImpulse(c.contact, c.p.a, c.p.b);
        const bool acted = c.p.a.velocity != before.p.a.velocity || c.p.b.velocity != before.p.b.velocity ||
                           c.p.a.angularVelocity != before.p.a.angularVelocity ||
                           c.p.b.angularVelocity != before.p.b.angularVelocity;
        if (!separating) {
            changes += acted;
            continue;
        }
        ASSERT_FALSE(acted) << "every point separates, yet the impulse changed the bodies to\n  a: " << turning(c.p.a)
                            << "\n  b: " << turning(c.p.b) << collisionText(before);
    }
    EXPECT_GT(changes, 0) << "no approaching contact got an impulse either: applyContactImpulse() does nothing yet";
}

// ---- In the engine -----------------------------------------------------------------------------------

GRADED_TEST(Worksheet6, SpinningBoxesKeepAngularMomentum, 3,
            "The scene spinning-boxes: three boxes spun about their largest, middle and smallest axes in zero gravity. "
            "Each keeps its angular momentum exactly; the one spun about its middle axis flips over (that axis turns "
            "to point the other way), the others only wobble. The rotation stage calls integrateRotation() for every "
            "movable body each step.",
            grading::dependsOn("TorqueFreeKeepsAngularMomentum"), grading::dependsOn("TorqueFreeEnergyBounded")) {
    load(engine, scenes().find("spinning-boxes"));
    ASSERT_TRUE(engine.requiredStages().contains(Stage::Rotation));
    const std::vector<Body> start = engine.bodies();
    // Per box: the lowest component along its angular momentum of the body axis it was spun about.
    std::vector<double> lowest(start.size(), 1.0);
    grading::steps(engine, 1000, [&](int k) {  // 10 s
        for (std::size_t i = 0; i < start.size(); ++i) {
            const Body& b = engine.bodies()[i];
            const Vec3 l0 = checks::worldInertia(start[i]) * start[i].angularVelocity;
            const Vec3 l = checks::worldInertia(b) * b.angularVelocity;
            // Rounding per step over 1000 steps, as in TorqueFreeKeepsAngularMomentum.
            ASSERT_LE((l - l0).norm(), 1e-11 * l0.norm()) << "step " << k << ": " << b.name << "'s angular momentum is "
                                                          << str(l) << ", it started as " << str(l0);
            Eigen::Index axis = 0;
            start[i].angularVelocity.cwiseAbs().maxCoeff(&axis);
            lowest[i] = std::min(lowest[i], (b.orientation * Vec3::Unit(axis)).dot(l0.normalized()));
        }
    });
    if (HasFailure()) return;
    for (std::size_t i = 0; i < start.size(); ++i) {
        const std::string& name = start[i].name;
        if (name == "middle-axis") {
            EXPECT_LT(lowest[i], -0.9) << "in 10 s the box spun about its middle axis never turned over (the lowest "
                                          "component of that axis along the angular momentum: "
                                       << lowest[i] << ")";
        } else {
            EXPECT_GT(lowest[i], 0.9) << "the box " << name << " spun about a stable axis turned away from it (the "
                                      << "lowest component of that axis along the angular momentum: " << lowest[i]
                                      << ")";
        }
    }
}

}  // namespace
}  // namespace gpl
