// The fluids' neighbour search (worksheet 9): every particle's neighbours, the other particles
// nearer to it than the smoothing length h, from a uniform grid of cells of side h.
//
// find() files the particles under their cells by a counting sort (count the particles of each
// cell, sum the counts into each cell's first entry, then place each particle), so that the
// particles of a cell lie together; each particle then tests only the particles of its own cell
// and the 26 around it (their positions read from a copy sorted by cell, one after another in
// memory), since a particle nearer than h lies at most one cell away. Of those 27, a cell whose
// nearest point lies h or farther from the particle is left out (about 6 on average), and the
// cells of a row that remain lie one after another in that order, so each row is one run of
// candidates; each candidate is written to the particle's row and kept or not by its test, without
// a branch (a candidate is a neighbour about once in six, which no branch predictor guesses). With
// a SecondThread, the two halves of the particles find their neighbours on two threads, each into a
// list of its own that is then joined: the same lists as on one thread. The grid spans the
// particles' bounding box; where that box is so large for the particles' number that the cells
// would outnumber them many times (a few particles flung far away), the cells grow wider than h,
// which keeps the search exact and its memory bounded. The neighbours are kept as one list per
// particle (compressed rows: particle i's are list()[start(i)] to list()[start(i + 1) - 1]), in the
// order of their cells, and within a cell ascending. Buffers are kept from call to call: once they
// have grown, find() allocates nothing.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "gpl/math.h"

namespace gpl {

class SecondThread;

class ParticleGrid {
public:
    /// Finds the neighbours of every point: the others at a distance below h (m, > 0; finite
    /// points). A point at exactly h is not a neighbour (the kernels vanish there).
    /// second: the thread that searches for the second half of the points (nullptr: all here).
    void find(const std::vector<Vec3>& points, double h, SecondThread* second = nullptr);

    /// Particle i's neighbours: indices list()[start(i)] .. list()[start(i + 1) - 1].
    std::uint32_t start(std::size_t i) const { return start_[i]; }
    std::uint32_t count(std::size_t i) const { return start_[i + 1] - start_[i]; }
    /// The rows one after another; entries from total() on are spare room kept for the next search.
    const std::vector<std::uint32_t>& list() const { return list_; }
    /// Neighbour pairs counted twice (i's list holds j and j's holds i).
    std::size_t total() const { return total_; }
    /// The grid of the last search: cells along each axis and the cells' side (m, >= h).
    const std::array<int, 3>& cells() const { return cells_; }
    double cellSide() const { return side_; }

private:
    std::array<int, 3> cells_{0, 0, 0};
    double side_ = 0.0;
    Vec3 origin_ = Vec3::Zero();
    std::vector<std::uint32_t> cellOf_;      ///< per point: its cell
    std::vector<std::uint32_t> cellStart_;   ///< per cell + 1: its first entry in sorted_
    std::vector<std::uint32_t> sorted_;      ///< the points ordered by cell
    std::vector<Vec3> sortedPoints_;         ///< their positions in the same order
    std::vector<std::uint32_t> start_;       ///< per point + 1: its first neighbour in list_
    std::vector<std::uint32_t> list_;        ///< every point's neighbours, one row after another
    std::size_t total_ = 0;                  ///< the entries of list_ in use
    std::vector<std::uint32_t> secondList_;  ///< the second half's rows while two threads search

    /// The neighbours of points [begin, end) into `out` from its start (it grows as needed and never
    /// shrinks), and start_[i + 1] for each: the entries of `out` up to its row's end. Returns the
    /// entries written.
    std::size_t search(const std::vector<Vec3>& points, double h, std::size_t begin, std::size_t end,
                       std::vector<std::uint32_t>& out);
};

}  // namespace gpl
