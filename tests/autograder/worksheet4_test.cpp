// Worksheet 4 autograder: the linear collision impulse with restitution, and ropes as contacts that
// only pull. The kernels are called directly on many configurations drawn from a fixed seed and
// compared with closed forms (momentum, -e times the normal velocity, the energy lost); whole scenes
// check bounces, resting contact and a rope in the engine.
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "contacts.h"
#include "gpl/collision.h"
#include "gpl/response.h"
#include "graded.h"

namespace gpl {
namespace {

using checks::Random;
using checks::str;

class Worksheet4 : public checks::ContactsTest {};

// Two bodies about to collide and their contact: a random normal, the pair approaching along it.
struct Collision {
    Body a, b;
    Contact contact;
    double approach;  // (v_b - v_a) . n before the impulse (m/s): < 0 approaching, > 0 separating
};

// The pair and its contact, for messages.
std::string pairText(const Collision& c) {
    return "\n  a: " + str(c.a) + "\n  b: " + str(c.b) + "\n  normal " + str(c.contact.normal) + ", restitution " +
           formatNumber(c.contact.restitution);
}

// `sign` -1: approaching along the normal; +1: separating. Masses 0.1 .. 10 kg, speeds up to 5 m/s.
Collision randomCollision(Random& rnd, double restitution, double sign = -1.0) {
    for (;;) {
        const double ra = rnd.uniform(0.1, 1.0), rb = rnd.uniform(0.1, 1.0);
        Collision c{sphere("a", ra, rnd.uniform(0.1, 10.0)), sphere("b", rb, rnd.uniform(0.1, 10.0)), {}, 0.0};
        Vec3 n = rnd.direction();
        c.a.position = rnd.inBox(10.0);
        c.b.position = c.a.position + (ra + rb - 0.01) * n;
        c.a.velocity = rnd.inBox(5.0);
        c.b.velocity = rnd.inBox(5.0);
        double vn = (c.b.velocity - c.a.velocity).dot(n);
        if (std::abs(vn) < 0.1) continue;  // hardly moving along the normal: tells little
        if (vn * sign < 0.0) {
            std::swap(c.a.velocity, c.b.velocity);
            vn = -vn;
        }
        c.contact = checks::contactAlong(n, 0.01, c.a.position + (ra - 0.005) * n, restitution);
        c.approach = vn;
        return c;
    }
}

// The normal velocity (v_b - v_a) . n of a pair.
double normalSpeed(const Contact& contact, const Body& a, const Body& b) {
    return (b.velocity - a.velocity).dot(contact.normal);
}

// Velocities round to ~1e-16 of the largest speed involved; 1e-12 of it allows any equivalent
// formula (reduced mass, centre-of-mass frame, ...), while every mistake here is off by ~0.1 m/s.
constexpr double kRounding = 1e-12;
double speedScale(const Collision& c) { return 1.0 + c.a.velocity.norm() + c.b.velocity.norm(); }

// Restitutions for the impulse tests: the ends 0 and 1 and values between.
double restitutionFor(Random& rnd, int i) { return i % 7 == 0 ? 0.0 : i % 7 == 1 ? 1.0 : rnd.uniform(0.0, 1.0); }

// Doing nothing keeps momentum and tangential velocities and never pulls: tests of those also ask
// that the impulse acted at all (on any pair), and leave how much to the other tests.
bool acted(const Collision& now, const Collision& before) {
    return now.a.velocity != before.a.velocity || now.b.velocity != before.b.velocity;
}
constexpr const char* kNeverActed = "the impulse never changed a velocity: applyCollisionImpulse() does nothing yet";

// ---- applyCollisionImpulse() -------------------------------------------------------------------------

GRADED_TEST(Worksheet4, ImpulseConservesMomentum, 3,
            "applyCollisionImpulse(): one impulse j n acts on b and its opposite -j n on a, so the total momentum "
            "m_a v_a + m_b v_b stays the same: change each velocity by the impulse times that body's inverse mass "
            "(worksheet 4, assignment 2).") {
    Random rnd(401);
    int changes = 0;
    for (int i = 0; i < 300; ++i) {
        Collision c = randomCollision(rnd, restitutionFor(rnd, i));
        const Collision before = c;
        applyCollisionImpulse(c.contact, c.a, c.b);
        changes += acted(c, before);
        const Vec3 p0 = before.a.mass * before.a.velocity + before.b.mass * before.b.velocity;
        const Vec3 p1 = c.a.mass * c.a.velocity + c.b.mass * c.b.velocity;
        // Relative to the momenta involved: rounding only (DESIGN: 1e-12).
        const double scale = before.a.mass * before.a.velocity.norm() + before.b.mass * before.b.velocity.norm();
        ASSERT_LE((p1 - p0).norm(), kRounding * scale)
            << "momentum " << str(p1) << " after the impulse, " << str(p0) << " before" << pairText(before);
    }
    EXPECT_GT(changes, 0) << kNeverActed;
}

GRADED_TEST(Worksheet4, ImpulseReversesNormalVelocity, 3,
            "applyCollisionImpulse(): afterwards (v_b - v_a) . n must be exactly -e times what it was: "
            "j = -(1 + e) v_rel / (1/m_a + 1/m_b), with the restitution e of the contact and both inverse "
            "masses.") {
    Random rnd(402);
    for (int i = 0; i < 300; ++i) {
        Collision c = randomCollision(rnd, restitutionFor(rnd, i));
        const Collision before = c;
        applyCollisionImpulse(c.contact, c.a, c.b);
        const double after = normalSpeed(c.contact, c.a, c.b), e = c.contact.restitution;
        const bool onePlusE = std::abs(after - (1.0 - e) * before.approach) < 1e-9;
        ASSERT_NEAR(after, -e * before.approach, kRounding * speedScale(before))
            << "normal velocity after the impulse; it was " << before.approach << " m/s, so with e = " << e
            << " it must become " << -e * before.approach << " m/s" << pairText(before)
            << (onePlusE ? "\n  this is (1 - e) times: the 1 of (1 + e) is missing" : "");
    }
}

GRADED_TEST(Worksheet4, ImpulseAnswersSlowApproaches, 2,
            "applyCollisionImpulse() for two free bodies that approach slowly, from 1e-5 to 1e-2 m/s: any approach, "
            "however slow, gets its impulse (-e times it afterwards); only a separating pair gets nothing. A threshold "
            "below which nothing happens lets resting bodies sink into each other.",
            grading::dependsOn("ImpulseReversesNormalVelocity")) {
    Random rnd(408);
    for (int i = 0; i < 300; ++i) {
        Collision c = randomCollision(rnd, restitutionFor(rnd, i));
        // Slow the approach down to 1e-5 .. 1e-2 m/s, evenly over the decades; the tangential parts stay.
        const Vec3 n = c.contact.normal;
        const double slow = -std::pow(10.0, rnd.uniform(-5.0, -2.0));
        c.b.velocity += (slow - c.approach) * n;
        c.approach = normalSpeed(c.contact, c.a, c.b);
        const Collision before = c;
        applyCollisionImpulse(c.contact, c.a, c.b);
        const double after = normalSpeed(c.contact, c.a, c.b), e = c.contact.restitution;
        // Speeds of a few m/s round to ~1e-15 m/s; the slowest approach is 1e-5 m/s.
        ASSERT_NEAR(after, -e * before.approach, kRounding * speedScale(before) + 1e-6 * std::abs(before.approach))
            << "normal velocity after the impulse; it was " << before.approach << " m/s, so with e = " << e
            << " it must become " << -e * before.approach << " m/s" << pairText(before)
            << (after == before.approach ? "\n  nothing happened: a slow approach needs its impulse too" : "");
    }
}

GRADED_TEST(Worksheet4, ImpulseKeepsTangentialVelocity, 2,
            "applyCollisionImpulse(): without friction the impulse acts along the normal only, so each body's "
            "velocity across the normal stays as it was: change the velocities by multiples of n, computed from "
            "the normal part (v_b - v_a) . n of the relative velocity only.") {
    Random rnd(403);
    int changes = 0;
    for (int i = 0; i < 300; ++i) {
        Collision c = randomCollision(rnd, restitutionFor(rnd, i));
        const Collision before = c;
        applyCollisionImpulse(c.contact, c.a, c.b);
        changes += acted(c, before);
        const Vec3 n = c.contact.normal;
        for (const auto& [now, old] : {std::pair{&c.a, &before.a}, std::pair{&c.b, &before.b}}) {
            const Vec3 change = now->velocity - old->velocity;
            ASSERT_LE((change - change.dot(n) * n).norm(), kRounding * speedScale(before))
                << now->name << "'s velocity changed across the normal by " << str(change - change.dot(n) * n)
                << pairText(before);
        }
    }
    EXPECT_GT(changes, 0) << kNeverActed;
}

GRADED_TEST(Worksheet4, ImpulseEnergyLoss, 2,
            "A collision with restitution e loses exactly (1 - e^2)/2 v_rel^2 / (1/m_a + 1/m_b) of kinetic energy "
            "(nothing when e = 1): it follows from momentum and from v_rel becoming -e v_rel. Use e itself, not e^2, "
            "in the impulse.") {
    Random rnd(404);
    for (int i = 0; i < 300; ++i) {
        Collision c = randomCollision(rnd, i % 5 == 0 ? 1.0 : rnd.uniform(0.0, 0.95));
        const Collision before = c;
        const double e = c.contact.restitution;
        applyCollisionImpulse(c.contact, c.a, c.b);
        const double k0 = kineticEnergy(before.a) + kineticEnergy(before.b);
        const double lost = k0 - kineticEnergy(c.a) - kineticEnergy(c.b);
        const double expected =
            0.5 * (1.0 - e * e) * before.approach * before.approach / (before.a.invMass + before.b.invMass);
        // Energies of ~1e3 J round to ~1e-13 J; 1e-12 of the energy allows any ordering.
        ASSERT_NEAR(lost, expected, kRounding * (1.0 + k0))
            << "kinetic energy lost in the collision (e = " << e << ")" << pairText(before);
    }
}

GRADED_TEST(Worksheet4, ImpulseChangesOnlyVelocities, 2,
            "applyCollisionImpulse() changes velocities only: positions (and orientations) stay exactly where they "
            "are. Overlaps are resolveInterpenetration()'s business, which runs as a stage of its own (worksheet 4, "
            "assignment 2).",
            grading::dependsOn("ImpulseReversesNormalVelocity")) {
    Random rnd(407);
    for (int i = 0; i < 300; ++i) {
        Collision c = randomCollision(rnd, restitutionFor(rnd, i));
        if (i % 4 == 3) c.a.makeStatic();
        const Collision before = c;
        applyCollisionImpulse(c.contact, c.a, c.b);
        for (const auto& [now, old] : {std::pair{&c.a, &before.a}, std::pair{&c.b, &before.b}}) {
            ASSERT_TRUE(now->position == old->position && now->orientation.coeffs() == old->orientation.coeffs())
                << now->name << " moved from " << str(old->position) << " to " << str(now->position)
                << ": an impulse changes velocities only" << pairText(before);
        }
    }
}

GRADED_TEST(Worksheet4, ImpulseNothingWhenSeparating, 2,
            "applyCollisionImpulse(): bodies that already move apart along the normal, (v_b - v_a) . n >= 0, get "
            "no impulse at all (a contact never pulls): return before changing anything.") {
    Random rnd(405);
    int changes = 0;
    for (int i = 0; i < 300; ++i) {
        const bool separating = i % 3 != 0;
        Collision c = randomCollision(rnd, restitutionFor(rnd, i), separating ? 1.0 : -1.0);
        if (i % 30 == 1) c.b.velocity = c.a.velocity;  // moving together: v_rel = 0 exactly, no impulse either
        const Collision before = c;
        applyCollisionImpulse(c.contact, c.a, c.b);
        if (!separating && i % 30 != 1) {
            changes += acted(c, before);
            continue;
        }
        ASSERT_LE((c.a.velocity - before.a.velocity).norm() + (c.b.velocity - before.b.velocity).norm(),
                  kRounding * speedScale(before))
            << "the bodies separate at " << normalSpeed(before.contact, before.a, before.b)
            << " m/s along the normal, yet the impulse changed their velocities to " << str(c.a.velocity) << " and "
            << str(c.b.velocity) << pairText(before);
    }
    EXPECT_GT(changes, 0) << "no approaching pair got an impulse either: " << kNeverActed;
}

GRADED_TEST(Worksheet4, ImpulseAgainstStaticBody, 2,
            "applyCollisionImpulse() with a static body (invMass 0, infinite mass): it keeps its zero velocity and "
            "the other body's normal velocity becomes -e times what it was; with inverse masses nothing is "
            "infinite (m_a m_b / (m_a + m_b) is infinity / infinity for a static body).") {
    Random rnd(406);
    for (int i = 0; i < 300; ++i) {
        Collision c = randomCollision(rnd, restitutionFor(rnd, i));
        Body& fixed = i % 2 == 0 ? c.b : c.a;
        Body& free = i % 2 == 0 ? c.a : c.b;
        fixed.makeStatic();  // a floor, a wall, an anchor
        double vn = normalSpeed(c.contact, c.a, c.b);
        if (vn >= 0.0) {
            free.velocity -= 2.0 * (free.velocity.dot(c.contact.normal)) * c.contact.normal;  // mirror: approach
            vn = normalSpeed(c.contact, c.a, c.b);
        }
        const Collision before = c;
        applyCollisionImpulse(c.contact, c.a, c.b);
        const double e = c.contact.restitution;
        ASSERT_TRUE(fixed.velocity == Vec3::Zero())
            << "the static body gained the velocity " << str(fixed.velocity) << pairText(before);
        ASSERT_TRUE(isFinite(free.velocity))
            << "the movable body's velocity is " << str(free.velocity) << pairText(before);
        ASSERT_NEAR(normalSpeed(c.contact, c.a, c.b), -e * vn, kRounding * speedScale(before))
            << "normal velocity against a static body; it was " << vn << " m/s" << pairText(before);
    }
}

// ---- ropeContact() -----------------------------------------------------------------------------------

// Two bodies `distance` apart on a rope of `length`.
std::pair<Body, Body> roped(Random& rnd, double distance) {
    const Vec3 xa = rnd.inBox(10.0);
    return {sphere("a", 0.2, rnd.uniform(0.1, 10.0)).at(xa),
            sphere("b", 0.3, rnd.uniform(0.1, 10.0)).at(xa + distance * rnd.direction())};
}

std::string ropeText(const Body& a, const Body& b, double length) {
    return "\n  a at " + str(a.position) + ", b at " + str(b.position) + ", " +
           formatNumber((a.position - b.position).norm()) + " m apart, rope length " + formatNumber(length) + " m";
}

GRADED_TEST(Worksheet4, RopeTautPulls, 3,
            "ropeContact() for a rope stretched beyond its length: the normal points along the rope from b towards "
            "a, (x_a - x_b) / |x_a - x_b|, so that 'separating' along it pulls the ends together; the depth is the "
            "stretch |x_a - x_b| - length, however small; one point on the rope between the ends (worksheet 4, "
            "assignment 1).") {
    Random rnd(411);
    for (int i = 0; i < 300; ++i) {
        const double length = rnd.uniform(0.5, 5.0);
        // Stretched by 0.1 % to 50 %, every fifth only by 1e-6 to 1e-3 m: any stretch at all pulls.
        const double stretch = i % 5 == 0 ? std::exp(rnd.uniform(std::log(1e-6), std::log(1e-3)))
                                          : length * rnd.uniform(0.001, 0.5);  // m
        const auto [a, b] = roped(rnd, length + stretch);
        const std::optional<Contact> c = ropeContact(a, b, length);
        const Vec3 ba = a.position - b.position;
        const double distance = ba.norm();
        const Vec3 normal = ba / distance;
        // Lengths from coordinates up to ~15 m: rounding of ~1e-15 m.
        const double tol = kRounding * (1.0 + a.position.norm() + b.position.norm());
        ASSERT_TRUE(c) << "no contact for a rope stretched by " << distance - length << " m" << ropeText(a, b, length);
        ASSERT_NEAR(c->normal.norm(), 1.0, kRounding) << "the normal " << str(c->normal) << " is not a unit vector";
        ASSERT_LE((c->normal - normal).norm(), kRounding)
            << "normal " << str(c->normal) << ", expected " << str(normal) << " (from b towards a)"
            << ropeText(a, b, length)
            << ((c->normal + normal).norm() < 1e-9 ? "\n  it is flipped: along it the engine would push the ends apart"
                                                   : "");
        ASSERT_NEAR(c->depth, distance - length, tol) << "depth, expected the stretch" << ropeText(a, b, length);
        ASSERT_EQ(c->pointCount, 1) << ropeText(a, b, length);
        const double t = (c->points[0] - b.position).dot(normal);  // from b towards a (m)
        ASSERT_LE((c->points[0] - b.position - t * normal).norm(), tol)
            << "the point " << str(c->points[0]) << " is off the rope" << ropeText(a, b, length);
        ASSERT_TRUE(t >= -tol && t <= distance + tol)
            << "the point " << str(c->points[0]) << " is not between the ends" << ropeText(a, b, length);
    }
}

GRADED_TEST(Worksheet4, RopeSlackDoesNothing, 2,
            "ropeContact(): a rope no longer than the distance of its ends, |x_a - x_b| <= length, is slack or just "
            "taut and does nothing: no contact (std::nullopt). A rope only pulls; it never pushes the ends apart.") {
    Random rnd(412);
    for (int i = 0; i < 300; ++i) {
        const double length = rnd.uniform(0.5, 5.0);
        const bool slack = i % 4 != 0;
        const auto [a, b] = roped(rnd, length * (slack ? rnd.uniform(0.0, 0.999) : 1.0 + rnd.uniform(0.001, 0.5)));
        const std::optional<Contact> c = ropeContact(a, b, length);
        if (slack) {
            ASSERT_FALSE(c) << "a slack rope, yet: " << str(c) << ropeText(a, b, length);
        } else {
            ASSERT_TRUE(c) << "a stretched rope, but no contact" << ropeText(a, b, length);
        }
    }
    // Exactly taut (distances exact in binary), and both ends at one point.
    const Body a = sphere("a", 0.2, 1.0).at({1.0, 2.0, 3.0});
    for (const auto& [at, length] : {std::pair{Vec3(1.75, 3.0, 3.0), 1.25}, std::pair{Vec3(1.0, 2.0, 3.0), 2.0}}) {
        const Body b = sphere("b", 0.2, 1.0).at(at);
        const std::optional<Contact> c = ropeContact(a, b, length);
        ASSERT_FALSE(c) << "a rope that is just taut (or slack) does nothing, yet: " << str(c)
                        << ropeText(a, b, length);
    }
}

// ---- In the engine -----------------------------------------------------------------------------------
// These step the engine with the student's worksheet-1 and 3 hooks too: they depend on those tests,
// so that a mistake there shows here as "not run" rather than as an impulse or rope mistake.

const StageSet kImpulses{Stage::ConstantAcceleration, Stage::Integration, Stage::CollisionDetection,
                         Stage::CollisionImpulses, Stage::Interpenetration};

GRADED_TEST(Worksheet4, BounceHeightsFallLikeESquared, 3,
            "A ball dropped on a floor (restitution 1) leaves it at e times its impact speed, so each rebound "
            "reaches e^2 times the height before. Check the restitution in applyCollisionImpulse().",
            grading::dependsOn("Worksheet1.MatchesDiscreteFreeFall"), grading::dependsOn("Worksheet3.SpherePlaneFloor"),
            grading::dependsOn("Worksheet3.ResolveStaticBodyUntouched")) {
    engine.setRequiredStages(kImpulses);
    const double h = 0.002, r = 0.2, drop = 2.0;  // s, m, m (above touching)
    engine.setTimeStep(h);
    engine.add(plane("floor", {0.0, 1.0, 0.0}));
    const double restitutions[] = {0.0, 0.3, 0.5, 0.7, 0.9};
    for (int i = 0; i < 5; ++i) {
        engine.add(sphere("e=" + formatNumber(restitutions[i]), r, 1.0 + i)
                       .at({1.0 * i, r + drop, 0.0})
                       .bouncy(restitutions[i]));
    }
    // Heights of the tops of each ball's flights above touching (m), the drop first.
    std::vector<std::vector<double>> apexes(6, std::vector<double>{drop});
    std::vector<double> highest(6, 0.0);
    std::vector<bool> rising(6, false);
    grading::steps(engine, 3000, [&](int) {  // 6 s: four bounces of the liveliest ball
        for (std::size_t i = 1; i < 6; ++i) {
            const Body& b = engine.bodies()[i];
            if (b.velocity.y() > 0.0) {
                rising[i] = true;
                highest[i] = b.position.y() - r;
            } else if (rising[i]) {
                rising[i] = false;
                apexes[i].push_back(std::max(highest[i], b.position.y() - r));
            }
        }
    });
    if (HasFailure()) return;
    const double g = engine.gravity().norm();
    for (std::size_t i = 1; i < 6; ++i) {
        const double e = restitutions[i - 1];
        const std::string name = engine.bodies()[i].name;
        const std::vector<double>& top = apexes[i];
        for (std::size_t k = 0; k + 1 < std::max<std::size_t>(top.size(), 2) && k < 4; ++k) {
            const double impact = std::sqrt(2.0 * g * top[k]);
            // The contact is found up to a step late, at most v h deep, which the resolution turns into
            // height; semi-implicit Euler's fall and rise each lose about v h / 2: 2 v h in all (5 % of
            // the 0.5 m the first bounce reaches with e = 0.5), while a wrong restitution law misses by
            // tens of percent.
            const double tol = 2.0 * impact * h;
            if (e * e * top[k] < 4.0 * tol) break;  // too low to tell e^2 from the step's error
            ASSERT_GT(top.size(), k + 1) << "ball " << name << " did not rise again after bounce " << k + 1;
            EXPECT_NEAR(top[k + 1], e * e * top[k], tol)
                << "ball " << name << ": bounce " << k + 1 << " from " << top[k] << " m reached " << top[k + 1]
                << " m, e^2 times is " << e * e * top[k] << " m";
        }
        if (e == 0.0) {
            const double after = top.size() > 1 ? *std::max_element(top.begin() + 1, top.end()) : 0.0;
            EXPECT_LE(after, 2.0 * std::sqrt(2.0 * g * drop) * h)
                << "ball " << name << " (e = 0) must not bounce, yet it rose " << after << " m";
            EXPECT_LT(engine.bodies()[i].position.y(), r + drop / 2) << "ball " << name << " never came down";
        }
    }
}

GRADED_TEST(Worksheet4, RestingBallStaysPut, 2,
            "A ball resting on a floor must stay there for good: each step gravity presses it into the floor "
            "by g h^2, the impulse stops (or barely bounces) it and the resolution lifts it out. It must neither "
            "sink nor jitter: check the sign of the impulse.",
            grading::dependsOn("Worksheet1.MatchesDiscreteFreeFall"), grading::dependsOn("Worksheet3.SpherePlaneFloor"),
            grading::dependsOn("Worksheet3.ResolveStaticBodyUntouched")) {
    engine.setRequiredStages(kImpulses);
    engine.add(plane("floor", {0.0, 1.0, 0.0}).at({0.0, -1.5, 0.0}));
    const double r = 0.3, restitutions[] = {0.0, 0.5, 1.0};
    for (int i = 0; i < 3; ++i) {
        engine.add(sphere("e=" + formatNumber(restitutions[i]), r, 0.5 + 2.0 * i)
                       .at({1.5 * i, -1.5 + r, 0.5 * i})
                       .bouncy(restitutions[i]));
    }
    const std::vector<Body> start = engine.bodies();
    const double h = engine.timeStep(), g = engine.gravity().norm();
    int contacts = 0;
    grading::steps(engine, 1000, [&](int k) {  // 10 s
        contacts += static_cast<int>(engine.contacts().size());
        for (std::size_t i = 1; i < start.size(); ++i) {
            const Body& b = engine.bodies()[i];
            // One step of gravity moves a ball at rest by g h^2 and gives it g h: a resting ball may be
            // found that deep in the floor, and bounce with at most that speed (e = 1), never more.
            ASSERT_LE(std::abs(b.position.y() - start[i].position.y()), g * h * h)
                << "step " << k << ": " << b.name << " is " << b.position.y() - start[i].position.y()
                << " m from where it rests" << (b.position.y() < start[i].position.y() ? " (sinking)" : " (jumping)");
            ASSERT_LE(b.velocity.norm(), g * h * (1.0 + 1e-9))
                << "step " << k << ": " << b.name << " moves at " << str(b.velocity);
            // No friction and no sideways impulse: x and z stay exactly (rounding aside).
            ASSERT_LE(std::hypot(b.position.x() - start[i].position.x(), b.position.z() - start[i].position.z()), 1e-12)
                << "step " << k << ": " << b.name << " drifted sideways to " << str(b.position);
        }
    });
    if (HasFailure()) return;
    EXPECT_GT(contacts, 1000) << "the balls hardly pressed on the floor (" << contacts << " contacts in 1000 steps)";
}

GRADED_TEST(Worksheet4, RopeHoldsFallingBall, 3,
            "A ball on a slack rope falls freely (the rope does nothing) until the rope is taut; from then on the "
            "rope holds it at exactly its length as it swings: the stretch is the depth, and resolving it pulls the "
            "ball back along the rope.",
            grading::dependsOn("Worksheet1.MatchesDiscreteFreeFall"),
            grading::dependsOn("Worksheet3.ResolveStaticBodyUntouched")) {
    // Contacts answered by moving positions (the velocity follows), as in worksheet 3: the rope alone.
    engine.setRequiredStages({Stage::ConstantAcceleration, Stage::Integration, Stage::Ropes, Stage::Interpenetration});
    const double length = 2.0, h = engine.timeStep();
    const Vec3 anchor(0.0, 5.0, 0.0), x0 = anchor + Vec3(-0.6 * length, 0.0, 0.3);
    engine.add(sphere("anchor", 0.05, 1.0).at(anchor).makeStatic());
    engine.add(sphere("ball", 0.2, 1.5).at(x0));
    engine.addRope("anchor", "ball", length);
    const Vec3 g = engine.gravity();
    bool taut = false;
    grading::steps(engine, 300, [&](int k) {
        const Body& ball = engine.body("ball");
        const double distance = (ball.position - anchor).norm();
        // Free fall from rest after k steps of semi-implicit Euler (worksheet 1).
        const Vec3 free = x0 + 0.5 * k * (k + 1) * h * h * g;
        // Rounding of positions of ~5 m over up to 300 steps: 1e-12 of them; anything a rope does is
        // at least a step's fall, g h^2 = 1e-3 m.
        const double tol = 1e-12 * 10.0;
        if (!taut && (free - anchor).norm() < length) {
            ASSERT_LE((ball.position - free).norm(), tol)
                << "step " << k << ": the rope is slack (the ball " << (free - anchor).norm() << " m from the anchor, "
                << "rope " << length << " m), so the ball falls freely to " << str(free) << ", but it is at "
                << str(ball.position) << ": a slack rope must do nothing";
            return;
        }
        taut = true;
        ASSERT_NEAR(distance, length, tol * 10.0)
            << "step " << k << ": the ball is " << distance << " m from the anchor; the taut rope must hold it at "
            << length << " m" << (distance > length ? " (it pulls too little or pushes)" : " (it pulls too far)");
    });
    if (HasFailure()) return;
    EXPECT_TRUE(taut) << "the rope never became taut: did the ball fall?";
    EXPECT_LT(engine.body("ball").position.y(), anchor.y() - 0.25 * length) << "the ball should hang below the anchor";
}

}  // namespace
}  // namespace gpl
