// Worksheet 8's soft bodies (SoftBodies, soft_bodies.h): the meshes' counts and shapes, bad input,
// and the scenes and chains stepped with the reference kernels (solutions/).
#include "gpl/soft_bodies.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "allocation_counter.h"
#include "gpl/scenes.h"
#include "gpl/soft_constraints.h"
#include "gpl/soft_sweeps.h"

namespace gpl {
namespace {

// ---- Meshes ----------------------------------------------------------------------------------------

struct LinkCounts {
    int stretch = 0, shear = 0, bend = 0, other = 0;
};

LinkCounts countLinks(const SoftBodies& soft, std::size_t mesh) {
    LinkCounts n;
    const SoftMesh& m = soft.meshes[mesh];
    for (std::uint32_t k = m.firstLink; k < m.firstLink + m.linkCount; ++k) {
        switch (soft.links[k].kind) {
            case LinkKind::Stretch:
                ++n.stretch;
                break;
            case LinkKind::Shear:
                ++n.shear;
                break;
            case LinkKind::Bend:
                ++n.bend;
                break;
            default:
                ++n.other;
        }
    }
    return n;
}

TEST(SoftBodies, ClothCountsItsLinksAndTriangles) {
    for (const auto& [nx, ny] : {std::array<int, 2>{2, 2}, {5, 4}, {7, 3}, {30, 20}}) {
        SoftBodies soft;
        ClothSpec c;
        c.nx = nx;
        c.ny = ny;
        const std::size_t m = soft.addCloth(c);
        const LinkCounts n = countLinks(soft, m);
        const std::string grid = std::to_string(nx) + " x " + std::to_string(ny);
        EXPECT_EQ(soft.x.size(), static_cast<std::size_t>(nx * ny)) << grid;
        EXPECT_EQ(n.stretch, (nx - 1) * ny + nx * (ny - 1)) << grid;
        EXPECT_EQ(n.shear, 2 * (nx - 1) * (ny - 1)) << grid;
        // One bend link per inner edge of the grid: (nx - 1) edges in each of the ny - 2 inner rows,
        // (nx - 2) in each of the ny - 1 rows of cells.
        EXPECT_EQ(n.bend, (nx - 1) * (ny - 2) + (nx - 2) * (ny - 1)) << grid;
        EXPECT_EQ(n.other, 0) << grid;
        EXPECT_EQ(soft.meshes[m].triangles.size(), static_cast<std::size_t>(2 * (nx - 1) * (ny - 1))) << grid;
    }
}

TEST(SoftBodies, ClothLinksHoldTheGridsDistances) {
    SoftBodies soft;
    ClothSpec c;
    c.nx = 6;
    c.ny = 5;
    c.spacing = 0.1;
    c.u = Vec3(1.0, 0.0, 1.0).normalized();
    c.v = Vec3::UnitY();
    soft.addCloth(c);
    const double s = c.spacing;
    for (const DistanceLink& l : soft.links) {
        // Rounding of the grid's coordinates (a few ulps of the cloth's size, 5 spacings).
        const double tolerance = 1e-13 * s;
        EXPECT_NEAR(l.rest, (soft.x[l.i] - soft.x[l.j]).norm(), tolerance);
        if (l.kind == LinkKind::Stretch) {
            EXPECT_NEAR(l.rest, s, tolerance);
        } else if (l.kind == LinkKind::Shear) {
            EXPECT_NEAR(l.rest, std::sqrt(2.0) * s, tolerance);
        } else if (l.kind == LinkKind::Bend) {
            // With the diagonals alternating, the two triangles at an inner edge hold the corners on
            // either side of it straight across: two spacings apart.
            EXPECT_NEAR(l.rest, 2.0 * s, tolerance);
        }
    }
    // Each triangle is a half cell, counter-clockwise about u x v.
    const Vec3 normal = c.u.cross(c.v);
    for (const auto& t : soft.meshes[0].triangles) {
        const Vec3 n = (soft.x[t[1]] - soft.x[t[0]]).cross(soft.x[t[2]] - soft.x[t[0]]);
        EXPECT_NEAR(n.dot(normal), s * s, 1e-13 * s * s);  // rounding, as above
    }
}

// The signed volume the closed surface encloses (the divergence theorem), m^3.
double enclosedVolume(const SoftBodies& soft, const SoftMesh& mesh) {
    double v = 0.0;
    for (const auto& t : mesh.triangles) v += soft.x[t[0]].dot(soft.x[t[1]].cross(soft.x[t[2]])) / 6.0;
    return v;
}

double restVolume(const SoftBodies& soft, const SoftMesh& mesh) {
    double v = 0.0;
    for (std::uint32_t k = mesh.firstVolume; k < mesh.firstVolume + mesh.volumeCount; ++k) v += soft.volumes[k].rest;
    return v;
}

TEST(SoftBodies, SoftCubeFillsItsVolumeWithPositiveTetrahedra) {
    for (int cells : {1, 2, 4}) {
        const double side = 0.5;
        const Vec3 centre(0.3, 1.0, -0.2);
        SoftBodies soft;
        const TetMeshSpec spec = makeSoftCube("cube", centre, side, cells);
        EXPECT_EQ(spec.tets.size(), static_cast<std::size_t>(6 * cells * cells * cells));
        const std::size_t m = soft.addSoftBody(spec);
        const SoftMesh& mesh = soft.meshes[m];
        const std::string at = std::to_string(cells) + " cells";
        EXPECT_EQ(soft.x.size(), static_cast<std::size_t>((cells + 1) * (cells + 1) * (cells + 1))) << at;
        // Edges: the lattice's along the axes, one diagonal on every square face, one inside every cell.
        const int c = cells;
        EXPECT_EQ(mesh.linkCount, static_cast<std::uint32_t>(3 * c * (c + 1) * (c + 1) + 3 * c * c * (c + 1) + c * c * c)) << at;
        EXPECT_EQ(mesh.volumeCount, static_cast<std::uint32_t>(6 * c * c * c)) << at;
        // Rounding: the sum of 6 c^3 volumes, each to a few ulps.
        const double cube = side * side * side;
        EXPECT_NEAR(restVolume(soft, mesh), cube, 1e-12 * cube) << at;
        for (std::uint32_t k = mesh.firstVolume; k < mesh.firstVolume + mesh.volumeCount; ++k) {
            const TetVolume& t = soft.volumes[k];
            EXPECT_GT(tetrahedronVolume({soft.x[t.v[0]], soft.x[t.v[1]], soft.x[t.v[2]], soft.x[t.v[3]]}), 0.0) << at;
        }
        // The surface: two triangles per square of the six faces, facing out, enclosing the cube.
        EXPECT_EQ(mesh.triangles.size(), static_cast<std::size_t>(12 * c * c)) << at;
        for (const auto& t : mesh.triangles) {
            const Vec3 n = (soft.x[t[1]] - soft.x[t[0]]).cross(soft.x[t[2]] - soft.x[t[0]]);
            EXPECT_GT(n.dot((soft.x[t[0]] + soft.x[t[1]] + soft.x[t[2]]) / 3.0 - centre), 0.0) << at;
        }
        EXPECT_NEAR(enclosedVolume(soft, mesh), cube, 1e-12 * cube) << at;  // rounding, as above
        // The whole mass: density times volume.
        double mass = 0.0;
        for (double m_i : soft.mass) mass += m_i;
        EXPECT_NEAR(mass, spec.density * cube, 1e-12 * mass) << at;  // rounding, as above
    }
}

TEST(SoftBodies, SoftBallIsClosedAndPositiveAndNearlyRound) {
    const double radius = 0.4;
    const Vec3 centre(0.0, 1.0, 0.0);
    SoftBodies soft;
    const std::size_t m = soft.addSoftBody(makeSoftBall("ball", centre, radius, 6));
    const SoftMesh& mesh = soft.meshes[m];
    for (std::uint32_t k = mesh.firstVolume; k < mesh.firstVolume + mesh.volumeCount; ++k) EXPECT_GT(soft.volumes[k].rest, 0.0);
    // Closed and outward: the surface encloses exactly the tetrahedra's volume (rounding of a sum of
    // a few hundred volumes).
    const double volume = restVolume(soft, mesh);
    EXPECT_NEAR(enclosedVolume(soft, mesh), volume, 1e-12 * volume);
    // A lattice of 6 cells cut to a ball and its surface moved out onto the sphere: within 10 % of
    // the ball's volume (the flat triangles between points on the sphere cut the caps away).
    const double ball = 4.0 / 3.0 * M_PI * radius * radius * radius;
    EXPECT_NEAR(volume, ball, 0.1 * ball);
    // On the sphere or inside it, to the rounding of a point moved onto it.
    for (const Vec3& q : soft.x) EXPECT_LE((q - centre).norm(), radius * (1.0 + 1e-12));
}

// ---- Bad input ---------------------------------------------------------------------------------------

// The call throws std::invalid_argument with one line naming the mesh.
template <class Add>
void expectRejected(Add add, const std::string& name, const std::string& what) {
    try {
        add();
        ADD_FAILURE() << what << ": no exception";
    } catch (const std::invalid_argument& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("'" + name + "'"), std::string::npos) << what << ": " << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << what << ": " << message;
    }
}

TEST(SoftBodies, BadClothIsRejectedNamingIt) {
    const auto cloth = [](auto change) {
        ClothSpec c;
        c.name = "sheet";
        c.nx = 4;
        c.ny = 3;
        change(c);
        return c;
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const std::vector<std::pair<std::string, ClothSpec>> bad = {
        {"nx 1", cloth([](ClothSpec& c) { c.nx = 1; })},
        {"ny 0", cloth([](ClothSpec& c) { c.ny = 0; })},
        {"spacing 0", cloth([](ClothSpec& c) { c.spacing = 0.0; })},
        {"spacing nan", cloth([&](ClothSpec& c) { c.spacing = nan; })},
        {"mass -1", cloth([](ClothSpec& c) { c.mass = -1.0; })},
        {"radius 0", cloth([](ClothSpec& c) { c.radius = 0.0; })},
        {"stretch compliance < 0", cloth([](ClothSpec& c) { c.stretchCompliance = -1e-6; })},
        {"shear compliance < 0", cloth([](ClothSpec& c) { c.shearCompliance = -1.0; })},
        {"bend compliance nan", cloth([&](ClothSpec& c) { c.bendCompliance = nan; })},
        {"stiffness 1.5", cloth([](ClothSpec& c) { c.stiffness = 1.5; })},
        {"stiffness -0.1", cloth([](ClothSpec& c) { c.stiffness = -0.1; })},
        {"pinned cell out of range", cloth([](ClothSpec& c) { c.pinned = {{0, 0}, {4, 0}}; })},
        {"pinned cell negative", cloth([](ClothSpec& c) { c.pinned = {{0, -1}}; })},
        {"u not unit", cloth([](ClothSpec& c) { c.u = Vec3(2.0, 0.0, 0.0); })},
        {"u along v", cloth([](ClothSpec& c) { c.v = c.u; })},
    };
    for (const auto& [what, spec] : bad) {
        SoftBodies soft;
        expectRejected([&, &spec = spec] { soft.addCloth(spec); }, "sheet", what);
        EXPECT_TRUE(soft.empty()) << what << ": nothing is added";
    }
    SoftBodies soft;
    soft.addCloth(cloth([](ClothSpec&) {}));
    expectRejected([&] { soft.addCloth(cloth([](ClothSpec&) {})); }, "sheet", "the name used twice");
}

TEST(SoftBodies, BadRopeIsRejectedNamingIt) {
    const auto rope = [](auto change) {
        RopeSpec r;
        r.name = "line";
        change(r);
        return r;
    };
    const std::vector<std::pair<std::string, RopeSpec>> bad = {
        {"segments 0", rope([](RopeSpec& r) { r.segments = 0; })},
        {"mass 0", rope([](RopeSpec& r) { r.mass = 0.0; })},
        {"radius -1", rope([](RopeSpec& r) { r.radius = -1.0; })},
        {"compliance < 0", rope([](RopeSpec& r) { r.compliance = -1e-9; })},
        {"stiffness 2", rope([](RopeSpec& r) { r.stiffness = 2.0; })},
        {"no length", rope([](RopeSpec& r) { r.end = r.start; })},
    };
    for (const auto& [what, spec] : bad) {
        SoftBodies soft;
        expectRejected([&, &spec = spec] { soft.addRope(spec); }, "line", what);
    }
}

TEST(SoftBodies, BadSoftBodyIsRejectedNamingIt) {
    const auto body = [](auto change) {
        TetMeshSpec s;
        s.name = "jelly";
        s.positions = {Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
        s.tets = {{0, 1, 2, 3}};
        change(s);
        return s;
    };
    const std::vector<std::pair<std::string, TetMeshSpec>> bad = {
        {"corner index out of range", body([](TetMeshSpec& s) { s.tets = {{0, 1, 2, 4}}; })},
        {"corner index negative", body([](TetMeshSpec& s) { s.tets = {{0, 1, -1, 3}}; })},
        {"negative volume", body([](TetMeshSpec& s) { s.tets = {{0, 2, 1, 3}}; })},
        {"zero volume", body([](TetMeshSpec& s) { s.positions[3] = Vec3(0.5, 0.5, 0.0); })},
        {"edge compliance < 0", body([](TetMeshSpec& s) { s.edgeCompliance = -1.0; })},
        {"volume compliance < 0", body([](TetMeshSpec& s) { s.volumeCompliance = -1.0; })},
        {"density 0", body([](TetMeshSpec& s) { s.density = 0.0; })},
        {"radius 0", body([](TetMeshSpec& s) { s.radius = 0.0; })},
        {"stiffness > 1", body([](TetMeshSpec& s) { s.stiffness = 1.01; })},
        {"a position in no tet", body([](TetMeshSpec& s) { s.positions.push_back(Vec3::Ones()); })},
        {"no tets", body([](TetMeshSpec& s) { s.tets.clear(); })},
    };
    for (const auto& [what, spec] : bad) {
        SoftBodies soft;
        expectRejected([&, &spec = spec] { soft.addSoftBody(spec); }, "jelly", what);
    }
    expectRejected([] { makeSoftCube("cube", Vec3::Zero(), 1.0, 0); }, "cube", "a cube of no cells");
    expectRejected([] { makeSoftBall("ball", Vec3::Zero(), 1.0, 1); }, "ball", "a ball of one cell");
}

// One sweep of XPBD projections (pairs of masses 1 and 2 kg) over the links in `sequence`, from `start`.
std::vector<Vec3> swept(const std::vector<Vec3>& start, const std::vector<DistanceLink>& links,
                        const std::vector<std::uint32_t>& sequence) {
    std::vector<Vec3> q = start;
    for (std::uint32_t k : sequence) {
        const DistanceLink& l = links[k];
        const DistanceCorrection c = solveDistanceConstraint(q[l.i], q[l.j], 1.0, 2.0, l.rest, 1e-4, 0.01, 0.0);
        q[l.i] += c.dx1;
        q[l.j] += c.dx2;
    }
    return q;
}

// The same sweep over the links in the order they were built.
std::vector<Vec3> sweptInBuiltOrder(const std::vector<Vec3>& start, const std::vector<DistanceLink>& links) {
    std::vector<std::uint32_t> inBuiltOrder(links.size());
    for (std::size_t k = 0; k < links.size(); ++k) inBuiltOrder[k] = static_cast<std::uint32_t>(k);
    return swept(start, links, inBuiltOrder);
}

TEST(SoftBodies, SweepOrderKeepsTheOrderOfLinksThatShareAParticle) {
    // Random links among 40 particles (some pairs twice): stored in sweep order, a sweep of
    // projections ends where the sweep in the built order does, to the bit.
    std::mt19937 random(8);
    std::uniform_int_distribution<std::uint32_t> particle(0, 39);
    std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
    std::vector<DistanceLink> built;
    while (built.size() < 300) {
        DistanceLink l;
        l.i = particle(random);
        l.j = particle(random);
        if (l.i == l.j) continue;
        l.rest = 0.5;
        built.push_back(l);
    }
    const std::vector<std::uint32_t> order = sweepOrder(built, 40);
    ASSERT_EQ(order.size(), built.size());
    std::vector<std::size_t> place(built.size(), built.size());
    for (std::size_t k = 0; k < order.size(); ++k) place.at(order[k]) = k;
    for (std::size_t a = 0; a < built.size(); ++a) {
        ASSERT_LT(place[a], built.size()) << "link " << a << " is not stored";
        for (std::size_t b = a + 1; b < built.size(); ++b) {
            const bool share = built[a].i == built[b].i || built[a].i == built[b].j || built[a].j == built[b].i ||
                               built[a].j == built[b].j;
            if (share) {
                EXPECT_LT(place[a], place[b]) << "links " << a << " and " << b;
            }
        }
    }
    std::vector<Vec3> start(40);
    for (Vec3& q : start) q = Vec3(coordinate(random), coordinate(random), coordinate(random));
    const std::vector<Vec3> expected = sweptInBuiltOrder(start, built), got = swept(start, built, order);
    EXPECT_EQ(std::memcmp(expected.data(), got.data(), expected.size() * sizeof(Vec3)), 0);
}

TEST(SoftBodies, ClothLinksAreStoredInSweepOrder) {
    // Stored in sweep order already (sorting them again changes nothing), a grid's consecutive links
    // share no particle but where a wave of a few links ends: one projection need not wait for the last.
    // (A cloth this size has fewer than kHalvesFrom links: it is not cut in halves.)
    SoftBodies soft;
    ClothSpec c;
    c.nx = c.ny = 24;
    soft.addCloth(c);
    ASSERT_LT(soft.links.size(), kHalvesFrom);
    ASSERT_EQ(soft.meshes[0].firstHalfLinks, 0u);
    const std::vector<std::uint32_t> order = sweepOrder(soft.links, soft.x.size());
    for (std::size_t k = 0; k < order.size(); ++k) ASSERT_EQ(order[k], k) << "link " << k;
    std::size_t sharing = 0;
    for (std::size_t k = 1; k < soft.links.size(); ++k) {
        const DistanceLink& a = soft.links[k - 1];
        const DistanceLink& b = soft.links[k];
        sharing += a.i == b.i || a.i == b.j || a.j == b.i || a.j == b.j;
    }
    // Built row by row, every stretch, shear and bend link of a row followed one that shared a particle.
    EXPECT_LT(sharing, soft.links.size() / 100);
}

TEST(SoftBodies, HalvesOrderGivesTheSweepOrdersResultWithHalvesThatShareNoParticle) {
    // Random links between nearby particles of a chain of 3000 (some pairs twice), enough to be cut:
    // the first half's links (both particles before the cut), then the second half's (both after),
    // then the rest; links that share a particle keep their sweep order, so a sweep of projections
    // in the stored order ends where the sweep in the built order does, to the bit.
    constexpr std::uint32_t n = 3000, cut = n / 2;
    std::mt19937 random(9);
    std::uniform_int_distribution<std::uint32_t> particle(0, n - 1), near(1, 6);
    std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
    std::vector<DistanceLink> built;
    while (built.size() < 2 * kHalvesFrom) {
        DistanceLink l;
        l.i = particle(random);
        l.j = l.i + near(random);
        if (l.j >= n) continue;
        if (built.size() % 2 == 0) std::swap(l.i, l.j);
        l.rest = 0.5;
        built.push_back(l);
    }
    const HalvesOrder halves = halvesOrder(built, cut, n);
    ASSERT_EQ(halves.order.size(), built.size());
    // Most links lie in a half: the halves are worth a thread each.
    EXPECT_GT(halves.first, built.size() / 4);
    EXPECT_GT(halves.second, built.size() / 4);
    const std::vector<std::uint32_t> sweep = sweepOrder(built, n);
    std::vector<std::size_t> place(built.size(), built.size()), wave(built.size());
    for (std::size_t k = 0; k < halves.order.size(); ++k) place.at(halves.order[k]) = k;
    for (std::size_t k = 0; k < sweep.size(); ++k) wave[sweep[k]] = k;
    for (std::size_t k = 0; k < halves.order.size(); ++k) {
        const DistanceLink& l = built[halves.order[k]];
        if (k < halves.first) {
            EXPECT_TRUE(l.i < cut && l.j < cut) << "stored link " << k;
        } else if (k < halves.first + halves.second) {
            EXPECT_TRUE(l.i >= cut && l.j >= cut) << "stored link " << k;
        }
    }
    std::vector<std::vector<std::uint32_t>> byParticle(n);
    for (std::uint32_t k = 0; k < built.size(); ++k) {
        ASSERT_LT(place[k], built.size()) << "link " << k << " is not stored";
        byParticle[built[k].i].push_back(k);
        byParticle[built[k].j].push_back(k);
    }
    for (const auto& sharing : byParticle) {
        for (std::size_t a = 0; a < sharing.size(); ++a) {
            for (std::size_t b = a + 1; b < sharing.size(); ++b) {
                EXPECT_EQ(wave[sharing[a]] < wave[sharing[b]], place[sharing[a]] < place[sharing[b]])
                    << "links " << sharing[a] << " and " << sharing[b];
            }
        }
    }
    std::vector<Vec3> start(n);
    for (Vec3& q : start) q = Vec3(coordinate(random), coordinate(random), coordinate(random));
    const std::vector<Vec3> expected = sweptInBuiltOrder(start, built), got = swept(start, built, halves.order);
    EXPECT_EQ(std::memcmp(expected.data(), got.data(), expected.size() * sizeof(Vec3)), 0);
}

namespace {

/// Soft bodies that hold one cloth of n x n particles, as ClothSpec builds it by default.
SoftBodies squareCloth(int n) {
    SoftBodies soft;
    ClothSpec c;
    c.nx = c.ny = n;
    soft.addCloth(c);
    return soft;
}

}  // namespace

TEST(SoftBodies, LargeClothIsCutInHalvesOfNearlyEqualWork) {
    // Built from both edges towards the middle row, the two halves wait alike for the links across
    // it: each holds close to half of the links (a thread's share), the rest a few per cent.
    for (const int n : {40, 64, 128}) {
        const SoftBodies soft = squareCloth(n);
        const SoftMesh& mesh = soft.meshes[0];
        const double links = mesh.linkCount;
        EXPECT_GT(mesh.firstHalfLinks / links, 0.45) << n;
        EXPECT_GT(mesh.secondHalfLinks / links, 0.45) << n;
        const std::uint32_t cut = mesh.first + mesh.count / 2;
        for (std::uint32_t k = 0; k < mesh.firstHalfLinks + mesh.secondHalfLinks; ++k) {
            const DistanceLink& l = soft.links[mesh.firstLink + k];
            const bool first = k < mesh.firstHalfLinks;
            ASSERT_EQ(l.i < cut, first) << n << ": link " << k;
            ASSERT_EQ(l.j < cut, first) << n << ": link " << k;
        }
    }
}

TEST(SoftBodies, LargeClothsHalvesHoldBackTheLinksThatWaitForTheRest) {
    // Each half's links that do not wait for the rest come first and move no particle that the rest
    // moves: on two threads they are swept while the rest of the sweep before is. The waiting ones
    // are few.
    for (const int n : {40, 64, 128}) {
        const SoftBodies soft = squareCloth(n);
        const SoftMesh& mesh = soft.meshes[0];
        std::vector<char> movedByRest(soft.x.size(), 0);
        for (std::uint32_t k = mesh.firstLink + mesh.firstHalfLinks + mesh.secondHalfLinks;
             k < mesh.firstLink + mesh.linkCount; ++k)
            movedByRest[soft.links[k].i] = movedByRest[soft.links[k].j] = 1;
        for (int half = 0; half < 2; ++half) {
            const std::uint32_t begin = mesh.firstLink + (half == 0 ? 0 : mesh.firstHalfLinks);
            const std::uint32_t count = half == 0 ? mesh.firstHalfLinks : mesh.secondHalfLinks;
            const std::uint32_t waiting = half == 0 ? mesh.firstHalfWaiting : mesh.secondHalfWaiting;
            EXPECT_GT(waiting, 0u) << n;
            EXPECT_LT(waiting, count / 4) << n;
            for (std::uint32_t k = begin; k < begin + count - waiting; ++k) {
                const DistanceLink& l = soft.links[k];
                ASSERT_FALSE(movedByRest[l.i] || movedByRest[l.j]) << n << ": link " << k;
            }
        }
    }
}

// ---- Stepping ----------------------------------------------------------------------------------------

TEST(SoftBodies, LargeClothSweptInHalvesOnTwoThreadsGivesTheSameStateAsOnOne) {
    // A cloth of 48 x 48 particles (about 13000 links, cut in halves) dropped on a sphere and a box,
    // XPBD and PBD: two threads sweep the halves at once, one thread all links in the stored order;
    // positions, velocities and multipliers end the same to the bit.
    for (const SoftMethod method : {SoftMethod::XPBD, SoftMethod::PBD}) {
        const std::vector<Body> bodies{sphere("ball", 0.5, 1.0).makeStatic().rough(0.5, 0.5),
                                       box("box", Vec3(0.3, 0.3, 0.3), 1.0).at(Vec3(0.6, 0.3, 0.0)).makeStatic()};
        const auto run = [&](int threads) {
            SoftBodies soft;
            soft.setThreads(threads);
            ClothSpec c;
            c.nx = c.ny = 48;
            c.spacing = 2.0 / 47;
            c.origin = Vec3(-1.0, 0.6, -1.0);
            c.method = method;
            c.stiffness = 0.8;
            c.stretchCompliance = 1e-6;
            soft.addCloth(c);
            EXPECT_GT(soft.meshes[0].firstHalfLinks, 0u);
            for (int step = 0; step < 60; ++step) {
                soft.predict(1.0 / 60.0, Vec3(0.0, -9.81, 0.0), step / 60.0);
                soft.findContacts(bodies, 1.0 / 60.0);
                soft.project(1.0 / 60.0, 10, bodies);
                soft.updateVelocities(1.0 / 60.0);
            }
            return soft;
        };
        const SoftBodies one = run(1), two = run(2);
        EXPECT_FALSE(one.contacts.empty());  // it lies on the bodies
        ASSERT_EQ(one.x.size(), two.x.size());
        EXPECT_EQ(std::memcmp(one.x.data(), two.x.data(), one.x.size() * sizeof(Vec3)), 0);
        EXPECT_EQ(std::memcmp(one.v.data(), two.v.data(), one.v.size() * sizeof(Vec3)), 0);
        for (std::size_t k = 0; k < one.links.size(); ++k) ASSERT_EQ(one.links[k].lambda, two.links[k].lambda) << k;
    }
}

TEST(SoftBodies, ThreadsAreOneOrTwo) {
    SoftBodies soft;
    EXPECT_THROW(soft.setThreads(0), std::invalid_argument);
    soft.setThreads(1);
    EXPECT_EQ(soft.threads(), 1);
    soft.setThreads(4);
    EXPECT_EQ(soft.threads(), 2);
}

TEST(SoftBodies, StagesAreNamedInStepOrder) {
    EXPECT_STREQ(stageName(Stage::SoftPredict), "predict");
    EXPECT_STREQ(stageName(Stage::SoftContacts), "soft contacts");
    EXPECT_STREQ(stageName(Stage::SoftProject), "project");
    EXPECT_STREQ(stageName(Stage::SoftVelocities), "soft velocities");
    EXPECT_LT(Stage::SoftPredict, Stage::SoftContacts);
    EXPECT_LT(Stage::SoftContacts, Stage::SoftProject);
    EXPECT_LT(Stage::SoftProject, Stage::SoftVelocities);
}

const std::vector<std::string> kWorksheet8Scenes = {"flag",      "cloth-on-sphere", "cloth-on-table",      "soft-cube",
                                                    "soft-ball", "rope-pbd-xpbd",   "cloth-stretchy-stiff"};

TEST(SoftBodies, ScenesLoadWithTheSoftStagesAndParticles) {
    for (const std::string& name : kWorksheet8Scenes) {
        const Scene& scene = scenes().find(name);
        EXPECT_EQ(scene.worksheet, 8) << name;
        EXPECT_TRUE(scene.key.empty()) << name;
        EXPECT_FALSE(scene.description.empty()) << name;
        PhysicsEngine e;
        load(e, scene);
        EXPECT_FALSE(e.softBodies().empty()) << name;
        for (Stage s : {Stage::SoftPredict, Stage::SoftContacts, Stage::SoftProject, Stage::SoftVelocities})
            EXPECT_TRUE(e.requiredStages().contains(s)) << name << ": " << stageName(s);
        // Loading another scene leaves none of its particles behind.
        load(e, scenes().find("falling-sphere"));
        EXPECT_TRUE(e.softBodies().empty()) << name;
    }
}

TEST(SoftBodies, PinnedParticlesNeverMove) {
    for (const std::string name : {"flag", "rope-pbd-xpbd", "cloth-stretchy-stiff"}) {
        PhysicsEngine e;
        load(e, scenes().find(name));
        const SoftBodies& soft = e.softBodies();
        std::vector<std::pair<std::size_t, Vec3>> pinned;
        for (std::size_t i = 0; i < soft.x.size(); ++i)
            if (soft.w[i] == 0.0) pinned.emplace_back(i, soft.x[i]);
        ASSERT_FALSE(pinned.empty()) << name;
        for (int step = 0; step < 1000; ++step) {  // 5 s
            e.step();
            for (const auto& [i, start] : pinned) {
                ASSERT_EQ(soft.x[i], start) << name << ": particle " << i << " at step " << e.stepCount();
                ASSERT_EQ(soft.v[i], Vec3::Zero()) << name << ": particle " << i << " at step " << e.stepCount();
            }
        }
    }
}

TEST(SoftBodies, NoParticleEndsAStepInsideABody) {
    // The ball, the table's box and the floor: every step, no particle's sphere lies deeper in a body
    // than a millionth of its radius (what the framework counts as touching). The sweeps end with
    // every contact pushed out, friction moving a particle only along the plane of its last push,
    // and a particle that the constraints pulled into a body that was not expected near it pushed
    // out after the sweeps: what is left is the rounding of a push.
    for (const std::string name : {"cloth-on-sphere", "cloth-on-table", "soft-cube", "soft-ball"}) {
        PhysicsEngine e;
        load(e, scenes().find(name));
        const SoftBodies& soft = e.softBodies();
        const double radius = soft.meshes[0].radius;
        double deepest = 0.0;
        std::size_t contacts = 0;
        for (int step = 0; step < 800; ++step) {  // 4 s: the fall, the landing and the settling
            e.step();
            deepest = std::max(deepest, soft.deepestPenetration(e.bodies()));
            for (const ParticleContact& c : soft.contacts) contacts += c.pushed;
        }
        EXPECT_LE(deepest, 1e-6 * radius) << name;
        EXPECT_GT(contacts, 0u) << name << ": the bodies pushed particles";
    }
}

TEST(SoftBodies, FrictionHoldsClothOnAnInclineBelowAtanMuAndSlowsItAsCoulombSaysAbove) {
    // A 3 x 3 cloth lying on a plane tilted by theta, mu_s = 0.6 and mu_d = 0.4: below atan mu_s
    // (31 degrees) it stays where it is; above, it slides down with a = g (sin theta - mu_d cos theta).
    // Each step the plane pushes the cloth out by g cos theta h^2 and friction answers the slide.
    const double g = 9.81, h = 0.01, muS = 0.6, muD = 0.4;
    for (const double degrees : {25.0, 40.0}) {
        const double theta = degrees * EIGEN_PI / 180.0;
        const Vec3 normal(std::sin(theta), std::cos(theta), 0.0);  // the plane falls towards +x
        const Vec3 down(std::cos(theta), -std::sin(theta), 0.0);   // along it, downhill
        const std::vector<Body> bodies{plane("incline", normal).rough(muS, muD)};
        SoftBodies soft;
        ClothSpec c;
        c.nx = c.ny = 3;
        c.spacing = 0.1;
        c.radius = 0.01;
        c.u = down;
        c.v = Vec3::UnitZ();
        c.origin = c.radius * normal;  // resting on the plane
        soft.addCloth(c);
        const std::vector<Vec3> start = soft.x;
        const int steps = 100;  // 1 s
        for (int s = 0; s < steps; ++s) {
            soft.predict(h, Vec3(0.0, -g, 0.0), s * h);
            soft.findContacts(bodies, h);
            soft.project(h, 10, bodies);
            soft.updateVelocities(h);
        }
        const double a = g * (std::sin(theta) - muD * std::cos(theta));
        for (std::size_t i = 0; i < soft.x.size(); ++i) {
            if (std::tan(theta) < muS) {
                // Held: each step's slide undone, to the rounding of the cloth's coordinates.
                EXPECT_LT((soft.x[i] - start[i]).norm(), 1e-12) << degrees << " degrees, particle " << i;
            } else {
                // Each step adds (g sin theta - mu_d g cos theta) h to the speed along the plane:
                // after 1 s, a t exactly, to rounding.
                EXPECT_NEAR(soft.v[i].dot(down), a * steps * h, 1e-9 * a) << degrees << " degrees, particle " << i;
                EXPECT_NEAR(soft.v[i].dot(normal), 0.0, 1e-9 * a) << degrees << " degrees, particle " << i;
            }
        }
    }
}

// The scene stepped 20 s: it stays finite and ends with no more energy than it started with.
void expectFiniteWithoutEnergyGain(const std::string& name) {
    PhysicsEngine e;
    load(e, scenes().find(name));
    // The flag's wind does work on it: here it flies in still air (its wind is tested below).
    if (name == "flag") e.softBodies().setWind(Vec3::Zero(), 0.0);
    const double start = e.totalEnergy();
    const auto steps = static_cast<int>(std::lround(20.0 / e.timeStep()));
    for (int step = 0; step < steps; ++step) ASSERT_NO_THROW(e.step()) << name << " at step " << step + 1;
    EXPECT_TRUE(e.allFinite()) << name;
    EXPECT_LE(e.totalEnergy(), start) << name;
}

// One test per scene, so that ctest runs them side by side.
TEST(SoftScenes, FlagStaysFiniteAndGainsNoEnergyOverTwentySeconds) { expectFiniteWithoutEnergyGain("flag"); }
TEST(SoftScenes, ClothOnSphereStaysFiniteAndGainsNoEnergyOverTwentySeconds) {
    expectFiniteWithoutEnergyGain("cloth-on-sphere");
}
TEST(SoftScenes, ClothOnTableStaysFiniteAndGainsNoEnergyOverTwentySeconds) {
    expectFiniteWithoutEnergyGain("cloth-on-table");
}
TEST(SoftScenes, SoftCubeStaysFiniteAndGainsNoEnergyOverTwentySeconds) { expectFiniteWithoutEnergyGain("soft-cube"); }
TEST(SoftScenes, SoftBallStaysFiniteAndGainsNoEnergyOverTwentySeconds) { expectFiniteWithoutEnergyGain("soft-ball"); }
TEST(SoftScenes, RopePbdXpbdStaysFiniteAndGainsNoEnergyOverTwentySeconds) {
    expectFiniteWithoutEnergyGain("rope-pbd-xpbd");
}
TEST(SoftScenes, ClothStretchyStiffStaysFiniteAndGainsNoEnergyOverTwentySeconds) {
    expectFiniteWithoutEnergyGain("cloth-stretchy-stiff");
}

TEST(SoftScenes, EveryWorksheet8SceneStepsASecondFinite) {
    // The short run that the sanitizer build keeps of the twenty-second runs above.
    for (const std::string& name : kWorksheet8Scenes) {
        PhysicsEngine e;
        load(e, scenes().find(name));
        const auto steps = static_cast<int>(std::lround(1.0 / e.timeStep()));
        for (int step = 0; step < steps; ++step) ASSERT_NO_THROW(e.step()) << name << " at step " << step + 1;
        EXPECT_TRUE(e.allFinite()) << name;
    }
}

TEST(SoftScenes, EveryWorksheet8SceneIsStepped) {
    // The tests above name every scene of worksheet 8: a new scene needs one.
    std::vector<std::string> worksheet8;
    for (const Scene& scene : scenes().all())
        if (scene.worksheet == 8) worksheet8.push_back(scene.name);
    EXPECT_EQ(worksheet8, kWorksheet8Scenes);
}

TEST(SoftBodies, FlagFluttersInTheWindNoFasterThanTheGusts) {
    PhysicsEngine e;
    load(e, scenes().find("flag"));
    SoftBodies& soft = e.softBodies();
    const std::size_t flag = soft.meshIndex("flag");
    double mass = 0.0;
    for (double m : soft.mass) mass += m;
    // The drag pulls each triangle's velocity towards the wind's, whose gusts reach 1.25 times its
    // speed along it and 0.2 times across it: the flag as a whole moves no faster.
    const double gust = soft.wind().norm() * std::hypot(1.25, 0.2);
    double sidewaysLow = 0.0, sidewaysHigh = 0.0;  // m, the flag's reach across the wind in the last 10 s
    for (int step = 0; step < 4000; ++step) {  // 20 s
        ASSERT_NO_THROW(e.step()) << "step " << step + 1;
        ASSERT_LE(soft.kineticEnergy(), 0.5 * mass * gust * gust) << "step " << step + 1;
        if (step < 2000) continue;
        for (const Vec3& q : soft.x) {
            sidewaysLow = std::min(sidewaysLow, q.z());
            sidewaysHigh = std::max(sidewaysHigh, q.z());
        }
    }
    // It flies downwind (its far edge beyond 80 % of its length from the pole) and flutters across
    // the wind (by more than a tenth of its length), its cloth stretched by less than a tenth.
    const SoftMesh& m = soft.meshes[flag];
    double reach = 0.0;
    for (std::uint32_t i = m.first; i < m.first + m.count; ++i) reach = std::max(reach, soft.x[i].x());
    const double length = (soft.x0[m.first + m.nx - 1] - soft.x0[m.first]).norm();
    EXPECT_GT(reach, 0.8 * length);
    EXPECT_GT(sidewaysHigh - sidewaysLow, 0.1 * length);
    EXPECT_LT(soft.largestStretch(flag, LinkKind::Stretch), 0.1);
}

TEST(SoftBodies, StepsAllocateNothingOnceTheirBuffersHaveGrown) {
    // The contacts, the self-collision pairs and the hash keep their memory from step to step: after
    // the fall and the landing, a step allocates nothing.
    for (const std::string name : {"flag", "cloth-on-sphere", "soft-ball"}) {
        PhysicsEngine e;
        load(e, scenes().find(name));
        for (int step = 0; step < 400; ++step) e.step();  // 2 s
        const long before = allocations;
        for (int step = 0; step < 200; ++step) e.step();
        EXPECT_EQ(allocations, before) << name;
    }
}

TEST(SoftBodies, StateAndRestoreReplayStepsToTheBit) {
    for (const std::string name : {"flag", "cloth-on-sphere", "soft-ball"}) {
        PhysicsEngine e;
        load(e, scenes().find(name));
        for (int step = 0; step < 200; ++step) e.step();  // 1 s: in the wind, on the ball, on the floor
        const PhysicsEngine::State saved = e.state();
        for (int step = 0; step < 50; ++step) e.step();
        const std::vector<Vec3> x = e.softBodies().x, v = e.softBodies().v;
        e.restore(saved);
        for (int step = 0; step < 50; ++step) e.step();
        ASSERT_EQ(x.size(), e.softBodies().x.size());
        EXPECT_EQ(std::memcmp(x.data(), e.softBodies().x.data(), x.size() * sizeof(Vec3)), 0) << name;
        EXPECT_EQ(std::memcmp(v.data(), e.softBodies().v.data(), v.size() * sizeof(Vec3)), 0) << name;
    }
}

TEST(SoftBodies, NonFiniteParticleIsNamedWithItsMeshAndStep) {
    PhysicsEngine e;
    load(e, scenes().find("rope-pbd-xpbd"));
    SoftBodies& soft = e.softBodies();
    const SoftMesh& rope = soft.meshes[soft.meshIndex("rope-xpbd")];
    e.step();
    // The particle below the pinned end: what it spreads to lies below it, so it is named.
    soft.x[rope.first + 1] = Vec3(std::numeric_limits<double>::infinity(), 0.0, 0.0);
    try {
        e.step();
        FAIL() << "no exception";
    } catch (const SimulationError& error) {
        const std::string message = error.what();
        EXPECT_NE(message.find("particle 1 of 'rope-xpbd'"), std::string::npos) << message;
        EXPECT_NE(message.find("step 2"), std::string::npos) << message;
    }
}

// ---- Chains: XPBD's closed form, PBD's iteration count --------------------------------------------------

// A vertical chain of `segments` links of 0.1 m from a pinned top, 0.1 kg per particle, stepped
// by SoftBodies alone (no rigid bodies) with h = 10 ms.
struct HangingChain {
    SoftBodies soft;
    double h = 0.01;
    Vec3 g{0.0, -9.81, 0.0};
    int segments;
    double particleMass = 0.1;

    HangingChain(int n, SoftMethod method, double compliance, double stiffness) : segments(n) {
        RopeSpec r;
        r.segments = n;
        r.start = Vec3(0.0, 10.0, 0.0);
        r.end = r.start - Vec3(0.0, 0.1 * n, 0.0);
        r.mass = particleMass * (n + 1);
        r.method = method;
        r.compliance = compliance;
        r.stiffness = stiffness;
        soft.addRope(r);
    }
    void run(int steps, int iterations) {
        const std::vector<Body> none;
        for (int s = 0; s < steps; ++s) {
            soft.predict(h, g, s * h);
            soft.findContacts(none, h);
            soft.project(h, iterations, none);
            soft.updateVelocities(h);
        }
    }
    double length() const { return (soft.x.back() - soft.x.front()).norm(); }
};

TEST(SoftBodies, HangingXpbdChainReachesTheStaticStretches) {
    // Segment j from the top carries the weight of the n - j particles below it, T_j = (n - j) m g,
    // and at rest stretches by alpha T_j. The multipliers start at 0 each step, so the chain at rest
    // is the closed form once a step's sweeps converge: 20 sweeps and more for 10 segments (with
    // fewer, the sweeps from the top leave segment j at rest stretched by more, alpha (T_j + T_j+1)
    // with one sweep).
    const double alpha = 1e-3;  // m/N: the top segment of 10 stretches by 1 % of its length
    for (int iterations : {20, 100}) {
        HangingChain chain(10, SoftMethod::XPBD, alpha, 1.0);
        chain.run(3000, iterations);  // 30 s: the chain's bounce dies out
        for (int j = 0; j < chain.segments; ++j) {
            const DistanceLink& link = chain.soft.links[j];
            const double stretch = (chain.soft.x[link.j] - chain.soft.x[link.i]).norm() - link.rest;
            const double tension = (chain.segments - j) * chain.particleMass * 9.81;
            // Within 1 % of the closed form: what the chain's motion keeps at the end.
            EXPECT_NEAR(stretch, alpha * tension, 0.01 * alpha * tension)
                << "segment " << j << ", " << iterations << " iterations";
        }
    }
}

TEST(SoftBodies, PbdChainStretchesLessWithMoreIterations) {
    double previous = std::numeric_limits<double>::infinity();
    for (int iterations : {2, 8, 32}) {
        HangingChain chain(20, SoftMethod::PBD, 0.0, 0.5);
        chain.run(500, iterations);  // 5 s
        const double stretch = chain.length() / 2.0 - 1.0;  // the chain's rest length is 2 m
        EXPECT_GT(stretch, 0.0) << iterations << " iterations";
        EXPECT_LT(stretch, previous) << iterations << " iterations";
        previous = stretch;
    }
}

}  // namespace
}  // namespace gpl
