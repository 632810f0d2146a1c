// Worksheet 8's meshes: cloth grids, ropes and tetrahedral soft bodies become particles, links and
// volumes of SoftBodies (soft_bodies.h), each checked before anything steps. The step that moves them
// is in soft_bodies.cpp.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "gpl/soft_bodies.h"
#include "gpl/soft_constraints.h"
#include "gpl/soft_sweeps.h"

namespace gpl {
namespace {

// One line naming the mesh and the field: "cloth 'flag': nx must be at least 2, got 1".
[[noreturn]] void badMesh(const char* kind, const std::string& name, const std::string& what) {
    throw std::invalid_argument(std::string(kind) + " '" + name + "': " + what);
}

void requirePositiveField(const char* kind, const std::string& name, const char* field, double value) {
    if (!std::isfinite(value) || value <= 0.0)
        badMesh(kind, name, std::string(field) + " must be a positive finite number, got " + formatNumber(value));
}

void requireCompliance(const char* kind, const std::string& name, const char* field, double value) {
    if (!std::isfinite(value) || value < 0.0)
        badMesh(kind, name, std::string(field) + " must be a finite number >= 0, got " + formatNumber(value));
}

void requireStiffness(const char* kind, const std::string& name, double value) {
    if (!(value >= 0.0 && value <= 1.0))
        badMesh(kind, name, "stiffness must lie in [0, 1], got " + formatNumber(value));
}

void requireFinitePoint(const char* kind, const std::string& name, const char* field, const Vec3& q) {
    if (!isFinite(q)) badMesh(kind, name, std::string(field) + " must be finite");
}

// 0 .. count - 1 in order.
std::vector<int> inOrder(int count) {
    std::vector<int> out(count);
    for (int k = 0; k < count; ++k) out[k] = k;
    return out;
}

// 0 .. count - 1 from both ends towards the middle: 0, count - 1, 1, count - 2, ...
std::vector<int> fromBothEdges(int count) {
    std::vector<int> out;
    for (int low = 0, high = count - 1; low <= high; ++low, --high) {
        out.push_back(low);
        if (high != low) out.push_back(high);
    }
    return out;
}

DistanceLink linkBetween(const std::vector<Vec3>& x, std::uint32_t i, std::uint32_t j, LinkKind kind,
                         double compliance, double stiffness) {
    DistanceLink l;
    l.i = i;
    l.j = j;
    l.rest = (x[i] - x[j]).norm();
    l.compliance = compliance;
    l.stiffness = stiffness;
    l.kind = kind;
    return l;
}

// The six tetrahedra of a unit cube around its diagonal from corner 0 to corner 7 (Kuhn's split),
// corners numbered by bits: bit 0 x, bit 1 y, bit 2 z. Each walks from 0 to 7 along the axes in
// one of the six orders; the order of its corners is fixed afterwards so that its volume is positive.
// The lattice mirrors the split from cell to cell along each axis: a cell shares each face's
// diagonal with its neighbour (their split is the mirror image across that face), and the mesh has
// no preferred diagonal, so that a cube of an even number of cells is as symmetric as the cube.
constexpr int kKuhnTets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

// A lattice of n x n x n cubes of side `cell` from `low`, each cut into Kuhn's six tetrahedra.
void kuhnLattice(const Vec3& low, double cell, int n, std::vector<Vec3>& positions,
                 std::vector<std::array<int, 4>>& tets) {
    const auto vertex = [n](int i, int j, int k) { return (k * (n + 1) + j) * (n + 1) + i; };
    positions.clear();
    tets.clear();
    for (int k = 0; k <= n; ++k)
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) positions.push_back(low + cell * Vec3(i, j, k));
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                for (const auto& t : kKuhnTets) {
                    std::array<int, 4> tet{};
                    for (int c = 0; c < 4; ++c) {
                        const int corner = t[c] ^ (i & 1) ^ ((j & 1) << 1) ^ ((k & 1) << 2);  // mirrored
                        tet[c] = vertex(i + (corner & 1), j + ((corner >> 1) & 1), k + ((corner >> 2) & 1));
                    }
                    const std::array<Vec3, 4> corners{positions[tet[0]], positions[tet[1]], positions[tet[2]],
                                                      positions[tet[3]]};
                    if (tetrahedronVolume(corners) < 0.0) std::swap(tet[2], tet[3]);
                    tets.push_back(tet);
                }
}

double volumeOf(const std::vector<Vec3>& positions, const std::array<int, 4>& t) {
    return tetrahedronVolume({positions[t[0]], positions[t[1]], positions[t[2]], positions[t[3]]});
}

}  // namespace

TetMeshSpec makeSoftCube(const std::string& name, const Vec3& centre, double side, int cells) {
    if (cells < 1) badMesh("soft body", name, "cells must be at least 1, got " + std::to_string(cells));
    requirePositiveField("soft body", name, "side", side);
    TetMeshSpec spec;
    spec.name = name;
    kuhnLattice(centre - Vec3::Constant(0.5 * side), side / cells, cells, spec.positions, spec.tets);
    return spec;
}

TetMeshSpec makeSoftBall(const std::string& name, const Vec3& centre, double radius, int cells) {
    if (cells < 2) badMesh("soft body", name, "cells must be at least 2, got " + std::to_string(cells));
    requirePositiveField("soft body", name, "radius", radius);
    std::vector<Vec3> lattice;
    std::vector<std::array<int, 4>> latticeTets;
    kuhnLattice(centre - Vec3::Constant(radius), 2.0 * radius / cells, cells, lattice, latticeTets);

    // The tetrahedra whose centroid lies in the ball, and the lattice vertices they use, renumbered.
    TetMeshSpec spec;
    spec.name = name;
    std::vector<int> number(lattice.size(), -1);
    for (const auto& t : latticeTets) {
        const Vec3 centroid = 0.25 * (lattice[t[0]] + lattice[t[1]] + lattice[t[2]] + lattice[t[3]]);
        if ((centroid - centre).norm() >= radius) continue;
        std::array<int, 4> kept{};
        for (int c = 0; c < 4; ++c) {
            if (number[t[c]] < 0) {
                number[t[c]] = static_cast<int>(spec.positions.size());
                spec.positions.push_back(lattice[t[c]]);
            }
            kept[c] = number[t[c]];
        }
        spec.tets.push_back(kept);
    }

    // The surface's vertices: corners of faces no other tetrahedron shares.
    std::vector<std::array<int, 3>> faces;
    for (const auto& t : spec.tets) {
        for (const auto& f : {std::array<int, 3>{t[1], t[2], t[3]}, std::array<int, 3>{t[0], t[2], t[3]},
                              std::array<int, 3>{t[0], t[1], t[3]}, std::array<int, 3>{t[0], t[1], t[2]}}) {
            std::array<int, 3> sorted = f;
            std::sort(sorted.begin(), sorted.end());
            faces.push_back(sorted);
        }
    }
    std::sort(faces.begin(), faces.end());
    std::vector<char> onSurface(spec.positions.size(), 0);
    for (std::size_t f = 0; f < faces.size();) {
        std::size_t g = f + 1;
        while (g < faces.size() && faces[g] == faces[f]) ++g;
        if (g - f == 1)
            for (int c : faces[f]) onSurface[c] = 1;
        f = g;
    }

    // Each surface vertex out onto the sphere, unless one of its tetrahedra would keep less than a
    // tenth of its lattice volume.
    std::vector<std::vector<int>> tetsOf(spec.positions.size());
    for (std::size_t t = 0; t < spec.tets.size(); ++t)
        for (int c : spec.tets[t]) tetsOf[c].push_back(static_cast<int>(t));
    const double cell = 2.0 * radius / cells;
    const double smallest = 0.1 * cell * cell * cell / 6.0;  // m^3, a tenth of a Kuhn tetrahedron
    for (std::size_t i = 0; i < spec.positions.size(); ++i) {
        const Vec3 d = spec.positions[i] - centre;
        if (!onSurface[i] || d.norm() == 0.0) continue;
        const Vec3 before = spec.positions[i];
        spec.positions[i] = centre + radius * d.normalized();
        for (int t : tetsOf[i]) {
            if (volumeOf(spec.positions, spec.tets[t]) < smallest) {
                spec.positions[i] = before;
                break;
            }
        }
    }
    return spec;
}

std::size_t SoftBodies::meshIndex(const std::string& name) const {
    for (std::size_t m = 0; m < meshes.size(); ++m)
        if (meshes[m].name == name) return m;
    throw std::out_of_range("no soft mesh named '" + name + "'");
}

std::vector<std::uint32_t> sweepOrder(const std::vector<DistanceLink>& links, std::size_t particles) {
    // Each link's wave: the first after the waves of every earlier link that shares a particle with
    // it. A link's wave is then later than that of each earlier link it shares a particle with, and
    // the links of one wave share none.
    std::vector<std::uint32_t> nextWave(particles, 0);  // per particle: the wave after its last link's
    std::vector<std::uint32_t> wave(links.size());
    std::uint32_t waves = 0;
    for (std::size_t k = 0; k < links.size(); ++k) {
        const std::uint32_t i = links[k].i, j = links[k].j;
        wave[k] = std::max(nextWave[i], nextWave[j]);
        nextWave[i] = nextWave[j] = wave[k] + 1;
        waves = std::max(waves, wave[k] + 1);
    }
    // Wave after wave, each in the links' order (a counting sort).
    std::vector<std::uint32_t> start(waves + 1, 0);
    for (std::uint32_t w : wave) ++start[w + 1];
    for (std::uint32_t w = 0; w < waves; ++w) start[w + 1] += start[w];
    std::vector<std::uint32_t> order(links.size());
    for (std::size_t k = 0; k < links.size(); ++k) order[start[wave[k]]++] = static_cast<std::uint32_t>(k);
    return order;
}

std::size_t SoftBodies::addMesh(SoftMesh mesh) {
    // The mesh's links stored in sweep order (sweepOrder()), a large mesh's in two halves and a seam
    // (halvesOrder()): links that share a particle keep the order they were built in, but for the
    // seam's, which come after the halves'.
    const auto first = links.begin() + mesh.firstLink;
    const std::vector<DistanceLink> built(first, first + mesh.linkCount);
    const HalvesOrder stored = halvesOrder(built, halvesCut(mesh), x.size());
    for (std::size_t k = 0; k < stored.order.size(); ++k)
        first[static_cast<std::ptrdiff_t>(k)] = built[stored.order[k]];
    mesh.firstHalfLinks = stored.first;
    mesh.secondHalfLinks = stored.second;
    movedByRest_.resize(x.size(), 0);
    selfPaired_.resize(x.size(), 0);
    markMovedByTheRest(mesh, links, volumes, movedByRest_);
    holdBackWaitingLinks(mesh, links, movedByRest_);
    meshes.push_back(std::move(mesh));
    force_.resize(x.size(), Vec3::Zero());
    return meshes.size() - 1;
}

std::size_t SoftBodies::addCloth(const ClothSpec& spec) {
    const char* kind = "cloth";
    const std::string& name = spec.name;
    for (const SoftMesh& m : meshes)
        if (m.name == name) badMesh(kind, name, "the name is already used");
    if (spec.nx < 2 || spec.ny < 2)
        badMesh(kind, name, "nx and ny must be at least 2, got " + std::to_string(spec.nx) + " x " + std::to_string(spec.ny));
    requirePositiveField(kind, name, "spacing", spec.spacing);
    requirePositiveField(kind, name, "mass", spec.mass);
    requirePositiveField(kind, name, "radius", spec.radius);
    requireCompliance(kind, name, "stretchCompliance", spec.stretchCompliance);
    requireCompliance(kind, name, "shearCompliance", spec.shearCompliance);
    requireCompliance(kind, name, "bendCompliance", spec.bendCompliance);
    requireStiffness(kind, name, spec.stiffness);
    requireFinitePoint(kind, name, "origin", spec.origin);
    // Unit and perpendicular to rounding (a few ulps of the numbers a scene writes).
    if (!(std::abs(spec.u.norm() - 1.0) < 1e-9 && std::abs(spec.v.norm() - 1.0) < 1e-9 && std::abs(spec.u.dot(spec.v)) < 1e-9))
        badMesh(kind, name, "u and v must be unit vectors perpendicular to each other");
    for (const auto& cell : spec.pinned) {
        if (cell[0] < 0 || cell[0] >= spec.nx || cell[1] < 0 || cell[1] >= spec.ny)
            badMesh(kind, name, "pinned cell (" + std::to_string(cell[0]) + ", " + std::to_string(cell[1]) +
                                    ") lies outside the grid of " + std::to_string(spec.nx) + " x " + std::to_string(spec.ny));
    }

    SoftMesh mesh;
    mesh.name = name;
    mesh.kind = SoftMesh::Kind::Cloth;
    mesh.method = spec.method;
    mesh.first = static_cast<std::uint32_t>(x.size());
    mesh.count = static_cast<std::uint32_t>(spec.nx * spec.ny);
    mesh.radius = spec.radius;
    mesh.selfCollision = spec.selfCollision;
    mesh.nx = spec.nx;
    mesh.ny = spec.ny;
    const std::uint32_t first = mesh.first;
    const int nx = spec.nx, ny = spec.ny;
    const auto id = [first, nx](int i, int j) { return first + static_cast<std::uint32_t>(j * nx + i); };

    const double particleMass = spec.mass / (nx * ny);
    const std::size_t meshNumber = meshes.size();
    for (int j = 0; j < ny; ++j) {
        for (int i = 0; i < nx; ++i) {
            const Vec3 q = spec.origin + spec.spacing * (i * spec.u + j * spec.v);
            x.push_back(q);
            p.push_back(q);
            x0.push_back(q);
            v.push_back(Vec3::Zero());
            mass.push_back(particleMass);
            w.push_back(1.0 / particleMass);
            meshOf.push_back(static_cast<std::uint32_t>(meshNumber));
        }
    }
    for (const auto& cell : spec.pinned) w[id(cell[0], cell[1])] = 0.0;

    mesh.firstLink = static_cast<std::uint32_t>(links.size());
    const double k = spec.stiffness;
    // Stretch: the grid's edges.
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i + 1 < nx; ++i)
            links.push_back(linkBetween(x, id(i, j), id(i + 1, j), LinkKind::Stretch, spec.stretchCompliance, k));
    // Rows that link a row to the next, and rows of cells, top to bottom; a cloth large enough to be
    // cut in halves (soft_sweeps.h), from both edges towards the middle, so that both halves wait
    // alike for the links across the middle.
    const long linkCount = static_cast<long>(nx - 1) * ny + static_cast<long>(nx) * (ny - 1) +
                           2L * (nx - 1) * (ny - 1) + static_cast<long>(nx - 1) * (ny - 2) +
                           static_cast<long>(nx - 2) * (ny - 1);
    const bool halves = linkCount >= kHalvesFrom;
    const std::vector<int> rowPairs = halves ? fromBothEdges(ny - 1) : inOrder(ny - 1);
    for (const int j : rowPairs)
        for (int i = 0; i < nx; ++i)
            links.push_back(linkBetween(x, id(i, j), id(i, j + 1), LinkKind::Stretch, spec.stretchCompliance, k));
    // Shear: both diagonals of every cell.
    for (const int j : rowPairs) {
        for (int i = 0; i + 1 < nx; ++i) {
            links.push_back(linkBetween(x, id(i, j), id(i + 1, j + 1), LinkKind::Shear, spec.shearCompliance, k));
            links.push_back(linkBetween(x, id(i + 1, j), id(i, j + 1), LinkKind::Shear, spec.shearCompliance, k));
        }
    }
    // Triangles: two per cell, split along a diagonal that alternates like a checkerboard.
    for (int j = 0; j + 1 < ny; ++j) {
        for (int i = 0; i + 1 < nx; ++i) {
            const std::uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
            if ((i + j) % 2 == 0) {
                mesh.triangles.push_back({a, b, c});
                mesh.triangles.push_back({a, c, d});
            } else {
                mesh.triangles.push_back({a, b, d});
                mesh.triangles.push_back({b, c, d});
            }
        }
    }
    // Bend: across every inner edge of the grid, the corners opposite it in its two triangles.
    // Each triangle's edges with its opposite corner, sorted by edge: a shared edge lists two.
    struct EdgeOpposite {
        std::uint32_t a, b, opposite;
        bool operator<(const EdgeOpposite& o) const { return a != o.a ? a < o.a : b < o.b; }
    };
    std::vector<EdgeOpposite> edges;
    for (const auto& t : mesh.triangles) {
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t a = t[e], b = t[(e + 1) % 3];
            edges.push_back({std::min(a, b), std::max(a, b), t[(e + 2) % 3]});
        }
    }
    std::sort(edges.begin(), edges.end());
    const auto gridEdge = [&](std::uint32_t a, std::uint32_t b) {
        const int ia = static_cast<int>(a - first) % nx, ja = static_cast<int>(a - first) / nx;
        const int ib = static_cast<int>(b - first) % nx, jb = static_cast<int>(b - first) / nx;
        return ia == ib || ja == jb;  // not a cell's diagonal
    };
    // The inner edges by their (first) particle's row, in the order of the rows above.
    const std::vector<int> rows = halves ? fromBothEdges(ny) : inOrder(ny);
    std::vector<int> rank(ny);
    for (int r = 0; r < ny; ++r) rank[rows[r]] = r;
    const auto row = [&](const EdgeOpposite& e) { return rank[static_cast<int>(e.a - first) / nx]; };
    std::stable_sort(edges.begin(), edges.end(),
                     [&](const EdgeOpposite& l, const EdgeOpposite& r) { return row(l) < row(r); });
    for (std::size_t e = 0; e + 1 < edges.size(); ++e) {
        const EdgeOpposite& one = edges[e];
        const EdgeOpposite& other = edges[e + 1];
        if (one.a != other.a || one.b != other.b || !gridEdge(one.a, one.b)) continue;
        links.push_back(linkBetween(x, one.opposite, other.opposite, LinkKind::Bend, spec.bendCompliance, k));
    }
    mesh.linkCount = static_cast<std::uint32_t>(links.size()) - mesh.firstLink;
    mesh.firstVolume = static_cast<std::uint32_t>(volumes.size());
    return addMesh(std::move(mesh));
}

std::size_t SoftBodies::addRope(const RopeSpec& spec) {
    const char* kind = "rope";
    const std::string& name = spec.name;
    for (const SoftMesh& m : meshes)
        if (m.name == name) badMesh(kind, name, "the name is already used");
    if (spec.segments < 1) badMesh(kind, name, "segments must be at least 1, got " + std::to_string(spec.segments));
    requirePositiveField(kind, name, "mass", spec.mass);
    requirePositiveField(kind, name, "radius", spec.radius);
    requireCompliance(kind, name, "compliance", spec.compliance);
    requireStiffness(kind, name, spec.stiffness);
    requireFinitePoint(kind, name, "start", spec.start);
    requireFinitePoint(kind, name, "end", spec.end);
    if (spec.start == spec.end) badMesh(kind, name, "start and end must differ");

    SoftMesh mesh;
    mesh.name = name;
    mesh.kind = SoftMesh::Kind::Rope;
    mesh.method = spec.method;
    mesh.first = static_cast<std::uint32_t>(x.size());
    mesh.count = static_cast<std::uint32_t>(spec.segments + 1);
    mesh.radius = spec.radius;
    const double particleMass = spec.mass / (spec.segments + 1);
    const std::size_t meshNumber = meshes.size();
    for (int s = 0; s <= spec.segments; ++s) {
        const Vec3 q = spec.start + (spec.end - spec.start) * (static_cast<double>(s) / spec.segments);
        x.push_back(q);
        p.push_back(q);
        x0.push_back(q);
        v.push_back(Vec3::Zero());
        mass.push_back(particleMass);
        w.push_back(s == 0 && spec.pinStart ? 0.0 : 1.0 / particleMass);
        meshOf.push_back(static_cast<std::uint32_t>(meshNumber));
    }
    mesh.firstLink = static_cast<std::uint32_t>(links.size());
    for (int s = 0; s < spec.segments; ++s) {
        links.push_back(linkBetween(x, mesh.first + s, mesh.first + s + 1, LinkKind::Rope, spec.compliance,
                                    spec.stiffness));
    }
    mesh.linkCount = static_cast<std::uint32_t>(spec.segments);
    mesh.firstVolume = static_cast<std::uint32_t>(volumes.size());
    return addMesh(std::move(mesh));
}

std::size_t SoftBodies::addSoftBody(const TetMeshSpec& spec) {
    const char* kind = "soft body";
    const std::string& name = spec.name;
    for (const SoftMesh& m : meshes)
        if (m.name == name) badMesh(kind, name, "the name is already used");
    if (spec.positions.empty() || spec.tets.empty()) badMesh(kind, name, "positions and tets must not be empty");
    requirePositiveField(kind, name, "density", spec.density);
    requirePositiveField(kind, name, "radius", spec.radius);
    requireCompliance(kind, name, "edgeCompliance", spec.edgeCompliance);
    requireCompliance(kind, name, "volumeCompliance", spec.volumeCompliance);
    requireStiffness(kind, name, spec.stiffness);
    const int n = static_cast<int>(spec.positions.size());
    for (int i = 0; i < n; ++i) {
        if (!isFinite(spec.positions[i]))
            badMesh(kind, name, "position " + std::to_string(i) + " must be finite");
    }
    std::vector<double> particleMass(spec.positions.size(), 0.0);
    for (std::size_t t = 0; t < spec.tets.size(); ++t) {
        const auto& tet = spec.tets[t];
        for (int c : tet) {
            if (c < 0 || c >= n)
                badMesh(kind, name, "tet " + std::to_string(t) + " has corner index " + std::to_string(c) +
                                        ", outside the " + std::to_string(n) + " positions");
        }
        const double volume = volumeOf(spec.positions, tet);
        if (!(volume > 0.0))
            badMesh(kind, name, "tet " + std::to_string(t) + " has volume " + formatNumber(volume) +
                                    " m^3: it must be positive (order its corners as tetrahedronVolume() says)");
        for (int c : tet) particleMass[c] += 0.25 * spec.density * volume;
    }
    for (int i = 0; i < n; ++i) {
        if (particleMass[i] == 0.0)
            badMesh(kind, name, "position " + std::to_string(i) + " is the corner of no tet, so it has no mass");
    }

    SoftMesh mesh;
    mesh.name = name;
    mesh.kind = SoftMesh::Kind::SoftBody;
    mesh.method = spec.method;
    mesh.first = static_cast<std::uint32_t>(x.size());
    mesh.count = static_cast<std::uint32_t>(n);
    mesh.radius = spec.radius;
    const std::uint32_t first = mesh.first;
    const std::size_t meshNumber = meshes.size();
    for (int i = 0; i < n; ++i) {
        x.push_back(spec.positions[i]);
        p.push_back(spec.positions[i]);
        x0.push_back(spec.positions[i]);
        v.push_back(Vec3::Zero());
        mass.push_back(particleMass[i]);
        w.push_back(1.0 / particleMass[i]);
        meshOf.push_back(static_cast<std::uint32_t>(meshNumber));
    }
    // Edges: the six of every tetrahedron, each once.
    std::vector<std::array<std::uint32_t, 2>> edges;
    for (const auto& tet : spec.tets) {
        for (int a = 0; a < 4; ++a) {
            for (int b = a + 1; b < 4; ++b) {
                const auto i = static_cast<std::uint32_t>(tet[a]), j = static_cast<std::uint32_t>(tet[b]);
                edges.push_back({std::min(i, j), std::max(i, j)});
            }
        }
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    mesh.firstLink = static_cast<std::uint32_t>(links.size());
    for (const auto& e : edges)
        links.push_back(linkBetween(x, first + e[0], first + e[1], LinkKind::Edge, spec.edgeCompliance, spec.stiffness));
    mesh.linkCount = static_cast<std::uint32_t>(edges.size());
    // Volumes, one per tetrahedron.
    mesh.firstVolume = static_cast<std::uint32_t>(volumes.size());
    for (const auto& tet : spec.tets) {
        TetVolume t;
        for (int c = 0; c < 4; ++c) t.v[c] = first + static_cast<std::uint32_t>(tet[c]);
        t.rest = volumeOf(spec.positions, tet);
        t.compliance = spec.volumeCompliance;
        t.stiffness = spec.stiffness;
        volumes.push_back(t);
    }
    mesh.volumeCount = static_cast<std::uint32_t>(spec.tets.size());
    // Surface: the faces no other tetrahedron shares, each turned to face outwards. A tetrahedron of
    // positive volume sees its faces (1 2 3), (0 3 2), (0 1 3), (0 2 1) counter-clockwise from outside.
    struct Face {
        std::array<std::uint32_t, 3> key, outward;
        bool operator<(const Face& o) const { return key < o.key; }
    };
    std::vector<Face> faces;
    for (const auto& tet : spec.tets) {
        const auto c = [&](int k) { return first + static_cast<std::uint32_t>(tet[k]); };
        for (const std::array<std::uint32_t, 3>& f : {std::array<std::uint32_t, 3>{c(1), c(2), c(3)},
                                                       std::array<std::uint32_t, 3>{c(0), c(3), c(2)},
                                                       std::array<std::uint32_t, 3>{c(0), c(1), c(3)},
                                                       std::array<std::uint32_t, 3>{c(0), c(2), c(1)}}) {
            Face face{f, f};
            std::sort(face.key.begin(), face.key.end());
            faces.push_back(face);
        }
    }
    std::sort(faces.begin(), faces.end());
    for (std::size_t f = 0; f < faces.size();) {
        std::size_t g = f + 1;
        while (g < faces.size() && faces[g].key == faces[f].key) ++g;
        if (g - f == 1) mesh.triangles.push_back(faces[f].outward);
        f = g;
    }
    return addMesh(std::move(mesh));
}

void SoftBodies::setPinned(std::uint32_t particle, bool pinned) {
    if (particle >= x.size())
        throw std::out_of_range("no particle number " + std::to_string(particle) + " (there are " +
                                std::to_string(x.size()) + ")");
    w[particle] = pinned ? 0.0 : 1.0 / mass[particle];
    if (pinned) v[particle] = Vec3::Zero();
}

void SoftBodies::setWind(const Vec3& velocity, double drag) {
    if (!isFinite(velocity)) throw std::invalid_argument("wind: velocity must be finite");
    if (!std::isfinite(drag) || drag < 0.0)
        throw std::invalid_argument("wind: drag must be a finite number >= 0, got " + formatNumber(drag));
    wind_ = velocity;
    windDrag_ = drag;
}

void SoftBodies::clear() {
    x.clear();
    p.clear();
    v.clear();
    w.clear();
    mass.clear();
    meshOf.clear();
    x0.clear();
    meshes.clear();
    links.clear();
    volumes.clear();
    contacts.clear();
    selfPairs.clear();
    force_.clear();
    movedByRest_.clear();
    selfPaired_.clear();
    wind_ = Vec3::Zero();
    windDrag_ = 0.0;
}

}  // namespace gpl
