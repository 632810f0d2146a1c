// Worksheet 5 autograder: boxes. sphereBox(), boxPlane() and boxBox() are called directly on
// configurations drawn from a fixed seed, each built so that its answer has a closed form (a face,
// an edge, a corner, the centre inside; a box flat on a plane; a box on a box; two edges crossing);
// the contact points are checked against the region where the bodies touch, never against one
// choice of point. Invariants (swapping the bodies) and a whole scene (boxes dropped on a floor)
// follow.
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "contacts.h"
#include "gpl/collision.h"
#include "graded.h"

namespace gpl {
namespace {

using checks::corners;
using checks::Random;
using checks::str;

class Worksheet5 : public checks::ContactsTest {};

// Lengths here come from coordinates up to ~20 m, which round to ~4e-15 m; 1e-12 of the scale
// allows any equivalent formula, while every mistake the tests look for is off by millimetres.
constexpr double kRounding = 1e-12;
double scaleOf(const Body& a, const Body& b) { return 1.0 + a.position.norm() + b.position.norm(); }

Body randomBox(Random& rnd, const std::string& name) {
    const Vec3 half(rnd.uniform(0.2, 2.0), rnd.uniform(0.2, 2.0), rnd.uniform(0.2, 2.0));
    return box(name, half, rnd.uniform(0.1, 10.0)).at(rnd.inBox(10.0)).rotated(rnd.rotation());
}

// A depth (m) between 1e-6 and 1e-3 m, log-uniform: overlaps smaller than a step's sinking under
// gravity, far above rounding, which no tolerance in a kernel may drop.
double shallow(Random& rnd) { return std::exp(rnd.uniform(std::log(1e-6), std::log(1e-3))); }

// The same box with its axes named anew: body axis i becomes axis (i + shift) % 3, the half extents
// and the orientation with it, so that the box in the world is the same.
Body relabelled(const Body& b, int shift) {
    if (shift % 3 == 0) return b;
    Mat3 cycle = Mat3::Zero();  // e_i -> e_{(i + shift) % 3}: a proper rotation
    Vec3 half;
    for (int i = 0; i < 3; ++i) {
        cycle((i + shift) % 3, i) = 1.0;
        half[(i + shift) % 3] = b.halfExtents[i];
    }
    Body r = box(b.name, half, b.mass).at(b.position).rotated((b.orientation * Quat(cycle.transpose())).normalized());
    r.velocity = b.velocity;
    r.angularVelocity = b.angularVelocity;
    return r;
}

// The box's axis k (unit, world frame).
Vec3 axis(const Body& box, int k) { return box.orientation * Vec3::Unit(k); }

std::string pairText(const Body& a, const Body& b) { return "\n  a: " + str(a) + "\n  b: " + str(b); }

// The normal is a unit vector within `tol` of the expected one; says so when it is flipped.
::testing::AssertionResult normalIs(const Contact& c, const Vec3& expected, double tol) {
    if (std::abs(c.normal.norm() - 1.0) > tol) {
        return ::testing::AssertionFailure() << "the normal " << str(c.normal) << " is not a unit vector";
    }
    if ((c.normal - expected).norm() <= tol) return ::testing::AssertionSuccess();
    auto failure = ::testing::AssertionFailure() << "normal " << str(c.normal) << ", expected " << str(expected);
    if ((c.normal + expected).norm() <= tol) failure << " (it is flipped)";
    return failure;
}

// ---- sphereBox() -------------------------------------------------------------------------------------

// A sphere whose closest point on the box is the point `local` (box frame) on the box's surface,
// `distance` away from it outside the box along the unit direction `out` (box frame).
Body sphereNear(const Body& box, const Vec3& local, const Vec3& out, double distance, double radius) {
    return sphere("ball", radius, 1.0).at(box.position + box.orientation * (local + distance * out));
}

// A sphere's contact: normal, depth, one point between the sphere's deepest point and the box.
void expectSphereContact(const std::optional<Contact>& c, const Body& ball, const Body& bx, const Vec3& normal,
                         double depth) {
    const double tol = kRounding * scaleOf(ball, bx);
    ASSERT_TRUE(c) << "no contact, but the sphere reaches " << depth << " m into the box" << pairText(ball, bx);
    ASSERT_TRUE(normalIs(*c, normal, tol / ball.radius)) << pairText(ball, bx);
    ASSERT_NEAR(c->depth, depth, tol) << "depth" << pairText(ball, bx);
    ASSERT_EQ(c->pointCount, 1) << "one point for a sphere" << pairText(ball, bx);
    // Along the normal from the centre: the box's surface at r - depth, the sphere's deepest point at r.
    const Vec3 off = c->points[0] - ball.position;
    const double along = off.dot(normal);
    ASSERT_LE((off - along * normal).norm(), tol) << "the point " << str(c->points[0])
                                                  << " is off the line through the centre along the normal"
                                                  << pairText(ball, bx);
    ASSERT_TRUE(along >= ball.radius - depth - tol && along <= ball.radius + tol)
        << "the point " << str(c->points[0]) << " is not between the sphere's deepest point and the box's surface"
        << pairText(ball, bx);
}

GRADED_TEST(Worksheet5, SphereBoxFace, 3,
            "sphereBox() near a face of a turned box: take the centre into the box's frame (R^T (x - c)), clamp it to "
            "the half extents for the closest point, and turn the difference back into the world frame. The normal "
            "points from the sphere into the box, the depth is r minus the distance (worksheet 5, assignment 2).") {
    Random rnd(501);
    for (int i = 0; i < 300; ++i) {
        const Body bx = randomBox(rnd, "box");
        const Vec3 h = bx.halfExtents;
        const int k = i % 3, u = (k + 1) % 3, v = (k + 2) % 3;
        const double side = i % 2 == 0 ? 1.0 : -1.0;
        Vec3 local = Vec3::Zero();
        local[k] = side * h[k];
        local[u] = rnd.uniform(-0.95, 0.95) * h[u];
        local[v] = rnd.uniform(-0.95, 0.95) * h[v];
        const double r = rnd.uniform(0.1, 1.0), distance = rnd.uniform(0.05, 0.95) * r;
        const Body ball = sphereNear(bx, local, side * Vec3::Unit(k), distance, r);
        expectSphereContact(sphereBox(ball, bx), ball, bx, -side * axis(bx, k), r - distance);
    }
}

GRADED_TEST(Worksheet5, SphereBoxEdgeAndCorner, 3,
            "sphereBox() near an edge or a corner: clamp every coordinate of the centre (in the box's frame) to its "
            "half extent; the closest point is then on the edge or the corner, and the normal is the unit vector "
            "from the centre to it, in the world frame.") {
    Random rnd(502);
    for (int i = 0; i < 300; ++i) {
        const Body bx = randomBox(rnd, "box");
        const Vec3 h = bx.halfExtents;
        // Outside in two coordinates (an edge) or all three (a corner); the other one inside.
        const bool corner = i % 2 == 1;
        const int inside = i % 3;
        Vec3 local, out = Vec3::Zero();
        for (int k = 0; k < 3; ++k) {
            const double side = rnd.uniform(-1.0, 1.0) < 0.0 ? -1.0 : 1.0;
            if (!corner && k == inside) {
                local[k] = rnd.uniform(-0.95, 0.95) * h[k];
            } else {
                local[k] = side * h[k];
                out[k] = side * rnd.uniform(0.2, 1.0);
            }
        }
        out.normalize();
        const double r = rnd.uniform(0.1, 1.0), distance = rnd.uniform(0.05, 0.95) * r;
        const Body ball = sphereNear(bx, local, out, distance, r);
        expectSphereContact(sphereBox(ball, bx), ball, bx, -(bx.orientation * out), r - distance);
    }
}

GRADED_TEST(Worksheet5, SphereBoxCentreInside, 2,
            "sphereBox() with the sphere's centre inside the box: clamping leaves the centre where it is, so there is "
            "no direction from the centre to the closest point. Push the sphere out through the nearest face: the "
            "normal is minus that face's outward normal, and the depth is r plus the distance to that face.") {
    Random rnd(503);
    for (int i = 0; i < 300; ++i) {
        const Body bx = randomBox(rnd, "box");
        const Vec3 h = bx.halfExtents;
        const int k = i % 3;
        const double side = i % 2 == 0 ? 1.0 : -1.0, hmin = h.minCoeff();
        const double room = rnd.uniform(0.0, 0.4) * hmin;  // to the nearest face (m)
        Vec3 local;
        for (int m = 0; m < 3; ++m) {  // every other face at least 5 % of the smallest half extent farther
            local[m] = m == k ? side * (h[k] - room) : rnd.uniform(-1.0, 1.0) * (h[m] - room - 0.05 * hmin);
        }
        const double r = rnd.uniform(0.1, 1.0);
        const Body ball = sphere("ball", r, 1.0).at(bx.position + bx.orientation * local);
        expectSphereContact(sphereBox(ball, bx), ball, bx, -side * axis(bx, k), r + room);
    }
}

GRADED_TEST(Worksheet5, SphereBoxApartOrTouching, 2,
            "sphereBox(): a sphere farther from the box than its radius, or exactly touching it (distance = r), has no "
            "contact (std::nullopt), as in sphereSphere(): compare the depth with > 0, not >= 0.") {
    Random rnd(504);
    for (int i = 0; i < 300; ++i) {
        const Body bx = randomBox(rnd, "box");
        // Off a face, or off a corner within the corner's outward octant (the corner is then closest).
        Vec3 local = Vec3(rnd.uniform(-1.0, 1.0), rnd.uniform(-1.0, 1.0), rnd.uniform(-1.0, 1.0)).cwiseProduct(bx.halfExtents);
        const int k = i % 3;
        const double side = local[k] < 0.0 ? -1.0 : 1.0;
        local[k] = side * bx.halfExtents[k];
        Vec3 out = side * Vec3::Unit(k);
        if (i % 2 == 1) {
            for (int m = 0; m < 3; ++m) {
                local[m] = local[m] < 0.0 ? -bx.halfExtents[m] : bx.halfExtents[m];
                out[m] = (local[m] < 0.0 ? -1.0 : 1.0) * rnd.uniform(0.1, 1.0);
            }
            out.normalize();
        }
        const double r = rnd.uniform(0.1, 1.0);
        const bool apart = i % 4 != 0;  // every fourth sphere reaches the box: that one must touch
        // Half of those only by a shallow overlap.
        const double reach = i % 8 == 0 ? r - shallow(rnd) : r * rnd.uniform(0.05, 0.95);
        const Body ball = sphereNear(bx, local, out, apart ? r * rnd.uniform(1.001, 3.0) : reach, r);
        const std::optional<Contact> c = sphereBox(ball, bx);
        if (apart) {
            ASSERT_FALSE(c) << "the sphere does not reach the box, yet: " << str(c) << pairText(ball, bx);
        } else {
            ASSERT_TRUE(c) << "the sphere reaches into the box, but there is no contact" << pairText(ball, bx);
        }
    }
    // Exactly touching, with distances exact in binary: a face, and an edge at distance 0.75-1-1.25.
    const Body bx = box("box", {0.5, 0.25, 1.0}, 1.0).at({1.0, 2.0, 3.0});
    for (const auto& [at, r] : {std::pair{Vec3(1.0, 2.75, 3.0), 0.5}, std::pair{Vec3(2.25, 3.25, 3.5), 1.25},
                                std::pair{Vec3(1.25, 2.0, 4.5), 0.5}}) {
        const Body ball = sphere("ball", r, 1.0).at(at);
        const std::optional<Contact> c = sphereBox(ball, bx);
        ASSERT_FALSE(c) << "the sphere exactly touches the box, which is no contact, yet: " << str(c)
                        << pairText(ball, bx);
    }
}

// ---- boxPlane() --------------------------------------------------------------------------------------

// Each point lies between a distinct corner behind the plane and the plane's surface, along the
// normal; the corners so matched are among the four deepest. Returns the failure, or success.
::testing::AssertionResult pointsAtDeepCorners(const Contact& c, const Body& bx, const Body& pl, double tol) {
    const Vec3 n = checks::worldNormal(pl);
    std::vector<Vec3> all = corners(bx);
    std::vector<double> heights;
    for (const Vec3& x : all) heights.push_back(checks::heightAbove(pl, x));
    std::vector<double> sorted = heights;
    std::sort(sorted.begin(), sorted.end());
    std::vector<bool> used(8, false);
    for (int p = 0; p < c.pointCount; ++p) {
        const Vec3& point = c.points[p];
        int match = -1;
        for (int k = 0; k < 8 && match < 0; ++k) {
            const Vec3 off = point - all[k];  // from the corner, along +n up to the plane
            const double along = off.dot(n);
            if (!used[k] && heights[k] < 0.0 && (off - along * n).norm() <= tol && along >= -tol &&
                along <= -heights[k] + tol) {
                match = k;
            }
        }
        if (match < 0) {
            return ::testing::AssertionFailure() << "point " << p << ", " << str(point)
                                                 << ", is not between a corner behind the plane (another point's "
                                                    "aside) and the plane's surface, along the normal";
        }
        used[match] = true;
        if (heights[match] > sorted[3] + tol) {
            return ::testing::AssertionFailure() << "point " << p << " belongs to a corner " << -heights[match]
                                                 << " m behind the plane, but four corners are deeper";
        }
    }
    return ::testing::AssertionSuccess();
}

GRADED_TEST(Worksheet5, BoxPlaneFlat, 3,
            "boxPlane() for a box lying flat, a little into the plane: all four bottom corners are behind it, so four "
            "points, one at each (or between it and the plane's surface); the depth is how far they are behind, and "
            "the normal points from the box into the plane: minus the plane's world normal (worksheet 5, "
            "assignment 3).") {
    Random rnd(511);
    for (int i = 0; i < 300; ++i) {
        Body bx = randomBox(rnd, "box");
        const int k = i % 3;
        const double side = i % 2 == 0 ? 1.0 : -1.0;
        // The plane's normal along the box's axis k: the face -side * axis k lies on it.
        Body pl = i % 4 < 2 ? plane("plane", side * axis(bx, k))
                            : plane("plane", Vec3::UnitY()).rotated(Quat::FromTwoVectors(Vec3::UnitY(), side * axis(bx, k)));
        const double depth = rnd.uniform(0.001, 0.9) * bx.halfExtents[k];
        pl.at(bx.position - (bx.halfExtents[k] - depth) * checks::worldNormal(pl));
        const std::optional<Contact> c = boxPlane(bx, pl);
        const double tol = kRounding * scaleOf(bx, pl);
        ASSERT_TRUE(c) << "no contact for a box " << depth << " m into the plane" << pairText(bx, pl);
        ASSERT_TRUE(normalIs(*c, -checks::worldNormal(pl), tol)) << pairText(bx, pl);
        ASSERT_NEAR(c->depth, depth, tol) << "depth" << pairText(bx, pl);
        ASSERT_EQ(c->pointCount, 4) << "a box lying flat touches the plane with its four bottom corners"
                                    << pairText(bx, pl);
        ASSERT_TRUE(pointsAtDeepCorners(*c, bx, pl, tol)) << pairText(bx, pl);
    }
}

GRADED_TEST(Worksheet5, BoxPlaneTilted, 3,
            "boxPlane() for a turned box: test all eight corners, x = c + R (+-h_x, +-h_y, +-h_z). Every corner behind "
            "the plane gives a point (at most four: the deepest), and the depth is that of the deepest corner, not "
            "of the first or the last one found.") {
    Random rnd(512);
    for (int i = 0; i < 300; ++i) {
        Body bx = randomBox(rnd, "box");
        Body pl = plane("plane", rnd.direction()).rotated(rnd.rotation());
        const Vec3 n = checks::worldNormal(pl);
        double lowest = INFINITY;  // of the box's corners along n, from its centre (m)
        for (const Vec3& x : corners(bx)) lowest = std::min(lowest, n.dot(x - bx.position));
        const double depth = rnd.uniform(0.001, 1.5) * bx.halfExtents.minCoeff();
        pl.at(bx.position + (lowest + depth) * n + rnd.uniform(0.0, 5.0) * rnd.perpendicular(n));
        int behind = 0;
        for (const Vec3& x : corners(bx)) behind += checks::heightAbove(pl, x) < 0.0;
        const std::optional<Contact> c = boxPlane(bx, pl);
        const double tol = kRounding * scaleOf(bx, pl);
        ASSERT_TRUE(c) << "no contact for a box " << depth << " m into the plane" << pairText(bx, pl);
        ASSERT_TRUE(normalIs(*c, -n, tol)) << pairText(bx, pl);
        ASSERT_NEAR(c->depth, depth, tol) << "depth: how far the deepest corner is behind the plane"
                                          << pairText(bx, pl);
        ASSERT_EQ(c->pointCount, std::min(behind, 4))
            << behind << " corners are behind the plane: one point each, at most four" << pairText(bx, pl);
        ASSERT_TRUE(pointsAtDeepCorners(*c, bx, pl, tol)) << pairText(bx, pl);
    }
}

GRADED_TEST(Worksheet5, BoxPlaneThinBoxKeepsDeepestFour, 2,
            "boxPlane() for a thin box tilted into the plane so that six corners are behind it: a contact holds four, "
            "the four deepest (sort the corners by height), not the first four found; the shallow ones at the raised "
            "end carry nothing the deep end does not.",
            grading::dependsOn("BoxPlaneTilted")) {
    Random rnd(514);
    for (int i = 0; i < 200; ++i) {
        const Quat frame = rnd.rotation();  // the plane's and the box's common turn
        Body pl = plane("plane", Vec3::UnitY()).rotated(frame).at(rnd.inBox(5.0));
        const Vec3 n = checks::worldNormal(pl);
        const double length = rnd.uniform(0.5, 1.5), thick = rnd.uniform(0.02, 0.08), width = rnd.uniform(0.3, 1.0);
        // Tilted about its width so that the low end's four corners are deep and the raised end's lower two
        // just behind the plane: six behind, the four deepest at the low end.
        const double tilt = std::asin(std::min(0.5, rnd.uniform(2.5, 5.0) * thick / length));
        const double shallow = -rnd.uniform(0.2, 0.8) * 2.0 * thick * std::cos(tilt);  // height of the raised end's lower corners
        const double centre = shallow - length * std::sin(tilt) + thick * std::cos(tilt);
        const Quat turn = frame * Quat(Eigen::AngleAxisd(rnd.uniform(0.0, 2.0 * M_PI), Vec3::UnitY())) *
                          Quat(Eigen::AngleAxisd(-tilt, Vec3::UnitZ()));
        Body bx = box("box", {length, thick, width}, 1.0).rotated(turn.normalized());
        bx.at(pl.position + centre * n + rnd.uniform(0.0, 3.0) * rnd.perpendicular(n));
        int behind = 0;
        for (const Vec3& x : corners(bx)) behind += checks::heightAbove(pl, x) < 0.0;
        ASSERT_EQ(behind, 6) << "the test's own box: " << behind << " corners behind the plane" << pairText(bx, pl);
        const std::optional<Contact> c = boxPlane(bx, pl);
        const double tol = kRounding * scaleOf(bx, pl);
        ASSERT_TRUE(c) << "no contact for a box six corners deep into the plane" << pairText(bx, pl);
        ASSERT_EQ(c->pointCount, 4) << "six corners are behind the plane: keep four" << pairText(bx, pl);
        ASSERT_TRUE(pointsAtDeepCorners(*c, bx, pl, tol)) << pairText(bx, pl);
    }
}

GRADED_TEST(Worksheet5, BoxPlaneApartOrTouching, 2,
            "boxPlane(): a box with no corner behind the plane has no contact (std::nullopt); neither has a box "
            "that exactly rests on it (corners at height 0 only touch it): count corners with height < 0.") {
    Random rnd(513);
    for (int i = 0; i < 300; ++i) {
        Body bx = randomBox(rnd, "box");
        Body pl = plane("plane", rnd.direction()).rotated(rnd.rotation());
        const Vec3 n = checks::worldNormal(pl);
        double lowest = INFINITY;
        for (const Vec3& x : corners(bx)) lowest = std::min(lowest, n.dot(x - bx.position));
        const bool apart = i % 4 != 0;  // every fourth box reaches a little behind the plane: that one touches
        const double behind = i % 8 == 0 ? shallow(rnd) : rnd.uniform(0.001, 0.1);  // m, half of them shallow
        pl.at(bx.position + (lowest + (apart ? -rnd.uniform(0.001, 2.0) : behind)) * n);
        const std::optional<Contact> c = boxPlane(bx, pl);
        if (apart) {
            ASSERT_FALSE(c) << "every corner is in front of the plane, yet: " << str(c) << pairText(bx, pl);
        } else {
            ASSERT_TRUE(c) << "a corner is behind the plane, but there is no contact" << pairText(bx, pl);
        }
    }
    // Exactly resting, heights exact in binary: flat on a face, unturned and turned half a turn about
    // z (a rotation whose matrix is exact).
    const Body floor = plane("floor", Vec3::UnitY()).at({0.0, -1.0, 0.0});
    const Body flat = box("flat", {0.5, 0.25, 1.0}, 1.0).at({3.0, -0.75, 2.0});
    const Body turned = box("turned", {0.5, 0.25, 1.0}, 1.0).at({3.0, -0.75, 2.0}).rotated(Quat(0.0, 0.0, 0.0, 1.0));
    for (const Body& bx : {flat, turned}) {
        const std::optional<Contact> c = boxPlane(bx, floor);
        ASSERT_FALSE(c) << "the box rests exactly on the plane, which is no contact, yet: " << str(c)
                        << pairText(bx, floor);
    }
}

// ---- boxBox() ----------------------------------------------------------------------------------------

// Box b standing on the face `side` (+1 or -1) times axis k of box a, `depth` into it, turned about
// that axis by `angle` and shifted along the face by (du, dv) times a's half extents.
Body standingOn(const Body& a, int k, double side, const Vec3& halfB, double depth, double angle, double du,
                double dv) {
    const Vec3 up = side * axis(a, k);
    const int u = (k + 1) % 3, v = (u + 1) % 3;
    const Quat turn(Eigen::AngleAxisd(angle, up));
    // b's axis k along a's: b is a turned about `up`.
    Body b = box("b", halfB, 1.0).rotated((turn * a.orientation).normalized());
    b.position = a.position + (a.halfExtents[k] + halfB[k] - depth) * up + du * a.halfExtents[u] * axis(a, u) +
                 dv * a.halfExtents[v] * axis(a, v);
    return b;
}

GRADED_TEST(Worksheet5, BoxBoxFace, 3,
            "boxBox() for a box standing on another's face, slightly into it: of the 15 axes, that face's normal has "
            "the least overlap, so it is the normal (from a towards b) and the overlap is the depth. Project both "
            "boxes on each axis: radius sum_i h_i |axis . R e_i|, and the overlap r_a + r_b - |axis . (c_b - c_a)| "
            "(worksheet 5, assignment 4).") {
    Random rnd(521);
    for (int i = 0; i < 300; ++i) {
        const Body a = randomBox(rnd, "a");
        const int k = i % 3;
        const Vec3 halfB(rnd.uniform(0.2, 2.0), rnd.uniform(0.2, 2.0), rnd.uniform(0.2, 2.0));
        const double depth = rnd.uniform(0.001, 0.1) * std::min(a.halfExtents[k], halfB[k]);
        const double side = (i / 3) % 2 == 0 ? 1.0 : -1.0;  // on top of a's face +k or under its face -k
        const Body b = standingOn(a, k, side, halfB, depth, rnd.uniform(0.0, 2.0 * M_PI), rnd.uniform(-0.5, 0.5),
                                  rnd.uniform(-0.5, 0.5));
        const std::optional<Contact> c = boxBox(a, b);
        const double tol = kRounding * scaleOf(a, b);
        ASSERT_TRUE(c) << "no contact, but b stands " << depth << " m deep on a's face" << pairText(a, b);
        ASSERT_TRUE(normalIs(*c, side * axis(a, k), tol)) << " (a's face normal towards b)" << pairText(a, b);
        ASSERT_NEAR(c->depth, depth, tol) << "depth" << pairText(a, b);
    }
}

GRADED_TEST(Worksheet5, BoxBoxStackPoints, 3,
            "boxBox() for a box on a box: the contact points must span where the faces overlap, one near each corner "
            "of the overlap, between the two faces. Clip the incident face (of the other box, facing the reference "
            "face) against the four side planes of the reference face and keep what lies behind the reference face; "
            "prefer a face axis to an edge axis that overlaps about as much.") {
    Random rnd(522);
    for (int i = 0; i < 300; ++i) {
        const Body a = randomBox(rnd, "a");
        const int k = i % 3, u = (k + 1) % 3, v = (k + 2) % 3;
        const Vec3 h = a.halfExtents;
        // b's face as large as a's or smaller, unturned or a quarter turn about the normal, so the
        // overlap is a rectangle: partly overhanging a's face when shifted.
        const bool quarter = i % 4 == 3;
        Vec3 halfB;
        halfB[k] = rnd.uniform(0.2, 2.0);
        halfB[quarter ? v : u] = rnd.uniform(0.3, 1.0) * h[u];
        halfB[quarter ? u : v] = rnd.uniform(0.3, 1.0) * h[v];
        const double du = i % 2 == 0 ? rnd.uniform(-0.5, 0.5) : 0.0, dv = i % 2 == 0 ? rnd.uniform(-0.5, 0.5) : 0.0;
        const double depth = rnd.uniform(0.001, 0.1) * std::min(h[k], halfB[k]);
        const Body b = standingOn(a, k, 1.0, halfB, depth, quarter ? M_PI / 2 : 0.0, du, dv);
        // The overlap of the two faces, in a's face coordinates (m).
        const double bu = quarter ? halfB[v] : halfB[u], bv = quarter ? halfB[u] : halfB[v];
        const double uLo = std::max(-h[u], du * h[u] - bu), uHi = std::min(h[u], du * h[u] + bu);
        const double vLo = std::max(-h[v], dv * h[v] - bv), vHi = std::min(h[v], dv * h[v] + bv);
        const std::optional<Contact> c = boxBox(a, b);
        const double tol = 1e-9 * scaleOf(a, b);  // the clipping's cuts divide by differences of ~1 m
        ASSERT_TRUE(c) << "no contact for a box standing " << depth << " m deep on another" << pairText(a, b);
        ASSERT_TRUE(normalIs(*c, axis(a, k), tol)) << pairText(a, b);
        const Vec3 top = a.position + h[k] * axis(a, k);  // the centre of a's face
        std::vector<bool> cornerSeen(4, false);
        for (int p = 0; p < c->pointCount; ++p) {
            const Vec3 off = c->points[p] - top;
            const double pu = off.dot(axis(a, u)), pv = off.dot(axis(a, v)), pk = off.dot(axis(a, k));
            ASSERT_TRUE(pk >= -depth - tol && pk <= tol && pu >= uLo - tol && pu <= uHi + tol && pv >= vLo - tol &&
                        pv <= vHi + tol)
                << "point " << p << ", " << str(c->points[p]) << ", is not where the faces overlap (between them)"
                << pairText(a, b);
            for (int q = 0; q < 4; ++q) {
                const double cu = q & 1 ? uHi : uLo, cv = q & 2 ? vHi : vLo;
                if (std::hypot(pu - cu, pv - cv) <= tol) cornerSeen[q] = true;
            }
        }
        for (int q = 0; q < 4; ++q) {
            ASSERT_TRUE(cornerSeen[q]) << "no contact point at the corner " << q << " of the rectangle where the faces "
                                       << "overlap (" << c->pointCount << " point(s)): the points must span it"
                                       << pairText(a, b);
        }
    }
}

// Two boxes whose edges cross: a turned by 45 degrees about x (an edge along x on top), b by 45
// degrees about z (an edge along z below), b's lowest edge `gap` above a's highest (< 0: into it);
// the whole carried by a random rotation and translation. Returns a, b and the crossing point.
struct Crossing {
    Body a, b;
    Vec3 up;     // the axis from a towards b (unit, world frame)
    Vec3 cross;  // where the two edges cross, on a's edge (m)
};

// With shiftA, shiftB the boxes' axes named anew (relabelled()), so that the separating axis is any
// of the nine cross products a_i x b_j.
Crossing crossingEdges(Random& rnd, double gap, int shiftA = 0, int shiftB = 0) {
    const double sa = rnd.uniform(0.3, 1.5), sb = rnd.uniform(0.3, 1.5);  // half extents across the edges
    const Quat R = rnd.rotation();
    const Vec3 t = rnd.inBox(10.0);
    const double ca = rnd.uniform(-0.5, 0.5) * 0.3, cb = rnd.uniform(-0.5, 0.5) * 0.3;  // along the edges (m)
    Body a = box("a", {rnd.uniform(0.5, 2.0), sa, sa}, 1.0).rotated(Quat(Eigen::AngleAxisd(M_PI / 4, Vec3::UnitX())));
    Body b = box("b", {sb, sb, rnd.uniform(0.5, 2.0)}, 1.0).rotated(Quat(Eigen::AngleAxisd(M_PI / 4, Vec3::UnitZ())));
    a.at({ca, 0.0, 0.0});
    b.at({0.0, std::sqrt(2.0) * (sa + sb) + gap, cb});
    return {relabelled(checks::carried(a, R, t), shiftA), relabelled(checks::carried(b, R, t), shiftB), R * Vec3::UnitY(),
            R * Vec3(0.0, std::sqrt(2.0) * sa, 0.0) + t};
}

// ---- Which four points: the overlap of two faces turned against each other -----------------------

using Point2 = Eigen::Vector2d;

// Twice the signed area of a polygon (its corners in order; counter-clockwise positive).
double twiceArea(const std::vector<Point2>& poly) {
    double s = 0.0;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const Point2& p = poly[i];
        const Point2& q = poly[(i + 1) % poly.size()];
        s += p.x() * q.y() - q.x() * p.y();
    }
    return s;
}

// The part of a convex polygon where d . x <= limit.
std::vector<Point2> clipped(const std::vector<Point2>& poly, const Point2& d, double limit) {
    std::vector<Point2> out;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const Point2& p = poly[i];
        const Point2& q = poly[(i + 1) % poly.size()];
        const double sp = d.dot(p) - limit, sq = d.dot(q) - limit;
        if (sp <= 0.0) out.push_back(p);
        if ((sp < 0.0) != (sq < 0.0) && sp != sq) out.push_back(p + (sp / (sp - sq)) * (q - p));
    }
    return out;
}

// How far the centroid of `region` lies inside the convex hull of `points` (m; negative: outside).
double centreMargin(std::vector<Point2> points, const std::vector<Point2>& region) {
    Point2 centroid = Point2::Zero();
    double area = 0.0;
    for (std::size_t i = 0; i < region.size(); ++i) {
        const Point2& p = region[i];
        const Point2& q = region[(i + 1) % region.size()];
        const double cross = p.x() * q.y() - q.x() * p.y();
        area += cross;
        centroid += cross * (p + q);
    }
    centroid /= 3.0 * area;
    Point2 middle = Point2::Zero();
    for (const Point2& p : points) middle += p / static_cast<double>(points.size());
    std::sort(points.begin(), points.end(), [&](const Point2& p, const Point2& q) {
        return std::atan2(p.y() - middle.y(), p.x() - middle.x()) < std::atan2(q.y() - middle.y(), q.x() - middle.x());
    });
    double margin = INFINITY;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Point2& p = points[i];
        const Point2& q = points[(i + 1) % points.size()];
        const Point2 edge = q - p;
        const double inside = (edge.x() * (centroid.y() - p.y()) - edge.y() * (centroid.x() - p.x())) / edge.norm();
        margin = std::min(margin, inside);
    }
    return margin;
}

GRADED_TEST(Worksheet5, BoxBoxKeepsPointsThatSpanTheOverlap, 2,
            "boxBox() for a box centred on another and turned about the normal by a generic angle: the clipped face is "
            "an octagon of eight corners, and a contact holds four. Keep the deepest and three that span the rest (far "
            "apart, around the overlap), so that the four surround the overlap's centre, where the box's weight acts; "
            "the first four found lie side by side, on one half, and let the box tip.",
            grading::dependsOn("BoxBoxStackPoints")) {
    Random rnd(525);
    int octagons = 0;
    for (int i = 0; i < 300; ++i) {
        const Body a = randomBox(rnd, "a");
        const int k = i % 3, u = (k + 1) % 3, v = (k + 2) % 3;
        const Vec3 h = a.halfExtents;
        Vec3 halfB;
        halfB[k] = rnd.uniform(0.2, 2.0);
        halfB[u] = rnd.uniform(0.8, 1.25) * h[u];
        halfB[v] = rnd.uniform(0.8, 1.25) * h[v];
        const double angle = rnd.uniform(0.25, 1.3);  // rad, between a sixth and five sixths of a quarter turn
        const double depth = rnd.uniform(0.001, 0.05) * std::min(h[k], halfB[k]);
        const Body b = standingOn(a, k, 1.0, halfB, depth, angle, 0.0, 0.0);
        const std::optional<Contact> c = boxBox(a, b);
        ASSERT_TRUE(c) << "no contact, but b stands " << depth << " m deep on a's face" << pairText(a, b);
        // The overlap of the two faces, in a's face plane: b's face (turned) cut to a's face.
        const Vec3 eu = axis(a, u), ev = axis(a, v);
        const auto in2 = [&](const Vec3& x) { return Point2(eu.dot(x - a.position), ev.dot(x - a.position)); };
        std::vector<Point2> overlap;
        for (const auto& [su, sv] : {std::pair{1.0, 1.0}, std::pair{-1.0, 1.0}, std::pair{-1.0, -1.0}, std::pair{1.0, -1.0}}) {
            overlap.push_back(in2(b.position + su * halfB[u] * axis(b, u) + sv * halfB[v] * axis(b, v)));
        }
        overlap = clipped(overlap, Point2(1.0, 0.0), h[u]);
        overlap = clipped(overlap, Point2(-1.0, 0.0), h[u]);
        overlap = clipped(overlap, Point2(0.0, 1.0), h[v]);
        overlap = clipped(overlap, Point2(0.0, -1.0), h[v]);
        if (overlap.size() < 8) continue;  // fewer corners: four points hold most of them
        ++octagons;
        ASSERT_EQ(c->pointCount, 4) << "the overlap has " << overlap.size() << " corners: keep four" << pairText(a, b);
        std::vector<Point2> kept;
        for (int p = 0; p < c->pointCount; ++p) kept.push_back(in2(c->points[p]));
        const double size = std::sqrt(std::abs(twiceArea(overlap)) / 2.0);  // m
        // Inside by more than rounding: four corners that surround the centre keep it 2 % of the overlap's
        // size or more inside; four side by side leave it outside or on their edge.
        EXPECT_GT(centreMargin(kept, overlap), 1e-9 * size)
            << "the overlap's centre lies outside the four points (by " << -centreMargin(kept, overlap)
            << " m): keep points around the overlap, not side by side" << pairText(a, b);
        if (HasFailure()) return;
    }
    EXPECT_GT(octagons, 50) << "too few overlaps with eight corners were drawn";
}

GRADED_TEST(Worksheet5, BoxBoxEdgeEdge, 3,
            "boxBox() for two edges crossing: no face axis has the least overlap here, the cross product of the two "
            "edges' directions has. Test all nine products a_i x b_j (normalised; skip the near-parallel ones), and "
            "give one point between the closest points of the two edges.") {
    Random rnd(523);
    for (int i = 0; i < 300; ++i) {
        const double depth = rnd.uniform(0.001, 0.1);
        const Crossing x = crossingEdges(rnd, -depth, i % 3, i / 3 % 3);
        const std::optional<Contact> c = boxBox(x.a, x.b);
        const double tol = kRounding * scaleOf(x.a, x.b);
        ASSERT_TRUE(c) << "no contact, but b's edge is " << depth << " m into a's" << pairText(x.a, x.b);
        ASSERT_TRUE(normalIs(*c, x.up, tol)) << " (across both edges, from a towards b)" << pairText(x.a, x.b);
        ASSERT_NEAR(c->depth, depth, tol) << "depth along the edges' common normal" << pairText(x.a, x.b);
        for (int p = 0; p < c->pointCount; ++p) {
            // Between a's edge and b's, which cross at x.cross and x.cross - depth * up.
            const Vec3 off = c->points[p] - x.cross;
            const double along = off.dot(x.up);
            ASSERT_TRUE((off - along * x.up).norm() <= tol && along >= -depth - tol && along <= tol)
                << "point " << p << ", " << str(c->points[p]) << ", is not between the two edges where they cross, "
                << str(x.cross) << " on a's edge" << pairText(x.a, x.b);
        }
    }
}

// Every point of the contact on the segment from the corner `tip` a depth (m) along `up`, to `tol`.
::testing::AssertionResult pointsBetween(const Contact& c, const Vec3& tip, const Vec3& up, double depth, double tol) {
    for (int p = 0; p < c.pointCount; ++p) {
        const Vec3 off = c.points[p] - tip;
        const double along = off.dot(up);
        if (!((off - along * up).norm() <= tol && along >= -tol && along <= depth + tol)) {
            return ::testing::AssertionFailure() << "point " << p << ", " << str(c.points[p])
                                                 << ", is not between the corner " << str(tip) << " and a's face";
        }
    }
    return ::testing::AssertionSuccess();
}

GRADED_TEST(Worksheet5, BoxBoxCorner, 2,
            "boxBox() for a corner of b poking into a face of a: the face's normal is the axis of least overlap, the "
            "depth is how far the corner is in, and the only point is at the corner (clipping b's facing face keeps "
            "only the corner behind a's face). The same with the boxes passed the other way round (the reference "
            "face is then the second box's), and for an edge of b lying across a's face: the edge's two ends (the "
            "incident face is b's face most against the normal, whatever its axis).") {
    Random rnd(524);
    for (int i = 0; i < 300; ++i) {
        const Body a = randomBox(rnd, "a");
        const int k = i % 3, u = (k + 1) % 3, v = (k + 2) % 3;
        const Vec3 up = axis(a, k);
        // b turned so that its corner (-1, -1, -1) points straight down towards a's face.
        const Quat down = Quat::FromTwoVectors(Vec3(-1.0, -1.0, -1.0).normalized(), -up);
        const Quat spin(Eigen::AngleAxisd(rnd.uniform(0.0, 2.0 * M_PI), up));
        const double s = rnd.uniform(0.2, 1.0) * a.halfExtents.minCoeff();
        Body b = box("b", Vec3::Constant(s), 1.0).rotated((spin * down).normalized());
        const double depth = rnd.uniform(0.001, 0.1) * s;
        const Vec3 tip = a.position + (a.halfExtents[k] - depth) * up + rnd.uniform(-0.3, 0.3) * a.halfExtents[u] * axis(a, u) +
                         rnd.uniform(-0.3, 0.3) * a.halfExtents[v] * axis(a, v);
        b.position = tip - b.orientation * Vec3(-s, -s, -s);
        const std::optional<Contact> c = boxBox(a, b);
        const double tol = 1e-9 * scaleOf(a, b);  // the turn's rounding and the clipping's divisions
        ASSERT_TRUE(c) << "no contact, but b's corner is " << depth << " m into a's face" << pairText(a, b);
        ASSERT_TRUE(normalIs(*c, up, tol)) << " (a's face normal)" << pairText(a, b);
        ASSERT_NEAR(c->depth, depth, tol) << "depth of the corner" << pairText(a, b);
        ASSERT_TRUE(pointsBetween(*c, tip, up, depth, tol)) << pairText(a, b);
        // Passed the other way round: a's face is now the second box's, and the normal points from b to a.
        const std::optional<Contact> r = boxBox(b, a);
        ASSERT_TRUE(r) << "boxBox(b, a): no contact, but b's corner is " << depth << " m into a's face" << pairText(b, a);
        ASSERT_TRUE(normalIs(*r, -up, tol)) << " (boxBox(b, a): minus a's face normal)" << pairText(b, a);
        ASSERT_NEAR(r->depth, depth, tol) << "boxBox(b, a): depth of the corner" << pairText(b, a);
        ASSERT_TRUE(pointsBetween(*r, tip, up, depth, tol))
            << " (boxBox(b, a): when the second box's face is the reference face, clip against that face)" << pairText(b, a);
    }
    // An edge of b across a's face k: b's axis k along a's axis u, its other two axes at 45 degrees to
    // the face, so that the edge (-, -) lies lowest; the edge shorter than the face and within it.
    for (int i = 0; i < 90; ++i) {
        const Body a = randomBox(rnd, "a");
        const int k = i % 3, u = (k + 1) % 3, v = (k + 2) % 3;
        const Vec3 up = axis(a, k), along = axis(a, u), across = axis(a, v);
        Mat3 turn;  // columns: b's axes k, k + 1, k + 2 in the world
        turn.col(k) = along;
        turn.col(u) = (up + across) / std::sqrt(2.0);
        turn.col(v) = (up - across) / std::sqrt(2.0);
        Vec3 half;
        half[k] = rnd.uniform(0.1, 0.4) * a.halfExtents[u];
        half[u] = rnd.uniform(0.2, 1.0);
        half[v] = rnd.uniform(0.2, 1.0);
        Body b = box("b", half, 1.0).rotated(Quat(turn).normalized());
        const double depth = rnd.uniform(0.001, 0.05) * std::min(half[u], half[v]);
        const double at = rnd.uniform(-0.5, 0.5) * (a.halfExtents[u] - half[k]);  // the edge's middle along u (m)
        const Vec3 middle =
            a.position + (a.halfExtents[k] - depth) * up + at * along + rnd.uniform(-0.5, 0.5) * a.halfExtents[v] * across;
        b.position = middle + (half[u] + half[v]) / std::sqrt(2.0) * up + (half[u] - half[v]) / std::sqrt(2.0) * across;
        const std::optional<Contact> c = boxBox(a, b);
        const double tol = 1e-9 * scaleOf(a, b);  // the turn's rounding and the clipping's divisions
        ASSERT_TRUE(c) << "no contact, but b's edge lies " << depth << " m into a's face" << pairText(a, b);
        ASSERT_TRUE(normalIs(*c, up, tol)) << " (a's face normal, b's edge on it)" << pairText(a, b);
        ASSERT_NEAR(c->depth, depth, tol) << "depth of b's edge" << pairText(a, b);
        ASSERT_EQ(c->pointCount, 2) << "b's edge lies across a's face: its two ends are the points" << pairText(a, b)
                                    << "\n  " << str(c);
        double lo = INFINITY, hi = -INFINITY;  // the points' places along the edge (m from its middle)
        for (int p = 0; p < 2; ++p) {
            const Vec3 off = c->points[p] - middle;
            const double t = off.dot(along), h = off.dot(up);
            ASSERT_TRUE((off - t * along - h * up).norm() <= tol && h >= -tol && h <= depth + tol)
                << "point " << p << ", " << str(c->points[p]) << ", is not between b's edge and a's face" << pairText(a, b);
            lo = std::min(lo, t);
            hi = std::max(hi, t);
        }
        ASSERT_NEAR(lo, -half[k], tol) << "the points are not at the two ends of b's edge" << pairText(a, b);
        ASSERT_NEAR(hi, half[k], tol) << "the points are not at the two ends of b's edge" << pairText(a, b);
    }
}

GRADED_TEST(Worksheet5, BoxBoxApartOrTouching, 2,
            "boxBox(): as soon as one axis separates the boxes there is no contact; boxes whose faces, edges or "
            "corners exactly touch (an overlap of 0 on some axis) have none either: a contact needs an overlap > 0 "
            "on every axis.") {
    Random rnd(525);
    for (int i = 0; i < 300; ++i) {
        const Body a = randomBox(rnd, "a");
        const int k = i % 3;
        const Vec3 halfB(rnd.uniform(0.2, 2.0), rnd.uniform(0.2, 2.0), rnd.uniform(0.2, 2.0));
        const bool apart = i % 4 != 0;  // every fourth b stands a little into a: that one must touch
        const double into = i % 8 == 0 ? shallow(rnd) : rnd.uniform(0.001, 0.1) * std::min(a.halfExtents[k], halfB[k]);
        const double depth = apart ? -rnd.uniform(0.001, 0.5) : into;
        const Body b = standingOn(a, k, 1.0, halfB, depth, rnd.uniform(0.0, 2.0 * M_PI), rnd.uniform(-0.5, 0.5),
                                  rnd.uniform(-0.5, 0.5));
        const std::optional<Contact> c = boxBox(a, b);
        if (apart) {
            ASSERT_FALSE(c) << "b floats above a's face, yet: " << str(c) << pairText(a, b);
        } else {
            ASSERT_TRUE(c) << "b stands " << depth << " m deep on a's face, but there is no contact" << pairText(a, b);
        }
    }
    // Exactly touching, in numbers exact in binary: face on face, edge on edge (unturned boxes), and
    // a box turned half a turn about y (its axes exact) face to face.
    const Body a = box("a", {0.5, 0.25, 1.0}, 1.0).at({1.0, 2.0, 3.0});
    const Body turned = box("b", {0.25, 0.5, 0.75}, 1.0).rotated(Quat(0.0, 0.0, 1.0, 0.0));
    for (Body b : {box("b", {0.25, 0.5, 0.75}, 1.0).at({1.25, 2.75, 3.5}),
                   box("b", {0.25, 0.5, 0.75}, 1.0).at({1.75, 2.75, 3.0}), Body(turned).at({1.0, 2.0, 4.75})}) {
        const std::optional<Contact> c = boxBox(a, b);
        ASSERT_FALSE(c) << "the boxes exactly touch, which is no contact, yet: " << str(c) << pairText(a, b);
    }
}

GRADED_TEST(Worksheet5, BoxBoxSeparatedAlongEdges, 2,
            "boxBox() for two turned boxes whose edges cross with a gap: every face axis overlaps (their bounding "
            "boxes do too), and only the cross product of the two edges separates them, whichever of the nine a_i x "
            "b_j it is. Without all nine edge axes they would count as touching.") {
    Random rnd(526);
    for (int i = 0; i < 300; ++i) {
        const bool apart = i % 4 != 0;  // every fourth pair crosses a little into each other: that one touches
        const Crossing x = crossingEdges(rnd, apart ? rnd.uniform(0.001, 0.1) : -rnd.uniform(0.001, 0.1), i % 3, i / 3 % 3);
        const std::optional<Contact> c = boxBox(x.a, x.b);
        if (apart) {
            ASSERT_FALSE(c) << "the edges cross with a gap between them, yet: " << str(c) << pairText(x.a, x.b);
        } else {
            ASSERT_TRUE(c) << "the edges cross into each other, but there is no contact" << pairText(x.a, x.b);
        }
    }
}

GRADED_TEST(Worksheet5, BoxBoxSwapNegatesNormal, 2,
            "boxBox(b, a) must describe the same contact as boxBox(a, b): the normal reversed (it points from the "
            "first box to the second), the same depth, the points in the same region. Orient the axis by the "
            "difference of the centres, c_b - c_a.",
            grading::dependsOn("Worksheet5.BoxBoxFace")) {
    Random rnd(527);
    int contacts = 0;
    for (int i = 0; i < 300; ++i) {
        const Body a = randomBox(rnd, "a");
        Body b = randomBox(rnd, "b");
        b.position = a.position + rnd.uniform(0.5, 1.2) * (a.halfExtents.norm() + b.halfExtents.norm()) / 2.0 *
                                      rnd.direction();
        const std::optional<Contact> ab = boxBox(a, b), ba = boxBox(b, a);
        ASSERT_EQ(ab.has_value(), ba.has_value()) << str(ab) << " one way, " << str(ba) << " the other" << pairText(a, b);
        if (!ab) continue;
        ++contacts;
        const double tol = kRounding * scaleOf(a, b);
        ASSERT_LE((ab->normal + ba->normal).norm(), tol)
            << "normal " << str(ab->normal) << " for (a, b) but " << str(ba->normal) << " for (b, a)" << pairText(a, b);
        ASSERT_NEAR(ab->depth, ba->depth, tol) << "depth for (a, b) and for (b, a)" << pairText(a, b);
    }
    EXPECT_GT(contacts, 50) << "too few of the pairs touched to tell";
}

// ---- In the engine -----------------------------------------------------------------------------------
// Stepped with the student's hooks of worksheets 1, 3 and 4 too: it depends on their tests.

GRADED_TEST(Worksheet5, BoxesComeToRestOnFloor, 3,
            "Boxes dropped on a floor (one flat, one tilted so that it lands on an edge, one on a corner) must "
            "come to rest on it and never sink through: boxPlane() must report the deepest corner's depth and a "
            "normal into the plane, so that the interpenetration stage lifts the box out and the impulse stops it.",
            grading::dependsOn("Worksheet1.MatchesDiscreteFreeFall"),
            grading::dependsOn("Worksheet3.ResolveStaticBodyUntouched"),
            grading::dependsOn("Worksheet4.RestingBallStaysPut"), grading::dependsOn("Worksheet5.BoxPlaneTilted")) {
    engine.setRequiredStages({Stage::ConstantAcceleration, Stage::Integration, Stage::CollisionDetection,
                              Stage::CollisionImpulses, Stage::Interpenetration});
    const Body floor = plane("floor", {0.0, 1.0, 0.0}).at({0.0, -0.5, 0.0});
    engine.add(floor);
    const Quat edge(Eigen::AngleAxisd(0.3, Vec3::UnitZ()));
    const Quat corner = Quat(Eigen::AngleAxisd(0.5, Vec3::UnitX())) * Quat(Eigen::AngleAxisd(0.4, Vec3::UnitZ()));
    engine.add(box("flat", {0.5, 0.3, 0.4}, 2.0).at({-2.0, 2.0, 0.0}).bouncy(0.3));
    engine.add(box("edge", {0.4, 0.4, 0.4}, 1.0).at({0.0, 3.0, 0.0}).rotated(edge).bouncy(0.3));
    engine.add(box("corner", {0.3, 0.6, 0.3}, 3.0).at({2.0, 2.5, 1.0}).rotated(corner).bouncy(0.3));
    const double h = engine.timeStep(), g = engine.gravity().norm();
    grading::steps(engine, 500, [&](int k) {  // 5 s: fallen, bounced and settled
        for (std::size_t i = 1; i < engine.bodies().size(); ++i) {
            const Body& b = engine.bodies()[i];
            double lowest = INFINITY;
            for (const Vec3& x : corners(b)) lowest = std::min(lowest, checks::heightAbove(floor, x));
            // Found a step late at most: the fall of one step, v h with v <= sqrt(2 g 3 m) < 8 m/s.
            ASSERT_GE(lowest, -8.0 * h) << "step " << k << ": box " << b.name << "'s lowest corner is " << -lowest
                                        << " m below the floor: it is sinking through";
        }
    });
    if (HasFailure()) return;
    for (std::size_t i = 1; i < engine.bodies().size(); ++i) {
        const Body& b = engine.bodies()[i];
        double lowest = INFINITY;
        for (const Vec3& x : corners(b)) lowest = std::min(lowest, checks::heightAbove(floor, x));
        // At rest as a ball is (worksheet 4, 5.1): within one step's fall, g h^2, of the floor, and
        // no faster than one step's gravity, g h.
        EXPECT_LE(std::abs(lowest), g * h * h) << "box " << b.name << " ends " << lowest << " m above the floor";
        EXPECT_LE(b.velocity.norm(), g * h * (1.0 + 1e-9)) << "box " << b.name << " still moves at " << str(b.velocity);
    }
}

}  // namespace
}  // namespace gpl
