// Worksheet 8's large meshes on two threads (soft_sweeps.h): a cut mesh's halves' contacts go with
// their half's links, unless the rest's links or volumes or a self-collision pair move their
// particle; one thread and two end every step in the same state to the bit.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "gpl/soft_bodies.h"
#include "gpl/soft_sweeps.h"

namespace gpl {
namespace {

// Steps `soft` (set up on `threads`) with the four parts as the engine calls them; counts the steps
// that had self-collision pairs and contacts.
struct Stepped {
    int withSelfPairs = 0, withContacts = 0;
};
Stepped stepSoft(SoftBodies& soft, const std::vector<Body>& bodies, int steps) {
    Stepped s;
    const double h = 1.0 / 60.0;
    for (int step = 0; step < steps; ++step) {
        soft.predict(h, Vec3(0.0, -9.81, 0.0), step * h);
        soft.findContacts(bodies, h);
        s.withSelfPairs += !soft.selfPairs.empty();
        s.withContacts += !soft.contacts.empty();
        soft.project(h, 10, bodies);
        soft.updateVelocities(h);
    }
    return s;
}

void expectSameState(const SoftBodies& one, const SoftBodies& two) {
    ASSERT_EQ(one.x.size(), two.x.size());
    EXPECT_EQ(std::memcmp(one.x.data(), two.x.data(), one.x.size() * sizeof(Vec3)), 0);
    EXPECT_EQ(std::memcmp(one.v.data(), two.v.data(), one.v.size() * sizeof(Vec3)), 0);
    ASSERT_EQ(one.links.size(), two.links.size());
    for (std::size_t k = 0; k < one.links.size(); ++k) ASSERT_EQ(one.links[k].lambda, two.links[k].lambda) << k;
    ASSERT_EQ(one.volumes.size(), two.volumes.size());
    for (std::size_t k = 0; k < one.volumes.size(); ++k) ASSERT_EQ(one.volumes[k].lambda, two.volumes[k].lambda) << k;
}

TEST(SoftHalves, SelfCollidingClothOnTwoThreadsGivesTheSameStateAsOnOne) {
    // A soft cloth of 48 x 48 particles (cut in halves) dropped across a thin bar folds onto itself:
    // the contacts of particles in a self-collision pair wait for the pairs, the others go with their
    // half's links; positions, velocities and multipliers end the same to the bit.
    const std::vector<Body> bodies{box("bar", Vec3(1.5, 0.05, 0.05), 1.0).makeStatic().rough(0.2, 0.2),
                                   plane("floor", Vec3::UnitY()).at(Vec3(0.0, -1.0, 0.0))};
    const auto run = [&](int threads, Stepped& stepped) {
        SoftBodies soft;
        soft.setThreads(threads);
        ClothSpec c;
        c.nx = c.ny = 48;
        c.spacing = 1.6 / 47;
        c.origin = Vec3(-0.8, 0.2, -0.8);
        c.stretchCompliance = 1e-6;
        c.radius = 0.012;
        c.selfCollision = true;
        soft.addCloth(c);
        EXPECT_GT(soft.meshes[0].firstHalfLinks, 0u);
        stepped = stepSoft(soft, bodies, 60);
        return soft;
    };
    Stepped one, two;
    const SoftBodies a = run(1, one), b = run(2, two);
    EXPECT_GT(one.withSelfPairs, 10);  // it folds onto itself over the bar
    EXPECT_GT(one.withContacts, 10);
    EXPECT_EQ(one.withSelfPairs, two.withSelfPairs);
    expectSameState(a, b);
}

TEST(SoftHalves, LargeSoftBodyOnTwoThreadsGivesTheSameStateAsOnOne) {
    // A soft ball of over 4096 edges (cut in halves) dropped on a box and the floor: its volumes, all
    // of the rest, move every particle after the halves' links, so every contact waits for them; one
    // thread and two end the same to the bit.
    const std::vector<Body> bodies{box("block", Vec3(0.2, 0.2, 0.2), 1.0).at(Vec3(0.25, 0.2, 0.0)).makeStatic(),
                                   plane("floor", Vec3::UnitY()).rough(0.5, 0.5)};
    const auto run = [&](int threads) {
        SoftBodies soft;
        soft.setThreads(threads);
        soft.addSoftBody(makeSoftBall("ball", Vec3(0.0, 0.9, 0.0), 0.4, 10));
        EXPECT_GT(soft.meshes[0].firstHalfLinks, 0u);
        EXPECT_GT(soft.meshes[0].volumeCount, 0u);
        const Stepped stepped = stepSoft(soft, bodies, 60);
        EXPECT_GT(stepped.withContacts, 10);
        return soft;
    };
    expectSameState(run(1), run(2));
}

TEST(SoftHalves, OnlyTheRestsLinksAndVolumesMarkTheirParticles) {
    // A cut cloth: the particles the rest's links move are marked, and only they; a cloth too small to
    // be cut marks none.
    SoftBodies soft;
    ClothSpec big;
    big.nx = big.ny = 48;
    soft.addCloth(big);
    ClothSpec small;
    small.name = "small";
    small.nx = small.ny = 8;
    small.origin = Vec3(0.0, 2.0, 0.0);
    soft.addCloth(small);
    std::vector<char> moved(soft.x.size(), 0);
    for (const SoftMesh& mesh : soft.meshes) markMovedByTheRest(mesh, soft.links, soft.volumes, moved);
    const SoftMesh& cut = soft.meshes[0];
    std::vector<char> expected(soft.x.size(), 0);
    for (std::uint32_t k = cut.firstLink + cut.firstHalfLinks + cut.secondHalfLinks; k < cut.firstLink + cut.linkCount; ++k)
        expected[soft.links[k].i] = expected[soft.links[k].j] = 1;
    EXPECT_EQ(moved, expected);
    std::size_t marked = 0;
    for (const char m : moved) marked += m;
    EXPECT_GT(marked, 0u);
    EXPECT_LT(marked, cut.count / 4);  // a band across the middle rows
}

}  // namespace
}  // namespace gpl
