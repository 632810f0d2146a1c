// The broad phase against its definition: the same pairs as testing every pair, on random scenes.
#include "gpl/broadphase.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

namespace gpl {
namespace {

// A random scene from a fixed seed: spheres and boxes of mixed sizes (some rotated, some static)
// packed densely enough that many pairs overlap, and planes of random tilt and offset.
std::vector<Body> randomScene(unsigned seed, int finite, int planes, double extent) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const auto point = [&]() -> Vec3 { return Vec3(unit(random), unit(random), unit(random)) * extent; };
    std::vector<Body> bodies;
    for (int i = 0; i < finite; ++i) {
        const std::string name = "body" + std::to_string(i);
        Body b = unit(random) < 0.6 ? sphere(name, 0.1 + 0.9 * unit(random), 1.0)
                                    : box(name, Vec3(0.1, 0.1, 0.1) + 0.8 * point() / extent, 1.0);
        b.at(point()).rotated(Quat(Eigen::AngleAxisd(6.3 * unit(random), point().normalized())));
        if (unit(random) < 0.15) b.makeStatic();
        bodies.push_back(b);
    }
    for (int i = 0; i < planes; ++i) {
        const Vec3 n = point() - Vec3::Constant(extent / 2.0);
        bodies.push_back(plane("plane" + std::to_string(i), n).at(point()));
    }
    std::shuffle(bodies.begin(), bodies.end(), random);  // planes and statics anywhere in the list
    return bodies;
}

TEST(BroadPhase, SamePairsAsTestingEveryPair) {
    BroadPhase broadPhase;
    std::size_t pairsSeen = 0;
    for (unsigned seed = 1; seed <= 40; ++seed) {
        const std::vector<Body> bodies = randomScene(seed, 10 + 7 * seed, seed % 4, 4.0 + seed / 4.0);
        const double margin = (seed % 3) * 0.1;  // none, and margins as the contact stages use them
        const std::vector<BodyPair>& found = broadPhase.findPairs(bodies, margin);  // buffers reused
        const std::vector<BodyPair> expected = bruteForcePairs(bodies, margin);
        ASSERT_EQ(found, expected) << "seed " << seed;
        pairsSeen += expected.size();
    }
    EXPECT_GT(pairsSeen, 1000u);  // the scenes are dense enough to test something
}

TEST(BroadPhase, OneThreadAndTwoFindTheSamePairs) {
    // Scenes for the grid (kGridFrom bodies on), each with one thread and two: the same pairs as
    // testing every pair. The last scene holds a body far larger than the cells and two far outside
    // the grid's range, which are tested against every other body.
    SecondThread second;
    const int grid = static_cast<int>(BroadPhase::kGridFrom);
    for (unsigned seed = 0; seed <= 3; ++seed) {
        std::vector<Body> bodies = seed == 0 ? randomScene(seed, grid, 2, 12.0)
                                             : randomScene(seed, grid + 1500 * static_cast<int>(seed), 2, 30.0);
        if (seed == 3) {
            bodies.push_back(box("slab", Vec3(40.0, 0.5, 40.0), 1.0).at(Vec3(15.0, 15.0, 15.0)).makeStatic());
            bodies.push_back(sphere("far", 1.0, 1.0).at(Vec3(1e9, 0.0, 0.0)));
            bodies.push_back(sphere("farther", 1.0, 1.0).at(Vec3(1e9, 1.5, 0.0)));
        }
        BroadPhase one, two;
        one.setThreads(1);
        two.setThreads(2);
        const std::vector<BodyPair> expected = bruteForcePairs(bodies, 0.1);
        ASSERT_GT(expected.size(), bodies.size());  // dense: more pairs than bodies
        EXPECT_EQ(one.findPairs(bodies, 0.1, &second), expected) << "seed " << seed;  // one thread: second unused
        EXPECT_EQ(two.findPairs(bodies, 0.1, &second), expected) << "seed " << seed;
    }
}

TEST(BroadPhase, TheGridFindsNeighboursInEveryDirection) {
    // A lattice of equal cubes around the origin (negative cells too), spaced so that each box
    // overlaps its 26 neighbours' (by 1 % of the spacing on the diagonals' axes) and no other's,
    // shifted to every offset within a cell (which row and column a neighbour lands in changes);
    // then the same lattice holding cubes of up to kLargeSizes median ones (filed in cells as wide
    // as the largest) and one just larger (tested against every other body instead). Cubes, not
    // spheres: two spheres on a diagonal pair only where their balls meet.
    const double half = 0.5, spacing = 0.99 * 2.0 * half;  // m
    for (int shift = 0; shift < 4; ++shift) {
        for (const bool mixed : {false, true}) {
            std::vector<Body> bodies;
            for (int x = -5; x < 5; ++x) {
                for (int y = -5; y < 5; ++y) {
                    for (int z = -5; z < 5; ++z) {
                        const Vec3 at = spacing * Vec3(x, y, z) + Vec3::Constant(0.3 * shift * half);
                        bodies.push_back(box("c" + std::to_string(bodies.size()), Vec3::Constant(half), 1.0).at(at));
                    }
                }
            }
            if (mixed) {
                const Vec3 big = Vec3::Constant(0.99 * BroadPhase::kLargeSizes * half);
                bodies.push_back(box("big", big, 1.0).at(Vec3(1.3, -2.1, 0.4)));
                bodies.push_back(box("larger", big * (1.01 / 0.99), 1.0).at(Vec3(-3.2, 2.5, -1.9)));
            }
            ASSERT_GE(bodies.size(), BroadPhase::kGridFrom);
            const std::vector<BodyPair> expected = bruteForcePairs(bodies);
            BroadPhase broadPhase;
            broadPhase.setThreads(1);
            EXPECT_EQ(broadPhase.findPairs(bodies), expected) << "shift " << shift << (mixed ? ", mixed sizes" : "");
            // Each inner cube of the plain lattice pairs with its 26 neighbours, 13 of them after it.
            if (!mixed) {
                EXPECT_GT(expected.size(), 13u * 8u * 8u * 8u);
            }
        }
    }
}

TEST(BroadPhase, AMovingSceneKeepsItsPairsRight) {
    // The sweep starts each call from the last call's order. The same bodies called again after
    // small moves (nearly sorted), after large ones (far from sorted) and after the spread has
    // turned to another axis must give the pairs of testing every pair each time.
    std::vector<Body> bodies = randomScene(7, 400, 1, 8.0);  // sort and sweep
    std::mt19937 random(7);
    std::uniform_real_distribution<double> step(-1.0, 1.0);
    BroadPhase broadPhase;
    for (int call = 0; call < 12; ++call) {
        const double reach = call < 6 ? 0.05 : 3.0;  // m per axis: small moves first, then large ones
        for (Body& b : bodies) {
            if (b.shape != Shape::Plane) b.position += reach * Vec3(step(random), step(random), step(random));
        }
        if (call == 9) {
            for (Body& b : bodies) b.position = Vec3(b.position.z() * 0.1, b.position.y(), b.position.x() * 3.0);
        }
        ASSERT_EQ(broadPhase.findPairs(bodies, 0.1), bruteForcePairs(bodies, 0.1)) << "call " << call;
    }
}

TEST(BroadPhase, KeptPairsAnswerAsASearchAnewWould) {
    // Small moves answered from the kept pairs, large ones searched anew, and every change that
    // the kept pairs cannot answer for (a body made static or movable, a plane moved or turned, a
    // body more, another margin): the pairs of testing every pair each time.
    std::vector<Body> bodies = randomScene(11, 700, 2, 9.0);  // the grid
    for (Body& b : bodies) b.velocity = Vec3(0.3, -0.2, 0.1);  // m/s, the way the small moves go
    std::mt19937 random(11);
    std::uniform_real_distribution<double> step(-1.0, 1.0);
    BroadPhase broadPhase;
    const double ahead = 0.05;  // s: the grown boxes reach 3 cm along the velocity
    const auto check = [&](const std::string& what) {
        ASSERT_EQ(broadPhase.findPairs(bodies, 0.1, nullptr, ahead), bruteForcePairs(bodies, 0.1)) << what;
    };
    for (int call = 0; call < 30; ++call) {
        const double reach = call % 10 == 9 ? 0.5 : 0.004;  // m per axis: mostly small moves
        for (Body& b : bodies) {
            if (b.shape != Shape::Plane && !b.isStatic()) b.position += reach * Vec3(step(random), step(random), step(random));
        }
        check("call " + std::to_string(call));
    }
    EXPECT_LT(broadPhase.searches(), 10u) << "small moves are answered from the kept pairs";
    EXPECT_GE(broadPhase.searches(), 4u) << "the large moves search anew";
    const auto firstOf = [&](auto pick) { return std::find_if(bodies.begin(), bodies.end(), pick); };
    const auto movable = firstOf([](const Body& b) { return b.shape != Shape::Plane && !b.isStatic(); });
    const auto fixed = firstOf([](const Body& b) { return b.shape != Shape::Plane && b.isStatic(); });
    const auto plane = firstOf([](const Body& b) { return b.shape == Shape::Plane; });
    ASSERT_TRUE(movable != bodies.end() && fixed != bodies.end() && plane != bodies.end());
    const std::size_t before = broadPhase.searches();
    movable->makeStatic();
    check("a body made static");
    fixed->invMass = 1.0;
    check("a static body made movable");
    plane->position += Vec3(0.0, 0.5, 0.0);
    check("a plane moved");
    plane->orientation = Quat(Eigen::AngleAxisd(0.3, Vec3::UnitX())) * plane->orientation;
    check("a plane turned");
    bodies.push_back(sphere("newcomer", 0.5, 1.0).at(bodies.front().position));
    check("a body more");
    ASSERT_EQ(broadPhase.findPairs(bodies, 0.2, nullptr, ahead), bruteForcePairs(bodies, 0.2)) << "another margin";
    EXPECT_EQ(broadPhase.searches(), before + 6) << "each change searched anew";
}

TEST(BroadPhase, AFewBodiesOutOfTheirBoxesAreUpdatedNotSearched) {
    // Up to kUpdateAtMost bodies that leave their grown boxes (far, across the scene, onto each
    // other, a static one moved, one through a plane) get their pairs anew against every other
    // body; more search anew. Each time the pairs of testing every pair.
    std::vector<Body> bodies = randomScene(5, 700, 2, 9.0);  // the grid
    std::mt19937 random(5);
    std::uniform_int_distribution<std::size_t> pick(0, bodies.size() - 1);
    BroadPhase broadPhase;
    const auto check = [&](const std::string& what) {
        ASSERT_EQ(broadPhase.findPairs(bodies, 0.1, nullptr, 0.05), bruteForcePairs(bodies, 0.1)) << what;
    };
    check("first call");
    const std::size_t searches = broadPhase.searches();
    const auto finite = [&](std::size_t i) { return bodies[i].shape != Shape::Plane; };
    for (int round = 0; round < 20; ++round) {
        const std::size_t moved = round % 5 == 4 ? BroadPhase::kUpdateAtMost : 1 + round % 4;
        std::size_t first = pick(random);
        while (!finite(first)) first = pick(random);
        for (std::size_t k = 0; k < moved; ++k) {
            std::size_t i = pick(random);
            while (!finite(i)) i = pick(random);
            // Onto the first moved body (a pair of two moved bodies), or anywhere in the scene.
            bodies[i].position = k % 3 == 1 ? bodies[first].position + Vec3(0.1, 0.0, 0.0)
                                            : Vec3(pick(random) % 9, pick(random) % 9, pick(random) % 9);
        }
        check("round " + std::to_string(round));
    }
    EXPECT_EQ(broadPhase.searches(), searches) << "a few bodies out: updated";
    EXPECT_EQ(broadPhase.updates(), 20u);
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        if (finite(i)) bodies[i].position += Vec3(3.0, 0.0, 0.0);  // every body out: a search
    }
    check("every body moved");
    EXPECT_EQ(broadPhase.searches(), searches + 1);
}

TEST(BroadPhase, StaticBodiesNeverPairWithEachOther) {
    std::vector<Body> bodies = {plane("floor", Vec3::UnitY()), box("shelf", {1, 1, 1}, 1.0).makeStatic(),
                                sphere("pillar", 1.0, 1.0).makeStatic(), sphere("ball", 0.5, 1.0).at({0, 0.4, 0})};
    BroadPhase broadPhase;
    const std::vector<BodyPair> expected = {{0, 3}, {1, 3}, {2, 3}};
    EXPECT_EQ(broadPhase.findPairs(bodies), expected);
}

TEST(BroadPhase, PlanesAreInfinite) {
    // A ball far away along the plane, just reaching it, pairs with it; one just above does not.
    std::vector<Body> bodies = {plane("tilted", Vec3(1, 1, 0)).at({0, -5, 0}),
                                sphere("far", 0.5, 1.0).at(Vec3(1e6, -1e6 - 5.0, 0.0) + Vec3(1, 1, 0).normalized() * 0.4),
                                sphere("above", 0.5, 1.0).at(Vec3(1e6, -1e6 - 5.0, 0.0) + Vec3(1, 1, 0) * 10.0)};
    BroadPhase broadPhase;
    const std::vector<BodyPair> expected = {{0, 1}};
    EXPECT_EQ(broadPhase.findPairs(bodies), expected);
}

TEST(BroadPhase, TouchingBoxesPairAndSeparatedOnesDoNot) {
    std::vector<Body> bodies = {sphere("a", 0.5, 1.0).at({0, 0, 0}), sphere("b", 0.5, 1.0).at({1.0, 0, 0}),
                                sphere("c", 0.5, 1.0).at({2.0 + 1e-9, 0, 0})};
    BroadPhase broadPhase;
    const std::vector<BodyPair> expected = {{0, 1}};
    EXPECT_EQ(broadPhase.findPairs(bodies), expected);
}

TEST(BroadPhase, SpheresPairOnlyWhereTheirBallsMeet) {
    // Spheres of radius 0.5 m side by side at a slant, 0.8 m apart on two axes: their boxes overlap
    // in the corners, but the balls are 1.13 m apart, 0.13 m more than they reach. A margin of 0.15
    // grows each radius by 7.5 cm, enough; 0.12 (6 cm each) is not. A cube in the sphere's place
    // reaches farther: its ball passes through its corners (0.87 m), and the two balls meet.
    const Vec3 slant(0.8, 0.8, 0.0);  // m
    std::vector<Body> spheres = {sphere("a", 0.5, 1.0), sphere("b", 0.5, 1.0).at(slant)};
    std::vector<Body> sphereAndBox = {sphere("a", 0.5, 1.0), box("b", Vec3::Constant(0.5), 1.0).at(slant)};
    BroadPhase broadPhase;
    const std::vector<BodyPair> pair = {{0, 1}};
    EXPECT_TRUE(broadPhase.findPairs(spheres).empty());
    EXPECT_TRUE(broadPhase.findPairs(spheres, 0.12).empty());
    EXPECT_EQ(broadPhase.findPairs(spheres, 0.15), pair);
    EXPECT_EQ(broadPhase.findPairs(sphereAndBox), pair);
    EXPECT_TRUE(bruteForcePairs(spheres).empty());
    EXPECT_EQ(bruteForcePairs(spheres, 0.15), pair);
    EXPECT_EQ(bruteForcePairs(sphereAndBox), pair);
    // The kept pairs answer the same: b moved towards a, inside the boxes the pairs were kept for.
    EXPECT_TRUE(broadPhase.findPairs(spheres).empty());
    const std::size_t searches = broadPhase.searches();
    spheres[1].position = Vec3(0.75, 0.75, 0.0);  // 1.06 m apart: still not touching
    EXPECT_TRUE(broadPhase.findPairs(spheres).empty());
    spheres[1].position = Vec3(0.705, 0.705, 0.0);  // 0.997 m apart: touching
    EXPECT_EQ(broadPhase.findPairs(spheres), pair);
    EXPECT_EQ(broadPhase.searches(), searches);
}

TEST(BroadPhase, BoxesPairOnlyWhereTheirBallsMeet) {
    // Two cubes of half extent 0.5 m, each turned by 45 degrees about z: each one's bounding box has
    // the half extents (0.71, 0.71, 0.5) m. With b's centre at 0.99 of their sum from a's on every
    // axis the boxes overlap, but the centres are 2.21 m apart, more than the balls through the
    // corners reach (2 x 0.87 m): no cube reaches the other. At (0.9, 0.9, 0.9) m, 1.56 m apart,
    // the balls meet and the pair is found.
    const Quat turn(Eigen::AngleAxisd(std::atan(1.0), Vec3::UnitZ()));  // 45 degrees
    std::vector<Body> cubes = {box("a", Vec3::Constant(0.5), 1.0).rotated(turn),
                               box("b", Vec3::Constant(0.5), 1.0).rotated(turn)};
    const Aabb boxA = boundingBox(cubes[0]);
    const Vec3 reach = 2.0 * 0.5 * (boxA.max - boxA.min);  // the two boxes' half extents, summed (m)
    cubes[1].at(0.99 * reach);
    const Aabb boxB = boundingBox(cubes[1]);
    ASSERT_TRUE((boxA.max.array() >= boxB.min.array()).all());  // the bounding boxes overlap
    ASSERT_GT((cubes[1].position - cubes[0].position).norm(), 2.0 * Vec3::Constant(0.5).norm());
    BroadPhase broadPhase;
    EXPECT_TRUE(broadPhase.findPairs(cubes).empty());
    EXPECT_TRUE(bruteForcePairs(cubes).empty());
    cubes[1].at(Vec3::Constant(0.9));
    const std::vector<BodyPair> pair = {{0, 1}};
    EXPECT_EQ(broadPhase.findPairs(cubes), pair);
    EXPECT_EQ(bruteForcePairs(cubes), pair);
}

TEST(BroadPhase, MarginFindsBodiesAboutToTouch) {
    // Spheres of radius 0.5 m, 1.05 m apart (a gap of 5 cm): a margin of a tenth of the radius on
    // each grows the gap's two sides by 5 cm each, so they pair; a margin of 0.04 does not reach.
    std::vector<Body> bodies = {sphere("a", 0.5, 1.0).at({0, 0, 0}), sphere("b", 0.5, 1.0).at({1.05, 0, 0}),
                                plane("floor", Vec3::UnitY()).at({0, -0.54, 0})};
    BroadPhase broadPhase;
    const std::vector<BodyPair> near = {{0, 1}, {0, 2}, {1, 2}};
    EXPECT_EQ(broadPhase.findPairs(bodies, 0.1), near);
    EXPECT_TRUE(broadPhase.findPairs(bodies, 0.04).empty());
}

TEST(BroadPhase, TurnedBoxIsBoundedByItsCorners) {
    // Without a margin, the bounds of a turned box are exactly the smallest and largest coordinates
    // of its eight corners: nothing of the box sticks out, and no more is bounded than that.
    std::mt19937 random(7);
    const auto unit = [&random] { return static_cast<double>(random()) / 4294967296.0; };
    for (int i = 0; i < 200; ++i) {
        const Vec3 half(0.1 + unit(), 0.1 + unit(), 0.1 + unit());
        const Vec3 direction = Vec3(unit() - 0.5, unit() - 0.5, unit() - 0.5).normalized();
        const Body b = box("box", half, 1.0).at(Vec3(unit(), unit(), unit()) * 10.0)
                           .rotated(Quat(Eigen::AngleAxisd(6.3 * unit(), direction)));
        Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
        for (int k = 0; k < 8; ++k) {
            const Vec3 signs(k & 1 ? 1.0 : -1.0, k & 2 ? 1.0 : -1.0, k & 4 ? 1.0 : -1.0);
            const Vec3 corner = b.position + b.orientation * signs.cwiseProduct(half);
            lo = lo.cwiseMin(corner);
            hi = hi.cwiseMax(corner);
        }
        const Aabb bounds = boundingBox(b);
        // Coordinates of ~10 m round to ~2e-15 m.
        EXPECT_LE((bounds.min - lo).cwiseAbs().maxCoeff(), 1e-12) << "turn " << i;
        EXPECT_LE((bounds.max - hi).cwiseAbs().maxCoeff(), 1e-12) << "turn " << i;
    }
}

TEST(BroadPhase, EmptyAndSingleScenes) {
    BroadPhase broadPhase;
    EXPECT_TRUE(broadPhase.findPairs({}).empty());
    EXPECT_TRUE(broadPhase.findPairs({sphere("alone", 1.0, 1.0)}).empty());
}

}  // namespace
}  // namespace gpl
