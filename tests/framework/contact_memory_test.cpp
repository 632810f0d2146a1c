// Contacts that persist (ContactMemory, friction.h): a point of this step finds last step's sums
// by where the bodies carry last step's points, whatever order, number or pair order the collision
// kernels return them in. Experiments run the friction stage on the resting scenes with the
// clippers' answers shuffled between the kernels and the stage; the small cases run the stage
// without sweeps, so that what it keeps is exactly what each point started from.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "gpl/collision.h"
#include "gpl/engine.h"
#include "gpl/friction.h"
#include "gpl/friction_stage.h"
#include "gpl/scenes.h"

namespace gpl {
namespace {

// What the clipper returns, changed between the collision kernels and the friction stage (step s).
using Shuffle = std::function<void(std::size_t s, std::vector<Contact>&)>;

// The largest speed of any material point of a body: its centre's plus its turning times the
// farthest a point lies from the centre (m/s).
double fastestPoint(const Body& b) {
    if (b.isStatic()) return 0.0;
    const double reach = b.shape == Shape::Box ? b.halfExtents.norm() : b.radius;
    return b.velocity.norm() + b.angularVelocity.norm() * reach;
}

// One step of a friction scene, as the engine's: gravity, integration, rotation, the contacts of
// every pair from the collision kernels (grown by kKeepGap, as detection grows them in a friction
// scene), shuffled, then the friction stage.
void stepWith(PhysicsEngine& e, FrictionStage& stage, std::vector<Contact>& contacts, const Shuffle& shuffle,
              std::size_t s) {
    e.updateConstantAcceleration();
    e.integrate();
    e.rotate();
    contacts.clear();
    std::vector<Body>& bodies = e.bodies();
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        for (std::size_t j = i + 1; j < bodies.size(); ++j) {
            if (bodies[i].isStatic() && bodies[j].isStatic()) continue;
            if (std::optional<Contact> c = collide(bodies, i, j, kKeepGap)) contacts.push_back(*c);
        }
    }
    if (shuffle) shuffle(s, contacts);
    stage.step(bodies, contacts, e.timeStep(), e.contactIterations(), e.interpenetrationIterations(), nullptr,
               e.contactSolver());
}

struct Column {
    /// Largest |L - W| / W over the steps after the first second and every contact, L the
    /// contact's total normal impulse and W the weight of the boxes above it times h.
    double carried = 0.0;
    /// Largest |L - L'| / W, L' the same pair's total a step before.
    double stepToStep = 0.0;
    double drift = 0.0;       ///< farthest a box ended from its start (m)
    double lastSecond = 0.0;  ///< fastest point of any box over the last second (m/s)
};

// A column of boxes of one mass on the floor (body 0; box i rests on box i - 1), `seconds` with the
// clipper's answers shuffled.
Column column(const std::string& scene, double seconds, const Shuffle& shuffle) {
    PhysicsEngine e;
    load(e, scenes().find(scene));
    const PhysicsEngine::State start = e.state();
    const std::size_t boxes = e.bodies().size() - 1;
    const double weight = e.bodies()[1].mass * e.gravity().norm() * e.timeStep();  // one box's, N s
    FrictionStage stage;
    std::vector<Contact> contacts;
    std::map<std::pair<std::size_t, std::size_t>, double> before;
    Column out;
    const std::size_t steps = static_cast<std::size_t>(std::lround(seconds / e.timeStep()));
    const std::size_t second = static_cast<std::size_t>(std::lround(1.0 / e.timeStep()));
    for (std::size_t s = 1; s <= steps; ++s) {
        stepWith(e, stage, contacts, shuffle, s);
        const ContactMemory& m = stage.memory();
        std::map<std::pair<std::size_t, std::size_t>, double> now;
        for (const ContactMemory::Entry& c : m.entries) {
            double total = 0.0;
            for (std::uint32_t k = c.first; k < c.first + c.pointCount; ++k) total += m.sums[k].normal;
            const std::pair<std::size_t, std::size_t> pair{std::min(c.a, c.b), std::max(c.a, c.b)};
            now[pair] = total;
            if (s <= second) continue;
            const double carried = static_cast<double>(boxes + 1 - pair.second) * weight;
            out.carried = std::max(out.carried, std::abs(total - carried) / carried);
            const auto was = before.find(pair);
            out.stepToStep =
                std::max(out.stepToStep, std::abs(total - (was == before.end() ? 0.0 : was->second)) / carried);
        }
        before = std::move(now);
        if (s + second > steps) {
            for (const Body& b : e.bodies()) out.lastSecond = std::max(out.lastSecond, fastestPoint(b));
        }
    }
    for (std::size_t i = 0; i < e.bodies().size(); ++i) {
        out.drift = std::max(out.drift, (e.bodies()[i].position - start.bodies[i].position).norm());
    }
    return out;
}

const Shuffle kReversed = [](std::size_t, std::vector<Contact>& cs) {
    for (Contact& c : cs) std::reverse(c.points.begin(), c.points.begin() + c.pointCount);
};
const Shuffle kRotated = [](std::size_t s, std::vector<Contact>& cs) {
    for (Contact& c : cs)
        std::rotate(c.points.begin(), c.points.begin() + s % c.pointCount, c.points.begin() + c.pointCount);
};
// One point fewer every step, another each time.
const Shuffle kOneFewer = [](std::size_t s, std::vector<Contact>& cs) {
    for (Contact& c : cs) {
        if (c.pointCount < 2) continue;
        const int k = static_cast<int>(s % c.pointCount);
        std::rotate(c.points.begin() + k, c.points.begin() + k + 1, c.points.begin() + c.pointCount);
        --c.pointCount;
    }
};
// Every other step one point fewer, another each time, and the step after it back: a point
// gained.
const Shuffle kFewerThenMore = [](std::size_t s, std::vector<Contact>& cs) {
    if (s % 2 == 0) return;
    kOneFewer(s / 2, cs);
};
// Every other step the pair in the other order: a and b swapped, the normal reversed.
const Shuffle kPairSwapped = [](std::size_t s, std::vector<Contact>& cs) {
    if (s % 2 == 0) return;
    for (Contact& c : cs) {
        std::swap(c.a, c.b);
        c.normal = -c.normal;
    }
};

// A column stands: every box within 1 cm of its start (the resting-contact tests' measure).
void expectStands(const std::string& what, const Column& c) {
    EXPECT_LT(c.drift, 0.01) << what << ": a box ended this far from its start (m)";
}

// A column as still as with the clipper's points as it returns them: its fastest point over the
// last second at most twice as fast, or below 10 um/s (where a column is at rest). Another order
// of the points is another order of the sweeps, which leaves another residual speed, by tens of
// per cent; a warm start lost moves it by orders of magnitude.
void expectAsStill(const std::string& what, const Column& shuffled, const Column& plain) {
    EXPECT_LT(shuffled.lastSecond, 2.0 * plain.lastSecond + 1e-5)
        << what << ": a point still moved this fast in the last second (m/s); " << plain.lastSecond
        << " as the clipper returns the points";
}

// Each contact of a still column carries the weight above it, and its sums hardly change from one
// step to the next: a thousandth of that weight (the plain clipper's columns keep both to a ten
// thousandth; a warm start lost for one point of four moves a quarter of it).
void expectCarries(const std::string& what, const Column& c) {
    EXPECT_LT(c.carried, 1e-3) << what << ": a contact's total normal impulse left the weight it carries by this share";
    EXPECT_LT(c.stepToStep, 1e-3)
        << what << ": a contact's total normal impulse changed in a step by this share of that weight";
}

void expectKeepsWarmStart(const Shuffle& shuffle, const std::string& how) {
    for (const char* scene : {"box-stack", "stack-10-offset"}) {
        const std::string what = std::string(scene) + ", " + how;
        const Column plain = column(scene, 10.0, {});
        expectStands(std::string(scene) + ", as the clipper returns it", plain);
        const Column shuffled = column(scene, 10.0, shuffle);
        expectCarries(what, shuffled);
        expectStands(what, shuffled);
        expectAsStill(what, shuffled, plain);
    }
}

TEST(ContactMemory, StackKeepsItsWarmStartWhenTheClipperReturnsThePointsInAnotherOrder) {
    expectKeepsWarmStart(kReversed, "points reversed");
    expectKeepsWarmStart(kRotated, "points rotated by another place each step");
}

TEST(ContactMemory, StackKeepsItsWarmStartWhenTheClipperLosesAPointEachStep) {
    expectKeepsWarmStart(kOneFewer, "one point fewer each step");
}

TEST(ContactMemory, StackKeepsItsWarmStartWhenTheClipperLosesAPointAndGainsItBack) {
    expectKeepsWarmStart(kFewerThenMore, "one point fewer every other step, back the step after");
}

TEST(ContactMemory, StackKeepsItsWarmStartWhenThePairComesInTheOtherOrder) {
    expectKeepsWarmStart(kPairSwapped, "pair order and normal reversed every other step");
}

// The resting scenes as the kernels return them: every point of a contact that last step had
// continues one of last step's points (ContactMemory::pairUp()).
TEST(ContactMemory, RestingScenesContinueEveryPoint) {
    for (const char* scene : {"box-stack", "stack-10", "stack-10-offset", "card-house"}) {
        PhysicsEngine e;
        load(e, scenes().find(scene));
        FrictionStage stage;
        std::vector<Contact> contacts;
        long points = 0, fresh = 0;
        for (std::size_t s = 1; s <= 500; ++s) {
            const ContactMemory was = stage.memory();
            // The bodies as the kernels see them: the stage moves them on after.
            const Shuffle seen = [&](std::size_t, std::vector<Contact>& cs) {
                for (const Contact& c : cs) {
                    bool flipped = false;
                    const ContactMemory::Entry* old = was.find(c.a, c.b, flipped);
                    if (old == nullptr) continue;
                    const ContactMemory::Pairing pairing =
                        was.pairUp(*old, flipped, c, e.bodies()[c.a], e.bodies()[c.b]);
                    points += c.pointCount;
                    for (int k = 0; k < c.pointCount; ++k) fresh += pairing[k] == ContactMemory::kNone ? 1 : 0;
                }
            };
            stepWith(e, stage, contacts, seen, s);
        }
        EXPECT_GT(points, 0) << scene;
        EXPECT_EQ(fresh, 0) << scene << ": points that continue none of last step's";
    }
}

// ---- One contact, the stage run without sweeps: what it keeps is what each point started from ----

constexpr double kStep = 0.01;  // s

// A cube of half side 0.5 m on the floor, its bottom corners (the box is a, the floor b, as
// collide() orders them: the normal points down).
struct CubeOnFloor {
    std::vector<Body> bodies{plane("floor", Vec3::UnitY()), box("cube", Vec3::Constant(0.5), 1.0).at({0.0, 0.5, 0.0})};
    std::array<Vec3, 4> corners{Vec3(-0.5, 0.0, -0.5), Vec3(0.5, 0.0, -0.5), Vec3(0.5, 0.0, 0.5), Vec3(-0.5, 0.0, 0.5)};
    FrictionStage stage;

    CubeOnFloor() {
        bodies[0].rough(0.5, 0.5);
        bodies[1].rough(0.5, 0.5).bouncy(0.0);
    }
    Contact contact(std::initializer_list<Vec3> points) const {
        Contact c;
        c.a = 1;
        c.b = 0;
        c.normal = -Vec3::UnitY();
        c.depth = 1e-4;
        c.friction = c.staticFriction = 0.5;
        for (const Vec3& p : points) c.points[c.pointCount++] = p;
        return c;
    }
    // A step of the stage with these points: the cube falling at g h, tipping and sliding, so that
    // every point's sums differ; ten sweeps, or none.
    void step(const Contact& c, int sweeps) {
        bodies[1].velocity = Vec3(0.05, -9.81 * kStep, 0.0);
        bodies[1].angularVelocity = Vec3(0.3, 0.0, 0.1);
        std::vector<Contact> contacts{c};
        stage.step(bodies, contacts, kStep, sweeps, 0, nullptr);
    }
    // The sums kept at the point nearest p (N s), and how many points the contact kept.
    ContactMemory::Sums at(const Vec3& p) const {
        const ContactMemory& m = stage.memory();
        std::uint32_t best = 0;
        for (std::uint32_t k = 1; k < m.points.size(); ++k) {
            if ((m.points[k] - p).norm() < (m.points[best] - p).norm()) best = k;
        }
        return m.sums[best];
    }
    double total() const {
        double sum = 0.0;
        for (const ContactMemory::Sums& s : stage.memory().sums) sum += s.normal;
        return sum;
    }
};

// Sums equal to the last bits of their size (the warm start copies them, the tangent turned into
// the same plane).
void expectSameSums(const ContactMemory::Sums& got, const ContactMemory::Sums& want, const std::string& what) {
    EXPECT_NEAR(got.normal, want.normal, 1e-12 * std::abs(want.normal)) << what;
    EXPECT_LT((got.tangent - want.tangent).norm(), 1e-12 * want.tangent.norm() + 1e-300) << what;
}

TEST(ContactMemory, PointsInAnotherOrderKeepTheirOwnSums) {
    CubeOnFloor cube;
    const auto& q = cube.corners;
    cube.step(cube.contact({q[0], q[1], q[2], q[3]}), 10);
    std::array<ContactMemory::Sums, 4> before;
    for (int k = 0; k < 4; ++k) before[k] = cube.at(q[k]);
    ASSERT_GT(std::abs(before[0].normal - before[2].normal), 1e-3 * before[0].normal) << "the corners' sums differ";
    cube.step(cube.contact({q[2], q[0], q[3], q[1]}), 0);
    for (int k = 0; k < 4; ++k) expectSameSums(cube.at(q[k]), before[k], "corner " + std::to_string(k));
}

TEST(ContactMemory, APointThatAppearsStartsFromZeroAndItsNeighboursKeepTheirs) {
    CubeOnFloor cube;
    const auto& q = cube.corners;
    cube.step(cube.contact({q[0], q[1], q[2]}), 10);
    std::array<ContactMemory::Sums, 3> before;
    for (int k = 0; k < 3; ++k) before[k] = cube.at(q[k]);
    cube.step(cube.contact({q[3], q[1], q[0], q[2]}), 0);
    for (int k = 0; k < 3; ++k) expectSameSums(cube.at(q[k]), before[k], "corner " + std::to_string(k));
    EXPECT_EQ(cube.at(q[3]).normal, 0.0);
    EXPECT_TRUE(cube.at(q[3]).tangent.isZero(0.0));
}

// The clipper returns another set: three corners and, for the fourth, a point on an edge. The
// fourth corner's sums go to the three (its load is not dropped for a step), and the new point
// starts from zero.
TEST(ContactMemory, AContactThatLosesAPointKeepsItsTotalNormalImpulse) {
    CubeOnFloor cube;
    const auto& q = cube.corners;
    cube.step(cube.contact({q[0], q[1], q[2], q[3]}), 10);
    const double total = cube.total();
    ASSERT_GT(cube.at(q[3]).normal, 1e-3 * total) << "the lost corner carried a share";
    const Vec3 edge = 0.5 * (q[2] + q[3]);
    cube.step(cube.contact({q[0], edge, q[1], q[2]}), 0);
    EXPECT_NEAR(cube.total(), total, 1e-12 * total) << "N s";
    EXPECT_EQ(cube.at(edge).normal, 0.0);
}

// One to one: two points of this step near one of last step's (the clipper returned a corner
// twice, a centimetre apart) do not both start from its sums.
TEST(ContactMemory, NoTwoPointsStartFromOnePointsSums) {
    CubeOnFloor cube;
    const auto& q = cube.corners;
    cube.step(cube.contact({q[0], q[1], q[2], q[3]}), 10);
    const double total = cube.total();
    const Vec3 twin = q[0] + Vec3(0.01, 0.0, 0.01);
    cube.step(cube.contact({q[0], q[1], q[2], twin}), 0);
    EXPECT_EQ(cube.at(twin).normal, 0.0) << "the second point near corner 0 took its sums too";
    EXPECT_NEAR(cube.total(), total, 1e-12 * total) << "N s";
}

// Two cubes (half side 0.5 m) overlapping by 0.4 mm, the upper one shifted by 0.1 m along x: the
// clipper may take either face as the reference and clip the other's to it, and may return the
// pair in either order. The four corners of the overlap are the same, on one face or the other.
struct TwoCubes {
    std::vector<Body> bodies{box("lower", Vec3::Constant(0.5), 1.0).at({0.0, 0.5, 0.0}),
                             box("upper", Vec3::Constant(0.5), 1.0).at({0.1, 1.5 - 4e-4, 0.0})};
    FrictionStage stage;

    TwoCubes() {
        for (Body& b : bodies) b.rough(0.5, 0.5).bouncy(0.0);
    }
    // The overlap's corners on the lower cube's top face (y = 1) or the upper's bottom face.
    std::array<Vec3, 4> corners(bool onUpper) const {
        const double y = onUpper ? 1.0 - 4e-4 : 1.0;
        return {Vec3(-0.4, y, -0.5), Vec3(0.5, y, -0.5), Vec3(0.5, y, 0.5), Vec3(-0.4, y, 0.5)};
    }
    void step(bool onUpper, bool lowerFirst, const std::array<int, 4>& order, int sweeps) {
        Contact c;
        c.a = lowerFirst ? 0 : 1;
        c.b = lowerFirst ? 1 : 0;
        c.normal = lowerFirst ? Vec3::UnitY() : Vec3(-Vec3::UnitY());
        c.depth = 4e-4;
        c.friction = c.staticFriction = 0.5;
        const std::array<Vec3, 4> q = corners(onUpper);
        for (int k : order) c.points[c.pointCount++] = q[k];
        bodies[0].velocity = Vec3(0.0, 0.0, 0.02);
        bodies[1].velocity = Vec3(0.05, -9.81 * kStep, 0.0);
        bodies[1].angularVelocity = Vec3(0.2, 0.0, -0.3);
        std::vector<Contact> contacts{c};
        stage.step(bodies, contacts, kStep, sweeps, 0, nullptr);
    }
    // The sums kept at the corner k (the point nearest it); the friction sum as the lower cube gets
    // it (the memory keeps it as b gets it).
    ContactMemory::Sums at(int k) const {
        const ContactMemory& m = stage.memory();
        const Vec3 p = corners(false)[k];
        std::uint32_t best = 0;
        for (std::uint32_t j = 1; j < m.points.size(); ++j) {
            if ((m.points[j] - p).norm() < (m.points[best] - p).norm()) best = j;
        }
        ContactMemory::Sums s = m.sums[best];
        if (m.entries.at(0).a == 0) s.tangent = -s.tangent;
        return s;
    }
};

TEST(ContactMemory, AFaceSwitchKeepsTheSums) {
    TwoCubes cubes;
    cubes.step(false, true, {0, 1, 2, 3}, 10);
    std::array<ContactMemory::Sums, 4> before;
    for (int k = 0; k < 4; ++k) before[k] = cubes.at(k);
    double friction = 0.0;  // N s
    for (const ContactMemory::Sums& b : before) friction = std::max(friction, b.tangent.norm());
    ASSERT_GT(friction, 0.0) << "the corners have friction sums";
    // The upper cube's face the reference now: the points on the lower's face, another order.
    cubes.step(true, true, {1, 2, 3, 0}, 0);
    for (int k = 0; k < 4; ++k) expectSameSums(cubes.at(k), before[k], "corner " + std::to_string(k));
}

TEST(ContactMemory, APairInTheOtherOrderKeepsTheSums) {
    TwoCubes cubes;
    cubes.step(false, true, {0, 1, 2, 3}, 10);
    std::array<ContactMemory::Sums, 4> before;
    for (int k = 0; k < 4; ++k) before[k] = cubes.at(k);
    // The upper cube first and the normal pointing down: its face the reference, as a clipper
    // that takes a's face sees it.
    cubes.step(true, false, {3, 2, 1, 0}, 0);
    ASSERT_EQ(cubes.stage.memory().entries.size(), 1u) << "one contact for the pair, not one per order";
    for (int k = 0; k < 4; ++k) expectSameSums(cubes.at(k), before[k], "corner " + std::to_string(k));
}

}  // namespace
}  // namespace gpl
