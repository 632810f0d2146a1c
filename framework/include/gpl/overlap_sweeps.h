// The interpenetration stage's sweeps over the near pairs (interpenetration.cpp): each sweep tests
// every pair with collide() and moves an overlapping one apart with resolveInterpenetration().
//
// A pair found apart stays apart until one of its bodies moves (the kernels are pure), so it is not
// tested again before that: every body has a version that counts its moves, and a pair found apart
// keeps its bodies' versions of that moment.
//
// From kSplitFrom pairs on, each sweep moves the two Halves (halves.h) of the pairs, then the pairs
// across the cut; with a SecondThread the two halves at once. One half after the other gives the
// same state to the bit, so one thread and two agree. Below, every pair is in one part, in the
// order of the broad phase.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "gpl/body.h"
#include "gpl/broadphase.h"
#include "gpl/contact.h"
#include "gpl/halves.h"
#include "gpl/second_thread.h"

namespace gpl {

class OverlapSweeps {
public:
    /// Near pairs from which the stage is cut in halves: below, a half's work would not pay for
    /// handing it over.
    static constexpr std::size_t kSplitFrom = 2048;

    /// Before the first sweep: the pairs' parts, in halves when there are kSplitFrom pairs or more
    /// and `mayCut` (a stage that also moves bodies between the sweeps, as ropes do, says false).
    /// inContacts[k]: pair k has a contact in the step's contacts already (the detection found it).
    /// With skipApart false every pair is tested in every sweep (for tests: the state is the same).
    void begin(const std::vector<BodyPair>& pairs, const std::vector<char>& inContacts, std::vector<Body>& bodies,
               bool mayCut, bool skipApart = true);
    /// One sweep; an overlap found in a pair without a contact yet is appended to `contacts` (the
    /// halves' after the sweep, left then right, then the middle's as found). True when any pair
    /// overlapped.
    bool sweep(std::vector<Body>& bodies, std::vector<Contact>& contacts, SecondThread* second);
    /// Body i was moved between the sweeps (only without a cut): its pairs are tested again.
    void moved(std::size_t i) { ++halves_.version(Halves::kMiddle, i); }
    /// After the last sweep: which pairs now have a contact.
    void end(std::vector<char>& inContacts) const;

private:
    /// What one part moves, in arrays of its own (a second thread writes nothing the first reads).
    struct alignas(64) Part {  // on cache lines of its own: the two threads write their parts
        struct Pair {
            std::size_t k;  ///< the pair's index among the near pairs
            std::size_t a, b;
            Body* bodyA;  ///< the bodies as the part sees them (a half's copy of a static body)
            Body* bodyB;
            std::uint32_t* versionA;  ///< their versions (moves counted)
            std::uint32_t* versionB;
        };
        std::vector<Pair> pairs;
        std::vector<std::uint32_t> seenA, seenB;  ///< per pair: its bodies' versions when it was found apart
        std::vector<char> apart;                  ///< per pair: found apart, and not tested since
        std::vector<char> inContacts;             ///< per pair: has a contact in the step's contacts
        std::vector<Contact> found;               ///< a half's new contacts of this sweep
        bool overlapping = false;
    };
    std::array<Part, 3> parts_;  ///< left half, right half, middle
    Halves halves_;
    bool skipApart_ = true;

    /// One sweep over a part's pairs; new contacts go to `contacts`.
    static void move(Part& part, std::vector<Contact>& contacts, bool skipApart);
};

}  // namespace gpl
