// Friction and resting contact in the engine (worksheet 7): sequential impulses with sums per
// contact point, then positions that follow the velocities. Each step
//   1. builds every body's world inverse inertia once (worldInverseInertia(); orientations do not
//      change during the stage): the points' preparation and the position correction read it,
//   2. measures each point's approach speed (what restitution answers) before anything changes it,
//      and prepares the point once with prepareContactPoint(): lever arms, tangents, inverse
//      effective masses and the normal velocity to reach, which the sweeps only read,
//   3. warm starts: a point of the same pair of bodies as one of last step's, within
//      kWarmStartDistance of it, starts from that point's sums (the friction sum turned into the new
//      tangent plane), applied once with applyWarmStart(),
//   4. sweeps contactIterations() times over every contact: applyNormalImpulse() at each of its
//      points (twice over when it has several: a face's points share its load), then
//      applyFrictionImpulse() at each against the normal sum just updated. A small stage runs the
//      plain loop of FrictionStage::sweep(); a large one runs in two halves at once on the
//      engine's second thread, skipping contacts that nothing has changed since they were last
//      solved (ContactSweeps, contact_sweeps.cpp), with the same result to the bit,
//   5. moves every body by h times the change of its velocity in the stage and turns it by h times
//      the change of its angular velocity: the integration stage moved the bodies with the
//      velocities before the impulses, so each body ends the step where its new velocity takes it
//      (x + h v, the semi-implicit Euler step of the velocities the contacts allow). A body resting
//      on the floor, whose impulses cancel the step's g h, does not sink; one held by static
//      friction on an incline does not creep,
//   6. removes a share of every point's overlap beyond kContactSlop with split impulses
//      (split_impulses.h): impulses on velocities of their own that move and turn the bodies and
//      are then forgotten, so position error never feeds energy into the velocities, and the slop
//      leaves resting contacts alone, so a pyramid is not pushed apart along its slanted normals
//      (where friction, which acts on velocities, does not hold it),
//   7. keeps the sums, sorted by pair, for the next step.
// The number of sweeps is fixed: a resting stack converges a little more every step through the
// warm start, so no sweep checks whether it is done.
#include <algorithm>
#include <cmath>
#include <optional>

#include "gpl/collision.h"
#include "gpl/engine.h"
#include "gpl/friction.h"
#include "gpl/pair_order.h"
#include "gpl/rotation.h"
#include "gpl/split_impulses.h"
#include "gpl/response.h"

namespace gpl {
namespace {

// Last step's entry of the pair (a, b), or nullptr: the first of a's entries with this b (they are
// sorted by b, and a plane has one per body on it: a search, not a walk through them all).
const ContactMemory::Entry* remembered(const ContactMemory& memory, std::size_t a, std::size_t b) {
    if (a + 1 >= memory.firstOf.size()) return nullptr;
    const auto begin = memory.entries.begin() + static_cast<std::ptrdiff_t>(memory.firstOf[a]);
    const auto end = memory.entries.begin() + static_cast<std::ptrdiff_t>(memory.firstOf[a + 1]);
    const auto found = std::lower_bound(begin, end, b, [](const ContactMemory::Entry& e, std::size_t i) { return e.b < i; });
    return found != end && found->b == b ? &*found : nullptr;
}

// Last step's sums of the point nearest to p (within kWarmStartDistance), with the friction sum
// projected onto the plane perpendicular to n; zero sums when there is none.
PointImpulse warmSums(const ContactMemory& memory, const ContactMemory::Entry* old, const Vec3& p, const Vec3& n) {
    PointImpulse s;
    if (old == nullptr) return s;
    double best = kWarmStartDistance * kWarmStartDistance;
    std::size_t found = SIZE_MAX;
    for (std::size_t k = old->first; k < old->first + old->pointCount; ++k) {
        const double d = (memory.points[k] - p).squaredNorm();
        if (d <= best) {
            best = d;
            found = k;
        }
    }
    if (found == SIZE_MAX) return s;
    s.normal = memory.sums[found].normal;
    const Vec3& t = memory.sums[found].tangent;
    s.tangent = t - n.dot(t) * n;
    return s;
}

}  // namespace

const char* contactSolverName(ContactSolver solver) {
    switch (solver) {
        case ContactSolver::SequentialImpulses: return "sequential impulses";
        case ContactSolver::SoftStep: return "soft step";
        case ContactSolver::Baumgarte: return "Baumgarte";
    }
    return "?";
}

void PhysicsEngine::solveContacts() {
    friction_.step(bodies_, contacts_, timeStep(), contactIterations_, interpenetrationIterations(),
                   threads() > 1 ? &second_ : nullptr, contactSolver_);
    recordOpenKernels();
}

void FrictionStage::step(std::vector<Body>& bodies, std::vector<Contact>& contacts, double h, int sweeps,
                         int positionSweeps, SecondThread* second, ContactSolver solver) {
    if (second != nullptr && sums_.size() >= ContactSweeps::kSplitFrom) second->wake();  // a large stage, as last step
    keepPoints(bodies, contacts);
    // 1. Each body's velocities now and its world inverse inertia, once.
    before_.resize(bodies.size());
    invI_.resize(bodies.size());
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        before_[i] = {bodies[i].velocity, bodies[i].angularVelocity};
        invI_[i] = worldInverseInertia(bodies[i]);
    }
    // The points' sums: contact c's points start at first_[c]; last step's entry of each pair.
    first_.assign(contacts.size() + 1, 0);
    remembered_.resize(contacts.size());
    for (std::size_t c = 0; c < contacts.size(); ++c) {
        first_[c + 1] = first_[c] + contacts[c].pointCount;
        remembered_[c] = remembered(memory_, contacts[c].a, contacts[c].b);
    }
    sums_.assign(first_.back(), PointImpulse{});
    // Each point's overlap now, along the normal through it (the contact's depth where that line
    // misses a body).
    depths_.resize(first_.back());
    for (std::size_t c = 0; c < contacts.size(); ++c) {
        const Contact& con = contacts[c];
        for (int k = 0; k < con.pointCount; ++k) {
            const double d = depthAlong(bodies[con.a], bodies[con.b], con.points[k], con.normal, kKeepGap);
            depths_[first_[c] + k] = std::isnan(d) ? con.depth : d;
        }
    }

    if (solver == ContactSolver::SoftStep) {
        for (std::size_t c = 0; c < contacts.size(); ++c) {
            start(contacts, c, bodies[contacts[c].a], bodies[contacts[c].b], &sums_[first_[c]]);
        }
        soft_.run(bodies, invI_, contacts, first_, depths_, sums_, h);
        keep(contacts, bodies);
        return;
    }

    // 2-4. Approaches, warm starts and the sweeps: a small stage in the plain loop below, a large
    // one in two halves (ContactSweeps, the same result to the bit); or the baseline's.
    if (solver == ContactSolver::Baumgarte) {
        for (std::size_t c = 0; c < contacts.size(); ++c) {
            start(contacts, c, bodies[contacts[c].a], bodies[contacts[c].b], &sums_[first_[c]]);
        }
        baumgarte_.run(bodies, invI_, contacts, first_, depths_, sums_, kContactSlop, h, sweeps);
    } else if (sums_.size() < ContactSweeps::kSplitFrom) {
        sweep(bodies, contacts, sweeps);
    } else {
        const ContactSweeps::Start begin = [this, &contacts](std::size_t c, const Body& a, const Body& b,
                                                             PointImpulse* sums) { start(contacts, c, a, b, sums); };
        sweeps_.run(contacts, first_, invI_, bodies, sums_, sweeps, true, second, &begin);
    }

    // Each point's overlap at the end of the step: its overlap now, less what the change of its
    // normal velocity in the stage moves it apart in h (for the position pass, which the baseline has not).
    for (std::size_t c = 0; solver != ContactSolver::Baumgarte && c < contacts.size(); ++c) {
        const Contact& con = contacts[c];
        for (int k = 0; k < con.pointCount; ++k) {
            const double now = normalVelocityAt(con, bodies[con.a], bodies[con.b], con.points[k]);
            depths_[first_[c] + k] -= h * (now - sums_[first_[c] + k].approach);
        }
    }

    // 5. The step's positions and orientations follow the velocities after the impulses.
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        Body& b = bodies[i];
        if (b.isStatic()) continue;
        b.position += h * (b.velocity - before_[i].first);
        const Vec3 turn = h * (b.angularVelocity - before_[i].second);  // rad, world frame
        if (!turn.isZero(0.0)) {
            const double angle = turn.norm();
            b.orientation = (Quat(Eigen::AngleAxisd(angle, turn / angle)) * b.orientation).normalized();
        }
    }

    // 6. Overlap left beyond the slop: split impulses, in positions only (the baseline's bias has
    // answered it in the velocities).
    if (solver == ContactSolver::Baumgarte) {
        keep(contacts, bodies);
        return;
    }
    split_.clear();
    for (std::size_t c = 0; c < contacts.size(); ++c) {
        const Contact& con = contacts[c];
        for (int k = 0; k < con.pointCount; ++k) {
            split_.add(con.a, con.b, con.points[k], con.normal, depths_[first_[c] + k], bodies, invI_[con.a],
                       invI_[con.b]);
        }
    }
    split_.run(bodies, invI_, kContactSlop, h, positionSweeps);

    // 7.
    keep(contacts, bodies);
}

void FrictionStage::keepPoints(const std::vector<Body>& bodies, std::vector<Contact>& contacts) {
    if (memory_.entries.empty()) return;
    for (const ContactMemory::Entry& e : memory_.entries) e.found = false;
    // Where last step's point k of a pair is now, and whether it still touches along normal n:
    // the midpoint of the two material points that met there, if they have not slid apart and
    // the bodies overlap there or are within kKeepGap of it.
    const auto touching = [&](const ContactMemory::Entry& e, std::uint32_t k, const Vec3& n) -> std::optional<Vec3> {
        const Body& a = bodies[e.a];
        const Body& b = bodies[e.b];
        const Vec3 pa = a.position + a.orientation * memory_.onA[k];
        const Vec3 pb = b.position + b.orientation * memory_.onB[k];
        const Vec3 apart = pb - pa;
        if ((apart - n.dot(apart) * n).squaredNorm() > kKeepSlide * kKeepSlide) return std::nullopt;
        const Vec3 p = 0.5 * (pa + pb);
        const double depth = depthAlong(a, b, p, n, kKeepGap);
        if (!(depth >= -kKeepGap)) return std::nullopt;  // apart, or the line misses a body (NaN)
        return p;
    };
    const std::size_t found = contacts.size();
    for (std::size_t c = 0; c < found; ++c) {
        Contact& con = contacts[c];
        const ContactMemory::Entry* old = remembered(memory_, con.a, con.b);
        if (old == nullptr) continue;
        old->found = true;
        const int reported = con.pointCount;
        for (std::uint32_t k = old->first; k < old->first + old->pointCount && con.pointCount < kMaxContactPoints; ++k) {
            bool near = false;  // a point of this step is where it was (a sphere's always is)
            for (int q = 0; q < reported && !near; ++q) {
                near = (con.points[q] - memory_.points[k]).squaredNorm() <= kWarmStartDistance * kWarmStartDistance;
            }
            if (near) continue;
            if (const std::optional<Vec3> p = touching(*old, k, con.normal)) con.points[con.pointCount++] = *p;
        }
    }
    // Pairs whose contact the kernels no longer report: their points that still touch.
    for (const ContactMemory::Entry& e : memory_.entries) {
        if (e.found || e.a >= bodies.size() || e.b >= bodies.size()) continue;
        Contact con;
        con.a = e.a;
        con.b = e.b;
        con.normal = e.normal;
        con.depth = -kKeepGap;
        con.restitution = e.restitution;
        con.friction = e.friction;
        con.staticFriction = e.staticFriction;
        for (std::uint32_t k = e.first; k < e.first + e.pointCount; ++k) {
            if (const std::optional<Vec3> p = touching(e, k, e.normal)) {
                con.points[con.pointCount++] = *p;
                con.depth = std::max(con.depth, depthAlong(bodies[e.a], bodies[e.b], *p, e.normal, kKeepGap));
            }
        }
        if (con.pointCount > 0) contacts.push_back(con);
    }
}

void FrictionStage::start(const std::vector<Contact>& contacts, std::size_t c, const Body& a, const Body& b,
                          PointImpulse* sums) const {
    const Contact& con = contacts[c];
    for (int k = 0; k < con.pointCount; ++k) {
        sums[k] = warmSums(memory_, remembered_[c], con.points[k], con.normal);
        sums[k].approach = normalVelocityAt(con, a, b, con.points[k]);
    }
}

void FrictionStage::sweep(std::vector<Body>& bodies, const std::vector<Contact>& contacts, int sweeps) {
    // Every point's approach is measured, and every point prepared, before any warm start: an
    // impulse at one point changes the velocities at the others.
    points_.resize(first_.back());
    for (std::size_t c = 0; c < contacts.size(); ++c) {
        const Contact& con = contacts[c];
        start(contacts, c, bodies[con.a], bodies[con.b], &sums_[first_[c]]);
        for (int k = 0; k < con.pointCount; ++k) {
            points_[first_[c] + k] = prepareContactPoint(con, k, bodies[con.a], bodies[con.b], invI_[con.a],
                                                         invI_[con.b], sums_[first_[c] + k].approach);
        }
    }
    for (std::size_t c = 0; c < contacts.size(); ++c) {
        const Contact& con = contacts[c];
        for (std::size_t i = first_[c]; i < first_[c + 1]; ++i) {
            const PointImpulse& s = sums_[i];
            if (s.normal != 0.0 || !s.tangent.isZero(0.0)) applyWarmStart(points_[i], bodies[con.a], bodies[con.b], s);
        }
    }
    // Each sweep visits every contact once: the normal impulses of its points, twice when it has
    // more than one (the points of a face share its load, and after one pass the first point holds
    // more than its share, which the second pass hands on), then their friction, bounded by the
    // normal sums as they now are.
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        for (std::size_t c = 0; c < contacts.size(); ++c) {
            Body& a = bodies[contacts[c].a];
            Body& b = bodies[contacts[c].b];
            const int normalPasses = first_[c + 1] - first_[c] > 1 ? 2 : 1;
            for (int pass = 0; pass < normalPasses; ++pass) {
                for (std::size_t i = first_[c]; i < first_[c + 1]; ++i) applyNormalImpulse(points_[i], a, b, sums_[i]);
            }
            for (std::size_t i = first_[c]; i < first_[c + 1]; ++i) applyFrictionImpulse(points_[i], a, b, sums_[i]);
        }
    }
}

void FrictionStage::keep(const std::vector<Contact>& contacts, const std::vector<Body>& bodies) {
    // Sorted by pair (a pair that detection found twice keeps its contacts in their order; the
    // first is the one warm starts find). The indices are sorted, not the contacts.
    ContactMemory& memory = memory_;
    orderByPair(contacts.size(), bodies.size(), [&contacts](std::size_t c) { return contacts[c].a; },
                [&contacts](std::size_t c) { return contacts[c].b; }, order_, memory.firstOf, placeAt_);
    memory.entries.resize(contacts.size());
    memory.points.resize(first_.back());
    memory.sums.resize(first_.back());
    memory.onA.resize(first_.back());
    memory.onB.resize(first_.back());
    std::uint32_t next = 0;  // the next entry's first point
    for (std::size_t m = 0; m < order_.size(); ++m) {
        const Contact& con = contacts[order_[m]];
        ContactMemory::Entry& e = memory.entries[m];
        e.a = con.a;
        e.b = con.b;
        e.normal = con.normal;
        e.first = next;
        e.pointCount = static_cast<std::uint32_t>(con.pointCount);
        e.restitution = con.restitution;
        e.friction = con.friction;
        e.staticFriction = con.staticFriction;
        const Body& a = bodies[con.a];
        const Body& b = bodies[con.b];
        for (int k = 0; k < con.pointCount; ++k, ++next) {
            const PointImpulse& s = sums_[first_[order_[m]] + k];
            memory.points[next] = con.points[k];
            memory.sums[next] = {s.normal, s.tangent};
            memory.onA[next] = a.orientation.conjugate() * (con.points[k] - a.position);
            memory.onB[next] = b.orientation.conjugate() * (con.points[k] - b.position);
        }
    }
}

}  // namespace gpl
