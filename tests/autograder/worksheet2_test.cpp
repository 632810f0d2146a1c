// Worksheet 2 autograder: position Verlet and velocity Verlet, called as pure kernels.
// Every test checks physics against a closed form, a measured order or an invariant.
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "gpl/integrators.h"
#include "graded.h"

namespace gpl {
namespace {

using Kernel = void (*)(ParticleState&, const AccelerationFunction&, double);

std::string str(const Vec3& v) {
    std::ostringstream out;
    out.precision(12);
    out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
    return out.str();
}

const Vec3 kGravity(0.0, -9.81, 0.0);

void gravity(const std::vector<Vec3>& x, const std::vector<Vec3>&, std::vector<Vec3>& a) {
    a.assign(x.size(), kGravity);
}

// x'' = -omega^2 x with omega = 2 rad/s.
constexpr double kOmega = 2.0;
void spring(const std::vector<Vec3>& x, const std::vector<Vec3>&, std::vector<Vec3>& a) {
    a.resize(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) a[i] = -kOmega * kOmega * x[i];
}

// A pendulum-like nonlinear force per component: x'' = -sin(x) (rad/s^2 for x in rad).
void nonlinear(const std::vector<Vec3>& x, const std::vector<Vec3>&, std::vector<Vec3>& a) {
    a.resize(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) a[i] = -x[i].array().sin().matrix();
}

const char* kernelName(Kernel kernel) { return kernel == positionVerlet ? "positionVerlet()" : "velocityVerlet()"; }

// `accel`, counting its calls in `calls`.
AccelerationFunction counting(const AccelerationFunction& accel, int& calls) {
    return [accel, &calls](const std::vector<Vec3>& x, const std::vector<Vec3>& v, std::vector<Vec3>& a) {
        ++calls;
        accel(x, v, a);
    };
}

double oscillatorEnergy(const ParticleState& s) {
    return 0.5 * s.v[0].squaredNorm() + 0.5 * kOmega * kOmega * s.x[0].squaredNorm();
}

class Worksheet2 : public ::testing::Test {
protected:
    void TearDown() override {
        const std::vector<std::string> open = kernelsNotImplemented();
        if (HasFailure() && !open.empty()) {
            std::string hooks;
            for (const auto& h : open) hooks += " " + h;
            ADD_FAILURE() << "hooks still not implemented:" << hooks;
        }
    }

    static ParticleState start(const Vec3& x0, const Vec3& v0, const AccelerationFunction& accel) {
        return startState({x0}, {v0}, accel);
    }

    static void run(Kernel kernel, ParticleState& s, const AccelerationFunction& accel, double h, int steps) {
        for (int i = 0; i < steps; ++i) kernel(s, accel, h);
    }

    // Position and velocity errors at t = 1.3 s of the oscillator from (1, 0), n steps.
    static std::pair<double, double> oscillatorErrors(Kernel kernel, int n) {
        const double t = 1.3, h = t / n;
        ParticleState s = start(Vec3(1.0, 0.0, 0.0), Vec3::Zero(), spring);
        run(kernel, s, spring, h, n);
        const double dx = (s.x[0] - Vec3(std::cos(kOmega * t), 0.0, 0.0)).norm();
        const double dv = (s.v[0] - Vec3(-kOmega * std::sin(kOmega * t), 0.0, 0.0)).norm();
        return {dx, dv};
    }

    // Slope of log(error) over log(h) from n, 2n, 4n, 8n steps (least squares).
    static double order(Kernel kernel, int n, bool velocity) {
        double sx = 0, sy = 0, sxx = 0, sxy = 0;
        for (int k = 0; k < 4; ++k) {
            const auto e = oscillatorErrors(kernel, n << k);
            const double x = std::log(1.0 / (n << k)), y = std::log(velocity ? e.second : e.first);
            sx += x, sy += y, sxx += x * x, sxy += x * y;
        }
        return (4 * sxy - sx * sy) / (4 * sxx - sx * sx);
    }

    void expectFreeFallExact(Kernel kernel) {
        const Vec3 x0(1.0, 20.0, -2.0), v0(3.0, 5.0, 1.0);
        const double h = 0.01;
        const int n = 500;
        ParticleState s = start(x0, v0, gravity);
        run(kernel, s, gravity, h, n);
        const double t = n * h;
        const Vec3 x = x0 + v0 * t + 0.5 * kGravity * t * t, v = v0 + kGravity * t;
        // 500 steps round at ~1e-16 each; a velocity from position differences divides that by h:
        // ~1e-12 relative. Any method error is a multiple of g h^2 ~ 1e-3.
        const double tol = 1e-9;
        EXPECT_LE((s.x[0] - x).norm(), tol * x.norm())
            << "position after 5 s is " << str(s.x[0]) << ", exactly " << str(x);
        EXPECT_LE((s.v[0] - v).norm(), tol * v.norm())
            << "velocity after 5 s is " << str(s.v[0]) << ", exactly " << str(v);
    }

    void expectEnergyBounded(Kernel kernel) {
        const double h = 0.5 / kOmega;  // h omega = 0.5, a quarter of the stability limit
        const int n = 100000;
        ParticleState s = start(Vec3(1.0, 0.0, 0.0), Vec3::Zero(), spring);
        const double e0 = oscillatorEnergy(s);
        double firstTenth = 0.0, lastTenth = 0.0;
        int crossings = 0;
        double before = s.x[0].x();
        grading::LinearForce oscillator;
        oscillator.k = kOmega * kOmega;  // spring()'s force, evaluated by the submission's engine
        grading::integratorSteps(kernel, s, oscillator, h, n, [&](int k) {
            const int i = k - 1;
            if ((before > 0.0) != (s.x[0].x() > 0.0)) ++crossings;
            before = s.x[0].x();
            const double deviation = std::abs(oscillatorEnergy(s) / e0 - 1.0);
            if (i < n / 10) firstTenth = std::max(firstTenth, deviation);
            if (i >= n - n / 10) lastTenth = std::max(lastTenth, deviation);
        });
        // Two zero crossings per period: n h omega / pi = 1.6e4 (Verlet runs 1 % fast at h omega = 0.5).
        const double expected = n * h * kOmega / M_PI;
        EXPECT_GT(crossings, 0.9 * expected) << "the oscillator crossed zero " << crossings << " times in " << n
                                             << " steps, about " << expected << " expected: it hardly moves";
        // A Verlet method's energy error oscillates with an amplitude set by h omega (0.06 for velocity
        // Verlet, 0.2 with position Verlet's one-sided velocity) and does not grow; 1 % growth from the
        // first to the last tenth is a drift.
        EXPECT_LE(lastTenth, 1.01 * firstTenth + 1e-12)
            << "the energy error grew from " << firstTenth << " (first 10^4 steps) to " << lastTenth
            << " (last 10^4 steps): the energy drifts";
        EXPECT_LT(firstTenth, 0.5) << "relative energy error " << firstTenth << " at h omega = 0.5";
    }
};

GRADED_TEST(Worksheet2, PositionVerletFirstStep, 2,
            "On the first step state.xPrev is empty: make up x_{-1} = x_0 - h v_0 + h^2/2 a_0 (a Taylor step back), "
            "so that x_1 = x_0 + h v_0 + h^2/2 a_0; then store x_0 in xPrev (worksheet 2, eq. 5). Start so "
            "whenever xPrev's size differs from x's (a body was added or removed), not only when it is empty.") {
    const Vec3 x0(0.5, -0.2, 0.1), v0(1.0, 2.0, -0.5);
    const double h = 0.01;
    ParticleState s = start(x0, v0, spring);
    const Vec3 a0 = s.a[0];
    positionVerlet(s, spring, h);
    ASSERT_EQ(s.xPrev.size(), 1u) << "xPrev must hold x_0 after the first step";
    const Vec3 x1 = x0 + h * v0 + 0.5 * h * h * a0;
    // A few roundings of numbers of size 1: 1e-13; the first-order start x_0 + h v_0 + h^2 a_0 is off by h^2 a/2 ~
    // 1e-5.
    EXPECT_LE((s.x[0] - x1).norm(), 1e-13) << "x_1 is " << str(s.x[0]) << ", expected " << str(x1);
    EXPECT_LE((s.xPrev[0] - x0).norm(), 1e-15)
        << "xPrev after the first step is " << str(s.xPrev[0]) << ", expected x_0";
    // v_1 agrees with the exact velocity to O(h^2) (4e-4 h^2 scale here); a first-order velocity is off by ~h a.
    const double t = h;
    const Vec3 vExact = -kOmega * std::sin(kOmega * t) * x0 + std::cos(kOmega * t) * v0;
    EXPECT_LE((s.v[0] - vExact).norm(), 1e-3 * v0.norm()) << "v_1 is " << str(s.v[0]) << ", exactly " << str(vExact);
    // Three particles whose xPrev still holds four from before a body was removed: a first step again.
    ParticleState three = startState({x0, Vec3(1.0, 0.0, 0.0), Vec3(0.0, 0.0, 2.0)}, {v0, Vec3::Zero(), -v0}, spring);
    three.xPrev.assign(4, Vec3(7.0, 7.0, 7.0));
    const ParticleState before = three;
    positionVerlet(three, spring, h);
    ASSERT_EQ(three.xPrev.size(), 3u) << "xPrev held 4 positions for 3 particles: it must be started afresh";
    for (std::size_t i = 0; i < 3; ++i) {
        const Vec3 expected = before.x[i] + h * before.v[i] + 0.5 * h * h * before.a[i];
        EXPECT_LE((three.x[i] - expected).norm(), 1e-13)
            << "particle " << i << " of 3, with an xPrev of 4 positions left from an earlier scene: x_1 is "
            << str(three.x[i]) << ", the first step's x_0 + h v_0 + h^2/2 a_0 is " << str(expected);
    }
}

GRADED_TEST(Worksheet2, PositionVerletExactForFreeFall, 3,
            "Under constant gravity position Verlet is exact: x_{n+1} = 2 x_n - x_{n-1} + h^2 a_n (h squared), and "
            "v_{n+1} = (3 x_{n+1} - 4 x_n + x_{n-1}) / (2 h) is the velocity at the NEW time.") {
    expectFreeFallExact(positionVerlet);
}

GRADED_TEST(Worksheet2, PositionVerletVelocityFromPositions, 2,
            "Derive the velocity from positions with a second-order difference: (x_{n+1} - x_n)/h is only first "
            "order (it is the velocity half a step earlier); use (3 x_{n+1} - 4 x_n + x_{n-1}) / (2 h).") {
    const double p = order(positionVerlet, 200, true);
    // Second order measured over h = T/200 .. T/1600: the slope is within 0.05 of 2; first order gives 1.
    EXPECT_NEAR(p, 2.0, 0.1) << "the velocity error converges with order " << p << ", expected 2";
}

GRADED_TEST(Worksheet2, PositionVerletSecondOrder, 3,
            "Halving h must divide the position error by 4 (second order): check the h^2 in front of a_n and the "
            "start-up step.") {
    const double p = order(positionVerlet, 100, false);
    // Over h = T/100 .. T/800 the O(h^3) terms shift the slope by < 0.02; first order gives 1.
    EXPECT_NEAR(p, 2.0, 0.1) << "the position error converges with order " << p << ", expected 2";
}

GRADED_TEST(Worksheet2, PositionVerletTimeReversible, 2,
            "Position Verlet is time reversible: swapping x and xPrev runs the motion backwards to the start. "
            "Keep the update symmetric: x_{n+1} = 2 x_n - x_{n-1} + h^2 a(x_n), then xPrev = x_n.") {
    const Vec3 x0(1.0, -0.5, 0.3), v0(0.2, 1.0, 0.0);
    const double h = 0.02;
    ParticleState s = start(x0, v0, nonlinear);
    run(positionVerlet, s, nonlinear, h, 1000);
    ASSERT_EQ(s.xPrev.size(), 1u) << "xPrev must hold the previous position";
    ASSERT_GT((s.x[0] - x0).norm(), 0.1) << "after 1000 steps the particle is still at the start";
    std::swap(s.x, s.xPrev);
    nonlinear(s.x, s.v, s.a);
    run(positionVerlet, s, nonlinear, h, 999);
    // 1000 steps there and back round ~1e-16 per step on a non-chaotic orbit: 1e-12; an asymmetric update misses
    // by O(h^2).
    EXPECT_LE((s.x[0] - x0).norm(), 1e-9)
        << "after 1000 steps forward and 1000 back the particle is at " << str(s.x[0]) << " instead of " << str(x0);
}

GRADED_TEST(Worksheet2, PositionVerletEnergyBounded, 3,
            "With h omega < 2 Verlet's energy error oscillates but never drifts, even over 10^5 steps: use "
            "x_{n-1} from the previous step (not x_0) and a_n at x_n.",
            grading::timeLimit(20)) {
    expectEnergyBounded(positionVerlet);
}

GRADED_TEST(Worksheet2, VelocityVerletOneStep, 2,
            "Velocity Verlet: x_{n+1} = x_n + h v_n + h^2/2 a_n; then a_{n+1} = a(x_{n+1}); then "
            "v_{n+1} = v_n + h/2 (a_n + a_{n+1}) (worksheet 2, eqs. 7-9).") {
    const Vec3 x0(0.5, -0.2, 0.1), v0(1.0, 2.0, -0.5);
    const double h = 0.01;
    ParticleState s = start(x0, v0, spring);
    const Vec3 a0 = s.a[0];
    velocityVerlet(s, spring, h);
    const Vec3 x1 = x0 + h * v0 + 0.5 * h * h * a0;
    const Vec3 a1 = -kOmega * kOmega * x1;
    const Vec3 v1 = v0 + 0.5 * h * (a0 + a1);
    // A few roundings of numbers of size 1: 1e-13; mistakes are O(h^2 a) ~ 1e-5 or larger.
    EXPECT_LE((s.x[0] - x1).norm(), 1e-13) << "x_1 is " << str(s.x[0]) << ", expected " << str(x1);
    EXPECT_LE((s.v[0] - v1).norm(), 1e-13) << "v_1 is " << str(s.v[0]) << ", expected " << str(v1);
    EXPECT_LE((s.a[0] - a1).norm(), 1e-13)
        << "state.a after the step is " << str(s.a[0]) << ", expected a(x_1) = " << str(a1);
}

GRADED_TEST(Worksheet2, VelocityVerletDampingSeesHalfStep, 2,
            "Velocity Verlet with a damped spring, a(x, v) = -k x - c v: the new accelerations are evaluated at the new "
            "positions and the half-step velocity v_n + h/2 a_n (the first half kick comes before the force "
            "evaluation), then v_{n+1} = v_{n+1/2} + h/2 a_{n+1} (worksheet 2, assignment 3).",
            grading::dependsOn("VelocityVerletOneStep")) {
    const double k = 4.0, c = 0.8;  // 1/s^2, 1/s
    const AccelerationFunction damped = [&](const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                                            std::vector<Vec3>& a) {
        a.resize(x.size());
        for (std::size_t i = 0; i < x.size(); ++i) a[i] = -k * x[i] - c * v[i];
    };
    const Vec3 x0(0.5, -0.2, 0.1), v0(1.0, 2.0, -0.5);
    const double h = 0.01;
    ParticleState s = start(x0, v0, damped);
    const Vec3 a0 = s.a[0];
    velocityVerlet(s, damped, h);
    const Vec3 x1 = x0 + h * v0 + 0.5 * h * h * a0;
    const Vec3 half = v0 + 0.5 * h * a0;
    const Vec3 a1 = -k * x1 - c * half;
    const Vec3 v1 = half + 0.5 * h * a1;
    // A few roundings of numbers of size 1: 1e-13; the old velocity in the force is off by c h/2 |a_n| h/2 ~ 1e-5.
    EXPECT_LE((s.a[0] - a1).norm(), 1e-13) << "state.a after the step is " << str(s.a[0]) << ", expected a(x_1, v_n + h/2 a_n) = "
                                          << str(a1);
    EXPECT_LE((s.v[0] - v1).norm(), 1e-13) << "v_1 is " << str(s.v[0]) << ", expected " << str(v1);
}

GRADED_TEST(Worksheet2, VelocityVerletExactForFreeFall, 2,
            "Under constant gravity velocity Verlet is exact: check the h^2/2 in the position update.") {
    expectFreeFallExact(velocityVerlet);
}

GRADED_TEST(Worksheet2, VelocityVerletSecondOrder, 3,
            "Halving h must divide the error by 4: the velocity needs the average of the old and the new "
            "acceleration, h/2 (a_n + a_{n+1}).") {
    const double p = order(velocityVerlet, 100, false);
    // As for position Verlet: within 0.1 of 2; a method that kicks with a_n alone is first order.
    EXPECT_NEAR(p, 2.0, 0.1) << "the position error converges with order " << p << ", expected 2";
}

GRADED_TEST(Worksheet2, VelocityVerletTimeReversible, 2,
            "Velocity Verlet is time reversible: run forward, flip the velocity, run the same number of steps and "
            "you are back at the start with the opposite velocity.") {
    const Vec3 x0(1.0, -0.5, 0.3), v0(0.2, 1.0, 0.0);
    const double h = 0.02;
    ParticleState s = start(x0, v0, nonlinear);
    run(velocityVerlet, s, nonlinear, h, 1000);
    ASSERT_GT((s.x[0] - x0).norm(), 0.1) << "after 1000 steps the particle is still at the start";
    for (Vec3& v : s.v) v = -v;
    run(velocityVerlet, s, nonlinear, h, 1000);
    // As for position Verlet: rounding only, ~1e-12.
    EXPECT_LE((s.x[0] - x0).norm(), 1e-9) << "back at " << str(s.x[0]) << " instead of " << str(x0);
    EXPECT_LE((s.v[0] + v0).norm(), 1e-9) << "velocity " << str(s.v[0]) << " instead of " << str(Vec3(-v0));
}

GRADED_TEST(Worksheet2, VelocityVerletEnergyBounded, 3,
            "With h omega < 2 velocity Verlet's energy error stays bounded over 10^5 steps: the position update "
            "needs the h^2/2 a_n term and the velocity the averaged acceleration.",
            grading::timeLimit(20)) {
    expectEnergyBounded(velocityVerlet);
}

GRADED_TEST(Worksheet2, OneForceEvaluationPerStep, 2,
            "Each step calls accel exactly once, for all particles at once at the new positions, and leaves "
            "state.a = a(x_{n+1}, v_{n+1}) for the next step; never recompute a_n at the start of a step (it is in "
            "state.a already). Move every particle with its own velocity: three particles of unequal masses joined "
            "by springs keep their total momentum, as their forces are equal and opposite.") {
    for (Kernel kernel : {positionVerlet, velocityVerlet}) {
        const char* name = kernelName(kernel);
        int calls = 0;
        const AccelerationFunction counted = counting(spring, calls);
        ParticleState s = start(Vec3(1.0, 0.0, 0.0), Vec3(0.0, 1.0, 0.0), spring);
        for (int i = 1; i <= 10; ++i) {
            kernel(s, counted, 0.05);
            std::vector<Vec3> a;
            spring(s.x, s.v, a);
            // The same function of the same positions: equal to rounding.
            ASSERT_LE((s.a[0] - a[0]).norm(), 1e-12)
                << name << ": after step " << i << " state.a is " << str(s.a[0]) << " but a(x) is " << str(a[0]);
        }
        EXPECT_EQ(calls, 10) << name << " evaluated the forces " << calls << " times in 10 steps";
    }
    // Masses 1, 3 and 2 kg in a row, joined by two springs of 40 N/m (rest length 0): the forces are
    // pairwise, so sum m_i a_i = 0 at every state and both methods keep sum m_i v_i.
    const std::vector<double> m{1.0, 3.0, 2.0};
    const AccelerationFunction chain = [&m](const std::vector<Vec3>& x, const std::vector<Vec3>&, std::vector<Vec3>& a) {
        const double k = 40.0;  // N/m
        a.assign(x.size(), Vec3::Zero());
        for (std::size_t i = 0; i + 1 < x.size(); ++i) {
            const Vec3 force = -k * (x[i] - x[i + 1]);  // N, on i; its opposite on i + 1
            a[i] += force / m[i];
            a[i + 1] -= force / m[i + 1];
        }
    };
    for (Kernel kernel : {positionVerlet, velocityVerlet}) {
        const char* name = kernelName(kernel);
        int calls = 0;
        const AccelerationFunction counted = counting(chain, calls);
        ParticleState s = startState({Vec3(0.0, 0.0, 0.0), Vec3(0.5, 0.2, 0.0), Vec3(1.0, -0.1, 0.3)},
                                     {Vec3(1.0, 0.0, 0.0), Vec3(0.0, -1.0, 0.5), Vec3(-0.5, 2.0, 0.0)}, chain);
        const auto momentum = [&m](const ParticleState& state) {
            Vec3 p = Vec3::Zero();
            for (std::size_t i = 0; i < m.size(); ++i) p += m[i] * state.v[i];
            return p;
        };
        const Vec3 p0 = momentum(s);  // kg m/s
        for (int i = 1; i <= 200; ++i) {
            kernel(s, counted, 0.01);
            // 200 steps of roundings on momenta of a few kg m/s (a velocity from position differences
            // divides them by h): 1e-10 kg m/s allows any order of operations; a step that mixes old and new
            // states for different particles is off by 1e-3 or more.
            ASSERT_LE((momentum(s) - p0).norm(), 1e-10)
                << name << ", three particles of 1, 3 and 2 kg joined by springs: after step " << i
                << " the total momentum is " << str(momentum(s)) << " kg m/s, at the start " << str(p0)
                << " (every particle moves with its own velocity, and all get the same step's accelerations)";
        }
        EXPECT_EQ(calls, 200) << name << " evaluated the forces of three particles " << calls
                              << " times in 200 steps: once per step, for all particles at once";
    }
}

}  // namespace
}  // namespace gpl
