// Friction and resting contact in the engine (worksheet 7): sequential impulses with sums per
// contact point, then positions that follow the velocities. Each step
//   1. builds every body's world inverse inertia once (worldInverseInertia(); orientations do not
//      change during the stage, and the kernels would otherwise rebuild R I^-1 R^T at every point
//      of every sweep),
//   2. measures each point's approach speed (what restitution answers) before anything changes it,
//   3. warm starts: a point of the same pair of bodies as one of last step's, within
//      kWarmStartDistance of it, starts from that point's sums (the friction sum turned into the new
//      tangent plane), applied once with applyWarmStart(); 2 and 3 are the sweeps' first pass (a
//      large stage's halves measure and warm start their own points at once),
//   4. sweeps contactIterations() times over every point (ContactSweeps, contact_sweeps.cpp):
//      applyNormalImpulse(), then applyFrictionImpulse() against the normal sum just updated; a
//      point whose last solve changed neither its sums nor its bodies, and whose bodies nothing has
//      changed since, is skipped (solving it again would change nothing: the kernels are pure),
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

void PhysicsEngine::solveContacts() {
    const bool twoThreads = threads() > 1 && sums_.size() >= ContactSweeps::kSplitFrom;  // as last step
    if (twoThreads) second_.wake();
    // Last step's entry of each contact's pair, for warm starting.
    rememberedOf_.resize(contacts_.size());
    for (std::size_t c = 0; c < contacts_.size(); ++c) {
        rememberedOf_[c] = remembered(contactMemory_, contacts_[c].a, contacts_[c].b);
    }
    before_.resize(bodies_.size());
    for (std::size_t i = 0; i < bodies_.size(); ++i) before_[i] = {bodies_[i].velocity, bodies_[i].angularVelocity};
    worldInvInertia_.resize(bodies_.size());
    for (std::size_t i = 0; i < bodies_.size(); ++i) worldInvInertia_[i] = worldInverseInertia(bodies_[i]);

    const double h = timeStep();
    // Sums per point: contact c's points start at first[c].
    std::vector<std::size_t>& first = firstPoint_;
    first.assign(contacts_.size() + 1, 0);
    for (std::size_t c = 0; c < contacts_.size(); ++c) first[c + 1] = first[c] + contacts_[c].pointCount;
    sums_.assign(first.back(), PointImpulse{});

    // Each point's overlap now, along the normal through it (the contact's depth where that line
    // misses a body).
    depths_.resize(first.back());
    for (std::size_t c = 0; c < contacts_.size(); ++c) {
        const Contact& con = contacts_[c];
        for (int k = 0; k < con.pointCount; ++k) {
            const double d = depthAlong(bodies_[con.a], bodies_[con.b], con.points[k], con.normal);
            depths_[first[c] + k] = std::isnan(d) ? con.depth : d;
        }
    }

    // Each point's approach and last step's sums, measured and warm started by the sweeps' first pass.
    const ContactSweeps::Start start = [this](std::size_t c, const Body& a, const Body& b, PointImpulse* sums) {
        const Contact& con = contacts_[c];
        const ContactMemory::Entry* old = rememberedOf_[c];
        for (int k = 0; k < con.pointCount; ++k) {
            sums[k] = warmSums(contactMemory_, old, con.points[k], con.normal);
            sums[k].approach = normalVelocityAt(con, a, b, con.points[k]);
        }
    };
    sweeps_.run(contacts_, first, worldInvInertia_, bodies_, sums_, contactIterations_, true,
                threads() > 1 ? &second_ : nullptr, &start);

    // Each point's overlap at the end of the step: its overlap now, less what the change of its
    // normal velocity in the stage moves it apart in h.
    for (std::size_t c = 0; c < contacts_.size(); ++c) {
        const Contact& con = contacts_[c];
        for (int k = 0; k < con.pointCount; ++k) {
            const double now = normalVelocityAt(con, bodies_[con.a], bodies_[con.b], con.points[k]);
            depths_[first[c] + k] -= h * (now - sums_[first[c] + k].approach);
        }
    }

    // The step's positions and orientations follow the velocities after the impulses.
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
        Body& b = bodies_[i];
        if (b.isStatic()) continue;
        b.position += h * (b.velocity - before_[i].first);
        const Vec3 turn = h * (b.angularVelocity - before_[i].second);  // rad, world frame
        if (!turn.isZero(0.0)) {
            const double angle = turn.norm();
            b.orientation = (Quat(Eigen::AngleAxisd(angle, turn / angle)) * b.orientation).normalized();
        }
    }
    // Overlap left beyond the slop: split impulses, in positions only.
    splitImpulses_.clear();
    for (std::size_t c = 0; c < contacts_.size(); ++c) {
        const Contact& con = contacts_[c];
        for (int k = 0; k < con.pointCount; ++k) {
            splitImpulses_.add(con.a, con.b, con.points[k], con.normal, depths_[first[c] + k], bodies_,
                               worldInvInertia_[con.a], worldInvInertia_[con.b]);
        }
    }
    splitImpulses_.run(bodies_, worldInvInertia_, kContactSlop, h, interpenetrationIterations());

    // Keep the sums for the next step, sorted by pair (a pair that interpenetration found twice
    // keeps its contacts in their order; the first is the one warm starts find). The indices are
    // sorted, not the contacts (176 bytes each).
    ContactMemory& memory = contactMemory_;
    std::vector<std::size_t>& order = order_;
    orderByPair(contacts_.size(), bodies_.size(), [this](std::size_t c) { return contacts_[c].a; },
                [this](std::size_t c) { return contacts_[c].b; }, order, memory.firstOf, placeAt_);
    memory.entries.resize(contacts_.size());
    memory.points.resize(first.back());
    memory.sums.resize(first.back());
    std::uint32_t next = 0;  // the next entry's first point
    for (std::size_t m = 0; m < order.size(); ++m) {
        const Contact& con = contacts_[order[m]];
        ContactMemory::Entry& e = memory.entries[m];
        e.a = con.a;
        e.b = con.b;
        e.normal = con.normal;
        e.first = next;
        e.pointCount = static_cast<std::uint32_t>(con.pointCount);
        for (int k = 0; k < con.pointCount; ++k, ++next) {
            const PointImpulse& s = sums_[first[order[m]] + k];
            memory.points[next] = con.points[k];
            memory.sums[next] = {s.normal, s.tangent};
        }
    }
    recordOpenKernels();
}

}  // namespace gpl
