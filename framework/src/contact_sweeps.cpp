// The friction stage's sweeps (friction.h): applyNormalImpulse() then applyFrictionImpulse() at every
// contact point, contactIterations() times, with idle points skipped; a large stage in two Halves.
//
// Skipping: per body, a version that counts its changes; per point, the versions of its two bodies
// when it was last solved, and whether that solve changed nothing. Such a point is skipped while
// both versions stand: the kernels are pure, so solving it again would change nothing.
#include <functional>

#include "gpl/friction.h"

namespace gpl {

void ContactSweeps::run(const std::vector<Contact>& contacts, const std::vector<std::size_t>& first,
                        const std::vector<Mat3>& invI, std::vector<Body>& bodies, std::vector<PointImpulse>& sums,
                        int sweeps, bool skipIdle, SecondThread* second) {
    split(contacts, first, invI, bodies, sums);
    const std::function<void()> left = [this, skipIdle] { solve(parts_[Halves::kLeft], skipIdle); };
    const std::function<void()> right = [this, skipIdle] { solve(parts_[Halves::kRight], skipIdle); };
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        if (halves_.cutInTwo()) {
            if (second != nullptr) {
                second->run(true, left, right);
            } else {
                left();
                right();
            }
            halves_.mergeStatics(bodies);
        }
        solve(parts_[Halves::kMiddle], skipIdle);
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

void sweepContacts(const std::vector<Contact>& contacts, const std::vector<std::size_t>& first,
                   const std::vector<Mat3>& invI, std::vector<Body>& bodies, std::vector<PointImpulse>& sums,
                   int sweeps, bool skipIdle) {
    ContactSweeps().run(contacts, first, invI, bodies, sums, sweeps, skipIdle);
}

}  // namespace gpl
