#include "contacts.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>

#include "gpl/collision.h"
#include "gpl/hooks.h"
#include "gpl/response.h"
#include "gpl/scenes.h"

namespace gpl::study {
namespace {

const double kG = -standardGravity().y();  // m/s^2

// The stages of an experiment: worksheet 3's (positions) or worksheet 4's (impulses), with or
// without gravity.
StageSet contactStages(Response r, bool gravity) {
    StageSet s{Stage::Integration, Stage::CollisionDetection, Stage::Interpenetration};
    if (gravity) s.insert(Stage::ConstantAcceleration);
    if (r == Response::Impulses) s.insert(Stage::CollisionImpulses);
    return s;
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

}  // namespace

const char* responseName(Response r) { return r == Response::Positions ? "positions" : "impulses"; }

std::vector<std::string> hooksNeeded(Response r) {
    std::vector<std::string> hooks = {"integrator()", "resolveInterpenetration()", "simulationTimestep()",
                                      "spherePlane()", "sphereSphere()"};
    if (r == Response::Impulses) hooks.push_back("applyCollisionImpulse()");
    std::sort(hooks.begin(), hooks.end());
    return hooks;
}

std::vector<std::string> openContactHooks() {
    // The kernels, each called once on two spheres that overlap and approach, over a plane.
    Body a = sphere("a", 0.5, 1.0);
    Body b = sphere("b", 0.5, 1.0).at({0.0, 0.8, 0.0}).moving({0.0, -1.0, 0.0});
    const Body floor = plane("floor", {0.0, 1.0, 0.0});
    sphereSphere(a, b);
    spherePlane(a, floor);
    const Contact c = Contact::at({0.0, 0.4, 0.0}, Vec3::UnitY(), 0.2);
    applyCollisionImpulse(c, a, b);
    resolveInterpenetration(c, a, b);
    std::set<std::string> open;
    for (const std::string& h : kernelsNotImplemented()) open.insert(h);
    // The engine's hooks: one step of a ball resting on a plane, every contact stage on.
    PhysicsEngine e;
    e.setRequiredStages(contactStages(Response::Impulses, true));
    e.add(floor);
    e.add(sphere("ball", 0.5, 1.0).at({0.0, 0.5, 0.0}));
    try {
        e.step();
    } catch (const SimulationError&) {
        // Written but broken: the experiments will say so when they run.
    }
    open.insert(e.missingHooks().begin(), e.missingHooks().end());
    std::vector<std::string> needed = hooksNeeded(Response::Impulses);
    std::vector<std::string> result;
    for (const std::string& h : open) {
        if (std::find(needed.begin(), needed.end(), h) != needed.end()) result.push_back(h);
    }
    return result;
}

double overlap(const Body& a, const Body& b) {
    if (a.shape == Shape::Sphere && b.shape == Shape::Sphere) {
        return std::max(0.0, a.radius + b.radius - (b.position - a.position).norm());
    }
    if (a.shape == Shape::Plane && b.shape == Shape::Sphere) return overlap(b, a);
    if (a.shape == Shape::Sphere && b.shape == Shape::Plane) {
        const Vec3 n = b.orientation * b.normal;
        return std::max(0.0, a.radius - n.dot(a.position - b.position));
    }
    return 0.0;
}

double largestOverlap(const std::vector<Body>& bodies) {
    double largest = 0.0;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        for (std::size_t j = i + 1; j < bodies.size(); ++j) largest = std::max(largest, overlap(bodies[i], bodies[j]));
    }
    return largest;
}

// ---- 1. Resolution iterations on a pile --------------------------------------------------------

// What Gauss-Seidel sweeps buy on a pile: every sweep answers each contact once (interpenetration
// looks again among the near pairs, so overlaps its own moves create are answered too), so the
// overlap and the approach speed left after the stages fall with the sweeps, while the cost of a
// step grows with them (at most linearly: a sweep that finds nothing to do ends the stage).
PileRun pileWithIterations(Response r, int iterations) {
    PhysicsEngine e;
    load(e, scenes().find("balls-in-a-box"));
    e.setRequiredStages(contactStages(r, true));
    e.setContactIterations(iterations);
    const int settle = 300, measure = 100;  // steps of 0.01 s
    for (int i = 0; i < settle; ++i) e.step();

    PileRun run;
    run.iterations = iterations;
    const PhysicsEngine::State settled = e.state();
    double contacts = 0.0, found = 0.0, depthSum = 0.0, approachSum = 0.0;
    for (int i = 0; i < measure; ++i) {
        e.step();
        const std::vector<Body>& bodies = e.bodies();
        for (const Contact& c : e.contacts()) {
            found += c.depth;
            const double depth = overlap(bodies[c.a], bodies[c.b]);
            depthSum += depth;
            run.largestDepth = std::max(run.largestDepth, depth);
            const double approach = std::max(0.0, -normalVelocity(c, bodies[c.a], bodies[c.b]));
            approachSum += approach;
            run.largestApproach = std::max(run.largestApproach, approach);
        }
        contacts += static_cast<double>(e.contacts().size());
        run.largestAnyPair = std::max(run.largestAnyPair, largestOverlap(bodies));
    }
    run.contactsPerStep = contacts / measure;
    if (contacts > 0.0) {
        run.foundDepth = found / contacts;
        run.meanDepth = depthSum / contacts;
        run.meanApproach = approachSum / contacts;
    }
    // Wall time: the same steps again without the ruler, three times over; the median step of the
    // fastest round, so that other work on the machine counts as little as it can.
    run.nsPerStep = INFINITY;
    for (int round = 0; round < 3; ++round) {
        e.restore(settled);
        std::vector<double> ns;
        for (int i = 0; i < measure; ++i) {
            const auto begin = std::chrono::steady_clock::now();
            e.step();
            ns.push_back(std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - begin).count());
        }
        run.nsPerStep = std::min(run.nsPerStep, median(ns));
    }
    return run;
}

// ---- 2. Time step against the largest speed that does not tunnel -------------------------------

namespace {

enum class Target { Sphere, Plane };

struct Shot {
    bool through = false;      ///< the ball ended beyond the target's centre (or behind the plane)
    double energyRatio = 0.0;  ///< its kinetic energy at the end over the one it came with
};

// A ball of radius ra fired straight down at speed v onto a static target at the origin (a sphere
// of radius rb, or the plane y = 0), no gravity, restitution 1, contacts answered with response r.
// After its first step the ball is phase * v h short of touching; it runs until, undisturbed, it
// would be as far beyond the target as it started short of it.
Shot shoot(Response r, Target target, double ra, double rb, double v, double h, double phase) {
    PhysicsEngine e;
    e.setGravity(Vec3::Zero());  // no gravity stage, and no gravity in the energy either
    e.setRequiredStages(contactStages(r, false));
    e.setTimeStep(h);
    const double reach = target == Target::Sphere ? ra + rb : ra, stride = v * h;
    if (target == Target::Sphere) {
        e.add(sphere("target", rb, 1.0).bouncy(1.0).makeStatic());
    } else {
        e.add(plane("target", {0.0, 1.0, 0.0}));
    }
    const double start = reach + phase * stride + stride;
    const std::size_t ball = e.add(sphere("ball", ra, 1.0).bouncy(1.0).at({0.0, start, 0.0}).moving({0.0, -v, 0.0}));
    const auto steps = static_cast<int>(std::ceil((2.0 * reach + (1.0 + phase) * stride) / stride)) + 1;
    for (int i = 0; i < steps; ++i) e.step();
    const Body& b = e.bodies()[ball];
    return {b.position.y() < 0.0, b.velocity.squaredNorm() / (v * v)};
}

}  // namespace

// Detection sees only where a step ends. A ball is turned back only when a step ends with its
// centre within R = r_a + r_b of the target's and short of it; a step that ends past the target's
// centre makes the contact normal point forwards, and interpenetration pushes the ball out on the
// far side. So a step v h longer than R can jump over the interval that turns the ball back.
bool tunnels(Response r, double ra, double rb, double v, double h, double phase) {
    return shoot(r, Target::Sphere, ra, rb, v, h, phase).through;
}

double tunnelFraction(Response r, double ra, double rb, double v, double h, int phases) {
    int through = 0;
    for (int j = 0; j < phases; ++j) through += tunnels(r, ra, rb, v, h, (j + 0.5) / phases) ? 1 : 0;
    return static_cast<double>(through) / phases;
}

double theoreticalTunnelFraction(Response r, double ra, double rb, double v, double h, int phases) {
    const double stride = v * h, reach = ra + rb;
    int through = 0;
    for (int j = 0; j < phases; ++j) {
        const double phase = (j + 0.5) / phases;
        const bool first = (1.0 - phase) * stride > reach;                       // past the centre at once
        const bool second = r == Response::Positions && phase * stride > reach;  // the slower step after
        through += first || second ? 1 : 0;
    }
    return static_cast<double>(through) / phases;
}

double largestSafeSpeed(Response r, double ra, double rb, double h, int phases) {
    const double scale = (ra + rb) / h;
    double safe = 0.25 * scale, through = 4.0 * scale;
    if (tunnelFraction(r, ra, rb, safe, h, phases) > 0.0) return 0.0;
    if (tunnelFraction(r, ra, rb, through, h, phases) == 0.0) return through;
    while (through - safe > 1e-9 * through) {
        const double mid = 0.5 * (safe + through);
        (tunnelFraction(r, ra, rb, mid, h, phases) > 0.0 ? through : safe) = mid;
    }
    return safe;
}

double theoreticalSafeSpeed(double ra, double rb, double h, int phases) {
    return (ra + rb) / (h * (1.0 - 0.5 / phases));
}

// ---- 3. Resting contact: a column ---------------------------------------------------------------

// A column at rest should stay at rest. Gravity sinks every sphere by g h^2 in each step, and the
// stages must lift the column back by exactly that. One sweep passes the floor's push up the column
// one contact at a time and halves it at each equal-mass contact, so with few sweeps the column
// settles at a steady overlap at which the lift is g h^2: it sinks, by less the more sweeps there
// are. With impulses the velocity the sweeps leave moves the column down again in every step, and
// interpenetration has to undo that as well.
Column restingColumn(Response r, const std::vector<double>& masses, int iterations, double radius, double seconds) {
    PhysicsEngine e;
    e.setRequiredStages(contactStages(r, true));
    e.setContactIterations(iterations);
    e.add(plane("floor", {0.0, 1.0, 0.0}));
    for (std::size_t i = 0; i < masses.size(); ++i) {
        e.add(sphere("sphere" + std::to_string(i), radius, masses[i])
                  .at({0.0, (2.0 * static_cast<double>(i) + 1.0) * radius, 0.0})
                  .bouncy(0.0));
    }
    const double rest = (2.0 * static_cast<double>(masses.size()) - 1.0) * radius;
    const auto steps = static_cast<int>(std::lround(seconds / e.timeStep()));
    Column c;
    c.spheres = static_cast<int>(masses.size());
    c.iterations = iterations;
    double low = INFINITY, high = -INFINITY, sum = 0.0;
    int measured = 0;
    for (int i = 0; i < steps; ++i) {
        e.step();
        const std::vector<Body>& bodies = e.bodies();  // the plane, then the spheres bottom to top
        for (std::size_t j = 2; j < bodies.size(); ++j) {
            c.passedThrough |= bodies[j].position.y() < bodies[j - 1].position.y();
        }
        if (i < steps / 2) continue;
        const double y = bodies.back().position.y();
        low = std::min(low, y);
        high = std::max(high, y);
        sum += y;
        ++measured;
        c.largestOverlap = std::max(c.largestOverlap, largestOverlap(bodies));
        for (const Body& b : bodies) c.largestSpeed = std::max(c.largestSpeed, b.velocity.norm());
    }
    c.jitter = high - low;
    c.sink = rest - sum / measured;
    return c;
}

Column restingColumn(Response r, int spheres, int iterations) {
    return restingColumn(r, std::vector<double>(static_cast<std::size_t>(spheres), 1.0), iterations);
}

double theoreticalOneSweepSink(int spheres) {
    const double n = spheres;
    return kG * kDefaultTimeStep * kDefaultTimeStep * n * (n - 1.0) / 2.0;
}

// ---- 4. Mass ratios -----------------------------------------------------------------------------

// A light sphere between the plane and a heavy one is the classic hard case: the plane pushes it
// out, the heavy sphere pushes it almost all the way back (it takes the share m_top/(m_bottom+m_top)
// of the pair's correction), so each sweep removes only a small part of the overlap.
double twoSphereResidual(Response r, double bottom, double top, int iterations) {
    const double radius = 0.25, depth = 1e-3;  // m
    PhysicsEngine e;
    e.setGravity(Vec3::Zero());
    // The stage alone: detection, then interpenetration or impulses; nothing integrates.
    e.setRequiredStages(r == Response::Positions ? StageSet{Stage::CollisionDetection, Stage::Interpenetration}
                                                 : StageSet{Stage::CollisionDetection, Stage::CollisionImpulses});
    e.setContactIterations(iterations);
    e.add(plane("floor", {0.0, 1.0, 0.0}));
    const Vec3 fall(0.0, -1.0, 0.0);  // m/s, for impulses
    const std::size_t lower =
        e.add(sphere("bottom", radius, bottom).at({0.0, radius - depth, 0.0}).moving(fall).bouncy(0.0));
    e.add(sphere("top", radius, top).at({0.0, 3.0 * radius - 2.0 * depth, 0.0}).moving(fall).bouncy(0.0));
    e.step();
    const Body& b = e.bodies()[lower];
    return r == Response::Positions ? overlap(b, e.bodies()[0]) : std::max(0.0, -b.velocity.y());
}

double theoreticalTwoSphereResidual(Response r, double bottom, double top, int iterations) {
    const double rho = top / (bottom + top);
    // Positions: the plane's 1 mm and the pair's 1 mm both end up at the plane: 2 mm.
    return std::pow(rho, iterations) * (r == Response::Positions ? 2e-3 : 1.0);
}

// The steady state of a resting two-sphere stack. Positions: each step starts the sweeps from the
// floor overlap p plus g h^2 and they leave rho^k of it, so p = rho^k (p + g h^2). Impulses: the
// stack ends a step moving down at w; the next step adds g h, the sweeps leave rho^k of it, so
// w = rho^k (w + g h); and interpenetration starts from p + (w + g h) h and leaves rho^k of that.
double theoreticalStackSink(Response r, double bottom, double top, int iterations) {
    const double q = std::pow(top / (bottom + top), iterations);
    const double gh2 = kG * kDefaultTimeStep * kDefaultTimeStep;
    return r == Response::Positions ? q * gh2 / (1.0 - q) : q * gh2 / ((1.0 - q) * (1.0 - q));
}

double theoreticalStackSpeed(Response r, double bottom, double top, int iterations) {
    if (r == Response::Positions) return 0.0;
    const double q = std::pow(top / (bottom + top), iterations);
    return q * kG * kDefaultTimeStep / (1.0 - q);
}

// ---- 5. Very fast, very small -------------------------------------------------------------------

// Tunnelling depends on v h / (r_a + r_b) alone (the fraction 1 - R/(v h) of start phases tunnels),
// whatever the size: a 1 mm ball at 1 m/s is a 1 m ball at 1000 m/s. A plane is a half-space and
// cannot be tunnelled. Nothing may become NaN or gain energy, however deep the first overlap.
Extreme fastSmall(double radius, double speed, int phases) {
    const double h = 0.01;
    Extreme x;
    x.radius = radius;
    x.speed = speed;
    x.stepOverR = speed * h / (2.0 * radius);
    x.theoryFraction = theoreticalTunnelFraction(Response::Impulses, radius, radius, speed, h, phases);
    int sphereThrough = 0, planeThrough = 0;
    try {
        for (int j = 0; j < phases; ++j) {
            const double phase = (j + 0.5) / phases;
            for (Target t : {Target::Sphere, Target::Plane}) {
                const Shot s = shoot(Response::Impulses, t, radius, radius, speed, h, phase);
                (t == Target::Sphere ? sphereThrough : planeThrough) += s.through ? 1 : 0;
                x.largestEnergyRatio = std::max(x.largestEnergyRatio, s.energyRatio);
            }
        }
    } catch (const SimulationError&) {
        x.finite = false;
    }
    x.sphereFraction = static_cast<double>(sphereThrough) / phases;
    x.planeFraction = static_cast<double>(planeThrough) / phases;
    return x;
}

}  // namespace gpl::study
