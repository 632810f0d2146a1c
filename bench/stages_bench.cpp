// gpl-bench-stages: what each stage of the time step costs (./lab bench stages), with Google
// Benchmark (Debian libbenchmark-dev). N is the number of spheres: a heap packed so that
// neighbours overlap (every contact stage has work), or a free fall (no contact at all).
//
//   BM_BroadPhase/N            the broad phase's search over the heap (sort and sweep below 512
//                              bodies, the grid from there; on one thread)
//   BM_BroadPhaseKept/N        the same heap answered from the pairs kept by the last call
//   BM_SphereSphere, BM_SpherePlane, BM_ResolveInterpenetration, BM_ApplyCollisionImpulse
//                              one call of each contact kernel
//   BM_SphereBox, BM_BoxPlane, BM_BoxBoxFace, BM_BoxBoxEdge, BM_BoxBoxApart
//                              one call of each box kernel (worksheet 5): a sphere off a turned
//                              box's edge; a box resting on a plane (four corners behind it); a box
//                              on a box (a face contact, clipped), two crossing edges, and two
//                              boxes apart on an edge axis (all fifteen axes tested)
//   BM_DetectCollisions/N, BM_Interpenetration/N, BM_Impulses/N
//                              one stage on the heap (the state is put back, untimed, before each;
//                              detection's broad phase then answers from the pairs it kept)
//   BM_Integration/N           integrate() on the free fall
//   BM_IntegrateRotation, BM_ApplyContactImpulse
//                              one call of each rotation kernel (a tumbling box; a box on four points)
//   BM_Rotation/N              the rotation stage, rotate(), on N tumbling boxes
//   BM_PrepareContactPoint, BM_NormalImpulse, BM_FrictionImpulse, BM_SolveContacts/N
//                              worksheet 7: one point of a box sliding on a rough floor prepared,
//                              and one sweep's normal and friction impulse there; the friction stage on the heap
//                              (friction 0.5, no sums of a last step to start from)
//   BM_StepFreeFall/N, BM_StepFreeFallIdleStages/N and BM_GravityAndIntegrationOnly/N
//                              a whole step of a scene that requires gravity and integration; the
//                              same scene holding springs, distance constraints, ropes, a container
//                              and a torque on every body, whose stages (rotation among them) it does
//                              not require (equal times: the stages a scene does not require cost
//                              nothing, their data included); and the two stages called directly
//                              (the rest of the first is the step's own check that every body is
//                              still finite)
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>
#include <utility>

#include "gpl/body.h"
#include "gpl/broadphase.h"
#include "gpl/collision.h"
#include "gpl/engine.h"
#include "gpl/friction.h"
#include "gpl/response.h"
#include "gpl/rotation.h"
#include "heap.h"

namespace {

using gpl::PhysicsEngine;
using gpl::Stage;
using gpl::Vec3;

// The heap's lattice squeezed to 0.95 m spacing: every neighbour overlaps a sphere of radius 0.5 m.
void packedHeap(PhysicsEngine& e, std::size_t n, bool rough = false) {
    gpl::StageSet stages{Stage::ConstantAcceleration, Stage::Integration, Stage::CollisionDetection,
                         Stage::Interpenetration, Stage::CollisionImpulses};
    if (rough) stages.insert(Stage::Friction);
    e.setRequiredStages(stages);
    e.setTimeStep(gpl::bench::kTimeStep);
    e.add(gpl::plane("ground", Vec3::UnitY()));
    std::size_t i = 0;
    for (const Vec3& p : gpl::bench::heapPositions(n)) {
        const Vec3 packed(0.95 / gpl::bench::kSpacing * p.x(), 0.5 + 0.95 / gpl::bench::kSpacing * (p.y() - 1.0),
                          0.95 / gpl::bench::kSpacing * p.z());
        e.add(gpl::sphere("s" + std::to_string(i++), gpl::bench::kRadius, gpl::bench::kMass)
                  .at(packed)
                  .moving(Vec3(0.0, -1.0, 0.0))
                  .bouncy(0.0)
                  .rough(rough ? gpl::bench::kFriction : 0.0, rough ? gpl::bench::kFriction : 0.0));
    }
}

void freeFall(PhysicsEngine& e, std::size_t n) {
    e.setTimeStep(gpl::bench::kTimeStep);
    for (std::size_t i = 0; i < n; ++i) {
        e.add(gpl::sphere("s" + std::to_string(i), 0.5, 1.0).at(Vec3(1.2 * static_cast<double>(i), 1e6, 0.0)));
    }
}

// A search anew at every call: the heap alternates with a copy of itself 100 m away, where no body's
// box is inside the one its pairs were kept for.
void BM_BroadPhase(benchmark::State& state) {
    PhysicsEngine e;
    packedHeap(e, static_cast<std::size_t>(state.range(0)));
    const std::vector<gpl::Body> here = e.bodies();
    std::vector<gpl::Body> away = here;
    for (gpl::Body& b : away) b.position.x() += 100.0;  // m
    gpl::BroadPhase broadPhase;
    bool flip = false;
    for (auto _ : state) {
        flip = !flip;
        benchmark::DoNotOptimize(broadPhase.findPairs(flip ? away : here, gpl::kContactMargin).size());
    }
    state.SetComplexityN(state.range(0));
}
BENCHMARK(BM_BroadPhase)->RangeMultiplier(4)->Range(64, 16384)->Complexity();

// The kept pairs answering: the same heap at every call.
void BM_BroadPhaseKept(benchmark::State& state) {
    PhysicsEngine e;
    packedHeap(e, static_cast<std::size_t>(state.range(0)));
    gpl::BroadPhase broadPhase;
    for (auto _ : state) benchmark::DoNotOptimize(broadPhase.findPairs(e.bodies(), gpl::kContactMargin).size());
    state.SetComplexityN(state.range(0));
}
BENCHMARK(BM_BroadPhaseKept)->RangeMultiplier(4)->Range(64, 16384)->Complexity();

void BM_SphereSphere(benchmark::State& state) {
    const gpl::Body a = gpl::sphere("a", 0.5, 1.0);
    const gpl::Body b = gpl::sphere("b", 0.5, 1.0).at(Vec3(0.3, 0.8, 0.1));
    for (auto _ : state) benchmark::DoNotOptimize(gpl::sphereSphere(a, b));
}
BENCHMARK(BM_SphereSphere);

void BM_SpherePlane(benchmark::State& state) {
    const gpl::Body s = gpl::sphere("s", 0.5, 1.0).at(Vec3(0.3, 0.4, 0.1));
    const gpl::Body p = gpl::plane("p", Vec3::UnitY());
    for (auto _ : state) benchmark::DoNotOptimize(gpl::spherePlane(s, p));
}
BENCHMARK(BM_SpherePlane);

gpl::Quat turn(double radians, const Vec3& axis) { return gpl::Quat(Eigen::AngleAxisd(radians, axis.normalized())); }

void BM_SphereBox(benchmark::State& state) {
    const gpl::Body s = gpl::sphere("s", 0.5, 1.0).at(Vec3(0.9, 0.9, 0.1));
    const gpl::Body b = gpl::box("b", Vec3(0.5, 0.5, 0.5), 1.0).rotated(turn(0.3, Vec3(0.0, 0.0, 1.0)));
    for (auto _ : state) benchmark::DoNotOptimize(gpl::sphereBox(s, b));
}
BENCHMARK(BM_SphereBox);

void BM_BoxPlane(benchmark::State& state) {
    const gpl::Body b = gpl::box("b", Vec3(0.5, 0.25, 0.4), 1.0).at(Vec3(0.3, 0.24, 0.1));
    const gpl::Body p = gpl::plane("p", Vec3::UnitY());
    for (auto _ : state) benchmark::DoNotOptimize(gpl::boxPlane(b, p));
}
BENCHMARK(BM_BoxPlane);

// Two boxes: b on a's top face turned by 0.3 rad (a clipped face contact); or each turned by 45
// degrees about another axis, their edges crossing `gap` apart (< 0: overlapping).
std::pair<gpl::Body, gpl::Body> boxPair(bool crossing, double gap) {
    if (!crossing) {
        return {gpl::box("a", Vec3(1.0, 0.25, 1.0), 1.0),
                gpl::box("b", Vec3(0.5, 0.25, 0.4), 1.0).at(Vec3(0.6, 0.49, 0.1)).rotated(turn(0.3, Vec3::UnitY()))};
    }
    return {gpl::box("a", Vec3(1.0, 0.5, 0.5), 1.0).rotated(turn(M_PI / 4, Vec3::UnitX())),
            gpl::box("b", Vec3(0.5, 0.5, 1.0), 1.0).at(Vec3(0.0, std::sqrt(2.0) + gap, 0.0)).rotated(turn(M_PI / 4, Vec3::UnitZ()))};
}

void BM_BoxBoxFace(benchmark::State& state) {
    const auto [a, b] = boxPair(false, 0.0);
    for (auto _ : state) benchmark::DoNotOptimize(gpl::boxBox(a, b));
}
BENCHMARK(BM_BoxBoxFace);

void BM_BoxBoxEdge(benchmark::State& state) {
    const auto [a, b] = boxPair(true, -0.01);
    for (auto _ : state) benchmark::DoNotOptimize(gpl::boxBox(a, b));
}
BENCHMARK(BM_BoxBoxEdge);

void BM_BoxBoxApart(benchmark::State& state) {
    const auto [a, b] = boxPair(true, 0.01);
    for (auto _ : state) benchmark::DoNotOptimize(gpl::boxBox(a, b));
}
BENCHMARK(BM_BoxBoxApart);

void BM_ResolveInterpenetration(benchmark::State& state) {
    gpl::Body a = gpl::sphere("a", 0.5, 1.0);
    gpl::Body b = gpl::sphere("b", 0.5, 2.0).at(Vec3(0.0, 0.9, 0.0));
    const gpl::Contact c = gpl::Contact::at(Vec3(0.0, 0.45, 0.0), Vec3::UnitY(), 0.1);
    for (auto _ : state) {
        gpl::resolveInterpenetration(c, a, b);  // the same contact again: the same work every time
        benchmark::DoNotOptimize(a.position);
        benchmark::DoNotOptimize(b.position);
    }
}
BENCHMARK(BM_ResolveInterpenetration);

void BM_ApplyCollisionImpulse(benchmark::State& state) {
    gpl::Body a = gpl::sphere("a", 0.5, 1.0);
    gpl::Body b = gpl::sphere("b", 0.5, 2.0).at(Vec3(0.0, 0.9, 0.0));
    const gpl::Contact c = gpl::Contact::at(Vec3(0.0, 0.45, 0.0), Vec3::UnitY(), 0.1);
    for (auto _ : state) {
        a.velocity = Vec3(0.0, 1.0, 0.0);  // approaching every time
        b.velocity = Vec3(0.0, -1.0, 0.0);
        gpl::applyCollisionImpulse(c, a, b);
        benchmark::DoNotOptimize(a.velocity);
        benchmark::DoNotOptimize(b.velocity);
    }
}
BENCHMARK(BM_ApplyCollisionImpulse);

// One contact stage on the packed heap, from the same state every time.
template <class Stages>
void heapStage(benchmark::State& state, Stages stages, bool rough = false) {
    PhysicsEngine e;
    packedHeap(e, static_cast<std::size_t>(state.range(0)), rough);
    const PhysicsEngine::State start = e.state();
    for (auto _ : state) {
        state.PauseTiming();
        e.restore(start);
        stages(e, false);  // what the stage needs first (the contacts), untimed
        state.ResumeTiming();
        stages(e, true);
    }
    state.SetComplexityN(state.range(0));
}

void BM_DetectCollisions(benchmark::State& state) {
    heapStage(state, [](PhysicsEngine& e, bool timed) {
        if (timed) e.detectCollisions();
    });
}
BENCHMARK(BM_DetectCollisions)->RangeMultiplier(4)->Range(64, 16384)->Complexity();

void BM_Interpenetration(benchmark::State& state) {
    heapStage(state, [](PhysicsEngine& e, bool timed) {
        if (timed)
            e.resolveInterpenetrations();
        else
            e.detectCollisions();
    });
}
BENCHMARK(BM_Interpenetration)->RangeMultiplier(4)->Range(64, 16384)->Complexity();

void BM_Impulses(benchmark::State& state) {
    heapStage(state, [](PhysicsEngine& e, bool timed) {
        if (timed)
            e.applyCollisionImpulses();
        else
            e.detectCollisions();
    });
}
BENCHMARK(BM_Impulses)->RangeMultiplier(4)->Range(64, 16384)->Complexity();

// The friction stage (worksheet 7) on the same heap, friction 0.5, from no sums of a last step.
void BM_SolveContacts(benchmark::State& state) {
    heapStage(
        state,
        [](PhysicsEngine& e, bool timed) {
            if (timed)
                e.solveContacts();
            else
                e.detectCollisions();
        },
        true);
}
BENCHMARK(BM_SolveContacts)->RangeMultiplier(4)->Range(64, 16384)->Complexity();

void BM_Integration(benchmark::State& state) {
    PhysicsEngine e;
    freeFall(e, static_cast<std::size_t>(state.range(0)));
    e.updateConstantAcceleration();
    for (auto _ : state) e.integrate();
    state.SetComplexityN(state.range(0));
}
BENCHMARK(BM_Integration)->RangeMultiplier(4)->Range(64, 16384)->Complexity();

// A box turning about no axis of its own (its angular velocity changes every step).
gpl::Body tumblingBox(const std::string& name) {
    return gpl::box(name, Vec3(0.15, 0.4, 0.8), 2.0)
        .rotated(gpl::Quat(Eigen::AngleAxisd(0.7, Vec3(1.0, 2.0, 3.0).normalized())))
        .spinning(Vec3(0.5, 3.0, 0.5));
}

void BM_IntegrateRotation(benchmark::State& state) {
    gpl::Body b = tumblingBox("box");
    for (auto _ : state) {
        gpl::integrateRotation(b, gpl::bench::kTimeStep);
        benchmark::DoNotOptimize(b.orientation);
        benchmark::DoNotOptimize(b.angularVelocity);
    }
}
BENCHMARK(BM_IntegrateRotation);

void BM_ApplyContactImpulse(benchmark::State& state) {
    const gpl::Body start = tumblingBox("box").at(Vec3(0.0, 0.3, 0.0)).moving(Vec3(0.0, -1.0, 0.0));
    gpl::Body floor = gpl::plane("floor", Vec3::UnitY());
    gpl::Contact c;
    c.normal = -Vec3::UnitY();  // from the box into the floor
    c.pointCount = 4;
    c.points = {Vec3(-0.15, 0.0, -0.4), Vec3(0.15, 0.0, -0.4), Vec3(0.15, 0.0, 0.4), Vec3(-0.15, 0.0, 0.4)};
    gpl::Body b = start;
    for (auto _ : state) {
        b.velocity = start.velocity;  // approaching every time
        b.angularVelocity = start.angularVelocity;
        gpl::applyContactImpulse(c, b, floor);
        benchmark::DoNotOptimize(b.velocity);
        benchmark::DoNotOptimize(b.angularVelocity);
    }
}
BENCHMARK(BM_ApplyContactImpulse);

// One point of a box sliding onto a rough floor (worksheet 7): the point prepared once per step,
// and one sweep's normal and friction impulse there, with the sums of earlier sweeps at zero each time.
struct SlidingPoint {
    gpl::Body box = tumblingBox("box").at(Vec3(0.0, 0.3, 0.0)).moving(Vec3(1.0, -1.0, 0.0)).rough(0.6, 0.5);
    gpl::Body floor = gpl::plane("floor", Vec3::UnitY()).rough(0.6, 0.5);
    gpl::Contact contact;
    gpl::Mat3 invIa, invIb;
    SlidingPoint() {
        contact.normal = -Vec3::UnitY();  // from the box into the floor
        contact.pointCount = 1;
        contact.points[0] = Vec3(0.15, 0.0, -0.4);
        contact.staticFriction = 0.6;
        contact.friction = 0.5;
        invIa = gpl::worldInverseInertia(box);
        invIb = gpl::worldInverseInertia(floor);
    }
    double approach() const { return gpl::normalVelocityAt(contact, box, floor, contact.points[0]); }
};

void BM_PrepareContactPoint(benchmark::State& state) {
    const SlidingPoint s;
    const double approach = s.approach();
    for (auto _ : state) {
        gpl::ContactPoint point = gpl::prepareContactPoint(s.contact, 0, s.box, s.floor, s.invIa, s.invIb, approach);
        benchmark::DoNotOptimize(point);
    }
}
BENCHMARK(BM_PrepareContactPoint);

template <class Kernel>
void pointImpulse(benchmark::State& state, Kernel kernel) {
    SlidingPoint s;
    const gpl::ContactPoint point =
        gpl::prepareContactPoint(s.contact, 0, s.box, s.floor, s.invIa, s.invIb, s.approach());
    gpl::Body b = s.box;
    for (auto _ : state) {
        b.velocity = s.box.velocity;
        b.angularVelocity = s.box.angularVelocity;
        gpl::PointImpulse sum;
        sum.normal = 1.0;  // N s: what the friction kernel's cone is measured against
        kernel(point, b, s.floor, sum);
        benchmark::DoNotOptimize(b.velocity);
        benchmark::DoNotOptimize(sum);
    }
}

void BM_NormalImpulse(benchmark::State& state) {
    pointImpulse(state, [](const gpl::ContactPoint& point, gpl::Body& a, gpl::Body& b, gpl::PointImpulse& sum) {
        gpl::applyNormalImpulse(point, a, b, sum);
    });
}
BENCHMARK(BM_NormalImpulse);

void BM_FrictionImpulse(benchmark::State& state) {
    pointImpulse(state, [](const gpl::ContactPoint& point, gpl::Body& a, gpl::Body& b, gpl::PointImpulse& sum) {
        gpl::applyFrictionImpulse(point, a, b, sum);
    });
}
BENCHMARK(BM_FrictionImpulse);

void BM_Rotation(benchmark::State& state) {
    PhysicsEngine e;
    e.setRequiredStages({Stage::Integration, Stage::Rotation});
    e.setTimeStep(gpl::bench::kTimeStep);
    for (int64_t i = 0; i < state.range(0); ++i) e.add(tumblingBox("b" + std::to_string(i)));
    for (auto _ : state) e.rotate();
    state.SetComplexityN(state.range(0));
}
BENCHMARK(BM_Rotation)->RangeMultiplier(4)->Range(64, 16384)->Complexity();

void BM_StepFreeFall(benchmark::State& state) {
    PhysicsEngine e;
    freeFall(e, static_cast<std::size_t>(state.range(0)));
    for (auto _ : state) e.step();
    state.SetComplexityN(state.range(0));
}
BENCHMARK(BM_StepFreeFall)->RangeMultiplier(4)->Range(64, 16384)->Complexity();

void BM_StepFreeFallIdleStages(benchmark::State& state) {
    PhysicsEngine e;
    const auto n = static_cast<std::size_t>(state.range(0));
    freeFall(e, n);
    // Data for the engine's other stages, none of which the scene requires.
    for (std::size_t i = 0; i + 1 < n; i += 2) {
        const std::string a = "s" + std::to_string(i), b = "s" + std::to_string(i + 1);
        e.addSpring(a, b, 100.0, 1.0);
        e.addDistanceConstraint(a, b);
        e.addRope(a, b, 2.0);
    }
    e.setContainer(Vec3(0.0, 1e6, 0.0), 1e9);
    // A torque on every body, for the rotation stage (worksheet 6); the particles do not turn, as
    // in any scene of particles or spheres.
    for (gpl::Body& b : e.bodies()) b.torque = Vec3(0.0, 0.0, 1.0);
    for (auto _ : state) e.step();
    state.SetComplexityN(state.range(0));
}
BENCHMARK(BM_StepFreeFallIdleStages)->RangeMultiplier(4)->Range(64, 16384)->Complexity();

void BM_GravityAndIntegrationOnly(benchmark::State& state) {
    PhysicsEngine e;
    freeFall(e, static_cast<std::size_t>(state.range(0)));
    for (auto _ : state) {
        e.updateConstantAcceleration();
        e.integrate();
    }
    state.SetComplexityN(state.range(0));
}
BENCHMARK(BM_GravityAndIntegrationOnly)->RangeMultiplier(4)->Range(64, 16384)->Complexity();

}  // namespace

BENCHMARK_MAIN();
