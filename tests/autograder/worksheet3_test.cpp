// Worksheet 3 autograder: sphere-sphere and sphere-plane contacts, and moving overlapping bodies
// apart. The kernels are called directly on many configurations drawn from a fixed seed and
// compared with the geometry (closed forms); whole scenes check what the engine makes of them.
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "contacts.h"
#include "gpl/collision.h"
#include "gpl/response.h"
#include "gpl/scenes.h"
#include "graded.h"

namespace gpl {
namespace {

using checks::Random;
using checks::str;

class Worksheet3 : public checks::ContactsTest {};

// Lengths computed from coordinates of size s (m) round to ~1e-16 s; 1e-12 s allows any
// equivalent formula, while every mistake these tests look for is off by millimetres or more.
constexpr double kRounding = 1e-12;

double scaleOf(const Body& a, const Body& b) {
    return 1.0 + a.position.norm() + b.position.norm() + a.radius + b.radius;
}

// Two spheres whose centres are a random fraction in [lo, hi] of the sum of their radii apart
// (overlapping below 1), masses 0.1 .. 10 kg.
std::pair<Body, Body> spherePair(Random& rnd, double lo, double hi) {
    const double ra = rnd.uniform(0.1, 2.0), rb = rnd.uniform(0.1, 2.0);
    const Vec3 xa = rnd.inBox(10.0);
    const Vec3 xb = xa + rnd.uniform(lo, hi) * (ra + rb) * rnd.direction();
    return {sphere("a", ra, rnd.uniform(0.1, 10.0)).at(xa), sphere("b", rb, rnd.uniform(0.1, 10.0)).at(xb)};
}

std::string pairText(const Body& a, const Body& b) { return "\n  a: " + str(a) + "\n  b: " + str(b); }

// Spheres exactly touching: coordinates and radii whose sums, differences, squares and square
// roots are exact in binary, so |x_b - x_a| equals r_a + r_b to the last bit.
std::vector<std::pair<Body, Body>> touchingSpheres() {
    return {{sphere("a", 0.5, 1.0).at({1.0, 2.0, 3.0}), sphere("b", 0.75, 2.0).at({1.75, 3.0, 3.0})},
            {sphere("a", 1.0, 1.0).at({-4.0, 0.5, 2.0}), sphere("b", 1.5, 1.0).at({-4.0, 0.5, 4.5})},
            {sphere("a", 3.0, 5.0).at({0.0, 0.0, 0.0}), sphere("b", 4.0, 0.5).at({2.0, 3.0, 6.0})},
            {sphere("a", 0.25, 1.0).at({10.0, -10.0, 10.0}), sphere("b", 0.25, 1.0).at({10.5, -10.0, 10.0})}};
}

// A plane with a random normal, turned by a random rotation and moved off the origin.
Body randomPlane(Random& rnd) { return plane("plane", rnd.direction()).at(rnd.inBox(10.0)).rotated(rnd.rotation()); }

// A sphere whose centre is `height` (m) in front of the plane, somewhere along it.
Body sphereAbove(Random& rnd, const Body& p, double radius, double height) {
    const Vec3 n = checks::worldNormal(p);
    const Vec3 along = rnd.uniform(0.0, 5.0) * rnd.perpendicular(n);
    return sphere("ball", radius, rnd.uniform(0.1, 10.0)).at(p.position + height * n + along);
}

std::string planeText(const Body& s, const Body& p) { return "\n  sphere: " + str(s) + "\n  plane: " + str(p); }

// Planes with normals along the axes (one turned half a turn about x, which is exact) and spheres
// exactly touching them.
std::vector<std::pair<Body, Body>> touchingPlanes() {
    return {{sphere("ball", 0.5, 1.0).at({1.5, 0.5, -2.0}), plane("floor", {0.0, 1.0, 0.0})},
            {sphere("ball", 0.75, 1.0).at({2.25, 7.0, 1.0}), plane("wall", {-1.0, 0.0, 0.0}).at({3.0, 0.0, 0.0})},
            {sphere("ball", 0.5, 1.0).at({0.25, 1.0, 0.5}),
             plane("ceiling", {0.0, 1.0, 0.0}).at({0.0, 1.5, 0.0}).rotated(Quat(0.0, 1.0, 0.0, 0.0))},
            {sphere("ball", 1.25, 1.0).at({0.0, 3.0, -1.25}), plane("back", {0.0, 0.0, 1.0}).at({0.0, 0.0, -2.5})}};
}

// The contact a sphere-plane kernel must report, from the geometry.
struct Expected {
    Vec3 normal;
    double depth;
};
Expected expectedPlaneContact(const Body& s, const Body& p) {
    return {-checks::worldNormal(p), s.radius - checks::heightAbove(p, s.position)};
}

// Compares a sphere-plane contact with the geometry; the message names what is off and how.
::testing::AssertionResult matchesPlane(const std::optional<Contact>& c, const Body& s, const Body& p) {
    const Expected e = expectedPlaneContact(s, p);
    const double tol = kRounding * scaleOf(s, p);
    if (!c) {
        return ::testing::AssertionFailure()
               << "no contact, but the sphere reaches " << e.depth << " m into the plane" << planeText(s, p);
    }
    // Written as "not within": a NaN fails too.
    if (!(std::abs(c->normal.norm() - 1.0) <= kRounding) || !((c->normal - e.normal).norm() <= kRounding)) {
        auto f = ::testing::AssertionFailure()
                 << "normal " << str(c->normal) << ", expected " << str(e.normal)
                 << " (from the sphere into the plane: minus the plane's world normal)" << planeText(s, p);
        if ((c->normal + e.normal).norm() < 1e-9) f << "\n  it is flipped: it points out of the plane";
        if ((c->normal - (-p.normal)).norm() < 1e-9) f << "\n  the plane's orientation was not applied to its normal";
        return f;
    }
    if (!(std::abs(c->depth - e.depth) <= tol)) {
        auto f = ::testing::AssertionFailure()
                 << "depth " << c->depth << " m, expected r - (n . (x - p)) = " << e.depth << " m" << planeText(s, p);
        if (std::abs(c->depth + e.depth) < 1e-9) f << "\n  the sign is flipped: depth is positive when they overlap";
        return f;
    }
    return ::testing::AssertionSuccess();
}

// Contacts answered by moving positions, the velocity following the move (worksheet 3's scenes).
const StageSet kPositional{Stage::ConstantAcceleration, Stage::Integration, Stage::CollisionDetection,
                           Stage::Interpenetration};

// ---- sphereSphere() -------------------------------------------------------------------------------

GRADED_TEST(Worksheet3, SphereSphereNormalAndDepth, 3,
            "sphereSphere(): the normal is the unit vector from a's centre towards b's, (x_b - x_a) / |x_b - x_a|; "
            "the depth is r_a + r_b - |x_b - x_a|, both radii, positive while they overlap (worksheet 3, "
            "assignment 1).") {
    Random rnd(301);
    for (int i = 0; i < 300; ++i) {
        const auto [a, b] = spherePair(rnd, 0.02, 0.98);
        const Vec3 ab = b.position - a.position;
        const Vec3 normal = ab / ab.norm();
        const double depth = checks::overlap(a, b);
        const std::optional<Contact> c = sphereSphere(a, b);
        ASSERT_TRUE(c) << "no contact, but the spheres overlap by " << depth << " m" << pairText(a, b);
        ASSERT_NEAR(c->normal.norm(), 1.0, kRounding) << "the normal " << str(c->normal) << " is not a unit vector";
        ASSERT_LE((c->normal - normal).norm(), kRounding)
            << "normal " << str(c->normal) << ", expected " << str(normal) << pairText(a, b)
            << ((c->normal + normal).norm() < 1e-9 ? "\n  it is flipped: it must point from a towards b" : "");
        ASSERT_NEAR(c->depth, depth, kRounding * scaleOf(a, b))
            << "depth, expected r_a + r_b - |x_b - x_a|" << pairText(a, b)
            << (std::abs(c->depth + depth) < 1e-9 ? "\n  the sign is flipped: depth is positive while they overlap"
                                                  : "");
    }
}

GRADED_TEST(Worksheet3, SphereSphereApartOrTouching, 2,
            "sphereSphere(): spheres that are apart, or touch at exactly one point (|x_b - x_a| = r_a + r_b), have "
            "no contact (std::nullopt); any overlap at all, however small, is a contact.") {
    Random rnd(302);
    for (int i = 0; i < 200; ++i) {
        const auto [a, b] = spherePair(rnd, 1.02, 3.0);
        const std::optional<Contact> c = sphereSphere(a, b);
        ASSERT_FALSE(c) << "the spheres are " << -checks::overlap(a, b) << " m apart, yet: " << str(c)
                        << pairText(a, b);
    }
    for (const auto& [a, b] : touchingSpheres()) {
        ASSERT_EQ(checks::overlap(a, b), 0.0) << "test setup: the spheres must touch exactly";
        const std::optional<Contact> c = sphereSphere(a, b);
        ASSERT_FALSE(c) << "the spheres touch at one point, which is no contact, yet: " << str(c) << pairText(a, b)
                        << "\n  only depth > 0 is a contact";
        // Overlaps of 1e-6 and 1e-9 of the radii are contacts: the smaller still 1e4 times the rounding of
        // the centres' distance (1e-16 of positions up to 20 m), and no tolerance of a student's may drop it.
        for (const double share : {1e-6, 1e-9}) {
            const double gap = share * (a.radius + b.radius);
            Body closer = b;
            closer.position -= gap * (b.position - a.position).normalized();
            const std::optional<Contact> d = sphereSphere(a, closer);
            ASSERT_TRUE(d) << "the spheres overlap by " << gap << " m but there is no contact" << pairText(a, closer)
                           << "\n  any overlap, however small, is a contact: compare the depth with 0, not a tolerance";
            ASSERT_NEAR(d->depth, gap, kRounding * scaleOf(a, b)) << "depth of a tiny overlap" << pairText(a, closer);
        }
    }
}

GRADED_TEST(Worksheet3, SphereSphereConcentric, 1,
            "sphereSphere(): spheres with the same centre have no line of centres; don't divide by the zero "
            "distance: use the normal (0, 1, 0) and the depth r_a + r_b.") {
    Random rnd(303);
    for (const auto& [ra, rb] : {std::pair{0.5, 0.5}, std::pair{0.3, 2.0}, std::pair{1.7, 0.2}}) {
        const Vec3 x = rnd.inBox(10.0);
        const Body a = sphere("a", ra, 1.0).at(x), b = sphere("b", rb, 3.0).at(x);
        const std::optional<Contact> c = sphereSphere(a, b);
        ASSERT_TRUE(c) << "concentric spheres overlap completely, but there is no contact" << pairText(a, b);
        ASSERT_TRUE(isFinite(c->normal) && std::isfinite(c->depth))
            << "not a number: " << str(c) << pairText(a, b) << "\n  x / 0 is NaN: test for the zero distance first";
        EXPECT_LE((c->normal - Vec3::UnitY()).norm(), kRounding)
            << "normal " << str(c->normal) << ", expected the fixed (0, 1, 0)" << pairText(a, b);
        EXPECT_NEAR(c->depth, ra + rb, kRounding * scaleOf(a, b)) << "depth, expected r_a + r_b" << pairText(a, b);
    }
}

GRADED_TEST(Worksheet3, SphereSphereSymmetric, 2,
            "sphereSphere(b, a) must describe the same contact as sphereSphere(a, b): the same depth and the "
            "opposite normal. Use each sphere's own radius (r_a + r_b) and the direction from the first towards "
            "the second.") {
    Random rnd(304);
    for (int i = 0; i < 300; ++i) {
        const bool apart = i % 5 == 4;
        const auto [a, b] = apart ? spherePair(rnd, 1.02, 2.0) : spherePair(rnd, 0.02, 0.98);
        const std::optional<Contact> ab = sphereSphere(a, b), ba = sphereSphere(b, a);
        if (apart) {
            ASSERT_FALSE(ab || ba) << "spheres apart: " << str(ab) << " and swapped " << str(ba) << pairText(a, b);
            continue;
        }
        ASSERT_TRUE(ab && ba) << "overlapping spheres: " << str(ab) << ", swapped: " << str(ba) << pairText(a, b);
        ASSERT_NEAR(ab->depth, ba->depth, kRounding * scaleOf(a, b))
            << "the depth changes when the spheres are swapped" << pairText(a, b);
        ASSERT_LE((ab->normal + ba->normal).norm(), kRounding)
            << "normals " << str(ab->normal) << " and swapped " << str(ba->normal) << ": they must be opposite"
            << pairText(a, b);
    }
}

GRADED_TEST(Worksheet3, SphereSphereContactPoint, 2,
            "sphereSphere(): the contact point lies on the line of centres inside both spheres (for example "
            "halfway between the two surfaces), in world coordinates; pointCount = 1 (Contact::at() sets it). "
            "When the smaller sphere lies within the larger, halfway between the surfaces can lie outside it: take "
            "a point of the stretch inside both.") {
    Random rnd(305);
    for (int i = 0; i < 300; ++i) {
        auto [a, b] = spherePair(rnd, 0.02, 0.98);
        if (i % 4 == 3) {  // the smaller sphere within the larger, off its centre
            Body& small = a.radius < b.radius ? a : b;
            const Body& large = a.radius < b.radius ? b : a;
            small.radius = rnd.uniform(0.05, 0.3) * large.radius;
            small.position = large.position + rnd.uniform(0.1, 0.9) * (large.radius - small.radius) * rnd.direction();
        }
        const std::optional<Contact> c = sphereSphere(a, b);
        ASSERT_TRUE(c) << "no contact" << pairText(a, b);
        ASSERT_EQ(c->pointCount, 1) << "a sphere touches anything at one point" << pairText(a, b);
        const Vec3 ab = b.position - a.position;
        const Vec3 n = ab.normalized();
        const Vec3 fromA = c->points[0] - a.position;
        const double along = fromA.dot(n);  // from a's centre along the line of centres (m)
        const double tol = kRounding * scaleOf(a, b);
        ASSERT_LE((fromA - along * n).norm(), tol)
            << "the point " << str(c->points[0]) << " is off the line of centres" << pairText(a, b);
        // Inside both spheres on that line: within r_a of a's centre and within r_b of b's.
        ASSERT_LE(std::abs(along - ab.norm()), b.radius + tol)
            << "the point " << str(c->points[0]) << " lies outside b" << pairText(a, b);
        ASSERT_LE(std::abs(along), a.radius + tol) << "the point " << str(c->points[0]) << " lies outside a"
                                                   << pairText(a, b);
    }
}

// ---- spherePlane() --------------------------------------------------------------------------------

GRADED_TEST(Worksheet3, SpherePlaneFloor, 2,
            "spherePlane() on the floor y = 0: the normal points from the sphere into the plane, (0, -1, 0); the "
            "depth is r - y, the radius minus the centre's height (worksheet 3, assignment 2).") {
    Random rnd(311);
    const Body floor = plane("floor", {0.0, 1.0, 0.0});
    for (int i = 0; i < 200; ++i) {
        const double r = rnd.uniform(0.1, 2.0);
        const Body s = sphere("ball", r, 1.0)
                           .at({rnd.uniform(-10.0, 10.0), rnd.uniform(0.02, 0.98) * r, rnd.uniform(-10.0, 10.0)});
        ASSERT_TRUE(matchesPlane(spherePlane(s, floor), s, floor));
    }
}

GRADED_TEST(Worksheet3, SpherePlaneTiltedAndOffset, 3,
            "spherePlane() for any plane: turn its normal into the world frame (orientation * normal) and measure "
            "the centre's height from the plane's own position, n . (x - p); the depth is r minus that height.") {
    Random rnd(312);
    for (int i = 0; i < 300; ++i) {
        const Body p = randomPlane(rnd);
        const double r = rnd.uniform(0.1, 2.0);
        const Body s = sphereAbove(rnd, p, r, rnd.uniform(0.02, 0.98) * r);
        ASSERT_TRUE(matchesPlane(spherePlane(s, p), s, p));
    }
}

GRADED_TEST(Worksheet3, SpherePlaneCentreBehind, 2,
            "spherePlane(): everything behind the plane is solid, so a sphere whose centre is behind it is a "
            "contact too, deeper than its radius: depth = r - n . (x - p) with a negative height (no absolute "
            "value).") {
    Random rnd(313);
    for (int i = 0; i < 200; ++i) {
        const Body p = randomPlane(rnd);
        const double r = rnd.uniform(0.1, 2.0);
        const Body s = sphereAbove(rnd, p, r, -rnd.uniform(0.0, 3.0) * r);
        const std::optional<Contact> c = spherePlane(s, p);
        ASSERT_TRUE(matchesPlane(c, s, p)) << "\n  (the centre is behind the plane)";
        ASSERT_GE(c->depth, r * (1.0 - kRounding)) << "the centre is behind the plane: the depth exceeds the radius";
    }
    const Body s = sphere("ball", 0.5, 1.0).at({1.0, 0.0, 2.0});
    const Body floor = plane("floor", {0.0, 1.0, 0.0});
    ASSERT_TRUE(matchesPlane(spherePlane(s, floor), s, floor)) << "\n  (the centre is on the plane)";
}

GRADED_TEST(Worksheet3, SpherePlaneApartOrTouching, 2,
            "spherePlane(): a sphere in front of the plane that does not reach it, or touches it at exactly one "
            "point (height = r), has no contact; any overlap, however small, is a contact.") {
    Random rnd(314);
    for (int i = 0; i < 200; ++i) {
        const Body p = randomPlane(rnd);
        const double r = rnd.uniform(0.1, 2.0);
        const Body s = sphereAbove(rnd, p, r, rnd.uniform(1.02, 5.0) * r);
        const std::optional<Contact> c = spherePlane(s, p);
        ASSERT_FALSE(c) << "the sphere is " << checks::heightAbove(p, s.position) - r
                        << " m in front of the plane, yet: " << str(c) << planeText(s, p);
    }
    for (const auto& [s, p] : touchingPlanes()) {
        ASSERT_EQ(checks::heightAbove(p, s.position), s.radius) << "test setup: the sphere must touch exactly";
        const std::optional<Contact> c = spherePlane(s, p);
        ASSERT_FALSE(c) << "the sphere touches the plane at one point, which is no contact, yet: " << str(c)
                        << planeText(s, p) << "\n  only depth > 0 is a contact";
        // 1e-6 and 1e-9 of the radius into the plane: contacts, the smaller still far above rounding.
        for (const double share : {1e-6, 1e-9}) {
            Body closer = s;
            closer.position -= share * s.radius * checks::worldNormal(p);
            ASSERT_TRUE(matchesPlane(spherePlane(closer, p), closer, p))
                << "\n  (an overlap of " << share * s.radius << " m: any overlap, however small, is a contact)";
        }
    }
}

GRADED_TEST(Worksheet3, SpherePlaneContactPoint, 2,
            "spherePlane(): the contact point lies on the line through the centre along the normal, between the "
            "sphere's deepest point and the plane (for example halfway); pointCount = 1.") {
    Random rnd(315);
    for (int i = 0; i < 300; ++i) {
        const Body p = randomPlane(rnd);
        const double r = rnd.uniform(0.1, 2.0);
        const Body s = sphereAbove(rnd, p, r, rnd.uniform(-1.0, 0.98) * r);
        const std::optional<Contact> c = spherePlane(s, p);
        ASSERT_TRUE(c) << "no contact" << planeText(s, p);
        ASSERT_EQ(c->pointCount, 1) << "a sphere touches a plane at one point" << planeText(s, p);
        const Vec3 into = -checks::worldNormal(p);
        const Vec3 fromCentre = c->points[0] - s.position;
        const double along = fromCentre.dot(into);
        const double height = checks::heightAbove(p, s.position);
        const double tol = kRounding * scaleOf(s, p);
        ASSERT_LE((fromCentre - along * into).norm(), tol)
            << "the point " << str(c->points[0]) << " is off the line through the centre along the normal"
            << planeText(s, p);
        // From the plane's surface (height along the normal) to the deepest point (r along it).
        ASSERT_GE(along, height - tol) << "the point " << str(c->points[0]) << " lies in front of the plane"
                                       << planeText(s, p);
        ASSERT_LE(along, r + tol) << "the point " << str(c->points[0]) << " lies beyond the sphere's deepest point"
                                  << planeText(s, p);
    }
}

// ---- resolveInterpenetration() --------------------------------------------------------------------

// The contact between two spheres, made here from the geometry.
Contact sphereContact(const Body& a, const Body& b) {
    const Vec3 ab = b.position - a.position;
    const Vec3 n = ab.normalized();
    return checks::contactAlong(n, checks::overlap(a, b), a.position + a.radius * n);
}

GRADED_TEST(Worksheet3, ResolveSeparatesPair, 3,
            "resolveInterpenetration(): move a against the normal and b along it so that together they move "
            "exactly `depth` apart: then they just touch. Only positions change, and nothing moves when the depth "
            "is 0 or negative (worksheet 3, assignment 3).") {
    Random rnd(321);
    for (int i = 0; i < 300; ++i) {
        const bool apart = i % 6 == 5;
        auto [a, b] = apart ? spherePair(rnd, 1.01, 1.5) : spherePair(rnd, 0.02, 0.98);
        const Body a0 = a, b0 = b;
        const Contact c = sphereContact(a, b);
        resolveInterpenetration(c, a, b);
        if (apart) {
            ASSERT_TRUE(a.position == a0.position && b.position == b0.position)
                << "a contact of depth " << c.depth << " m (not overlapping) moved the bodies" << pairText(a0, b0);
            continue;
        }
        const double tol = kRounding * scaleOf(a0, b0);
        const Vec3 moved = (b.position - b0.position) - (a.position - a0.position);
        ASSERT_LE((moved - moved.dot(c.normal) * c.normal).norm(), tol)
            << "the bodies moved across the normal" << pairText(a0, b0);
        ASSERT_NEAR(moved.dot(c.normal), c.depth, tol)
            << "they moved this far apart along the normal, but the depth is " << c.depth << " m" << pairText(a0, b0)
            << (moved.dot(c.normal) < 0.0 ? "\n  they moved towards each other: a moves along -n, b along +n" : "");
        ASSERT_NEAR(checks::overlap(a, b), 0.0, tol)
            << "after resolving, the spheres must just touch" << pairText(a, b);
        ASSERT_TRUE(a.velocity == a0.velocity && b.velocity == b0.velocity)
            << "the velocities changed: only positions are this kernel's business";
    }
}

GRADED_TEST(Worksheet3, ResolveSeparatesShallowOverlaps, 2,
            "resolveInterpenetration(): an overlap of a micrometre is an overlap too: move the bodies apart by the "
            "whole depth however small it is (a tolerance below which nothing moves leaves resting bodies sinking "
            "into each other, a little more every step).",
            grading::dependsOn("ResolveSeparatesPair")) {
    Random rnd(324);
    for (int i = 0; i < 200; ++i) {
        // Depths from 1e-7 m to 1e-4 m, evenly over the decades.
        const double depth = std::pow(10.0, rnd.uniform(-7.0, -4.0));
        const double ra = rnd.uniform(0.1, 2.0), rb = rnd.uniform(0.1, 2.0);
        const Vec3 xa = rnd.inBox(10.0), n = rnd.direction();
        Body a = sphere("a", ra, rnd.uniform(0.1, 10.0)).at(xa);
        Body b = sphere("b", rb, rnd.uniform(0.1, 10.0)).at(xa + (ra + rb - depth) * n);
        const Body a0 = a, b0 = b;
        const Contact c = sphereContact(a, b);
        resolveInterpenetration(c, a, b);
        const double moved = ((b.position - b0.position) - (a.position - a0.position)).dot(c.normal);
        // Coordinates of ~10 m round to ~1e-15 m; the smallest depth is 1e-7 m, and leaving it alone is off by all of it.
        ASSERT_NEAR(moved, c.depth, kRounding * scaleOf(a0, b0) + 1e-3 * c.depth)
            << "a contact of depth " << c.depth << " m moved the bodies " << moved << " m apart" << pairText(a0, b0)
            << (moved == 0.0 ? "\n  nothing moved: a small overlap must be resolved too" : "");
    }
}

GRADED_TEST(Worksheet3, ResolveMassWeighted, 3,
            "resolveInterpenetration(): each body moves by a share of the depth proportional to its inverse mass, "
            "invMass / (invMass_a + invMass_b): the lighter body moves more, and the centre of mass of the pair "
            "stays where it was.") {
    Random rnd(322);
    for (int i = 0; i < 300; ++i) {
        auto [a, b] = spherePair(rnd, 0.02, 0.98);
        if (i % 10 == 0) b = sphere("b", b.radius, a.mass).at(b.position);  // equal masses: equal shares
        const Body a0 = a, b0 = b;
        const Contact c = sphereContact(a, b);
        resolveInterpenetration(c, a, b);
        const double da = (a.position - a0.position).norm(), db = (b.position - b0.position).norm();
        ASSERT_GT(da + db, 0.0) << "nothing moved, but the spheres overlap by " << c.depth << " m" << pairText(a0, b0);
        // The centre of mass moves by (m_a dx_a + m_b dx_b) / (m_a + m_b): rounding of the moves only.
        const Vec3 com =
            (a.mass * (a.position - a0.position) + b.mass * (b.position - b0.position)) / (a.mass + b.mass);
        ASSERT_LE(com.norm(), kRounding * scaleOf(a0, b0))
            << "the centre of mass moved by " << str(com) << "; a moved " << da << " m, b " << db << " m"
            << pairText(a0, b0) << "\n  the shares must be invMass_a / (invMass_a + invMass_b) and invMass_b / (...)";
        if (a.mass != b.mass) {
            ASSERT_EQ(a.mass<b.mass, da> db)
                << "a moved " << da << " m, b " << db << " m: the lighter body must move more" << pairText(a0, b0);
        }
    }
}

GRADED_TEST(Worksheet3, ResolveStaticBodyUntouched, 2,
            "resolveInterpenetration(): a static body (invMass 0) never moves; the movable one takes the whole "
            "depth. Two static bodies: nothing moves (and nothing is divided by zero).") {
    Random rnd(323);
    for (int i = 0; i < 200; ++i) {
        // A sphere against a static plane, the plane second (as the engine orders them).
        const Body p = randomPlane(rnd);
        const double r = rnd.uniform(0.1, 2.0);
        Body s = sphereAbove(rnd, p, r, rnd.uniform(-0.5, 0.98) * r);
        Body q = p;
        const Body s0 = s;
        const Expected e = expectedPlaneContact(s, p);
        resolveInterpenetration(checks::contactAlong(e.normal, e.depth, s.position), s, q);
        ASSERT_TRUE(q.position == p.position && q.orientation.coeffs() == p.orientation.coeffs())
            << "the static plane moved to " << str(q.position) << planeText(s0, p);
        ASSERT_TRUE(isFinite(s.position)) << "the sphere's position is no longer finite" << planeText(s0, p);
        ASSERT_NEAR(checks::heightAbove(p, s.position), r, kRounding * scaleOf(s0, p))
            << "height of the sphere's centre after resolving: it must just touch the plane" << planeText(s0, p);
    }
    for (int i = 0; i < 200; ++i) {
        // A static sphere against a movable one, either first or second.
        auto [a, b] = spherePair(rnd, 0.02, 0.98);
        Body& fixed = i % 2 == 0 ? a : b;
        fixed.makeStatic();
        const Body a0 = a, b0 = b;
        resolveInterpenetration(sphereContact(a, b), a, b);
        const Body& fixed0 = i % 2 == 0 ? a0 : b0;
        ASSERT_TRUE(fixed.position == fixed0.position) << "the static sphere moved" << pairText(a0, b0);
        ASSERT_NEAR(checks::overlap(a, b), 0.0, kRounding * scaleOf(a0, b0))
            << "the movable sphere must take the whole depth" << pairText(a0, b0);
    }
    auto [a, b] = spherePair(rnd, 0.2, 0.5);
    a.makeStatic();
    b.makeStatic();
    const Body a0 = a, b0 = b;
    resolveInterpenetration(sphereContact(a, b), a, b);
    ASSERT_TRUE(a.position == a0.position && b.position == b0.position)
        << "two static bodies moved: a to " << str(a.position) << ", b to " << str(b.position);
}

// ---- In the engine --------------------------------------------------------------------------------
// These step the engine with the student's worksheet-1 hooks too: they depend on worksheet 1's
// tests, so that a mistake there shows here as "not run" rather than as a contact mistake.

GRADED_TEST(Worksheet3, SlidesDownTiltedPlane, 2,
            "A ball on a tilted, offset plane without friction slides down it with the acceleration g minus its "
            "normal part (g sin(tilt)), staying exactly on the plane: each step spherePlane() finds the small "
            "overlap gravity made and resolveInterpenetration() removes exactly that along the plane's normal.",
            grading::dependsOn("Worksheet1.MatchesDiscreteFreeFall"),
            grading::dependsOn("Worksheet1.StaticBodiesUntouched")) {
    Random rnd(331);
    const Quat tilts[] = {Quat(Eigen::AngleAxisd(M_PI / 6.0, Vec3::UnitZ())),
                          Quat(Eigen::AngleAxisd(-0.35, Vec3::UnitX())), rnd.rotation()};
    for (const Quat& tilt : tilts) {
        engine.clear();
        engine.setRequiredStages(kPositional);
        const double h = engine.timeStep(), r = 0.3;
        const Body slope = plane("slope", {0.0, 1.0, 0.0}).at({2.0, -1.0, 0.5}).rotated(tilt);
        const Vec3 n = checks::worldNormal(slope);
        if (n.dot(engine.gravity()) >= 0.0) continue;  // a ceiling: the ball would fall away from it
        const Vec3 x0 = slope.position + r * n + 1.5 * rnd.perpendicular(n);
        const Vec3 v0 = 0.8 * rnd.perpendicular(n);
        engine.add(slope);
        engine.add(sphere("ball", r, 1.5).at(x0).moving(v0));
        // Along the plane the ball falls freely with g_t = g - (g.n) n: the discrete semi-implicit Euler
        // fall of worksheet 1, x_k = x_0 + k h v_0 + k(k+1)/2 h^2 g_t.
        const Vec3 g = engine.gravity(), gt = g - g.dot(n) * n;
        grading::steps(engine, 200, [&](int k) {
            const Body& ball = engine.body("ball");
            const Vec3 x = x0 + k * h * v0 + 0.5 * k * (k + 1) * h * h * gt, v = v0 + k * h * gt;
            // 200 steps of roundings of ~1e-15 m (positions of ~10 m), the velocity's divided by h:
            // 1e-10 m and 1e-8 m/s; a missed or misdirected correction is off by g h^2 = 1e-3 m per step.
            ASSERT_LE((ball.position - x).norm(), 1e-10 * (1.0 + x.norm()))
                << "step " << k << ": the ball is at " << str(ball.position) << ", sliding without friction it is at "
                << str(x) << " (height above the plane " << checks::heightAbove(slope, ball.position) << " m, radius "
                << r << " m)\n  plane: " << str(slope);
            ASSERT_LE((ball.velocity - v).norm(), 1e-8 * (1.0 + v.norm()))
                << "step " << k << ": velocity " << str(ball.velocity) << ", expected " << str(v);
        });
        if (HasFailure()) return;
        EXPECT_TRUE(engine.bodies()[0].position == slope.position) << "the static plane moved";
    }
}

GRADED_TEST(Worksheet3, CollisionsConserveMomentum, 2,
            "Without gravity, balls of different masses that collide keep their total momentum: the engine turns "
            "each move into a velocity (dx / h), so the moves must keep the centre of mass where it is: shares "
            "proportional to the inverse masses.",
            grading::dependsOn("Worksheet1.MatchesDiscreteFreeFall"),
            grading::dependsOn("Worksheet1.StaticBodiesUntouched")) {
    engine.setRequiredStages(kPositional);
    engine.setGravity(Vec3::Zero());
    Random rnd(332);
    for (int i = 0; i < 12; ++i) {
        const Vec3 x = 3.0 * rnd.direction();
        engine.add(sphere("ball" + std::to_string(i), rnd.uniform(0.2, 0.5), rnd.uniform(0.2, 5.0))
                       .at(x)
                       .moving(-rnd.uniform(1.0, 3.0) * x.normalized() + 0.3 * rnd.direction()));
    }
    const Vec3 p0 = engine.linearMomentum();
    double scale = 0.0;  // kg m/s
    for (const Body& b : engine.bodies()) scale += b.mass * b.velocity.norm();
    int contacts = 0, changed = 0;  // contacts the engine reports; steps in which a ball's velocity changed
    std::vector<Vec3> velocities;
    for (const Body& b : engine.bodies()) velocities.push_back(b.velocity);
    grading::steps(engine, 300, [&](int k) {
        contacts += static_cast<int>(engine.contacts().size());
        // Without gravity only a collision changes a velocity: the checker's own evidence that the
        // balls met (the engine's contact list is the submission's word).
        bool met = false;
        for (std::size_t j = 0; j < velocities.size(); ++j) {
            const Vec3& v = engine.bodies()[j].velocity;
            met = met || (v - velocities[j]).norm() > 1e-6 * (1.0 + velocities[j].norm());
            velocities[j] = v;
        }
        changed += met ? 1 : 0;
        // Positions of ~3 m round to ~1e-15 m, which dx / h turns into ~1e-13 m/s per contact and step:
        // over 300 steps far below 1e-10 of the momenta; an equal split is off by ~m depth / h.
        ASSERT_LE((engine.linearMomentum() - p0).norm(), 1e-10 * scale)
            << "step " << k << ": total momentum " << str(engine.linearMomentum()) << ", at the start " << str(p0);
    });
    if (HasFailure()) return;
    // The balls are drawn anew in every run; a handful of contacts already tests the shares.
    EXPECT_GT(contacts, 5) << "the balls hardly collided (" << contacts << " contacts in 300 steps)";
    EXPECT_GT(changed, 5) << "the balls' velocities changed in " << changed << " steps of 300: they hardly collided, "
                          << "and momentum that nothing exchanges is kept by any engine";
}

GRADED_TEST(Worksheet3, NoTunnellingWhileStepBelowRadius, 3,
            "In the worksheet's scenes every ball moves less than its radius per step, so the engine finds every "
            "overlap with a plane before the centre passes it; no ball may end up behind a floor or a wall. Check "
            "the sign of spherePlane()'s depth and normal, and that resolveInterpenetration() moves the ball out.",
            grading::dependsOn("Worksheet1.MatchesDiscreteFreeFall"),
            grading::dependsOn("Worksheet1.StaticBodiesUntouched")) {
    for (const char* name : {"balls-in-a-box", "valley"}) {
        load(engine, scenes().find(name));
        const std::vector<Body> start = engine.bodies();
        const double h = engine.timeStep();
        int contacts = 0;
        grading::steps(engine, 1000, [&](int k) {
            contacts += static_cast<int>(engine.contacts().size());
            for (const Body& s : engine.bodies()) {
                if (s.shape != Shape::Sphere) continue;
                // The premise: a step moves a ball by less than its radius.
                ASSERT_LT(s.velocity.norm() * h, s.radius)
                    << "scene '" << name << "', step " << k << ": " << s.name << " moves " << s.velocity.norm() * h
                    << " m per step, more than its radius: contacts must not make balls this fast";
                for (const Body& p : engine.bodies()) {
                    if (p.shape != Shape::Plane) continue;
                    ASSERT_GT(checks::heightAbove(p, s.position), 0.0)
                        << "scene '" << name << "', step " << k << ": the centre of " << str(s) << " is behind "
                        << str(p) << ": it went through";
                }
            }
        });
        if (HasFailure()) return;
        EXPECT_GT(contacts, 0) << "scene '" << name << "': no contact in 1000 steps";
        for (std::size_t i = 0; i < start.size(); ++i) {
            const Body& b = engine.bodies()[i];
            if (start[i].isStatic()) {
                EXPECT_TRUE(b.position == start[i].position) << "scene '" << name << "': static " << b.name << " moved";
            } else {
                EXPECT_LT(b.position.y(), start[i].position.y() - 0.5)
                    << "scene '" << name << "': " << b.name << " did not come down";
            }
        }
    }
}

}  // namespace
}  // namespace gpl
