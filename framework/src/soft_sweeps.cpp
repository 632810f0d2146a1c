// A large mesh's links in two halves and the rest (soft_sweeps.h): the order they are stored in,
// and a sweep whose halves the second thread shares.
#include "gpl/soft_sweeps.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <thread>

#include "gpl/soft_constraints.h"

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

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

// A range of a mesh's links [begin, end).
struct LinkRange {
    std::uint32_t begin, end;
};

// Half 0 or 1 of a cut mesh's links, as they are stored: the first half's from firstLink on, then the
// second half's.
LinkRange halfLinks(const SoftMesh& mesh, int half) {
    const std::uint32_t begin = mesh.firstLink + (half == 0 ? 0 : mesh.firstHalfLinks);
    return {begin, begin + (half == 0 ? mesh.firstHalfLinks : mesh.secondHalfLinks)};
}

// Half 0 or 1 of the mesh's links, then what the caller does after it.
void sweepHalf(const HalfSweep& s, int half) {
    const LinkRange links = halfLinks(s.mesh, half);
    sweepLinkRange(s, links.begin, links.end);
    s.then(half);
}

// What the two threads of sweepOverlapped() tell each other. It lies on the caller's stack, which
// outlives both: SecondThread::run() returns when both threads are done.
struct Overlap {
    const HalfSweep& s;
    const std::function<void()>& rest;
    std::atomic<int> firstDone{0};    ///< sweeps whose first half (links and then(0)) is done
    std::atomic<int> secondTaken{0};  ///< the second half's parts taken so far, by either thread
    std::atomic<int> secondDone{0};   ///< the second half's parts done
    std::atomic<int> restTaken{0};    ///< sweeps whose rest a thread has taken
    std::atomic<int> restDone{0};     ///< sweeps whose rest is done
    std::atomic<bool> failed{false};  ///< a thread threw: the other stops waiting for it
};

// Spins until count reaches target (true), or until a thread failed (false). Every few microseconds
// it offers the core to any other thread waiting for it.
bool waitFor(const std::atomic<int>& count, int target, const std::atomic<bool>& failed) {
    for (int k = 0;; ++k) {
        if (count.load(std::memory_order_acquire) >= target) return true;
        if (failed.load(std::memory_order_relaxed)) return false;
#if defined(__x86_64__) || defined(__i386__)
        _mm_pause();
#endif
        if ((k & 63) == 63) std::this_thread::yield();
    }
}

// A half's links that do not wait for the rest (stored first), and those that do (stored last).
LinkRange readyLinks(const SoftMesh& mesh, int half) {
    const LinkRange all = halfLinks(mesh, half);
    return {all.begin, all.end - (half == 0 ? mesh.firstHalfWaiting : mesh.secondHalfWaiting)};
}
LinkRange waitingLinks(const SoftMesh& mesh, int half) {
    return {readyLinks(mesh, half).end, halfLinks(mesh, half).end};
}
void sweep(const HalfSweep& s, LinkRange range) { sweepLinkRange(s, range.begin, range.end); }
// The half's multipliers to 0, by the thread that sweeps it, where its links then stay in the cache.
void resetMultipliers(const HalfSweep& s, int half) {
    const std::uint32_t end = waitingLinks(s.mesh, half).end;
    for (std::uint32_t k = readyLinks(s.mesh, half).begin; k < end; ++k) s.links[k].lambda = 0.0;
}

// The rest of sweep k, once both its halves are done, unless the other thread has taken it.
void sweepRest(Overlap& o, int k) {
    int untaken = k;
    if (!o.restTaken.compare_exchange_strong(untaken, k + 1)) return;
    o.rest();
    o.restDone.store(k + 1, std::memory_order_release);
}

// Part k of the second half, on the thread that took it: in sweep k, its links that do not wait;
// the rest of sweep k - 1 if the first half of that sweep is done and nobody has taken it (the first
// half's thread is behind: on a core another program shares); then, once that rest is done, then(2)
// for it, its waiting links and then(1). Part `iterations` is then(2) for the last sweep's rest. The
// thread that takes a part waits for the part before, which the other thread may have taken.
bool sweepSecondHalfPart(Overlap& o, int k) {
    const HalfSweep& s = o.s;
    if (!waitFor(o.secondDone, k, o.failed)) return false;
    if (k == 0) resetMultipliers(s, 1);
    if (k < s.iterations) sweep(s, readyLinks(s.mesh, 1));
    if (k > 0 && o.firstDone.load(std::memory_order_acquire) >= k) sweepRest(o, k - 1);
    if (!waitFor(o.restDone, k, o.failed)) return false;
    if (k > 0) s.then(2);
    if (k < s.iterations) {
        sweep(s, waitingLinks(s.mesh, 1));
        s.then(1);
    }
    o.secondDone.store(k + 1, std::memory_order_release);
    return true;
}

// The second thread: the second half's parts that the caller has not taken, in order, from the first
// it finds untaken.
void sweepSecondHalves(Overlap& o) {
    try {
        int k = o.secondTaken.load(std::memory_order_relaxed);
        while (k <= o.s.iterations) {
            if (!o.secondTaken.compare_exchange_weak(k, k + 1)) continue;  // k is now the count taken
            if (!sweepSecondHalfPart(o, k)) return;
            ++k;
        }
    } catch (...) {
        o.failed = true;
        throw;
    }
}

// The caller: sweep by sweep, once the rest of the sweep before is done, its half's waiting links and
// then(0), the next sweep's links that do not wait, then (once the second half's part of the sweep is
// done, or doing it here when the second thread has not taken it) the rest, unless the second thread
// has taken it.
void sweepFirstHalvesAndRest(Overlap& o) {
    const HalfSweep& s = o.s;
    // Takes part k of the second half if the second thread has not, and returns once it is done.
    const auto secondHalfPart = [&o](int k) {
        int untaken = k;
        if (o.secondTaken.compare_exchange_strong(untaken, k + 1)) return sweepSecondHalfPart(o, k);
        return waitFor(o.secondDone, k + 1, o.failed);
    };
    try {
        resetMultipliers(s, 0);
        sweep(s, readyLinks(s.mesh, 0));
        for (int k = 0; k < s.iterations; ++k) {
            if (!waitFor(o.restDone, k, o.failed)) return;
            sweep(s, waitingLinks(s.mesh, 0));
            s.then(0);
            o.firstDone.store(k + 1, std::memory_order_release);
            if (k + 1 < s.iterations) sweep(s, readyLinks(s.mesh, 0));
            if (!secondHalfPart(k)) return;
            sweepRest(o, k);
        }
        secondHalfPart(s.iterations);
    } catch (...) {
        o.failed = true;
        throw;
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
                 const std::vector<double>& w, double h, int iterations, SecondThread& second,
                 const std::function<void(int)>& then) {
    const HalfSweep s{mesh, links, p, w, h, iterations, then};
    // Each captures one reference, which fits in std::function's own storage: a step allocates nothing.
    const std::function<void()> first = [&s] { sweepHalf(s, 0); };
    const std::function<void()> other = [&s] { sweepHalf(s, 1); };
    second.run(true, first, other);
}

void sweepOverlapped(const SoftMesh& mesh, std::vector<DistanceLink>& links, std::vector<Vec3>& p,
                     const std::vector<double>& w, double h, int iterations, SecondThread& second,
                     const std::function<void(int)>& then, const std::function<void()>& rest) {
    const HalfSweep s{mesh, links, p, w, h, iterations, then};
    Overlap o{s, rest};
    const std::function<void()> first = [&o] { sweepFirstHalvesAndRest(o); };
    const std::function<void()> other = [&o] { sweepSecondHalves(o); };
    // The step's sweeps in one hand-over: it stands for one a sweep (sweepHalves()).
    second.run(true, first, other, static_cast<std::uint64_t>(std::max(iterations, 1)));
}

void holdBackWaitingLinks(SoftMesh& mesh, std::vector<DistanceLink>& links, const std::vector<char>& moved) {
    std::vector<char> waits(moved);  // per particle: the rest or a waiting link moves it
    std::vector<DistanceLink> ready, waiting;
    for (int half = 0; half < 2; ++half) {
        const auto [begin, end] = halfLinks(mesh, half);
        ready.clear();
        waiting.clear();
        for (std::uint32_t k = begin; k < end; ++k) {
            const DistanceLink& link = links[k];
            if (waits[link.i] || waits[link.j]) {
                waits[link.i] = waits[link.j] = 1;
                waiting.push_back(link);
            } else {
                ready.push_back(link);
            }
        }
        std::copy(ready.begin(), ready.end(), links.begin() + begin);
        std::copy(waiting.begin(), waiting.end(), links.begin() + begin + ready.size());
        (half == 0 ? mesh.firstHalfWaiting : mesh.secondHalfWaiting) = static_cast<std::uint32_t>(waiting.size());
    }
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


// SoftBodies::project() on two threads, where a mesh is cut in halves: the plain loop's sweeps with
// each cut mesh's halves swept at once, and its contacts grouped so that each half's go with its
// links (soft_sweeps.h). The result is the plain loop's to the bit.
void SoftBodies::projectInHalves(double h, int iterations, const std::vector<Body>& bodies) {
    // The second thread woken to spin while this one prepares.
    second_.wake();
    groupContacts();
    const auto cut = [](const SoftMesh& mesh) { return mesh.firstHalfLinks > 0; };
    const auto cutMeshes = std::count_if(meshes.begin(), meshes.end(), cut);
    // A cut mesh's halves' contacts are pushed out right after their half's links.
    struct HalfContacts {
        SoftBodies& soft;
        const std::vector<Body>& bodies;
        double h;
        int iterations;
        std::size_t mesh;
    } halfContacts{*this, bodies, h, iterations, 0};
    // Part 0 or 1: the mesh's halves' contacts; 2: the rest's contacts in its second half.
    const std::function<void(int)> pushHalfContacts = [&halfContacts](int part) {
        SoftBodies& soft = halfContacts.soft;
        const std::size_t group =
            part < 2 ? 2 * halfContacts.mesh + static_cast<std::size_t>(part) : 2 * soft.meshes.size() + 1;
        const std::size_t end =
            group + 1 < soft.contactGroups_.size() ? soft.contactGroups_[group + 1] : soft.contacts.size();
        soft.pushOutOfBodies(halfContacts.h, halfContacts.bodies, soft.contactGroups_[group], end);
    };
    // One cut mesh and no self-collision pairs: each half's sweeps overlap the rest of the sweep
    // before (sweepOverlapped()); each thread sets its half's multipliers to 0.
    const bool overlapped = cutMeshes == 1 && selfPairs.empty();
    halfContacts.mesh = static_cast<std::size_t>(std::find_if(meshes.begin(), meshes.end(), cut) - meshes.begin());
    std::size_t halvesBegin = links.size(), halvesEnd = links.size();
    if (overlapped) {
        const SoftMesh& mesh = meshes[halfContacts.mesh];
        halvesBegin = mesh.firstLink;
        halvesEnd = halvesBegin + mesh.firstHalfLinks + mesh.secondHalfLinks;
    }
    for (std::size_t k = 0; k < halvesBegin; ++k) links[k].lambda = 0.0;
    for (std::size_t k = halvesEnd; k < links.size(); ++k) links[k].lambda = 0.0;
    for (TetVolume& volume : volumes) volume.lambda = 0.0;
    for (ParticleContact& c : contacts) {
        c.pushed = false;
        c.depth = 0.0;
        c.friction = Vec3::Zero();
    }
    if (overlapped) {
        const std::function<void()> sweepRest = [&halfContacts] {
            SoftBodies& soft = halfContacts.soft;
            for (const SoftMesh& mesh : soft.meshes) {
                const bool halves = &mesh == &soft.meshes[halfContacts.mesh];
                soft.sweepMesh(mesh, mesh.firstLink + (halves ? mesh.firstHalfLinks + mesh.secondHalfLinks : 0),
                               halfContacts.h, halfContacts.iterations);
            }
            const std::size_t rest = 2 * soft.meshes.size();
            soft.pushOutOfBodies(halfContacts.h, halfContacts.bodies, soft.contactGroups_[rest],
                                 soft.contactGroups_[rest + 1]);
        };
        sweepOverlapped(meshes[halfContacts.mesh], links, p, w, h, iterations, second_, pushHalfContacts, sweepRest);
        catchMissedContacts(bodies);
        return;
    }
    for (int iteration = 0; iteration < iterations; ++iteration) {
        for (std::size_t m = 0; m < meshes.size(); ++m) {
            const SoftMesh& mesh = meshes[m];
            // A cut mesh: its halves' links swept at once, each followed by its contacts; then the rest.
            std::uint32_t firstLink = mesh.firstLink;
            if (mesh.firstHalfLinks > 0) {
                halfContacts.mesh = m;
                sweepHalves(mesh, links, p, w, h, iterations, second_, pushHalfContacts);
                firstLink += mesh.firstHalfLinks + mesh.secondHalfLinks;
            }
            sweepMesh(mesh, firstLink, h, iterations);
        }
        pushSelfPairs();
        // The contacts that did not go with a half's links.
        pushOutOfBodies(h, bodies, contactGroups_[2 * meshes.size()], contacts.size());
    }
    catchMissedContacts(bodies);
}

void SoftBodies::groupContacts() {
    // Each contact's group: 2 m + half for mesh m's halves, 2 M for the rest, 2 M + 1 for the rest's
    // in the second half of a cut mesh; then a counting sort.
    for (const auto& pair : selfPairs) selfPaired_[pair[0]] = selfPaired_[pair[1]] = 1;
    const std::size_t rest = 2 * meshes.size();
    const auto group = [this, rest](const ParticleContact& c) {
        const std::uint32_t i = c.particle;
        const SoftMesh& mesh = meshes[meshOf[i]];
        if (mesh.firstHalfLinks == 0 || selfPaired_[i]) return rest;
        const std::size_t half = i < halvesCut(mesh) ? 0 : 1;
        return movedByRest_[i] ? rest + half : 2 * std::size_t{meshOf[i]} + half;
    };
    groupEnds_.assign(rest + 2, 0);
    for (const ParticleContact& c : contacts) ++groupEnds_[group(c)];
    contactGroups_.assign(rest + 2, 0);
    for (std::size_t g = 0; g < rest + 1; ++g) contactGroups_[g + 1] = contactGroups_[g] + groupEnds_[g];
    std::copy(contactGroups_.begin(), contactGroups_.end(), groupEnds_.begin());
    grouped_.resize(contacts.size());
    for (const ParticleContact& c : contacts) grouped_[groupEnds_[group(c)]++] = c;
    contacts.swap(grouped_);
    for (const auto& pair : selfPairs) selfPaired_[pair[0]] = selfPaired_[pair[1]] = 0;
}

}  // namespace gpl
