// Worksheet 5, hidden tests: graded by instructors and on Gradescope, left out of student releases
// (./lab release drops every file that declares a hidden test; such a file holds hidden tests only).
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "contacts.h"
#include "gpl/collision.h"
#include "graded.h"

namespace gpl {
namespace {

using checks::carried;
using checks::corners;
using checks::Random;
using checks::str;

class Worksheet5Hidden : public checks::ContactsTest {};

Body randomBox(Random& rnd, const std::string& name) {
    const Vec3 half(rnd.uniform(0.2, 2.0), rnd.uniform(0.2, 2.0), rnd.uniform(0.2, 2.0));
    return box(name, half, 1.0).at(rnd.inBox(5.0)).rotated(rnd.rotation());
}

GRADED_TEST(Worksheet5Hidden, ContactsFollowTheBodies, 3,
            "Turning and moving the whole scene must turn the normal and the points with it and leave the depth "
            "alone: compute everything in the boxes' own frames and from differences of positions.",
            grading::dependsOn("Worksheet5.SphereBoxFace"), grading::dependsOn("Worksheet5.BoxPlaneTilted"),
            grading::dependsOn("Worksheet5.BoxBoxFace"), grading::hidden()) {
    Random rnd(551);
    int contacts = 0;
    for (int i = 0; i < 300; ++i) {
        const Quat R = rnd.rotation();
        const Vec3 t = rnd.inBox(50.0);
        const Body a = randomBox(rnd, "a");
        Body b = randomBox(rnd, "b");
        b.position = a.position + rnd.uniform(0.3, 1.2) * (a.halfExtents.norm() + b.halfExtents.norm()) / 2.0 *
                                      rnd.direction();
        const double r = rnd.uniform(0.1, 1.0);
        const Body ball = sphere("ball", r, 1.0).at(a.position + rnd.uniform(0.0, 1.2) * (a.halfExtents.norm() + r) *
                                                                      rnd.direction());
        const Body p = plane("plane", rnd.direction()).at(a.position + rnd.uniform(-1.0, 1.0) * a.halfExtents.norm() *
                                                                           rnd.direction());
        // Coordinates up to ~100 m round to ~2e-14 m; the clipping divides by differences of ~0.1 m:
        // 1e-10 of the scale, while a frame mistake moves things by centimetres.
        const double tol = 1e-10 * (1.0 + a.position.norm() + t.norm());
        const struct {
            std::optional<Contact> here, there;
            const char* what;
        } cases[] = {{sphereBox(ball, a), sphereBox(carried(ball, R, t), carried(a, R, t)), "sphereBox()"},
                     {boxPlane(a, p), boxPlane(carried(a, R, t), carried(p, R, t)), "boxPlane()"},
                     {boxBox(a, b), boxBox(carried(a, R, t), carried(b, R, t)), "boxBox()"}};
        for (const auto& c : cases) {
            ASSERT_EQ(c.here.has_value(), c.there.has_value())
                << c.what << ": " << str(c.here) << " before, " << str(c.there) << " after turning and moving the scene";
            if (!c.here) continue;
            ++contacts;
            ASSERT_NEAR(c.there->depth, c.here->depth, tol)
                << c.what << ": the depth changed when the whole scene was turned and moved";
            ASSERT_LE((c.there->normal - R * c.here->normal).norm(), tol)
                << c.what << ": normal " << str(c.there->normal) << " after turning, expected the turned "
                << str(R * c.here->normal);
            // Where clipping leaves more than four points, which four to keep is a choice that rounding
            // may tip when two are equally good: the points are compared where there is no such choice.
            if (c.here->pointCount == kMaxContactPoints && c.what == std::string("boxBox()")) continue;
            ASSERT_EQ(c.there->pointCount, c.here->pointCount) << c.what << ": the number of points changed";
            for (int k = 0; k < c.here->pointCount; ++k) {
                const Vec3 moved = R * c.here->points[k] + t;
                bool found = false;
                for (int m = 0; m < c.there->pointCount; ++m) found = found || (c.there->points[m] - moved).norm() <= tol;
                ASSERT_TRUE(found) << c.what << ": the point " << str(c.here->points[k]) << " did not move with the "
                                   << "scene to " << str(moved);
            }
        }
    }
    EXPECT_GT(contacts, 300) << "too few of the configurations touched to tell";
}

GRADED_TEST(Worksheet5Hidden, StackOfBoxesStands, 3,
            "A stack of three boxes on a floor must stand still: each box's contact with the one below must push it "
            "straight up by the overlap (the normal from a to b, the depth of the face axis), never sideways along an "
            "edge axis.",
            grading::dependsOn("Worksheet1.MatchesDiscreteFreeFall"),
            grading::dependsOn("Worksheet3.ResolveStaticBodyUntouched"),
            grading::dependsOn("Worksheet4.RestingBallStaysPut"), grading::dependsOn("Worksheet5.BoxBoxStackPoints"),
            grading::hidden()) {
    engine.setRequiredStages({Stage::ConstantAcceleration, Stage::Integration, Stage::CollisionDetection,
                              Stage::CollisionImpulses, Stage::Interpenetration});
    engine.add(plane("floor", {0.0, 1.0, 0.0}));
    const Vec3 half(0.5, 0.25, 0.4);
    for (int k = 0; k < 3; ++k) {
        engine.add(box("box" + std::to_string(k + 1), half, 1.0 + k)
                       .at({0.05 * k, half.y() * (2 * k + 1), -0.03 * k})
                       .rotated(Quat(Eigen::AngleAxisd(0.2 * k, Vec3::UnitY())))
                       .bouncy(0.0));
    }
    const std::vector<Body> start = engine.bodies();
    grading::steps(engine, 300, [&](int step) {  // 3 s
        for (std::size_t i = 1; i < start.size(); ++i) {
            const Body& b = engine.bodies()[i];
            // The column of worksheet 4 (5.4) creeps by rounding at most; a wrong contact moves it by
            // centimetres within a step or two.
            ASSERT_LE((b.position - start[i].position).norm(), 0.01)
                << "step " << step << ": " << b.name << " moved from " << str(start[i].position) << " to "
                << str(b.position);
        }
    });
    if (HasFailure()) return;
    double lowest = INFINITY;
    for (const Vec3& x : corners(engine.bodies()[1])) lowest = std::min(lowest, x.y());
    EXPECT_GE(lowest, -engine.gravity().norm() * engine.timeStep() * engine.timeStep())
        << "the bottom box sank into the floor";
}

}  // namespace
}  // namespace gpl
