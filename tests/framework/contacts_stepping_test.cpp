// The contact stages stepped with the reference hooks (solutions/): an instructor's tree only.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "gpl/broadphase.h"
#include "gpl/collision.h"
#include "gpl/engine.h"
#include "gpl/friction.h"
#include "gpl/friction_stage.h"
#include "gpl/rotation.h"
#include "gpl/scenes.h"

namespace gpl {
namespace {

const StageSet kPositional{Stage::ConstantAcceleration, Stage::Integration, Stage::CollisionDetection,
                           Stage::Interpenetration};
const StageSet kImpulses{Stage::ConstantAcceleration, Stage::Integration, Stage::CollisionDetection,
                         Stage::CollisionImpulses, Stage::Interpenetration};

// Largest overlap of any pair of bodies in the engine's current state (m), as the reference
// kernels measure it: spheres, boxes and planes.
double largestOverlap(const PhysicsEngine& e) {
    double worst = 0.0;
    const auto& bodies = e.bodies();
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        for (std::size_t j = i + 1; j < bodies.size(); ++j) {
            if (const std::optional<Contact> c = collide(bodies, i, j)) worst = std::max(worst, c->depth);
        }
    }
    return worst;
}

// A rough floor and `count` bodies over it on a lattice of spacing 1.2 m, `side` by `side` a layer
// (jittered a little), every third a cube turned its own way, the others spheres of radius 0.5 m.
void addRoughHeap(PhysicsEngine& e, int count, int side) {
    e.add(plane("floor", Vec3::UnitY()).rough(0.5, 0.5));
    for (int n = 0; n < count; ++n) {
        const Vec3 at(1.2 * (n % side), 1.0 + 1.2 * (n / (side * side)), 1.2 * ((n / side) % side) + 0.01 * (n % 7));
        const std::string name = "b" + std::to_string(n);
        const Quat turn(Eigen::AngleAxisd(0.1 * n, Vec3(1, 2, 3).normalized()));
        Body b = n % 3 == 0 ? box(name, Vec3::Constant(0.3), 1.0).rotated(turn) : sphere(name, 0.5, 1.0);
        e.add(b.at(at).bouncy(0.0).rough(0.6, 0.5));
    }
}

TEST(Contacts, DetectionFillsTheFrameworkFields) {
    PhysicsEngine e;
    e.setRequiredStages({Stage::CollisionDetection});
    e.add(sphere("ball", 0.5, 1.0).at({0, 0.4, 0}).bouncy(0.6));
    e.add(plane("floor", Vec3::UnitY()));  // listed after the ball: the sphere still comes first
    e.add(sphere("other", 0.5, 1.0).at({0.9, 0.45, 0}).bouncy(0.5));
    e.step();
    ASSERT_EQ(e.contacts().size(), 3u);
    for (const Contact& c : e.contacts()) {
        EXPECT_NEAR(c.normal.norm(), 1.0, 1e-15);
        EXPECT_GT(c.depth, 0.0);
        EXPECT_EQ(c.pointCount, 1);
        EXPECT_NE(e.bodies()[c.a].shape, Shape::Plane) << "a sphere comes first against a plane";
        EXPECT_DOUBLE_EQ(c.restitution,
                         combineRestitution(e.bodies()[c.a].restitution, e.bodies()[c.b].restitution));
    }
    // Pairs in body order: ball-floor, ball-other, floor-other (as other-floor).
    EXPECT_EQ(e.contacts()[0].b, 1u);
    EXPECT_EQ(e.contacts()[1].b, 2u);
    EXPECT_EQ(e.contacts()[2].a, 2u);
    EXPECT_TRUE(e.contacts()[2].normal.isApprox(-Vec3::UnitY()));
}

TEST(Contacts, PositionalLandingComesToRestOnTheFloor) {
    // Without impulses the velocity follows the correction: the ball lands plastically and then
    // rests exactly on the floor (each step it sinks by g h^2 and is put back with its velocity).
    PhysicsEngine e;
    e.setRequiredStages(kPositional);
    e.add(plane("floor", Vec3::UnitY()));
    e.add(sphere("ball", 0.5, 1.0).at({0, 3, 0}).bouncy(1.0));
    for (int i = 0; i < 300; ++i) e.step();
    const Body& ball = e.body("ball");
    EXPECT_NEAR(ball.position.y(), 0.5, 1e-12);  // rounding of positions of order 1 m
    EXPECT_LT(ball.velocity.norm(), 1e-9);        // g h = 0.1 m/s cancelled to rounding
}

TEST(Contacts, ImpulsesBounceWithTheCombinedRestitution) {
    // Dropped from 2 m onto a floor (restitution 1): the first rebound reaches e^2 of the drop
    // height. The discrete step blurs the moment of impact by up to one step: h v / H ~ 3 %.
    PhysicsEngine e;
    e.setRequiredStages(kImpulses);
    e.setTimeStep(0.001);
    e.add(plane("floor", Vec3::UnitY()));
    e.add(sphere("ball", 0.5, 1.0).at({0, 2.5, 0}).bouncy(0.7));
    double apex = 0.0;
    bool bounced = false;
    for (int i = 0; i < 2000; ++i) {
        e.step();
        const Body& ball = e.body("ball");
        bounced = bounced || ball.velocity.y() > 0.0;
        if (bounced) apex = std::max(apex, ball.position.y() - 0.5);
        if (bounced && ball.velocity.y() < 0.0) break;
    }
    EXPECT_NEAR(apex / 2.0, 0.49, 0.49 * 0.03);
}

TEST(Contacts, MoreIterationsLeaveLessOverlapInAStack) {
    // A column of eight spheres resting on a floor, solved by positions: every step each sphere
    // sinks by g h^2 = 1 mm and the sweeps lift the column back; more sweeps leave less overlap.
    double previous = 1e300;
    for (int iterations : {1, 4, 32}) {
        PhysicsEngine e;
        e.setRequiredStages(kPositional);
        e.setContactIterations(iterations);
        e.add(plane("floor", Vec3::UnitY()));
        for (int i = 0; i < 8; ++i) e.add(sphere("s" + std::to_string(i), 0.5, 1.0).at({0, 0.5 + 1.0 * i, 0}));
        for (int i = 0; i < 200; ++i) e.step();
        const double overlap = largestOverlap(e);
        EXPECT_LT(overlap, previous) << iterations << " iterations";
        previous = overlap;
    }
    EXPECT_LT(previous, 1e-3 * 0.5);  // 32 sweeps for 8 spheres: a thousandth of the radius at most
}

TEST(Contacts, InterpenetrationSweepsAreTheirOwnSetting) {
    // The column above with 32 impulse sweeps: fewer sweeps of interpenetration alone leave more
    // overlap, and interpenetration set to 32 is the same to the bit as not set.
    const auto column = [](int interpenetration) {
        PhysicsEngine e;
        e.setRequiredStages(kPositional);
        e.setContactIterations(32);
        e.setInterpenetrationIterations(interpenetration);
        e.add(plane("floor", Vec3::UnitY()));
        for (int i = 0; i < 8; ++i) e.add(sphere("s" + std::to_string(i), 0.5, 1.0).at({0, 0.5 + 1.0 * i, 0}));
        for (int i = 0; i < 200; ++i) e.step();
        return e;
    };
    const double one = largestOverlap(column(1)), all = largestOverlap(column(32));
    EXPECT_GT(one, 2.0 * all) << "1 sweep against 32";
    const PhysicsEngine notSet = column(0), set = column(32);
    for (std::size_t i = 0; i < set.bodies().size(); ++i) {
        EXPECT_EQ(set.bodies()[i].position, notSet.bodies()[i].position) << set.bodies()[i].name;
    }
}

TEST(Contacts, RopeHoldsAPendulumAtItsLength) {
    // A ball on a 2 m rope released sideways: the rope never stretches beyond its length by more
    // than one step's outward drift (v h)^2 / (2 L) once resolved, and the ball swings below the anchor.
    PhysicsEngine e;
    e.setRequiredStages({Stage::ConstantAcceleration, Stage::Integration, Stage::Ropes, Stage::CollisionImpulses,
                         Stage::Interpenetration});
    e.add(sphere("anchor", 0.05, 1.0).at({0, 5, 0}).makeStatic());
    e.add(sphere("bob", 0.2, 1.0).at({2, 5, 0}));
    e.addRope("anchor", "bob", 2.0);
    double lowest = 5.0;
    for (int i = 0; i < 300; ++i) {
        e.step();
        EXPECT_LE((e.body("bob").position - e.body("anchor").position).norm(), 2.0 + 1e-12);
        lowest = std::min(lowest, e.body("bob").position.y());
    }
    EXPECT_NEAR(lowest, 3.0, 0.01);  // the bottom of the swing, 2 m below the anchor (to 0.5 %)
}

TEST(Contacts, NewtonsCradlePassesTheImpulseAlong) {
    // The first ball hits the row; the last one swings out with (nearly) all of its speed while the
    // first stops: momentum and energy go through the three in the middle.
    PhysicsEngine e;
    load(e, scenes().find("newtons-cradle"));
    double fastestLast = 0.0, firstThen = 0.0;
    for (int i = 0; i < 600; ++i) {
        e.step();
        const double last = e.body("ball5").velocity.norm();
        if (last > fastestLast) {
            fastestLast = last;
            firstThen = e.body("ball1").velocity.norm();
        }
    }
    // Released from 40 degrees on 2 m: v = sqrt(2 g L (1 - cos 40 deg)) = 3.03 m/s at the bottom.
    const double v = std::sqrt(2.0 * 9.81 * 2.0 * (1.0 - std::cos(40.0 * M_PI / 180.0)));
    EXPECT_GT(fastestLast, 0.9 * v);
    EXPECT_LT(firstThen, 0.1 * v);
}

TEST(Contacts, EveryContactSceneStaysFiniteAndSeparated) {
    // The contact solvers' test scenes (stacks, mass ratios, dominoes) are measured by ./lab bench
    // solvers and tested where they stand (resting_contact_test.cpp); here, the worksheets' own.
    SceneRegistry solverScenes;
    addStackingScenes(solverScenes);
    for (const Scene& s : scenes().all()) {
        // From worksheet 3 on; worksheets 8 and 9 move particles, which their own tests step.
        if (s.worksheet < 3 || s.worksheet >= 8) continue;
        const auto& others = solverScenes.all();
        if (std::any_of(others.begin(), others.end(), [&s](const Scene& o) { return o.name == s.name; })) continue;
        PhysicsEngine e;
        load(e, s);
        const int steps = s.name == "heap" ? 300 : static_cast<int>(2.0 / s.timeStep);
        for (int i = 0; i < steps; ++i) ASSERT_NO_THROW(e.step()) << s.name;
        // After resolution nothing overlaps by more than a hundredth of the smallest size (a radius or
        // a half extent).
        double smallest = 1e300;
        for (const Body& b : e.bodies()) {
            if (b.isStatic()) continue;
            smallest = std::min(smallest, b.shape == Shape::Box ? b.halfExtents.minCoeff() : b.radius);
        }
        EXPECT_LT(largestOverlap(e), 0.01 * smallest) << s.name;
    }
}

TEST(Contacts, OneThreadAndTwoGiveTheSameStateBitForBit) {
    // 3000 spheres (above the size where the broad phase splits its sweep) dropped on a floor: the
    // heap with one thread and with two, every position and velocity exactly equal.
    const auto drop = [](int threads) {
        PhysicsEngine e;
        e.setRequiredStages(kImpulses);
        e.setThreads(threads);
        e.setTimeStep(1.0 / 60.0);
        e.add(plane("floor", Vec3::UnitY()));
        for (int i = 0; i < 3000; ++i) {
            const Vec3 at(1.2 * (i % 15), 1.0 + 1.2 * (i / 225), 1.2 * ((i / 15) % 15) + 0.01 * (i % 7));
            e.add(sphere("s" + std::to_string(i), 0.5, 1.0).at(at).bouncy(0.0));
        }
        for (int s = 0; s < 120; ++s) e.step();  // 2 s: the lower layers have landed
        return e.state();
    };
    const PhysicsEngine::State one = drop(1), two = drop(2);
    ASSERT_EQ(one.bodies.size(), two.bodies.size());
    for (std::size_t i = 0; i < one.bodies.size(); ++i) {
        ASSERT_EQ(one.bodies[i].position, two.bodies[i].position) << "body " << i;
        ASSERT_EQ(one.bodies[i].velocity, two.bodies[i].velocity) << "body " << i;
    }
}

TEST(Contacts, FrictionStageOnOneThreadAndTwoGivesTheSameStateBitForBit) {
    // The heap above with worksheet 7's friction stage and rotation, every third body a cube: the
    // summed impulses, warm starting and the contacts kept at rest depend on the order of the
    // contacts, which must not depend on the threads of the broad phase.
    const auto drop = [](int threads) {
        PhysicsEngine e;
        StageSet stages = kImpulses;
        stages.insert(Stage::Friction);
        stages.insert(Stage::Rotation);
        e.setRequiredStages(stages);
        e.setThreads(threads);
        e.setTimeStep(1.0 / 60.0);
        addRoughHeap(e, 2400, 15);
        for (int s = 0; s < 90; ++s) e.step();  // 1.5 s: the lower layers have landed and rest
        return e.state();
    };
    const PhysicsEngine::State one = drop(1), two = drop(2);
    ASSERT_EQ(one.bodies.size(), two.bodies.size());
    for (std::size_t i = 0; i < one.bodies.size(); ++i) {
        ASSERT_EQ(one.bodies[i].position, two.bodies[i].position) << "body " << i;
        ASSERT_EQ(one.bodies[i].velocity, two.bodies[i].velocity) << "body " << i;
        ASSERT_EQ(one.bodies[i].orientation.coeffs(), two.bodies[i].orientation.coeffs()) << "body " << i;
        ASSERT_EQ(one.bodies[i].angularVelocity, two.bodies[i].angularVelocity) << "body " << i;
    }
}

// A heap of spheres and cubes that has landed (some contacts pressing, some parting), with the
// next step's gravity in its velocities and its contacts found anew: what the friction stage sweeps.
struct LandedHeap {
    std::vector<Body> bodies;
    std::vector<Contact> contacts;
    std::vector<std::size_t> first{0};  // contact c's points start at first[c]
    std::vector<Mat3> invI;
};

LandedHeap landedHeap(int count, int side) {
    PhysicsEngine e;
    e.setRequiredStages({Stage::ConstantAcceleration, Stage::Integration, Stage::Rotation, Stage::CollisionDetection,
                         Stage::Interpenetration, Stage::Friction});
    e.setTimeStep(1.0 / 60.0);
    addRoughHeap(e, count, side);
    for (int s = 0; s < 100; ++s) e.step();
    LandedHeap heap;
    heap.bodies = e.bodies();
    for (Body& b : heap.bodies) {
        if (!b.isStatic()) b.velocity += e.gravity() * e.timeStep();  // the next step's gravity: contacts press
    }
    // Every pair, not the broad phase's: the contacts' order is then the bodies' order.
    const std::vector<BodyPair> pairs = bruteForcePairs(heap.bodies, kContactMargin);
    for (const BodyPair& pair : pairs) {
        if (const std::optional<Contact> c = collide(heap.bodies, pair.a, pair.b)) {
            heap.contacts.push_back(*c);
            heap.first.push_back(heap.first.back() + c->pointCount);
        }
    }
    for (const Body& b : heap.bodies) heap.invI.push_back(worldInverseInertia(b));
    return heap;
}

TEST(Contacts, FrictionSweepsSkipOnlyPointsThatWouldNotChange) {
    // Ten sweeps that skip idle points and ten that solve every point, from the same state, give the
    // same velocities and sums to the bit: in a heap solved in the contacts' order, and in one large
    // enough to be cut in halves.
    for (const auto& [count, side] : {std::pair{150, 5}, std::pair{1000, 14}}) {
        SCOPED_TRACE(std::to_string(count) + " bodies");
        const LandedHeap heap = landedHeap(count, side);
        ASSERT_GT(heap.contacts.size(), heap.bodies.size() / 4);  // bodies at rest on others and the floor
        if (count > 150) {
            ASSERT_GE(heap.first.back(), ContactSweeps::kSplitFrom);  // cut in halves
        }
        std::vector<Body> skipping = heap.bodies, solving = heap.bodies;
        std::vector<PointImpulse> skippingSums(heap.first.back()), solvingSums(heap.first.back());
        sweepContacts(heap.contacts, heap.first, heap.invI, skipping, skippingSums, 10, true);
        sweepContacts(heap.contacts, heap.first, heap.invI, solving, solvingSums, 10, false);
        int parted = 0;
        for (std::size_t k = 0; k < solvingSums.size(); ++k) {
            ASSERT_EQ(skippingSums[k].normal, solvingSums[k].normal) << "point " << k;
            ASSERT_EQ(skippingSums[k].tangent, solvingSums[k].tangent) << "point " << k;
            parted += solvingSums[k].normal == 0.0 ? 1 : 0;
        }
        EXPECT_GT(parted, 0);  // some points part: skipped once idle
        for (std::size_t i = 0; i < heap.bodies.size(); ++i) {
            ASSERT_EQ(skipping[i].velocity, solving[i].velocity) << "body " << i;
            ASSERT_EQ(skipping[i].angularVelocity, solving[i].angularVelocity) << "body " << i;
        }
    }
}

TEST(Contacts, FrictionSweepsInHalvesOnTwoThreadsGiveTheSameStateAsOnOne) {
    // The heap cut in halves: solved at once on two threads, and one half after the other on one;
    // the second time with a first pass that starts every point (its approach measured, a normal
    // sum of a tenth of m g h to warm start from, a gap to close at every third contact).
    const LandedHeap heap = landedHeap(1000, 14);
    ASSERT_GE(heap.first.back(), ContactSweeps::kSplitFrom);
    const ContactSweeps::Start start = [&heap](std::size_t c, const Body& a, const Body& b, PointImpulse* sums,
                                               double* closing) {
        const Contact& con = heap.contacts[c];
        for (int k = 0; k < con.pointCount; ++k) {
            sums[k].normal = 0.1 * 9.81 / 60.0;  // N s
            sums[k].approach = normalVelocityAt(con, a, b, con.points[k]);
            closing[k] = c % 3 == 0 ? 0.05 : 0.0;  // m/s: every third contact still apart when its step began
        }
    };
    std::vector<Body> one, two;
    std::vector<PointImpulse> oneSums, twoSums;
    for (const ContactSweeps::Start* first : {static_cast<const ContactSweeps::Start*>(nullptr), &start}) {
        one = heap.bodies;
        oneSums.assign(heap.first.back(), PointImpulse{});
        ContactSweeps().run(heap.contacts, heap.first, heap.invI, one, oneSums, 10, true, nullptr, first);
        SecondThread second;
        ContactSweeps sweeps;
        for (int step = 0; step < 2; ++step) {  // the second time, the thread is there already
            two = heap.bodies;
            twoSums.assign(heap.first.back(), PointImpulse{});
            sweeps.run(heap.contacts, heap.first, heap.invI, two, twoSums, 10, true, &second, first);
            for (std::size_t k = 0; k < oneSums.size(); ++k) {
                ASSERT_EQ(oneSums[k].normal, twoSums[k].normal) << "point " << k;
                ASSERT_EQ(oneSums[k].tangent, twoSums[k].tangent) << "point " << k;
                ASSERT_EQ(oneSums[k].approach, twoSums[k].approach) << "point " << k;
            }
            for (std::size_t i = 0; i < heap.bodies.size(); ++i) {
                ASSERT_EQ(one[i].velocity, two[i].velocity) << "body " << i;
                ASSERT_EQ(one[i].angularVelocity, two[i].angularVelocity) << "body " << i;
            }
        }
    }
    // The first pass measured every approach before it warm started any point (the warm starts
    // would change the approaches of the points after them), and then warm started them.
    for (std::size_t c = 0; c < heap.contacts.size(); ++c) {
        const Contact& con = heap.contacts[c];
        for (int k = 0; k < con.pointCount; ++k) {
            EXPECT_EQ(oneSums[heap.first[c] + k].approach,
                      normalVelocityAt(con, heap.bodies[con.a], heap.bodies[con.b], con.points[k]));
        }
    }
    one = heap.bodies;
    oneSums.assign(heap.first.back(), PointImpulse{});
    ContactSweeps().run(heap.contacts, heap.first, heap.invI, one, oneSums, 0, true, nullptr, &start);
    double pushed = 0.0;  // the warm starts' momentum along y (kg m/s): the heap's points push up
    for (std::size_t i = 0; i < one.size(); ++i) {
        if (!one[i].isStatic()) pushed += one[i].mass * (one[i].velocity - heap.bodies[i].velocity).y();
    }
    EXPECT_GT(pushed, 0.0);
    one = heap.bodies;
    oneSums.assign(heap.first.back(), PointImpulse{});
    ContactSweeps().run(heap.contacts, heap.first, heap.invI, one, oneSums, 10);
    // And the sweeps did their work: the pressing points approach far less than before them.
    const auto worstApproach = [&heap](const std::vector<Body>& bodies) {
        double worst = 0.0;  // m/s
        for (const Contact& con : heap.contacts) {
            for (int k = 0; k < con.pointCount; ++k)
                worst = std::min(worst, normalVelocityAt(con, bodies[con.a], bodies[con.b], con.points[k]));
        }
        return worst;
    };
    // Ten sweeps from zero sums take most of the worst approach away: four fifths at least. (How much
    // more depends on the heap's graph of contacts; sweeps that do nothing, or push the wrong way,
    // leave all of it.)
    EXPECT_GT(worstApproach(one), 0.2 * worstApproach(heap.bodies));
}

TEST(Contacts, SecondThreadRunsBothHalvesAndHandsBackWhatTheirsThrew) {
    SecondThread second;
    std::vector<int> ran;
    std::thread::id theirsOn;
    second.run(false, [&] { ran.push_back(1); }, [&] { ran.push_back(2); });
    EXPECT_EQ(ran, (std::vector<int>{1, 2}));  // not used: here, mine first
    // Their half runs on the second thread, or here when this half is done before that thread has
    // begun it (it may be waiting for a core): each half exactly once either way. A half of ours
    // that waits a little for theirs to begin gives the second thread the time to take it.
    int mine = 0;
    std::atomic<int> theirs{0};
    std::atomic<bool> elsewhere{false};
    const auto waitFor = [](const std::atomic<int>& count, int before) {
        const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(50);
        while (count.load() == before && std::chrono::steady_clock::now() < until) std::this_thread::yield();
    };
    const std::thread::id here = std::this_thread::get_id();
    // Until their half has run on the second thread once (a thread that lost its gains sleeps for a
    // while, and ours then waits out each half).
    int handed = 0;
    for (; handed < 1000 && !elsewhere.load(); ++handed) {
        second.run(true, [&] { ++mine, waitFor(theirs, handed); }, [&] {
            if (std::this_thread::get_id() != here) elsewhere = true, theirsOn = std::this_thread::get_id();
            ++theirs;
        });
    }
    EXPECT_EQ(mine, handed);
    EXPECT_EQ(theirs.load(), handed);
    EXPECT_TRUE(elsewhere.load());
    for (int k = 0; k < 1000; ++k) second.run(true, [&] { ++mine; }, [&] { ++theirs; });  // whoever takes it
    EXPECT_EQ(mine, handed + 1000);
    EXPECT_EQ(theirs.load(), handed + 1000);
    EXPECT_THROW(second.run(true, [] {}, [] { throw std::runtime_error("theirs failed"); }), std::runtime_error);
    second.wake();  // as a stage does before its first hand-over
    second.run(true, [&] { ++mine; }, [&] { ++theirs; });  // and it goes on working
    EXPECT_EQ(theirs.load(), handed + 1001);
    SecondThread copy = second;  // an engine's copy makes its own thread when it needs one
    std::atomic<int> copied{0};
    std::thread::id copyOn = here;
    for (int k = 0; k < 1000 && copyOn == here; ++k) {
        copy.run(true, [&] { waitFor(copied, k); }, [&] { copyOn = std::this_thread::get_id(), ++copied; });
    }
    EXPECT_NE(copyOn, theirsOn);
    EXPECT_NE(copyOn, here);
}

TEST(Contacts, ThreadsAreCheckedAndRemembered) {
    PhysicsEngine e;
    EXPECT_THROW(e.setThreads(0), std::invalid_argument);
    e.setThreads(1);
    EXPECT_EQ(e.threads(), 1);
    e.setThreads(2);
    EXPECT_EQ(e.threads(), 2);
}

}  // namespace
}  // namespace gpl
