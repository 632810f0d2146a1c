// Worksheet 3, hidden tests: graded by instructors and on Gradescope, left out of student releases
// (./lab release drops every file that declares a hidden test; such a file holds hidden tests only).
#include <cmath>
#include <optional>
#include <string>

#include "contacts.h"
#include "gpl/collision.h"
#include "gpl/response.h"
#include "graded.h"

namespace gpl {
namespace {

using checks::carried;
using checks::Random;
using checks::str;

class Worksheet3Hidden : public checks::ContactsTest {};

GRADED_TEST(Worksheet3Hidden, ContactsFollowTheBodies, 2,
            "Turning and moving the whole scene must turn the contact's normal with it and leave its depth alone: "
            "compute everything from differences of positions and from the plane's own point and orientation.",
            grading::dependsOn("Worksheet3.SphereSphereNormalAndDepth"),
            grading::dependsOn("Worksheet3.SpherePlaneFloor"), grading::hidden()) {
    Random rnd(351);
    for (int i = 0; i < 300; ++i) {
        const Quat R = rnd.rotation();
        const Vec3 t = rnd.inBox(100.0);
        const double ra = rnd.uniform(0.1, 2.0), rb = rnd.uniform(0.1, 2.0);
        const Vec3 xa = rnd.inBox(10.0);
        const double distance = rnd.uniform(0.1, 1.5) * (ra + rb);
        const Body a = sphere("a", ra, 1.0).at(xa), b = sphere("b", rb, 2.0).at(xa + distance * rnd.direction());
        const Body p = plane("plane", rnd.direction()).at(rnd.inBox(10.0)).rotated(rnd.rotation());
        const Body s = sphere("ball", ra, 1.0)
                           .at(p.position + rnd.uniform(-1.0, 1.5) * ra * checks::worldNormal(p) +
                               rnd.uniform(0.0, 5.0) * rnd.perpendicular(checks::worldNormal(p)));
        // Coordinates up to ~200 m round to ~3e-14 m: 1e-12 of that scale for depths; a direction
        // taken from a difference over a distance d carries that rounding divided by d.
        const double scale = 1.0 + 200.0 + 2.0 * (ra + rb);
        const struct {
            std::optional<Contact> here, there;
            const char* what;
            double spread;  // m: the length the normal is taken over
        } cases[] = {{sphereSphere(a, b), sphereSphere(carried(a, R, t), carried(b, R, t)), "sphereSphere()", distance},
                     {spherePlane(s, p), spherePlane(carried(s, R, t), carried(p, R, t)), "spherePlane()", 1.0}};
        for (const auto& c : cases) {
            ASSERT_EQ(c.here.has_value(), c.there.has_value())
                << c.what << ": " << str(c.here) << " before, " << str(c.there) << " after turning by " << str(R.vec())
                << " (w " << R.w() << ") and moving by " << str(t);
            if (!c.here) continue;
            ASSERT_NEAR(c.there->depth, c.here->depth, 1e-12 * scale)
                << c.what << ": the depth changed when the whole scene was turned and moved by " << str(t);
            ASSERT_LE((c.there->normal - R * c.here->normal).norm(), 1e-12 * scale / c.spread)
                << c.what << ": normal " << str(c.there->normal) << " after turning, expected the turned "
                << str(R * c.here->normal);
        }
    }
}

GRADED_TEST(Worksheet3Hidden, DetectedOverlapsResolveToTouching, 2,
            "Feeding the contact of sphereSphere() or spherePlane() to resolveInterpenetration() must leave the "
            "bodies exactly touching: the depth and the normal of one kernel are what the other one moves by.",
            grading::dependsOn("Worksheet3.SphereSphereNormalAndDepth"),
            grading::dependsOn("Worksheet3.SpherePlaneFloor"), grading::hidden()) {
    Random rnd(352);
    for (int i = 0; i < 300; ++i) {
        const double ra = rnd.uniform(0.1, 2.0), rb = rnd.uniform(0.1, 2.0);
        const Vec3 xa = rnd.inBox(10.0);
        Body a = sphere("a", ra, rnd.uniform(0.1, 10.0)).at(xa);
        Body b = sphere("b", rb, rnd.uniform(0.1, 10.0)).at(xa + rnd.uniform(0.0, 0.98) * (ra + rb) * rnd.direction());
        if (i % 10 == 0) b.position = a.position;  // concentric: the fixed normal
        if (i % 4 == 1) a.makeStatic();
        const Body a0 = a, b0 = b;
        const std::optional<Contact> c = sphereSphere(a, b);
        ASSERT_TRUE(c) << "no contact\n  a: " << str(a) << "\n  b: " << str(b);
        resolveInterpenetration(*c, a, b);
        // Rounding of coordinates up to ~15 m: 1e-12 of them.
        ASSERT_NEAR((b.position - a.position).norm(), ra + rb, 1e-12 * (15.0 + ra + rb))
            << "after resolving " << str(c) << " the centres are not r_a + r_b apart\n  a: " << str(a0)
            << "\n  b: " << str(b0);
    }
    for (int i = 0; i < 300; ++i) {
        const Body p = plane("plane", rnd.direction()).at(rnd.inBox(10.0)).rotated(rnd.rotation());
        const double r = rnd.uniform(0.1, 2.0);
        const Vec3 n = checks::worldNormal(p);
        Body s = sphere("ball", r, 1.0)
                     .at(p.position + rnd.uniform(-1.0, 0.98) * r * n + rnd.uniform(0.0, 5.0) * rnd.perpendicular(n));
        Body q = p;
        const Body s0 = s;
        const std::optional<Contact> c = spherePlane(s, p);
        ASSERT_TRUE(c) << "no contact\n  sphere: " << str(s) << "\n  plane: " << str(p);
        resolveInterpenetration(*c, s, q);
        ASSERT_NEAR(checks::heightAbove(p, s.position), r, 1e-12 * (30.0 + r))
            << "after resolving " << str(c) << " the sphere does not just touch the plane\n  sphere: " << str(s0)
            << "\n  plane: " << str(p);
    }
}

}  // namespace
}  // namespace gpl
