// The broad phase: which pairs of bodies may touch, found without testing every pair.
//
// Every finite body (sphere, box) gets an axis-aligned bounding box. Up to a few hundred bodies,
// sort and sweep: the boxes are sorted along the axis on which they spread most, and each is tested
// only against those that begin before it ends there. From kGridFrom bodies on, where the sweep's
// slabs hold ever more boxes (a thousand spheres in a heap: 5 times the grid's time), a uniform
// grid of cells as wide as the largest box: each box is filed under the cell of its centre, and
// tested only against the boxes of its own and the neighbouring cells, each pair once. A body
// larger than kLargeSizes median boxes (or far outside the grid's range) is tested against every
// other body instead, so that one large body does not make every cell large. Static planes are
// infinite: each pairs with every movable body whose box reaches the plane. Two static bodies never
// pair. Two finite bodies pair only when their bounding balls meet as well as their boxes: the boxes
// of two spheres side by side at a slant overlap in their corners (in a settled heap of spheres, a
// third of the pairs of boxes), the boxes of two turned boxes where neither box reaches, and every
// pair found costs the contact stages a kernel call or more. The result
// is exactly the pairs whose bounding volumes overlap (bruteForcePairs() tests every pair the same
// way), sorted. The work grows with the number of bodies, not with the size of the scene.
//
// A margin grows every box and ball by a fraction of its body's size (the radius, or a box's
// smallest half extent), so that the pairs also hold bodies that are about to touch: the contact
// stages look for new overlaps among them while they move bodies apart.
//
// Pairs are kept from one call to the next. Each call finds them for boxes grown by a skin as
// well (kSkin times the body's size on every side, and as far as the body's velocity carries it in
// `ahead` seconds), keeps those and the grown boxes, and answers the next calls from them for as
// long as every body's box stays inside its grown one, the bodies and the margin are the same, and
// no static body has changed: a pair that overlaps then overlaps with the grown boxes too, so
// testing the kept pairs again gives exactly the pairs of searching anew, in the same order. When
// a few bodies (up to kUpdateAtMost) have left their grown boxes and nothing else has changed,
// those get grown boxes anew and their kept pairs are found again against every other body's grown
// box (update()): the kept pairs then again hold every pair of grown boxes that overlap, and the
// answer is the same. In a settled heap most calls that would search anew find one to a dozen
// bodies out.
//
// With two threads (setThreads(), the default where the machine has two cores) and a SecondThread
// handed to findPairs() (the engine's), the grid tests its boxes in two halves at once; the pairs
// are sorted after, so the result is the same.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "gpl/body.h"
#include "gpl/second_thread.h"

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

/// A body's bounding ball, grown by the margin as its box is: a sphere's is the sphere itself, a
/// box's the ball through its corners; a plane has none (radius < 0).
struct Ball {
    Vec3 centre = Vec3::Zero();  ///< m
    double radius = -1.0;        ///< m
};

class BroadPhase {
public:
    /// Pairs whose bounding volumes, grown by `margin` times each body's size, overlap (touching
    /// counts), sorted by (a, b). The buffers are kept between calls, so a step allocates nothing
    /// once the scene has settled.
    /// `second`: the thread that tests half the boxes with two threads (see setThreads()); without
    /// one, this one tests them all.
    /// `ahead` (s): how far along its velocity the grown box reaches (the engine: a few time steps).
    const std::vector<BodyPair>& findPairs(const std::vector<Body>& bodies, double margin = 0.0,
                                           SecondThread* second = nullptr, double ahead = 0.0);
    /// Calls so far that searched anew (the others answered from the kept pairs).
    std::size_t searches() const { return searches_; }
    /// Calls so far that updated the kept pairs of a few bodies out of their grown boxes.
    std::size_t updates() const { return updates_; }
    /// Threads the grid's tests may use (1 or 2; more count as 2).
    void setThreads(int threads) { threads_ = threads < 2 ? 1 : 2; }
    int threads() const { return threads_; }
    /// From this many finite bodies on, the grid, on two threads where it may (below, sort and
    /// sweep on one: as fast there, and handing work over would cost more than it saves).
    static constexpr std::size_t kGridFrom = 512;
    /// In the grid, a body larger than this many times the median body is tested against every other.
    static constexpr double kLargeSizes = 4.0;
    /// The skin of the kept pairs' boxes, in times each body's size (as the margin).
    static constexpr double kSkin = 0.2;
    /// Bodies out of their grown boxes up to which a call updates their kept pairs (each tested
    /// against every other body) rather than searching anew.
    static constexpr std::size_t kUpdateAtMost = 32;

private:
    /// A body's box.
    struct Entry {
        Aabb box;
        std::size_t index;
        bool isStatic;
    };
    /// The grid's cell of a box's centre: the cell's packed coordinates and the entry.
    struct Filed {
        std::uint64_t cell;
        std::uint32_t entry;
        bool operator<(const Filed& o) const { return cell < o.cell || (cell == o.cell && entry < o.entry); }
    };
    /// A box as the sweep tests it, packed in the sweep's order.
    struct Swept {
        Aabb box;
        std::size_t index;
        bool isStatic;
    };
    std::vector<Entry> entries_;
    std::vector<std::uint32_t> order_;  ///< entries_ sorted along the sweep's axis, kept for the next call
    int orderAxis_ = -1;                ///< the axis order_ is sorted along
    std::vector<Swept> swept_;  ///< the boxes in the sweep's order, or in the grid's (filed_)
    std::vector<Filed> filed_;
    std::vector<std::size_t> large_;  ///< entries tested against every other entry
    std::vector<double> sizes_;       ///< each entry's largest extent (m), for the grid's cell size
    std::vector<std::size_t> planes_;
    std::vector<BodyPair> pairs_;
    std::vector<BodyPair> placed_;      ///< sortPairs()'s output, swapped with pairs_
    std::vector<std::size_t> pairOrder_;  ///< sortPairs()'s order of pairs_ (orderByPair())
    std::vector<std::size_t> firsts_;     ///< sortPairs()'s range per first body
    std::vector<std::size_t> cursor_;     ///< sortPairs()'s place per first body
    std::vector<BodyPair> secondHalf_;  ///< the second thread's pairs
    // What the kept pairs were found for: per body its grown box (planes: their position and normal
    // as min and max) and its kind (kindOf()), the margin, and the pairs of the grown boxes.
    std::vector<Aabb> grown_;
    std::vector<char> kind_;
    std::vector<Aabb> now_;  ///< this call's boxes with the margin alone, per body
    std::vector<Ball> balls_;  ///< and the balls, likewise
    double grownMargin_ = -1.0;
    std::vector<BodyPair> kept_;
    std::vector<std::size_t> out_;  ///< this call's bodies out of their grown boxes
    std::vector<char> left_;        ///< per body: in out_ (update()'s)
    std::vector<BodyPair> fresh_;   ///< update()'s new pairs
    std::size_t searches_ = 0;
    std::size_t updates_ = 0;
    int threads_ = defaultThreads();

    /// True when nothing but the bodies' boxes has changed since the kept pairs were found (see
    /// the head of this file); fills now_, balls_ and out_.
    bool sameScene(const std::vector<Body>& bodies, double margin);
    /// Grown boxes anew for the bodies of out_, and their kept pairs found again against every
    /// other body's grown box.
    void update(const std::vector<Body>& bodies, double margin, double ahead);
    /// A body's box grown by the skin and along its velocity.
    static Aabb grownBox(const Body& body, double margin, double ahead);
    /// pairs_: the kept pairs whose boxes in now_ overlap (or reach their plane).
    void filterKept();
    /// The pairs of entries_ by sort and sweep, into pairs_.
    void sweep();
    /// The sweep's tests of the boxes swept_[first, last) against those after them, into pairs.
    void sweepFrom(int axis, std::size_t first, std::size_t last, std::vector<BodyPair>& pairs) const;
    /// Sorts order_ by the boxes' lower ends along the axis, starting from the last call's order.
    void sortAlong(int axis);
    /// Sorts pairs_ by (a, b) for a scene of this many bodies.
    void sortPairs(std::size_t bodies);
    /// The pairs of entries_ by the grid, into pairs_; half of them on `second` when it is given.
    void grid(SecondThread* second);
    /// Tests the boxes filed_[first, last) against their neighbours after them, into pairs.
    void testNeighbours(std::size_t first, std::size_t last, std::vector<BodyPair>& pairs) const;
    static int defaultThreads();
};

/// The same pairs by testing every pair of bodies: O(N^2), for tests and as the definition.
std::vector<BodyPair> bruteForcePairs(const std::vector<Body>& bodies, double margin = 0.0);

}  // namespace gpl
