// A large mesh's links in two halves and the rest (soft_sweeps.h): the order they are stored in,
// and a sweep whose halves the second thread shares.
#include "gpl/soft_sweeps.h"

#include <cmath>
#include <functional>

#include "gpl/soft_constraints.h"

namespace gpl {
namespace {

// What one part's sweep needs: the plain loop's arguments, and the part's links [begin, end).
struct HalfSweep {
    std::vector<DistanceLink>& links;
    std::vector<Vec3>& p;
    const std::vector<double>& w;
    SoftMethod method;
    double h;
    int iterations;
};

// The plain loop of SoftBodies::project() over links [begin, end).
void sweepLinkRange(const HalfSweep& s, std::uint32_t begin, std::uint32_t end) {
    std::vector<Vec3>& p = s.p;
    const std::vector<double>& w = s.w;
    if (s.method == SoftMethod::XPBD) {
        for (std::uint32_t k = begin; k < end; ++k) {
            DistanceLink& link = s.links[k];
            const DistanceCorrection c = solveDistanceConstraint(p[link.i], p[link.j], w[link.i], w[link.j], link.rest,
                                                                 link.compliance, s.h, link.lambda);
            p[link.i] += c.dx1;
            p[link.j] += c.dx2;
            link.lambda += c.dlambda;
        }
        return;
    }
    double stiffness = -1.0, perSweep = 0.0;  // the last stiffness seen, and its per-sweep share
    for (std::uint32_t k = begin; k < end; ++k) {
        const DistanceLink& link = s.links[k];
        if (link.stiffness != stiffness) {
            stiffness = link.stiffness;
            perSweep = 1.0 - std::pow(1.0 - stiffness, 1.0 / s.iterations);
        }
        const DistanceCorrection c =
            solveDistanceConstraint(p[link.i], p[link.j], w[link.i], w[link.j], link.rest, 0.0, s.h, 0.0);
        p[link.i] += perSweep * c.dx1;
        p[link.j] += perSweep * c.dx2;
    }
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
                 const std::vector<double>& w, double h, int iterations, SecondThread& second) {
    const HalfSweep s{links, p, w, mesh.method, h, iterations};
    // Each captures what fits in std::function's own storage: a step allocates nothing.
    const std::function<void()> first = [&s, &mesh] {
        sweepLinkRange(s, mesh.firstLink, mesh.firstLink + mesh.firstHalfLinks);
    };
    const std::function<void()> other = [&s, &mesh] {
        const std::uint32_t begin = mesh.firstLink + mesh.firstHalfLinks;
        sweepLinkRange(s, begin, begin + mesh.secondHalfLinks);
    };
    second.run(true, first, other);
}

}  // namespace gpl
