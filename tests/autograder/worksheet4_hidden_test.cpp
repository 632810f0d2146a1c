// Worksheet 4, hidden tests: graded by instructors and on Gradescope, left out of student releases
// (./lab release drops every file that declares a hidden test; such a file holds hidden tests only).
#include <cmath>
#include <string>

#include "contacts.h"
#include "gpl/response.h"
#include "graded.h"

namespace gpl {
namespace {

using checks::Random;
using checks::str;

class Worksheet4Hidden : public checks::ContactsTest {};

GRADED_TEST(Worksheet4Hidden, ImpulseSameInEveryInertialFrame, 2,
            "The impulse may depend only on relative velocities: seen from a frame that moves with constant "
            "velocity u, every velocity after the collision is the same plus u. Use (v_b - v_a) . n, never one "
            "body's velocity alone.",
            grading::hidden()) {
    Random rnd(451);
    int changes = 0;
    for (int i = 0; i < 300; ++i) {
        const double ra = rnd.uniform(0.1, 1.0), rb = rnd.uniform(0.1, 1.0);
        Body a = sphere("a", ra, rnd.uniform(0.1, 10.0)).at(rnd.inBox(10.0)).moving(rnd.inBox(5.0));
        Body b = sphere("b", rb, rnd.uniform(0.1, 10.0)).moving(rnd.inBox(5.0));
        Vec3 n = rnd.direction();
        if ((b.velocity - a.velocity).dot(n) > 0.0) n = -n;  // approaching along n
        b.position = a.position + (ra + rb - 0.01) * n;
        const Contact c = checks::contactAlong(n, 0.01, a.position + ra * n, rnd.uniform(0.0, 1.0));
        const Vec3 u = rnd.inBox(20.0);  // m/s: the other frame
        Body a2 = a, b2 = b;
        a2.velocity += u;
        b2.velocity += u;
        const Body a0 = a, b0 = b;
        applyCollisionImpulse(c, a, b);
        applyCollisionImpulse(c, a2, b2);
        // Speeds up to ~40 m/s: 1e-12 of them is rounding; a frame-dependent impulse is off by ~u.
        const double tol = 1e-12 * (1.0 + a0.velocity.norm() + b0.velocity.norm() + u.norm());
        changes += a.velocity != a0.velocity || b.velocity != b0.velocity;
        ASSERT_LE((a2.velocity - u - a.velocity).norm() + (b2.velocity - u - b.velocity).norm(), tol)
            << "after the collision seen from a frame moving at " << str(u) << " the velocities are "
            << str(a2.velocity - u) << " and " << str(b2.velocity - u) << " (back in this frame), here "
            << str(a.velocity) << " and " << str(b.velocity) << "\n  a: " << str(a0) << "\n  b: " << str(b0);
    }
    EXPECT_GT(changes, 0) << "the impulse never changed a velocity: applyCollisionImpulse() does nothing yet";
}

GRADED_TEST(Worksheet4Hidden, HeadOnCollisionMatchesClosedForm, 2,
            "Two balls colliding head on leave with v_a' = (m_a v_a + m_b v_b - m_b e (v_a - v_b)) / (m_a + m_b) "
            "and v_b' = (m_a v_a + m_b v_b - m_a e (v_b - v_a)) / (m_a + m_b): each velocity change is the impulse "
            "divided by that ball's own mass.",
            grading::dependsOn("Worksheet1.MatchesDiscreteFreeFall"),
            grading::dependsOn("Worksheet3.SphereSphereNormalAndDepth"),
            grading::dependsOn("Worksheet3.ResolveMassWeighted"), grading::hidden()) {
    Random rnd(452);
    for (const double e : {0.0, 0.4, 0.8, 1.0}) {
        for (int i = 0; i < 4; ++i) {
            engine.clear();
            engine.setRequiredStages({Stage::ConstantAcceleration, Stage::Integration, Stage::CollisionDetection,
                                      Stage::CollisionImpulses, Stage::Interpenetration});
            engine.setGravity(Vec3::Zero());
            const Vec3 axis = rnd.direction(), start = rnd.inBox(5.0);
            const double ma = rnd.uniform(0.2, 5.0), mb = rnd.uniform(0.2, 5.0);
            const double va = rnd.uniform(1.0, 3.0), vb = -rnd.uniform(0.0, 3.0);  // along the axis (m/s)
            engine.add(sphere("a", 0.3, ma).at(start).moving(va * axis).bouncy(e));
            engine.add(sphere("b", 0.4, mb).at(start + 1.5 * axis).moving(vb * axis).bouncy(1.0));
            grading::steps(engine, 150, [](int) {});  // 1.5 s: they close 0.8 m at 1 m/s or more
            const double p = ma * va + mb * vb;
            const double va1 = (p - mb * e * (va - vb)) / (ma + mb), vb1 = (p - ma * e * (vb - va)) / (ma + mb);
            // One impulse, exact to rounding of speeds of a few m/s (1e-12 of them); a mistake in the
            // impulse is off by a sizeable part of the closing speed.
            const double tol = 1e-12 * (1.0 + std::abs(va) + std::abs(vb));
            EXPECT_LE((engine.body("a").velocity - va1 * axis).norm(), tol)
                << "e = " << e << ", masses " << ma << " and " << mb << " kg, speeds " << va << " and " << vb
                << " m/s along " << str(axis) << ": a leaves with " << str(engine.body("a").velocity) << ", expected "
                << str(va1 * axis);
            EXPECT_LE((engine.body("b").velocity - vb1 * axis).norm(), tol)
                << "e = " << e << ", masses " << ma << " and " << mb << " kg: b leaves with "
                << str(engine.body("b").velocity) << ", expected " << str(vb1 * axis);
        }
    }
}

}  // namespace
}  // namespace gpl
