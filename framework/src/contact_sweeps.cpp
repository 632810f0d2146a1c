// The friction stage's sweeps (friction_stage.h): a first pass that measures, prepares and warm starts
// every point, then at every contact its points' applyNormalImpulse() (twice for more than one
// point) and applyFrictionImpulse(), contactIterations() times, with idle contacts skipped; a large
// stage in two Halves (halves.h), which come first here.
//
// Skipping: per body, a version that counts its changes; per contact (kept at its first point), the
// versions of its two bodies when it was last solved, and whether that solve changed nothing. Such
// a contact is skipped while both versions stand: the kernels are pure, so solving it again would
// change nothing.
#include <algorithm>
#include <array>
#include <functional>

#include "gpl/friction.h"
#include "gpl/friction_stage.h"
#include "gpl/halves.h"
#include "gpl/second_thread.h"

namespace gpl {
namespace {

/// A body's velocities before a contact's solve.
struct Velocities {
    Vec3 v, w;
    explicit Velocities(const Body& body) : v(body.velocity), w(body.angularVelocity) {}
    bool differ(const Body& body) const { return body.velocity != v || body.angularVelocity != w; }
};

/// One contact's solve: its points' normal impulses (twice over for more than one point: the points
/// of a face share its load, and after one pass the first holds more than its share), then their
/// friction at those that hold an impulse. True when it changed a sum.
bool solveContact(const ContactPoint* points, PointImpulse* sums, int count, Body& a, Body& b) {
    if (count == 1) {
        const double normal = sums[0].normal;
        const Vec3 tangent = sums[0].tangent;
        applyNormalImpulse(points[0], a, b, sums[0]);
        if (holdsImpulse(sums[0])) applyFrictionImpulse(points[0], a, b, sums[0]);
        return sums[0].normal != normal || sums[0].tangent != tangent;
    }
    std::array<double, kMaxContactPoints> normals;
    std::array<Vec3, kMaxContactPoints> tangents;
    for (int k = 0; k < count; ++k) {
        normals[k] = sums[k].normal;
        tangents[k] = sums[k].tangent;
    }
    for (int pass = 0; pass < 2; ++pass) {
        for (int k = 0; k < count; ++k) applyNormalImpulse(points[k], a, b, sums[k]);
    }
    for (int k = 0; k < count; ++k) {
        if (holdsImpulse(sums[k])) applyFrictionImpulse(points[k], a, b, sums[k]);
    }
    bool changed = false;
    for (int k = 0; k < count; ++k) changed = changed || sums[k].normal != normals[k] || sums[k].tangent != tangents[k];
    return changed;
}

/// How many contacts ahead solve() asks for the bodies.
constexpr std::size_t kAhead = 4;

/// Asks for the cache lines of a body that the sweeps' kernels read and write: its first two
/// (position, velocity, masses, angular velocity; body.h). The rest of what they read is the point's.
inline void prefetchBody(const Body* body) {
    const char* at = reinterpret_cast<const char*>(body);
    __builtin_prefetch(at, 1);
    __builtin_prefetch(at + 64, 1);
}

}  // namespace

void Halves::whole(std::size_t bodies) {
    cut_ = false;
    side_.assign(bodies, kLeft);
    local_.resize(bodies);
    for (std::size_t i = 0; i < bodies; ++i) local_[i] = i;
    versions_[kLeft].assign(bodies, 0);
    statics_.clear();
}

void Halves::begin(const std::vector<Body>& bodies) {
    cut_ = true;
    side_.assign(bodies.size(), kNone);
    local_.assign(bodies.size(), 0);
    movable_.clear();
    statics_.clear();
}

void Halves::finish(const std::vector<Body>& bodies) {
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
    for (std::size_t k = 0; k < movable_.size(); ++k) {
        const Vec3& x = bodies[movable_[k]].position;
        lo = k == 0 ? x : lo.cwiseMin(x);
        hi = k == 0 ? x : hi.cwiseMax(x);
    }
    int axis = 0;
    (hi - lo).maxCoeff(&axis);
    along_.clear();
    for (const std::size_t i : movable_) along_.push_back(bodies[i].position[axis]);
    double median = 0.0;
    if (!along_.empty()) {
        const auto middle = along_.begin() + static_cast<std::ptrdiff_t>(along_.size() / 2);
        std::nth_element(along_.begin(), middle, along_.end());
        median = *middle;
    }
    for (int half : {kLeft, kRight}) members_[half].clear();
    for (const std::size_t i : movable_) {
        const int s = bodies[i].position[axis] < median ? kLeft : kRight;
        side_[i] = s;
        local_[i] = members_[s].size();
        members_[s].push_back(i);
    }
    for (int half : {kLeft, kRight}) versions_[half].assign(members_[half].size(), 0);
}

void Halves::registerStatics(std::size_t a, std::size_t b) {
    if (part(a, b) == kMiddle) return;
    for (const std::size_t i : {a, b}) {
        if (side_[i] != kNone || std::find(statics_.begin(), statics_.end(), i) != statics_.end()) continue;
        local_[i] = statics_.size();
        statics_.push_back(i);
    }
}

void Halves::copyStatics(const std::vector<Body>& bodies) {
    for (int half : {kLeft, kRight}) {
        copies_[half].clear();
        for (const std::size_t i : statics_) copies_[half].push_back(bodies[i]);
        staticVersions_[half].assign(statics_.size(), LineVersion{});
    }
}

void Halves::mergeStatics(std::vector<Body>& bodies) {
    for (std::size_t s = 0; s < statics_.size(); ++s) {
        Body& body = bodies[statics_[s]];
        const Body& left = copies_[kLeft][s];
        const Body& right = copies_[kRight][s];
        const Vec3 x = (left.position - body.position) + (right.position - body.position);
        const Vec3 v = (left.velocity - body.velocity) + (right.velocity - body.velocity);
        const Vec3 w = (left.angularVelocity - body.angularVelocity) + (right.angularVelocity - body.angularVelocity);
        if (x.isZero(0.0) && v.isZero(0.0) && w.isZero(0.0)) continue;
        body.position += x;
        body.velocity += v;
        body.angularVelocity += w;
        for (int half : {kLeft, kRight}) {
            copies_[half][s] = body;
            ++staticVersions_[half][s].value;
        }
    }
}


void ContactSweeps::run(const std::vector<Contact>& contacts, const std::vector<std::size_t>& first,
                        const std::vector<Mat3>& invI, std::vector<Body>& bodies, std::vector<PointImpulse>& sums,
                        int sweeps, bool skipIdle, SecondThread* second, const Start* start) {
    split(contacts, first, invI, bodies, sums);
    const bool cut = halves_.cutInTwo();
    if (start != nullptr) {
        warmStart(contacts, *start, bodies, second);
    } else {
        for (Part& part : parts_) measure(part, contacts, nullptr);
    }
    const std::function<void()> left = [this, skipIdle] { solve(parts_[Halves::kLeft], skipIdle); };
    const std::function<void()> right = [this, skipIdle] { solve(parts_[Halves::kRight], skipIdle); };
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        if (cut) bothHalves(left, right, bodies, second);
        solve(parts_[Halves::kMiddle], skipIdle);
    }
    for (const Part& part : parts_) {
        for (const Job& job : part.jobs) {
            for (int k = 0; k < job.contact->pointCount; ++k) sums[job.global + k] = part.sums[job.point + k];
        }
    }
}

void ContactSweeps::warmStart(const std::vector<Contact>& contacts, const Start& start, std::vector<Body>& bodies,
                              SecondThread* second) {
    measure(parts_[Halves::kMiddle], contacts, &start);  // its bodies are the halves': before their warm starts
    if (halves_.cutInTwo()) {
        Part& left = parts_[Halves::kLeft];
        Part& right = parts_[Halves::kRight];
        const std::function<void()> mine = [&] {
            measure(left, contacts, &start);
            applyWarmStarts(left);
        };
        const std::function<void()> theirs = [&] {
            measure(right, contacts, &start);
            applyWarmStarts(right);
        };
        bothHalves(mine, theirs, bodies, second);
    }
    applyWarmStarts(parts_[Halves::kMiddle]);
}

void ContactSweeps::bothHalves(const std::function<void()>& left, const std::function<void()>& right,
                               std::vector<Body>& bodies, SecondThread* second) {
    if (second != nullptr) {
        second->run(true, left, right);
    } else {
        left();
        right();
    }
    halves_.mergeStatics(bodies);
}

void ContactSweeps::measure(Part& part, const std::vector<Contact>& contacts, const Start* start) {
    std::array<double, kMaxContactPoints> closing;
    closing.fill(0.0);
    for (const Job& job : part.jobs) {
        if (start != nullptr) {
            (*start)(static_cast<std::size_t>(job.contact - contacts.data()), *job.a, *job.b, &part.sums[job.point],
                     closing.data());
        }
        for (int k = 0; k < job.contact->pointCount; ++k) {
            ContactPoint& point = part.points[job.point + k];
            point = prepareContactPoint(*job.contact, k, *job.a, *job.b, *job.invIa, *job.invIb,
                                        part.sums[job.point + k].approach);
            mayCloseGap(point, closing[k]);
        }
    }
}

void ContactSweeps::applyWarmStarts(Part& part) {
    for (const Job& job : part.jobs) {
        for (int k = 0; k < job.contact->pointCount; ++k) {
            const std::size_t i = job.point + k;
            const PointImpulse& s = part.sums[i];
            if (holdsImpulse(s)) applyWarmStart(part.points[i], *job.a, *job.b, s);
        }
    }
}

void ContactSweeps::split(const std::vector<Contact>& contacts, const std::vector<std::size_t>& first,
                          const std::vector<Mat3>& invI, std::vector<Body>& bodies,
                          const std::vector<PointImpulse>& sums) {
    if (sums.size() < kSplitFrom) {
        halves_.whole(bodies.size());
    } else {
        halves_.cut(bodies, contacts);
    }
    for (Part& part : parts_) {
        part.jobs.clear();
        part.sums.clear();
    }
    for (std::size_t c = 0; c < contacts.size(); ++c) {
        const Contact& con = contacts[c];
        const int p = halves_.part(con.a, con.b);
        Part& part = parts_[p];
        part.jobs.push_back({&con, &halves_.body(p, con.a, bodies), &halves_.body(p, con.b, bodies), &invI[con.a],
                             &invI[con.b], &halves_.version(p, con.a), &halves_.version(p, con.b), part.sums.size(),
                             first[c]});
        const auto from = sums.begin() + static_cast<std::ptrdiff_t>(first[c]);
        part.sums.insert(part.sums.end(), from, from + con.pointCount);
    }
    for (Part& part : parts_) {
        part.points.resize(part.sums.size());
        part.records.assign(part.sums.size(), Record{});
        part.shared.clear();
    }
    if (!halves_.cutInTwo()) return;
    // The bodies of the pairs across the cut: the middle writes them, and so does each one's half.
    inMiddle_.assign(bodies.size(), 0);
    for (const Job& job : parts_[Halves::kMiddle].jobs) {
        for (const std::size_t i : {job.contact->a, job.contact->b}) {
            if (inMiddle_[i]) continue;
            inMiddle_[i] = 1;
            parts_[Halves::kMiddle].shared.push_back(&bodies[i]);
            parts_[halves_.part(i, i)].shared.push_back(&bodies[i]);
        }
    }
}

void ContactSweeps::solve(Part& part, bool skipIdle) {
    // The bodies the other thread wrote last are asked for at once, not each when the solve reaches
    // it: their first two cache lines (the velocities, which the sweeps write; body.h).
    for (const Body* b : part.shared) {
        __builtin_prefetch(b, 1);
        __builtin_prefetch(reinterpret_cast<const char*>(b) + 64, 1);
    }
    const std::size_t jobs = part.jobs.size();
    for (std::size_t j = 0; j < jobs; ++j) {
        // The bodies of a contact a few ahead are asked for now: what the kernels read and write of
        // them (the velocities) is then in the cache when the solve reaches them.
        if (j + kAhead < jobs) {
            const Job& next = part.jobs[j + kAhead];
            prefetchBody(next.a);
            prefetchBody(next.b);
        }
        const Job& job = part.jobs[j];
        // A contact is solved whole, as in the plain loop (friction.cpp), and skipped whole. Its
        // first point holds the contact's record.
        Record& record = part.records[job.point];
        std::uint32_t& versionA = *job.versionA;
        std::uint32_t& versionB = *job.versionB;
        if (skipIdle && record.idle && record.seenA == versionA && record.seenB == versionB) continue;
        Body& a = *job.a;
        Body& b = *job.b;
        const Velocities wereA(a), wereB(b);
        const bool sumsChanged =
            solveContact(&part.points[job.point], &part.sums[job.point], job.contact->pointCount, a, b);
        const bool aChanged = wereA.differ(a);
        const bool bChanged = wereB.differ(b);
        if (aChanged) ++versionA;  // written only on a change: a store would claim the line
        if (bChanged) ++versionB;
        record = {versionA, versionB, !aChanged && !bChanged && !sumsChanged};
    }
}

void sweepContacts(const std::vector<Contact>& contacts, const std::vector<std::size_t>& first,
                   const std::vector<Mat3>& invI, std::vector<Body>& bodies, std::vector<PointImpulse>& sums,
                   int sweeps, bool skipIdle) {
    ContactSweeps().run(contacts, first, invI, bodies, sums, sweeps, skipIdle);
}

}  // namespace gpl
