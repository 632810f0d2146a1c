// Worksheet 1 autograder: gravity, the time step and the semi-implicit Euler integrator.
// Every test checks physics against a closed form or an invariant, never stored numbers.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "gpl/engine.h"
#include "gpl/scenes.h"
#include "graded.h"

namespace gpl {
namespace {

std::string str(const Vec3& v) {
    std::ostringstream out;
    out.precision(10);
    out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
    return out.str();
}

// Relative closeness with a floor of 1 (m, m/s) for values near zero.
::testing::AssertionResult near(const Vec3& actual, const Vec3& expected, double relTol, const std::string& what) {
    const double err = (actual - expected).norm();
    const double scale = std::max(1.0, expected.norm());
    if (err <= relTol * scale) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << what << " is " << str(actual) << ", expected " << str(expected)
                                         << " (off by " << err << ")";
}

// Fails with near()'s message alone; further text can be streamed after it.
#define EXPECT_CLOSE(actual, expected, relTol, what)                                       \
    if (const ::testing::AssertionResult gpl_close = near(actual, expected, relTol, what)) \
        ;                                                                                  \
    else                                                                                   \
        ADD_FAILURE() << gpl_close.message()

class Worksheet1 : public ::testing::Test {
protected:
    PhysicsEngine engine;

    void TearDown() override {
        if (HasFailure() && !engine.missingHooks().empty()) {
            std::string hooks;
            for (const auto& h : engine.missingHooks()) hooks += " " + h;
            ADD_FAILURE() << "hooks still not implemented:" << hooks;
        }
    }

    // Spheres and boxes from 0.1 kg to 1000 kg at rest, 10 m up, no stages forced off.
    void addMassLine() {
        const double masses[] = {0.1, 1.0, 1000.0};
        int i = 0;
        for (double m : masses) {
            engine.add(sphere("sphere" + std::to_string(i), 0.5, m).at({2.0 * i, 10.0, 0.0}));
            engine.add(box("box" + std::to_string(i), {0.5, 0.5, 0.5}, m).at({2.0 * i, 10.0, 3.0}));
            ++i;
        }
    }

    std::vector<const Scene*> worksheetScenes() const {
        std::vector<const Scene*> out;
        for (const Scene& s : scenes().all()) {
            if (s.worksheet == 1) out.push_back(&s);
        }
        return out;
    }

    void steps(int n) {
        grading::steps(engine, n, [](int) {});
    }

    // Steps for a long run of the loaded scene: `wanted`, but at most 2e6 body-steps, so that the
    // 1000-body scene runs 2000 steps (under a second here, a few in sanitizer builds).
    int longRun(int wanted) const {
        const auto bodies = static_cast<int>(std::max<std::size_t>(1, engine.bodies().size()));
        return std::clamp(2000000 / bodies, 2000, wanted);
    }
};

// The exact semi-implicit Euler step from (x, v) with acceleration g.
struct State {
    Vec3 x, v;
};
State symplecticStep(const State& s, const Vec3& g, double h) {
    const Vec3 v = s.v + h * g;
    return {s.x + h * v, v};
}

// Rounding in one update of a few additions: a handful of ulps; 1e-12 relative allows any
// algebraically equivalent ordering while a wrong update is off by h^2 g ~ 1e-3 or more.
constexpr double kOneStepTol = 1e-12;

GRADED_TEST(Worksheet1, GravityIndependentOfMass, 2,
            "Every body falls with the same acceleration g, whatever its mass: use the acceleration "
            "accumulator as it is (v += h * a), not multiplied or divided by the mass (worksheet 1, "
            "assignment 3, eq. 2 with F = m g).") {
    addMassLine();
    const double h = engine.timeStep();
    engine.step();
    for (const Body& b : engine.bodies()) {
        EXPECT_CLOSE(b.velocity, h * engine.gravity(), kOneStepTol,
                     "velocity of " + b.name + " (" + std::to_string(b.mass) + " kg)");
    }
}

GRADED_TEST(Worksheet1, GravityPointsDown, 2,
            "Bodies must fall down (negative y): add h times the acceleration to the velocity; gravity "
            "(0, -9.81, 0) already carries the sign (worksheet 1, assignment 3).") {
    addMassLine();
    std::vector<double> y0;
    for (const Body& b : engine.bodies()) y0.push_back(b.position.y());
    steps(10);
    for (std::size_t i = 0; i < engine.bodies().size(); ++i) {
        const Body& b = engine.bodies()[i];
        EXPECT_LT(b.velocity.y(), 0.0) << b.name << " should be falling after 10 steps, velocity " << str(b.velocity);
        EXPECT_LT(b.position.y(), y0[i]) << b.name << " should be lower after 10 steps";
    }
}

GRADED_TEST(Worksheet1, SimulationTimestepAppliesGravity, 2,
            "simulationTimestep() must call updateConstantAcceleration() so that gravity reaches the "
            "bodies' acceleration accumulators (worksheet 1, assignment 3, first item).") {
    engine.add(sphere("ball", 0.5, 2.0).at({0.0, 5.0, 0.0}));
    ASSERT_EQ(engine.body("ball").acceleration, Vec3::Zero());
    engine.simulationTimestep();
    const Body& b = engine.body("ball");
    EXPECT_CLOSE(b.acceleration, engine.gravity(), kOneStepTol, "acceleration accumulator after one step")
        << "\n  the accumulator does not hold gravity: is updateConstantAcceleration() called?";
    EXPECT_LT(b.velocity.y(), 0.0) << "one call of simulationTimestep() left the ball at rest";
}

GRADED_TEST(Worksheet1, GravityAppliedExactlyOnce, 2,
            "Gravity is in the accumulator already: the integrator uses body.acceleration and does not "
            "add gravity() again; simulationTimestep() applies it once per step.") {
    engine.add(sphere("ball", 0.5, 1.0).at({0.0, 5.0, 0.0}));
    const double h = engine.timeStep();
    engine.step();
    const Vec3 v = engine.body("ball").velocity;
    EXPECT_CLOSE(v, h * engine.gravity(), kOneStepTol, "velocity after one step from rest")
        << "\n  expected h g = " << str(h * engine.gravity())
        << (std::abs(v.y() - 2.0 * h * engine.gravity().y()) < 1e-9 ? "; you applied gravity twice (2 h g)" : "");
}

GRADED_TEST(Worksheet1, GravityAppliedBeforeIntegrating, 2,
            "In simulationTimestep() the forces come first: call updateConstantAcceleration() before "
            "integrator(), so the very first step already feels gravity.") {
    engine.add(sphere("ball", 0.5, 1.0).at({0.0, 5.0, 0.0}));
    const double h = engine.timeStep();
    engine.step();
    const Vec3 first = engine.body("ball").velocity;
    steps(9);
    const Vec3 tenth = engine.body("ball").velocity;
    const bool late = first.isZero() && (tenth - 9.0 * h * engine.gravity()).norm() < 1e-9;
    EXPECT_CLOSE(first, h * engine.gravity(), kOneStepTol, "velocity after the first step")
        << (late ? "\n  the first step did not accelerate the ball, the later ones did: gravity is applied after "
                   "the integrator"
                 : "");
    EXPECT_CLOSE(tenth, 10.0 * h * engine.gravity(), kOneStepTol, "velocity after ten steps");
}

GRADED_TEST(Worksheet1, AccelerationResetEachStep, 2,
            "The acceleration accumulator holds gravity once, anew each step: use "
            "updateConstantAcceleration(), which sets it, rather than adding gravity to it yourself.",
            grading::dependsOn("SimulationTimestepAppliesGravity")) {
    engine.add(box("crate", {0.5, 0.5, 0.5}, 3.0).at({0.0, 50.0, 0.0}));
    const double h = engine.timeStep();
    const int n = 50;
    steps(n);
    const Body& b = engine.body("crate");
    EXPECT_CLOSE(b.acceleration, engine.gravity(), kOneStepTol, "acceleration accumulator after 50 steps");
    // 50 additions of h g round to about 1e-14 relative; a summed accumulator is off by a factor ~n/2.
    EXPECT_CLOSE(b.velocity, n * h * engine.gravity(), 1e-10, "velocity after 50 steps")
        << "\n  velocity must grow linearly in time (v = n h g)";
}

GRADED_TEST(Worksheet1, StaticBodiesUntouched, 2,
            "Static bodies (isStatic(), inverse mass 0) never move: skip them in the integrator and use "
            "the acceleration accumulator, which is zero for them.") {
    load(engine, scenes().find("static-and-movable"));
    const std::vector<Body> before = engine.bodies();
    steps(200);
    int moved = 0;
    for (std::size_t i = 0; i < before.size(); ++i) {
        const Body& b = engine.bodies()[i];
        if (before[i].isStatic()) {
            EXPECT_EQ(b.position, before[i].position) << "static body " << b.name << " moved";
            EXPECT_EQ(b.velocity, before[i].velocity) << "static body " << b.name << " gained a velocity";
            EXPECT_TRUE(b.orientation.isApprox(before[i].orientation, 0.0)) << "static body " << b.name << " turned";
        } else if (b.position != before[i].position) {
            ++moved;
        }
    }
    EXPECT_GT(moved, 0) << "no movable body moved in 200 steps: the check on static bodies means nothing yet";
}

GRADED_TEST(Worksheet1, OneStepIsSemiImplicitEuler, 3,
            "Update the velocity first and move the body with the NEW velocity: v += h a; x += h v "
            "(semi-implicit Euler, worksheet 1, assignment 3, last item).") {
    const State s0{Vec3(1.0, 2.0, 3.0), Vec3(4.0, 5.0, -6.0)};
    const double h = 0.02;
    engine.setTimeStep(h);
    engine.add(sphere("ball", 0.5, 1.5).at(s0.x).moving(s0.v));
    engine.step();
    const State expected = symplecticStep(s0, engine.gravity(), h);
    const Body& b = engine.body("ball");
    EXPECT_CLOSE(b.velocity, expected.v, kOneStepTol, "velocity after one step");
    const bool explicitEuler = (b.position - (s0.x + h * s0.v)).norm() < 1e-9;
    EXPECT_CLOSE(b.position, expected.x, kOneStepTol, "position after one step")
        << (explicitEuler ? "\n  this is explicit Euler (x += h v with the old velocity): it adds m g^2 h^2 / 2 of "
                            "energy every step; move the body with the updated velocity instead"
                          : "");
}

GRADED_TEST(Worksheet1, UsesEngineTimeStep, 2,
            "Take the time step from timeStep(), never a constant in your code: scenes and the grader "
            "change it.") {
    const State s0{Vec3(0.0, 1.0, 0.0), Vec3(1.0, 2.0, 0.5)};
    for (double h : {0.001, 0.005, 0.02, 0.05}) {
        PhysicsEngine e;
        e.setTimeStep(h);
        e.add(sphere("ball", 0.5, 1.0).at(s0.x).moving(s0.v));
        e.step();
        const State expected = symplecticStep(s0, e.gravity(), h);
        EXPECT_CLOSE(e.body("ball").velocity, expected.v, kOneStepTol, "velocity") << " with h = " << h << " s";
        EXPECT_CLOSE(e.body("ball").position, expected.x, kOneStepTol, "position") << " with h = " << h << " s";
    }
}

GRADED_TEST(Worksheet1, MatchesDiscreteFreeFall, 3,
            "After n steps semi-implicit Euler gives v_n = v0 + n h g and x_n = x0 + n h v0 + n(n+1)/2 h^2 g, at any "
            "speed (a bullet at 670 m/s too); check that every step uses the same h and the new velocity, and that "
            "nothing caps the speed.",
            grading::dependsOn("OneStepIsSemiImplicitEuler"), grading::dependsOn("UsesEngineTimeStep")) {
    const Vec3 x0(-10.0, 1.0, 0.0), v0(10.6, 10.6, 0.0);
    const double h = 0.004;
    const int n = 1000;
    engine.setTimeStep(h);
    const Vec3 bullet0(600.0, 300.0, 0.0);  // m/s
    engine.add(sphere("projectile", 0.3, 0.5).at(x0).moving(v0));
    engine.add(sphere("bullet", 0.01, 0.01).at(x0 + Vec3(0.0, 0.0, 5.0)).moving(bullet0));
    steps(n);
    const Vec3 g = engine.gravity();
    const Vec3 vn = v0 + n * h * g;
    const Vec3 xn = x0 + n * h * v0 + 0.5 * n * (n + 1) * h * h * g;
    // 1000 steps accumulate about 1000 roundings (~2e-13 relative); explicit Euler is off by n h^2 g (0.16 m).
    const double tol = 1e-10;
    EXPECT_CLOSE(engine.body("projectile").velocity, vn, tol, "velocity after 1000 steps");
    EXPECT_CLOSE(engine.body("projectile").position, xn, tol, "position after 1000 steps");
    EXPECT_CLOSE(engine.body("bullet").velocity, Vec3(bullet0 + n * h * g), tol, "the bullet's velocity after 1000 steps");
    EXPECT_CLOSE(engine.body("bullet").position,
                 Vec3(x0 + Vec3(0.0, 0.0, 5.0) + n * h * bullet0 + 0.5 * n * (n + 1) * h * h * g), tol,
                 "the bullet's position after 1000 steps");
}

GRADED_TEST(Worksheet1, EnergyNeverIncreases, 3,
            "Total energy must not grow: explicit Euler adds m g^2 h^2 / 2 per step; semi-implicit Euler "
            "(velocity first, then position with the new velocity) never adds any.",
            grading::dependsOn("GravityPointsDown"), grading::timeLimit(20)) {
    for (const Scene* scene : worksheetScenes()) {
        load(engine, *scene);
        const std::vector<Body> start = engine.bodies();
        double previous = engine.totalEnergy();
        grading::steps(engine, longRun(10000), [&](int i) {
            const double energy = engine.totalEnergy();
            // Rounding in the energy sums is a few ulps of the largest term; 1e-12 of the terms'
            // magnitude (at most ~1e6 J after 100 s of fall) is far below the smallest genuine
            // increase, m g^2 h^2 / 2 = 5e-4 J for the lightest body at h = 0.01 s.
            const double scale = engine.kineticEnergy() + std::abs(engine.potentialEnergy()) + 1.0;
            ASSERT_LE(energy, previous + 1e-12 * scale)
                << "scene '" << scene->name << "': total energy rose by " << energy - previous << " J in step " << i;
            previous = energy;
        });
        if (HasFailure()) return;
        bool moved = false;
        for (std::size_t i = 0; i < start.size(); ++i) moved |= engine.bodies()[i].position != start[i].position;
        EXPECT_TRUE(moved) << "scene '" << scene->name << "': nothing moved, so energy cannot tell anything yet";
    }
}

GRADED_TEST(Worksheet1, StaysFinite, 1,
            "Positions and velocities must stay finite numbers: check for divisions by a zero mass "
            "(static bodies) and assert isFinite() in your integrator.",
            grading::timeLimit(20)) {
    for (const Scene* scene : worksheetScenes()) {
        load(engine, *scene);
        const double y0 = engine.bodies().back().position.y();
        ASSERT_NO_THROW(steps(longRun(5000))) << "scene '" << scene->name << "'";
        EXPECT_TRUE(engine.allFinite()) << "scene '" << scene->name << "'";
        EXPECT_LT(engine.bodies().back().position.y(), y0) << "scene '" << scene->name << "': the last body never fell";
    }
}

}  // namespace
}  // namespace gpl
