// Friction and resting contact in the engine (worksheet 7): sequential impulses with sums per
// contact point, then positions that follow the velocities. Each step
//   1. builds every body's world inverse inertia once (worldInverseInertia(); orientations do not
//      change during the stage): the points' preparation and the position correction read it,
//   2. measures each point's approach speed (what restitution answers) before anything changes it,
//      and prepares the point once with prepareContactPoint(): lever arms, an axis along the
//      normal and each tangent (what reads the point's velocity along it and pushes the bodies
//      along it, and its inverse effective mass) and the normal velocity to reach, which the sweeps
//      only read,
//   3. warm starts: a point that continues one of last step's of the same pair of bodies starts
//      from that point's sums (ContactMemory::match(): one to one, by where the bodies carry last
//      step's points, within kWarmStartDistance), applied once with applyWarmStart(),
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
// warm start, so no sweep checks whether it is done. A large stage on two threads also runs its
// loops over the contacts or the bodies in two halves (inHalves()), and its split impulses in the
// sweeps' halves: the same result as on one thread.
#include <algorithm>
#include <cmath>
#include <optional>

#include "gpl/collision.h"
#include "gpl/engine.h"
#include "gpl/friction.h"
#include "gpl/friction_stage.h"
#include "gpl/pair_order.h"
#include "gpl/response.h"
#include "gpl/rotation.h"
#include "gpl/split_impulses.h"

namespace gpl {

const ContactMemory::Entry* ContactMemory::find(std::size_t a, std::size_t b, bool& flipped) const {
    // The first of a's entries with this b (they are sorted by b, and a plane has one per body on
    // it: a search, not a walk through them all).
    const auto first = [this](std::size_t i, std::size_t j) -> const Entry* {
        if (i + 1 >= firstOf.size()) return nullptr;
        const auto begin = entries.begin() + static_cast<std::ptrdiff_t>(firstOf[i]);
        const auto end = entries.begin() + static_cast<std::ptrdiff_t>(firstOf[i + 1]);
        const auto found = std::lower_bound(begin, end, j, [](const Entry& e, std::size_t k) { return e.b < k; });
        return found != end && found->b == j ? &*found : nullptr;
    };
    flipped = false;
    if (const Entry* e = first(a, b)) return e;
    flipped = true;
    return first(b, a);
}

Vec3 ContactMemory::pointNow(std::uint32_t k, const Body& a, const Body& b) const {
    return 0.5 * ((a.position + a.orientation * onA[k]) + (b.position + b.orientation * onB[k]));
}

ContactMemory::Pairing ContactMemory::pairUp(const Entry& old, bool flipped, const Contact& contact, const Body& a,
                                             const Body& b) const {
    // Every pair of a point now and a point then within kWarmStartDistance, the nearest first; a
    // pair is taken when neither of its points is taken yet. Ties go to the lower indices, so the
    // answer depends on nothing but the points.
    const int count = contact.pointCount;
    const std::uint32_t was = old.pointCount;
    std::array<std::array<double, kMaxContactPoints>, kMaxContactPoints> d{};  // squared, m^2
    for (std::uint32_t q = 0; q < was; ++q) {
        const Vec3 then = flipped ? pointNow(old.first + q, b, a) : pointNow(old.first + q, a, b);
        for (int k = 0; k < count; ++k) d[k][q] = (contact.points[k] - then).squaredNorm();
    }
    Pairing pairing;
    pairing.fill(kNone);
    std::array<bool, kMaxContactPoints> taken{};
    for (int round = 0; round < count; ++round) {
        double best = kWarmStartDistance * kWarmStartDistance;
        int bestK = -1;
        std::uint32_t bestQ = 0;
        for (int k = 0; k < count; ++k) {
            if (pairing[k] != kNone) continue;
            for (std::uint32_t q = 0; q < was; ++q) {
                if (!taken[q] && d[k][q] <= best && (bestK < 0 || d[k][q] < best)) {
                    best = d[k][q];
                    bestK = k;
                    bestQ = q;
                }
            }
        }
        if (bestK < 0) break;
        pairing[bestK] = old.first + bestQ;
        taken[bestQ] = true;
    }
    return pairing;
}

void ContactMemory::match(const Entry* old, bool flipped, const Contact& contact, const Body& a, const Body& b,
                          PointImpulse* sums, const Pairing* paired) const {
    const int count = contact.pointCount;
    for (int k = 0; k < count; ++k) {
        sums[k].normal = 0.0;
        sums[k].tangent = Vec3::Zero();
    }
    if (old == nullptr) return;
    const Pairing pairing = paired != nullptr ? *paired : pairUp(*old, flipped, contact, a, b);
    // The sums of the points continued, and of those that no point continues.
    std::array<bool, kMaxContactPoints> continued{};
    double kept = 0.0;  // N s
    for (int k = 0; k < count; ++k) {
        if (pairing[k] == kNone) continue;
        sums[k].normal = this->sums[pairing[k]].normal;
        sums[k].tangent = this->sums[pairing[k]].tangent;
        continued[pairing[k] - old->first] = true;
        kept += sums[k].normal;
    }
    double lostNormal = 0.0;
    Vec3 lostTangent = Vec3::Zero();
    for (std::uint32_t q = 0; q < old->pointCount; ++q) {
        if (continued[q]) continue;
        lostNormal += this->sums[old->first + q].normal;
        lostTangent += this->sums[old->first + q].tangent;
    }
    // Handed on in proportion to the normal sums continued; then turned into this step's tangent
    // plane (the friction sums of a pair in the other order reversed, as its normal is).
    const bool handOn = kept > 0.0 && (lostNormal > 0.0 || !lostTangent.isZero(0.0));
    const Vec3& n = contact.normal;
    for (int k = 0; k < count; ++k) {
        if (pairing[k] == kNone) continue;
        if (handOn) {
            const double share = sums[k].normal / kept;
            sums[k].normal += share * lostNormal;
            sums[k].tangent += share * lostTangent;
        }
        const Vec3 t = flipped ? Vec3(-sums[k].tangent) : sums[k].tangent;
        sums[k].tangent = t - n.dot(t) * n;
    }
}

const char* contactSolverName(ContactSolver solver) {
    switch (solver) {
        case ContactSolver::SequentialImpulses: return "sequential impulses";
        case ContactSolver::SoftStep: return "soft step";
        case ContactSolver::Baumgarte: return "Baumgarte";
    }
    return "?";
}

void PhysicsEngine::solveContacts() {
    friction_->step(bodies_, contacts_, timeStep(), contactIterations_, interpenetrationIterations(),
                    threads() > 1 ? &second_ : nullptr, contactSolver_);
    recordOpenKernels();
}

void FrictionStage::step(std::vector<Body>& bodies, std::vector<Contact>& contacts, double h, int sweeps,
                         int positionSweeps, SecondThread* second, ContactSolver solver) {
    // A large stage (as last step's) runs in halves on two threads or on one, whichever the second
    // thread finds cheaper now: the stage is timed from here to its end (second_thread.h).
    const bool large = solver == ContactSolver::SequentialImpulses && sums_.size() >= ContactSweeps::kSplitFrom;
    const SecondThread::Stage timed(large ? second : nullptr, sums_.size());
    // The loops below that visit each contact or body once touch different data at each: a large
    // stage runs them in two halves (inHalves(), second_thread.h).
    SecondThread* const twoThreads = timed.second();  // null: this run of the stage is on one thread
    keepPoints(bodies, contacts, twoThreads);
    // 1. Each body's velocities now and its world inverse inertia, once.
    before_.resize(bodies.size());
    invI_.resize(bodies.size());
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        before_[i] = {bodies[i].velocity, bodies[i].angularVelocity};
        invI_[i] = worldInverseInertia(bodies[i]);
    }
    // The points' sums: contact c's points start at first_[c].
    first_.assign(contacts.size() + 1, 0);
    for (std::size_t c = 0; c < contacts.size(); ++c) first_[c + 1] = first_[c] + contacts[c].pointCount;
    sums_.assign(first_.back(), PointImpulse{});
    // Each point's overlap now, along the normal through it (the contact's depth where that line
    // misses a body).
    depths_.resize(first_.back());
    inHalves(twoThreads, contacts.size(), [&](std::size_t c) {
        const Contact& con = contacts[c];
        for (int k = 0; k < con.pointCount; ++k) {
            const double d = depthAlong(bodies[con.a], bodies[con.b], con.points[k], con.normal, kKeepGap);
            depths_[first_[c] + k] = std::isnan(d) ? con.depth : d;
        }
    });

    if (solver == ContactSolver::SoftStep) {
        for (std::size_t c = 0; c < contacts.size(); ++c) {
            start(contacts, c, bodies[contacts[c].a], bodies[contacts[c].b], &sums_[first_[c]]);
        }
        soft_.run(bodies, invI_, contacts, first_, depths_, sums_, h);
        keep(contacts, bodies);
        return;
    }

    const Halves* cut = nullptr;  // a large stage's halves, which the position correction sweeps too
    // 2-4. Approaches, warm starts and the sweeps: a small stage in the plain loop below, a large
    // one in two halves (ContactSweeps, the same result to the bit); or the baseline's.
    if (solver == ContactSolver::Baumgarte) {
        for (std::size_t c = 0; c < contacts.size(); ++c) {
            start(contacts, c, bodies[contacts[c].a], bodies[contacts[c].b], &sums_[first_[c]]);
        }
        baumgarte_.run(bodies, invI_, contacts, first_, depths_, sums_, kContactSlop, h, sweeps);
    } else if (sums_.size() < ContactSweeps::kSplitFrom) {
        sweep(bodies, contacts, sweeps, h);
    } else {
        const ContactSweeps::Start begin = [this, &contacts, h](std::size_t c, const Body& a, const Body& b,
                                                                PointImpulse* sums, double* closing) {
            start(contacts, c, a, b, sums, h, closing);
        };
        sweeps_.run(contacts, first_, invI_, bodies, sums_, sweeps, true, twoThreads, &begin);
        cut = &sweeps_.halves();
    }

    // Each point's overlap at the end of the step: its overlap now, less what the change of its
    // normal velocity in the stage moves it apart in h (for the position pass, which the baseline has not).
    inHalves(twoThreads, solver != ContactSolver::Baumgarte ? contacts.size() : 0, [&](std::size_t c) {
        const Contact& con = contacts[c];
        for (int k = 0; k < con.pointCount; ++k) {
            const double now = normalVelocityAt(con, bodies[con.a], bodies[con.b], con.points[k]);
            depths_[first_[c] + k] -= h * (now - sums_[first_[c] + k].approach);
        }
    });

    // 5. The step's positions and orientations follow the velocities after the impulses.
    inHalves(twoThreads, bodies.size(), [&](std::size_t i) {
        Body& b = bodies[i];
        if (b.isStatic()) return;
        b.position += h * (b.velocity - before_[i].first);
        const Vec3 turn = h * (b.angularVelocity - before_[i].second);  // rad, world frame
        if (!turn.isZero(0.0)) {
            const double angle = turn.norm();
            b.orientation = (Quat(Eigen::AngleAxisd(angle, turn / angle)) * b.orientation).normalized();
        }
    });

    // 6. Overlap left beyond the slop: split impulses, in positions only (the baseline's bias has
    // answered it in the velocities).
    if (solver == ContactSolver::Baumgarte) {
        keep(contacts, bodies);
        return;
    }
    split_.resize(first_.back());
    inHalves(twoThreads, contacts.size(), [&](std::size_t c) {
        const Contact& con = contacts[c];
        for (int k = 0; k < con.pointCount; ++k) {
            const std::size_t i = first_[c] + k;
            split_.set(i, con.a, con.b, con.points[k], con.normal, depths_[i], bodies, invI_[con.a], invI_[con.b]);
        }
    });
    split_.run(bodies, invI_, kContactSlop, h, positionSweeps, cut, twoThreads);

    // 7.
    keep(contacts, bodies, twoThreads);
}

void FrictionStage::keepPoints(const std::vector<Body>& bodies, std::vector<Contact>& contacts,
                               SecondThread* twoThreads) {
    remembered_.assign(contacts.size(), nullptr);
    flipped_.assign(contacts.size(), 0);
    paired_.assign(contacts.size(), 0);
    pairings_.resize(contacts.size());
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
        if (depthAlong(a, b, p, n, kKeepGap) >= -kKeepGap) return p;
        // A box's corner lies on its edges, where the line along the normal grazes the box: it
        // misses it (NaN) or leaves it through a side. The line kKeepSlide inwards, towards the
        // bodies' centres, answers for the corner.
        Vec3 centre = Vec3::Zero();
        int solids = 0;
        for (const Body* body : {&a, &b}) {
            if (body->shape == Shape::Plane) continue;
            centre += body->position;
            ++solids;
        }
        Vec3 inwards = centre / solids - p;
        inwards -= n.dot(inwards) * n;
        if (inwards.norm() <= kKeepSlide) return std::nullopt;
        const double depth = depthAlong(a, b, p + kKeepSlide * inwards.normalized(), n, kKeepGap);
        if (!(depth >= -kKeepGap)) return std::nullopt;  // apart, or the line misses a body (NaN)
        return p;
    };
    const std::size_t found = contacts.size();
    inHalves(twoThreads, found, [&](std::size_t c) {
        Contact& con = contacts[c];
        bool flipped = false;
        const ContactMemory::Entry* old = memory_.find(con.a, con.b, flipped);
        remembered_[c] = old;
        flipped_[c] = flipped;
        if (old == nullptr) return;
        if (con.pointCount >= kMaxContactPoints) return;  // no room for a point kept
        // Last step's points that no point of this step continues.
        std::array<bool, kMaxContactPoints> continued{};
        const ContactMemory::Pairing pairing = memory_.pairUp(*old, flipped, con, bodies[con.a], bodies[con.b]);
        for (int k = 0; k < con.pointCount; ++k) {
            if (pairing[k] != ContactMemory::kNone) continued[pairing[k] - old->first] = true;
        }
        const Vec3 n = flipped ? Vec3(-con.normal) : con.normal;  // in the entry's order
        const int reported = con.pointCount;
        for (std::uint32_t q = 0; q < old->pointCount && con.pointCount < kMaxContactPoints; ++q) {
            if (continued[q]) continue;
            if (const std::optional<Vec3> p = touching(*old, old->first + q, n)) con.points[con.pointCount++] = *p;
        }
        // The contact as it was: its warm start pairs it up the same way (match()).
        if (con.pointCount == reported) {
            pairings_[c] = pairing;
            paired_[c] = 1;
        }
    });
    for (std::size_t c = 0; c < found; ++c) {
        if (remembered_[c] != nullptr) remembered_[c]->found = true;
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
        if (con.pointCount > 0) {
            contacts.push_back(con);
            bool flipped = false;
            remembered_.push_back(memory_.find(con.a, con.b, flipped));  // the pair's first entry
            flipped_.push_back(flipped);
            paired_.push_back(0);
        }
    }
    pairings_.resize(contacts.size());
}

void FrictionStage::start(const std::vector<Contact>& contacts, std::size_t c, const Body& a, const Body& b,
                          PointImpulse* sums, double h, double* closing) const {
    const Contact& con = contacts[c];
    memory_.match(remembered_[c], flipped_[c], con, a, b, sums, paired_[c] ? &pairings_[c] : nullptr);
    for (int k = 0; k < con.pointCount; ++k) {
        sums[k].approach = normalVelocityAt(con, a, b, con.points[k]);
        // Integration has moved the point by h times its approach: at the step's start its gap was
        // at least -depth - h approach, with the contact's depth (its deepest point's: a point's own
        // depth along the normal is not defined at a corner), which a normal velocity of -gap / h
        // closes by the step's end. Only against a static body: between two that move, a wedge
        // (the top sphere of a tetrahedron) closing its gaps pushes the bodies below apart, step
        // after step.
        if (closing != nullptr) closing[k] = a.isStatic() || b.isStatic() ? -con.depth / h - sums[k].approach : 0.0;
    }
}

void FrictionStage::sweep(std::vector<Body>& bodies, const std::vector<Contact>& contacts, int sweeps, double h) {
    // Every point's approach is measured, and every point prepared, before any warm start: an
    // impulse at one point changes the velocities at the others.
    points_.resize(first_.back());
    std::array<double, kMaxContactPoints> closing;
    for (std::size_t c = 0; c < contacts.size(); ++c) {
        const Contact& con = contacts[c];
        start(contacts, c, bodies[con.a], bodies[con.b], &sums_[first_[c]], h, closing.data());
        for (int k = 0; k < con.pointCount; ++k) {
            ContactPoint& point = points_[first_[c] + k];
            point = prepareContactPoint(con, k, bodies[con.a], bodies[con.b], invI_[con.a], invI_[con.b],
                                        sums_[first_[c] + k].approach);
            mayCloseGap(point, closing[k]);
        }
    }
    for (std::size_t c = 0; c < contacts.size(); ++c) {
        const Contact& con = contacts[c];
        for (std::size_t i = first_[c]; i < first_[c + 1]; ++i) {
            const PointImpulse& s = sums_[i];
            if (holdsImpulse(s)) applyWarmStart(points_[i], bodies[con.a], bodies[con.b], s);
        }
    }
    // Each sweep visits every contact once: the normal impulses of its points, twice when it has
    // more than one (the points of a face share its load, and after one pass the first point holds
    // more than its share, which the second pass hands on), then their friction, bounded by the
    // normal sums as they now are, at the points that hold an impulse.
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        for (std::size_t c = 0; c < contacts.size(); ++c) {
            Body& a = bodies[contacts[c].a];
            Body& b = bodies[contacts[c].b];
            const int normalPasses = first_[c + 1] - first_[c] > 1 ? 2 : 1;
            for (int pass = 0; pass < normalPasses; ++pass) {
                for (std::size_t i = first_[c]; i < first_[c + 1]; ++i) applyNormalImpulse(points_[i], a, b, sums_[i]);
            }
            for (std::size_t i = first_[c]; i < first_[c + 1]; ++i) {
                if (holdsImpulse(sums_[i])) applyFrictionImpulse(points_[i], a, b, sums_[i]);
            }
        }
    }
}

void FrictionStage::keep(const std::vector<Contact>& contacts, const std::vector<Body>& bodies,
                         SecondThread* twoThreads) {
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
        next += e.pointCount;
    }
    inHalves(twoThreads, order_.size(), [&](std::size_t m) {
        const Contact& con = contacts[order_[m]];
        const Body& a = bodies[con.a];
        const Body& b = bodies[con.b];
        for (int k = 0; k < con.pointCount; ++k) {
            const std::uint32_t i = memory.entries[m].first + static_cast<std::uint32_t>(k);
            const PointImpulse& s = sums_[first_[order_[m]] + k];
            memory.points[i] = con.points[k];
            memory.sums[i] = {s.normal, s.tangent};
            memory.onA[i] = a.orientation.conjugate() * (con.points[k] - a.position);
            memory.onB[i] = b.orientation.conjugate() * (con.points[k] - b.position);
        }
    });
}

}  // namespace gpl
