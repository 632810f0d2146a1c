// A large mesh's links in two halves and the rest (soft_sweeps.h): the order they are stored in,
// and a sweep whose halves the second thread shares.
#include "gpl/soft_sweeps.h"

#include <cmath>
#include <functional>

#include "gpl/soft_constraints.h"

namespace gpl {
namespace {

// What one part's sweep needs: the plain loop's arguments, and what each half does after its links.
struct HalfSweep {
    const SoftMesh& mesh;
    std::vector<DistanceLink>& links;
    std::vector<Vec3>& p;
    const std::vector<double>& w;
    double h;
    int iterations;
    const std::function<void(int)>& then;
};

// The plain loop of SoftBodies::project() over links [begin, end). What it reads of `s` it keeps in
// locals: `s` lies on the caller's stack, and the thread that reads it after every projection would
// otherwise fetch that cache line anew each time the caller's own half writes its stack beside it.
void sweepLinkRange(const HalfSweep& s, std::uint32_t begin, std::uint32_t end) {
    DistanceLink* const links = s.links.data();
    Vec3* const p = s.p.data();
    const double* const w = s.w.data();
    const double h = s.h;
    if (s.mesh.method == SoftMethod::XPBD) {
        for (std::uint32_t k = begin; k < end; ++k) {
            DistanceLink& link = links[k];
            const DistanceCorrection c = solveDistanceConstraint(p[link.i], p[link.j], w[link.i], w[link.j], link.rest,
                                                                 link.compliance, h, link.lambda);
            p[link.i] += c.dx1;
            p[link.j] += c.dx2;
            link.lambda += c.dlambda;
        }
        return;
    }
    const int iterations = s.iterations;
    double stiffness = -1.0, perSweep = 0.0;  // the last stiffness seen, and its per-sweep share
    for (std::uint32_t k = begin; k < end; ++k) {
        const DistanceLink& link = links[k];
        if (link.stiffness != stiffness) {
            stiffness = link.stiffness;
            perSweep = 1.0 - std::pow(1.0 - stiffness, 1.0 / iterations);
        }
        const DistanceCorrection c =
            solveDistanceConstraint(p[link.i], p[link.j], w[link.i], w[link.j], link.rest, 0.0, h, 0.0);
        p[link.i] += perSweep * c.dx1;
        p[link.j] += perSweep * c.dx2;
    }
}

// Half 0 or 1 of the mesh's links, then what the caller does after it.
void sweepHalf(const HalfSweep& s, int half) {
    const std::uint32_t begin = s.mesh.firstLink + (half == 0 ? 0 : s.mesh.firstHalfLinks);
    sweepLinkRange(s, begin, begin + (half == 0 ? s.mesh.firstHalfLinks : s.mesh.secondHalfLinks));
    s.then(half);
}

}  // namespace

HalvesOrder halvesOrder(const std::vector<DistanceLink>& links, std::uint32_t cut, std::size_t particles) {
    HalvesOrder out;
    out.order = sweepOrder(links, particles);
    if (links.size() < kHalvesFrom) return out;
    // In sweep order: a link waits for the seam when it crosses the cut, or when it shares a particle
    // with an earlier link that waits. The others go first, each half's in sweep order: no link
    // before them shares a particle with them, and the halves share none.
    std::vector<char> waits(particles, 0);  // per particle: a link that waits has moved it
    std::vector<std::uint32_t> halves[2], rest;
    for (const std::uint32_t k : out.order) {
        const DistanceLink& link = links[k];
        const bool first = link.i < cut;
        if (first != (link.j < cut) || waits[link.i] || waits[link.j]) {
            waits[link.i] = waits[link.j] = 1;
            rest.push_back(k);
        } else {
            halves[first ? 0 : 1].push_back(k);
        }
    }
    out.first = static_cast<std::uint32_t>(halves[0].size());
    out.second = static_cast<std::uint32_t>(halves[1].size());
    out.order = halves[0];
    out.order.insert(out.order.end(), halves[1].begin(), halves[1].end());
    out.order.insert(out.order.end(), rest.begin(), rest.end());
    return out;
}

void sweepHalves(const SoftMesh& mesh, std::vector<DistanceLink>& links, std::vector<Vec3>& p,
                 const std::vector<double>& w, double h, int iterations, SecondThread& second,
                 const std::function<void(int)>& then) {
    const HalfSweep s{mesh, links, p, w, h, iterations, then};
    // Each captures one reference, which fits in std::function's own storage: a step allocates nothing.
    const std::function<void()> first = [&s] { sweepHalf(s, 0); };
    const std::function<void()> other = [&s] { sweepHalf(s, 1); };
    second.run(true, first, other);
}

void markMovedByTheRest(const SoftMesh& mesh, const std::vector<DistanceLink>& links,
                        const std::vector<TetVolume>& volumes, std::vector<char>& moved) {
    if (mesh.firstHalfLinks == 0) return;
    for (std::uint32_t k = mesh.firstLink + mesh.firstHalfLinks + mesh.secondHalfLinks;
         k < mesh.firstLink + mesh.linkCount; ++k)
        moved[links[k].i] = moved[links[k].j] = 1;
    for (std::uint32_t k = mesh.firstVolume; k < mesh.firstVolume + mesh.volumeCount; ++k)
        for (const std::uint32_t corner : volumes[k].v) moved[corner] = 1;
}

}  // namespace gpl
