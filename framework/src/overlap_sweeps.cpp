// The interpenetration stage's sweeps (overlap_sweeps.h): the near pairs tested and moved apart,
// a large stage in two Halves (halves.h) and the pairs across the cut.
#include "gpl/overlap_sweeps.h"

#include <functional>
#include <optional>

#include "gpl/collision.h"
#include "gpl/response.h"

namespace gpl {

void OverlapSweeps::begin(const std::vector<BodyPair>& pairs, const std::vector<char>& inContacts,
                          std::vector<Body>& bodies, bool mayCut, bool skipApart) {
    skipApart_ = skipApart;
    if (!mayCut || pairs.size() < kSplitFrom) {
        halves_.whole(bodies.size());
    } else {
        halves_.cut(bodies, pairs);
    }
    for (Part& part : parts_) part.pairs.clear();
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        const std::size_t a = pairs[k].a, b = pairs[k].b;
        int p = halves_.part(a, b);
        if (p > Halves::kMiddle) p = Halves::kMiddle;  // two static bodies: no contact, anywhere
        parts_[p].pairs.push_back({k, a, b, &halves_.body(p, a, bodies), &halves_.body(p, b, bodies),
                                   &halves_.version(p, a), &halves_.version(p, b)});
    }
    for (Part& part : parts_) {
        const std::size_t n = part.pairs.size();
        part.seenA.assign(n, 0);
        part.seenB.assign(n, 0);
        part.apart.assign(n, 0);
        part.inContacts.resize(n);
        for (std::size_t q = 0; q < n; ++q) part.inContacts[q] = inContacts[part.pairs[q].k];
    }
}

bool OverlapSweeps::sweep(std::vector<Body>& bodies, std::vector<Contact>& contacts, SecondThread* second) {
    bool overlapping = false;
    if (halves_.cutInTwo()) {
        Part& left = parts_[Halves::kLeft];
        Part& right = parts_[Halves::kRight];
        const std::function<void()> moveLeft = [this, &left] { move(left, left.found, skipApart_); };
        const std::function<void()> moveRight = [this, &right] { move(right, right.found, skipApart_); };
        left.found.clear();
        right.found.clear();
        if (second != nullptr) {
            second->run(true, moveLeft, moveRight);
        } else {
            moveLeft();
            moveRight();
        }
        halves_.mergeStatics(bodies);
        for (const Part* half : {&left, &right}) {
            contacts.insert(contacts.end(), half->found.begin(), half->found.end());
            overlapping |= half->overlapping;
        }
    }
    Part& middle = parts_[Halves::kMiddle];
    move(middle, contacts, skipApart_);
    return overlapping || middle.overlapping;
}

void OverlapSweeps::end(std::vector<char>& inContacts) const {
    for (const Part& part : parts_) {
        for (std::size_t q = 0; q < part.pairs.size(); ++q) inContacts[part.pairs[q].k] = part.inContacts[q];
    }
}

void OverlapSweeps::move(Part& part, std::vector<Contact>& contacts, bool skipApart) {
    part.overlapping = false;
    for (std::size_t q = 0; q < part.pairs.size(); ++q) {
        const Part::Pair& pair = part.pairs[q];
        std::uint32_t& versionA = *pair.versionA;
        std::uint32_t& versionB = *pair.versionB;
        if (skipApart && part.apart[q] && part.seenA[q] == versionA && part.seenB[q] == versionB) {
            continue;  // apart, and neither body has moved since
        }
        const std::optional<Contact> c = collide(*pair.bodyA, pair.a, *pair.bodyB, pair.b);
        part.apart[q] = !c;
        if (!c) {
            part.seenA[q] = versionA;
            part.seenB[q] = versionB;
            continue;
        }
        part.overlapping = true;
        // The kernels take the bodies in the contact's order (collide() may have swapped them).
        const bool swapped = c->a != pair.a;
        Body& a = swapped ? *pair.bodyB : *pair.bodyA;
        Body& b = swapped ? *pair.bodyA : *pair.bodyB;
        const Vec3 wasA = a.position, wasB = b.position;
        resolveInterpenetration(*c, a, b);
        // A version is written only on a move (a store would claim the line from the other thread).
        if (a.position != wasA) ++(swapped ? versionB : versionA);
        if (b.position != wasB) ++(swapped ? versionA : versionB);  // a static body never moves
        if (!part.inContacts[q]) contacts.push_back(*c);
        part.inContacts[q] = 1;
    }
}

}  // namespace gpl
