// Two halves of a large contact stage, for two threads (the friction stage's sweeps).
//
// The movable bodies of the stage's pairs are cut at their median along the axis on which they
// spread most. A pair whose movable bodies lie on one side belongs to that half, one across the cut
// to the middle. A stage solves the two halves (at once, on a SecondThread), then the middle. The
// halves share no movable body, and each has its own copies of the static bodies: a correct kernel
// never changes a static body (its inverse mass and inertia are zero), and what a wrong one does to a
// copy reaches the body when the halves are done (mergeStatics()), as it would without the cut. One
// half after the other gives the same result to the bit, and the cut depends on the bodies alone,
// never on the threads.
//
// Each half solves its movable bodies where they are, in the engine's array (each body on cache lines
// of its own), not in packed copies: copying the bodies in and out costs more than it saves.
//
// Each body also has a version that counts its changes, kept per side (a thread writes only its own
// side's), for stages that skip what nothing has changed since it was last looked at.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "gpl/body.h"

namespace gpl {

class Halves {
public:
    static constexpr int kLeft = 0, kRight = 1, kMiddle = 2, kNone = 3;

    /// Cuts the movable bodies of `pairs` (anything with body indices .a and .b).
    template <class Pair>
    void cut(const std::vector<Body>& bodies, const std::vector<Pair>& pairs) {
        begin(bodies);
        for (const Pair& p : pairs) see(bodies, p.a), see(bodies, p.b);
        finish(bodies);
        for (const Pair& p : pairs) {
            if (side_[p.a] == kNone || side_[p.b] == kNone) registerStatics(p.a, p.b);  // most pairs have none
        }
        copyStatics(bodies);
    }
    /// No cut: every body on one side, every pair in the middle (a small stage).
    void whole(std::size_t bodies);

    /// The part of a pair of bodies: kLeft, kRight or kMiddle (a pair of two static bodies: kNone).
    int part(std::size_t a, std::size_t b) const {
        if (!cut_) return kMiddle;
        const int sa = side_[a], sb = side_[b];
        return sa == kNone ? sb : sb == kNone ? sa : sa == sb ? sa : kMiddle;
    }
    /// Body i as part `part` sees it: in a half, the half's copy of a static body; otherwise the body.
    Body& body(int part, std::size_t i, std::vector<Body>& bodies) {
        if (part == kMiddle || side_[i] != kNone) return bodies[i];
        return copies_[part][local_[i]];
    }
    /// Body i's version as part `part` sees it (its copy's for a static body in a half).
    std::uint32_t& version(int part, std::size_t i) {
        if (side_[i] == kNone) return part == kMiddle ? uncounted_ : staticVersions_[part][local_[i]].value;
        return versions_[side_[i]][local_[i]];
    }
    /// After the halves: what they did to their copies of the static bodies reaches the bodies, and
    /// the copies start again from the bodies.
    void mergeStatics(std::vector<Body>& bodies);
    bool cutInTwo() const { return cut_; }

private:
    bool cut_ = false;
    /// What version() gives for a body of no side in the middle, where no pair has one (a pair of a
    /// static body belongs to its other body's half): never compared, but never out of range.
    std::uint32_t uncounted_ = 0;
    std::vector<int> side_;                     ///< per body: kLeft, kRight, or kNone (static)
    std::vector<std::size_t> local_;            ///< per body: its place in its side's members_ (or statics_)
    std::array<std::vector<std::size_t>, 2> members_;     ///< per side, its movable bodies
    std::array<std::vector<std::uint32_t>, 2> versions_;  ///< per side, per movable body
    std::vector<std::size_t> movable_;          ///< the movable bodies of the pairs
    std::vector<double> along_;                 ///< their coordinates along the cut's axis
    std::vector<std::size_t> statics_;          ///< the static bodies of the halves' pairs
    std::array<std::vector<Body>, 2> copies_;   ///< per half, its copies of statics_
    /// A copy's version on a cache line of its own: both halves count changes to their copies of the
    /// same static body at once, and two counters on one line would pass it between the cores.
    struct alignas(64) LineVersion {
        std::uint32_t value = 0;
    };
    std::array<std::vector<LineVersion>, 2> staticVersions_;  ///< per half, per copy

    void begin(const std::vector<Body>& bodies);
    void see(const std::vector<Body>& bodies, std::size_t i) {
        if (bodies[i].isStatic() || side_[i] != kNone) return;
        side_[i] = kLeft;  // seen; its side follows in finish()
        movable_.push_back(i);
    }
    void finish(const std::vector<Body>& bodies);
    void registerStatics(std::size_t a, std::size_t b);
    void copyStatics(const std::vector<Body>& bodies);
};

}  // namespace gpl
