// The friction stage's sweeps (friction.h): applyNormalImpulse() then applyFrictionImpulse() at every
// contact point, contactIterations() times, with idle points skipped.
//
// A stage of kSplitFrom points or more is cut in two halves, at the median of its movable bodies
// along the axis on which they spread most. A contact whose movable bodies lie on one side belongs
// to that half; one across the cut belongs to the middle. Each sweep solves the two halves, then the
// middle. The halves share no movable body, and each has its own copies of the static bodies and
// its own arrays, so they can be solved at the same time on two threads; one after the other they
// give the same result to the bit. The cut depends on the contacts alone, never on the threads.
//
// Skipping: per body, a version that counts its changes; per point, the versions of its two bodies
// when it was last solved, and whether that solve changed nothing. Such a point is skipped while
// both versions stand: the kernels are pure, so solving it again would change nothing.
#include <algorithm>
#include <functional>
#include <limits>

#include "gpl/friction.h"

namespace gpl {

void ContactSweeps::run(const std::vector<Contact>& contacts, const std::vector<std::size_t>& first,
                        const std::vector<Mat3>& invI, std::vector<Body>& bodies, std::vector<PointImpulse>& sums,
                        int sweeps, bool skipIdle, SecondThread* second) {
    split(contacts, first, invI, bodies, sums);
    const bool halves = !parts_[kLeft].jobs.empty() || !parts_[kRight].jobs.empty();
    const std::function<void()> left = [this, skipIdle] { solve(parts_[kLeft], skipIdle); };
    const std::function<void()> right = [this, skipIdle] { solve(parts_[kRight], skipIdle); };
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        if (halves) {
            for (int half : {kLeft, kRight}) {
                for (std::size_t s = 0; s < statics_.size(); ++s) copies_[half][s] = bodies[statics_[s]];
            }
            if (second != nullptr) {
                second->run(true, left, right);
            } else {
                left();
                right();
            }
            mergeStatics(bodies);
        }
        solve(parts_[kMiddle], skipIdle);
    }
    for (const Part& part : parts_) {
        for (const Job& job : part.jobs) {
            for (int k = 0; k < job.contact->pointCount; ++k) sums[job.global + k] = part.sums[job.point + k];
        }
    }
}

void ContactSweeps::split(const std::vector<Contact>& contacts, const std::vector<std::size_t>& first,
                          const std::vector<Mat3>& invI, std::vector<Body>& bodies,
                          const std::vector<PointImpulse>& sums) {
    const std::size_t n = bodies.size();
    side_.assign(n, kNone);
    local_.assign(n, 0);
    statics_.clear();
    std::vector<int> partOf(contacts.size(), kMiddle);
    if (sums.size() < kSplitFrom) {
        // One part, the middle, in the order of the contacts; every body on one side.
        versions_[kLeft].assign(n, 0);
        for (std::size_t i = 0; i < n; ++i) side_[i] = kLeft, local_[i] = i;
    } else {
        // The movable bodies in contact, each once, and their extent.
        movable_.clear();
        Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
        for (const Contact& c : contacts) {
            for (const std::size_t i : {c.a, c.b}) {
                if (bodies[i].isStatic() || side_[i] != kNone) continue;
                side_[i] = kLeft;  // seen
                movable_.push_back(i);
                lo = lo.cwiseMin(bodies[i].position);
                hi = hi.cwiseMax(bodies[i].position);
            }
        }
        int axis = 0;
        (hi - lo).maxCoeff(&axis);
        cut_.clear();
        for (const std::size_t i : movable_) cut_.push_back(bodies[i].position[axis]);
        const auto middle = cut_.begin() + static_cast<std::ptrdiff_t>(cut_.size() / 2);
        std::nth_element(cut_.begin(), middle, cut_.end());
        const double median = *middle;
        for (int half : {kLeft, kRight}) versions_[half].clear();
        for (const std::size_t i : movable_) {
            const int s = bodies[i].position[axis] < median ? kLeft : kRight;
            side_[i] = s;
            local_[i] = versions_[s].size();
            versions_[s].push_back(0);
        }
        for (std::size_t c = 0; c < contacts.size(); ++c) {
            const int sa = side_[contacts[c].a], sb = side_[contacts[c].b];
            partOf[c] = sa == kNone ? sb : sb == kNone ? sa : sa == sb ? sa : kMiddle;
            for (const std::size_t i : {contacts[c].a, contacts[c].b}) {
                if (side_[i] != kNone || std::find(statics_.begin(), statics_.end(), i) != statics_.end()) continue;
                local_[i] = statics_.size();
                statics_.push_back(i);
            }
        }
        for (int half : {kLeft, kRight}) {
            copies_[half].assign(statics_.size(), Body{});
            staticVersions_[half].assign(statics_.size(), 0);
        }
    }
    for (Part& part : parts_) {
        part.jobs.clear();
        part.sums.clear();
    }
    for (std::size_t c = 0; c < contacts.size(); ++c) {
        const int p = partOf[c];
        Part& part = parts_[p];
        Job job;
        job.contact = &contacts[c];
        const auto place = [&](std::size_t i, Body*& body, std::uint32_t*& version) {
            const bool copy = p != kMiddle && side_[i] == kNone;  // a static body in a half
            body = copy ? &copies_[p][local_[i]] : &bodies[i];
            version = copy ? &staticVersions_[p][local_[i]] : &versions_[side_[i]][local_[i]];
        };
        place(contacts[c].a, job.a, job.versionA);
        place(contacts[c].b, job.b, job.versionB);
        job.invIa = &invI[contacts[c].a];
        job.invIb = &invI[contacts[c].b];
        job.point = part.sums.size();
        job.global = first[c];
        part.jobs.push_back(job);
        part.sums.insert(part.sums.end(), sums.begin() + static_cast<std::ptrdiff_t>(first[c]),
                         sums.begin() + static_cast<std::ptrdiff_t>(first[c] + contacts[c].pointCount));
    }
    for (Part& part : parts_) {
        part.seenA.assign(part.sums.size(), 0);
        part.seenB.assign(part.sums.size(), 0);
        part.idle.assign(part.sums.size(), 0);
    }
}

void ContactSweeps::solve(Part& part, bool skipIdle) {
    for (const Job& job : part.jobs) {
        const Contact& con = *job.contact;
        Body& a = *job.a;
        Body& b = *job.b;
        std::uint32_t& versionA = *job.versionA;
        std::uint32_t& versionB = *job.versionB;
        for (int k = 0; k < con.pointCount; ++k) {
            const std::size_t i = job.point + k;
            if (skipIdle && part.idle[i] && part.seenA[i] == versionA && part.seenB[i] == versionB) continue;
            PointImpulse& s = part.sums[i];
            const PointImpulse sumWas = s;
            const Vec3 va = a.velocity, wa = a.angularVelocity, vb = b.velocity, wb = b.angularVelocity;
            applyNormalImpulse(con, k, *job.invIa, *job.invIb, a, b, s);
            applyFrictionImpulse(con, k, *job.invIa, *job.invIb, a, b, s);
            const bool aChanged = a.velocity != va || a.angularVelocity != wa;
            const bool bChanged = b.velocity != vb || b.angularVelocity != wb;
            versionA += aChanged ? 1 : 0;
            versionB += bChanged ? 1 : 0;
            part.seenA[i] = versionA;
            part.seenB[i] = versionB;
            part.idle[i] = !aChanged && !bChanged && s.normal == sumWas.normal && s.tangent == sumWas.tangent;
        }
    }
}

void ContactSweeps::mergeStatics(std::vector<Body>& bodies) {
    // A correct hook never changes a static body (its inverse mass and inertia are zero); what a
    // wrong one did to either half's copy reaches the body, as it would without the cut.
    for (std::size_t s = 0; s < statics_.size(); ++s) {
        Body& body = bodies[statics_[s]];
        const Body& left = copies_[kLeft][s];
        const Body& right = copies_[kRight][s];
        const Vec3 v = (left.velocity - body.velocity) + (right.velocity - body.velocity);
        const Vec3 w = (left.angularVelocity - body.angularVelocity) + (right.angularVelocity - body.angularVelocity);
        if (v.isZero(0.0) && w.isZero(0.0)) continue;
        body.velocity += v;
        body.angularVelocity += w;
        for (int half : {kLeft, kRight}) ++staticVersions_[half][s];
    }
}

void sweepContacts(const std::vector<Contact>& contacts, const std::vector<std::size_t>& first,
                   const std::vector<Mat3>& invI, std::vector<Body>& bodies, std::vector<PointImpulse>& sums,
                   int sweeps, bool skipIdle) {
    ContactSweeps().run(contacts, first, invI, bodies, sums, sweeps, skipIdle);
}

}  // namespace gpl
