// Friction and resting contact in the engine (worksheet 7): sequential impulses with sums per
// contact point. Each step
//   0. keeps the contacts of last step's pairs that now touch at depth ~0 (kContactSlop), whole,
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
//      point whose last solve changed nothing, and whose bodies nothing has changed since, is
//      skipped (solving it again would change nothing: the kernels are pure); a large stage in two
//      Halves at once on the engine's second thread, the same to the bit as on one,
//   5. moves every body by h times the change of its velocity in the stage, less its parts along the
//      normals of the body's contacts, and turns it by h times the change of its angular velocity:
//      the integration stage moved the bodies with the velocities before the impulses, and the
//      interpenetration stage has already undone the motion along the normals. A block held by
//      static friction on an incline then does not creep down by g h^2 sin(theta) a step,
//   6. keeps the sums, sorted by pair, for the next step.
// The number of sweeps is fixed: a resting stack converges a little more every step through the
// warm start, so no sweep checks whether it is done. (A stop once no sum changes by more than a
// thousandth of m g h would not help the benchmark heaps: after ten sweeps half or more of their
// points still change by more.)
#include <algorithm>
#include <optional>

#include "gpl/collision.h"
#include "gpl/engine.h"
#include "gpl/friction.h"
#include "gpl/pair_order.h"
#include "gpl/rotation.h"

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

// The contact of bodies[i] and bodies[j] with body j moved by `shift` (m) and back; positions are
// restored exactly.
std::optional<Contact> collideShifted(std::vector<Body>& bodies, std::size_t i, std::size_t j, const Vec3& shift) {
    const Vec3 kept = bodies[j].position;
    bodies[j].position = kept + shift;
    std::optional<Contact> c = collide(bodies, i, j);
    bodies[j].position = kept;
    return c;
}

}  // namespace

void PhysicsEngine::keepRestingContacts() {
    // Last step's pairs: is each still in contact, and how deep?
    std::vector<int>& found = found_;
    found.assign(contactMemory_.entries.size(), -1);
    rememberedOf_.resize(contacts_.size());
    for (std::size_t c = 0; c < contacts_.size(); ++c) {
        const ContactMemory::Entry* old = remembered(contactMemory_, contacts_[c].a, contacts_[c].b);
        rememberedOf_[c] = old;
        if (old != nullptr) {
            const std::size_t m = static_cast<std::size_t>(old - contactMemory_.entries.data());
            if (found[m] < 0) found[m] = static_cast<int>(c);
        }
    }
    for (std::size_t m = 0; m < contactMemory_.entries.size(); ++m) {
        const ContactMemory::Entry& e = contactMemory_.entries[m];
        if (e.a >= bodies_.size() || e.b >= bodies_.size()) continue;
        if (found[m] >= 0 && contacts_[found[m]].depth >= kContactSlop) continue;
        // A contact of a sphere has one point, any contact at most kMaxContactPoints: one that has
        // them all already is whole, and looking again would find no more.
        const bool sphere = bodies_[e.a].shape == Shape::Sphere || bodies_[e.b].shape == Shape::Sphere;
        const int whole = sphere ? 1 : kMaxContactPoints;
        if (found[m] >= 0 && contacts_[found[m]].pointCount >= whole) continue;
        // b moved towards a along last step's normal (it points from a to b).
        std::optional<Contact> near = collideShifted(bodies_, e.a, e.b, -kContactSlop * e.normal);
        if (!near || near->a != e.a || near->b != e.b) continue;
        if (found[m] >= 0 && near->pointCount <= contacts_[found[m]].pointCount) continue;
        near->depth = std::max(0.0, near->depth - kContactSlop);  // as touching: the impulses keep the gap
        if (found[m] >= 0) {
            contacts_[found[m]] = *near;
        } else {
            contacts_.push_back(*near);
            rememberedOf_.push_back(remembered(contactMemory_, e.a, e.b));
        }
    }
}

void PhysicsEngine::solveContacts() {
    const bool twoThreads = threads() > 1 && sums_.size() >= ContactSweeps::kSplitFrom;  // as last step
    if (twoThreads) second_.wake();
    keepRestingContacts();
    before_.resize(bodies_.size());
    for (std::size_t i = 0; i < bodies_.size(); ++i) before_[i] = {bodies_[i].velocity, bodies_[i].angularVelocity};
    worldInvInertia_.resize(bodies_.size());
    for (std::size_t i = 0; i < bodies_.size(); ++i) worldInvInertia_[i] = worldInverseInertia(bodies_[i]);

    // Sums per point: contact c's points start at first[c].
    std::vector<std::size_t>& first = firstPoint_;
    first.assign(contacts_.size() + 1, 0);
    for (std::size_t c = 0; c < contacts_.size(); ++c) first[c + 1] = first[c] + contacts_[c].pointCount;
    sums_.assign(first.back(), PointImpulse{});

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

    // The step's positions and orientations with the velocities after the impulses; along the
    // contact normals interpenetration has moved the bodies already.
    const double h = timeStep();
    normals_.assign(bodies_.size(), {});
    for (const Contact& con : contacts_) {
        for (const std::size_t i : {con.a, con.b}) {
            Normals& basis = normals_[i];
            if (basis.count == 3 || bodies_[i].isStatic()) continue;  // a static body does not move
            Vec3 n = con.normal;  // its part not yet in the basis (Gram-Schmidt)
            for (int k = 0; k < basis.count; ++k) n -= n.dot(basis.axes[k]) * basis.axes[k];
            const double length = n.norm();
            if (length > 1e-3) basis.axes[basis.count++] = n / length;
        }
    }
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
        Body& b = bodies_[i];
        if (b.isStatic()) continue;
        Vec3 move = h * (b.velocity - before_[i].first);  // m
        for (int k = 0; k < normals_[i].count; ++k) move -= move.dot(normals_[i].axes[k]) * normals_[i].axes[k];
        b.position += move;
        const Vec3 turn = h * (b.angularVelocity - before_[i].second);  // rad, world frame
        if (!turn.isZero(0.0)) {
            const double angle = turn.norm();
            b.orientation = (Quat(Eigen::AngleAxisd(angle, turn / angle)) * b.orientation).normalized();
        }
    }

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
