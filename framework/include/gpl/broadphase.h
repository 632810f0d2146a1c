// The broad phase: which pairs of bodies may touch, found without testing every pair.
//
// Sort and sweep: every finite body (sphere, box) gets an axis-aligned bounding box; the boxes are
// sorted along the axis on which the bodies spread most, and a sweep along it tests only boxes
// whose intervals overlap there. Static planes are infinite: each pairs with every movable body
// whose box reaches the plane. Two static bodies never pair. The result is exactly the pairs whose
// bounding volumes overlap (bruteForcePairs() tests every pair the same way), in the same order.
//
// A margin grows every box by a fraction of its body's size (the radius, or a box's smallest half
// extent), so that the pairs also hold bodies that are about to touch: the contact stages look for
// new overlaps among them while they move bodies apart.
//
// With two threads (setThreads(), the default where the machine has two cores) a large sweep is
// split in two halves that run at once; the pairs are sorted after, so the result is the same.
#pragma once

#include <cstddef>
#include <vector>

#include "gpl/body.h"

namespace gpl {

/// Two bodies by index, a < b.
struct BodyPair {
    std::size_t a = 0;
    std::size_t b = 0;
    bool operator==(const BodyPair& o) const { return a == o.a && b == o.b; }
    bool operator<(const BodyPair& o) const { return a < o.a || (a == o.a && b < o.b); }
};

/// Axis-aligned bounding box of a sphere or a box in world coordinates (m).
struct Aabb {
    Vec3 min = Vec3::Zero();
    Vec3 max = Vec3::Zero();
};
/// The box grown on every side by `margin` times the body's size (radius or smallest half extent).
Aabb boundingBox(const Body& body, double margin = 0.0);

class BroadPhase {
public:
    /// Pairs whose bounding volumes, grown by `margin` times each body's size, overlap (touching
    /// counts), sorted by (a, b). The buffers are kept between calls, so a step allocates nothing
    /// once the scene has settled.
    const std::vector<BodyPair>& findPairs(const std::vector<Body>& bodies, double margin = 0.0);
    /// Threads the sweep may use (1 or 2; more count as 2). It uses two only from kParallelFrom
    /// bodies on, where the second thread costs less than it saves.
    void setThreads(int threads) { threads_ = threads < 2 ? 1 : 2; }
    int threads() const { return threads_; }
    static constexpr std::size_t kParallelFrom = 2048;

private:
    /// A body's box as the sweep reads it: packed and sorted, so the inner loop walks memory in order
    /// and never touches the (large) bodies themselves.
    struct Entry {
        double lo, hi;  ///< the box's extent along the sweep axis
        Aabb box;
        std::size_t index;
        bool isStatic;
    };
    std::vector<Entry> entries_;
    std::vector<std::size_t> planes_;
    std::vector<BodyPair> pairs_;
    std::vector<BodyPair> secondHalf_;  ///< the second thread's pairs
    int threads_ = defaultThreads();

    /// The sweep over entries_[first, last), each against the entries after it, into pairs.
    void sweep(std::size_t first, std::size_t last, std::vector<BodyPair>& pairs) const;
    static int defaultThreads();
};

/// The same pairs by testing every pair of bodies: O(N^2), for tests and as the definition.
std::vector<BodyPair> bruteForcePairs(const std::vector<Body>& bodies, double margin = 0.0);

}  // namespace gpl
