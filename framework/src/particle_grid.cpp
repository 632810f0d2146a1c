// The fluids' neighbour search: a counting sort of the particles into a uniform grid, then each
// particle's 27 cells (particle_grid.h).
#include "gpl/particle_grid.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "gpl/second_thread.h"

namespace gpl {
namespace {
namespace neighbourgrid {

/// Most cells the grid has per particle: more would cost memory and time for empty cells.
constexpr double kCellsPerParticle = 4.0;

int cellCoordinate(double offset, double side, int cells) {
    return std::clamp(static_cast<int>(std::floor(offset / side)), 0, cells - 1);
}

}  // namespace neighbourgrid
}  // namespace

void ParticleGrid::find(const std::vector<Vec3>& points, double h, SecondThread* second) {
    using namespace neighbourgrid;
    assert(h > 0.0);
    const std::size_t n = points.size();
    start_.assign(n + 1, 0);
    total_ = 0;
    if (n == 0) return;

    // The grid: the points' bounding box in cells of side h, wider where they would be too many.
    Vec3 lower = points[0], upper = points[0];
    for (const Vec3& q : points) {
        lower = lower.cwiseMin(q);
        upper = upper.cwiseMax(q);
    }
    const Vec3 extent = upper - lower;
    side_ = h;
    const double most = kCellsPerParticle * static_cast<double>(n) + 64.0;
    while ((std::floor(extent.x() / side_) + 1) * (std::floor(extent.y() / side_) + 1) *
               (std::floor(extent.z() / side_) + 1) >
           most)
        side_ *= 2.0;
    origin_ = lower;
    for (int a = 0; a < 3; ++a) cells_[a] = static_cast<int>(std::floor(extent[a] / side_)) + 1;
    const std::size_t cellCount = static_cast<std::size_t>(cells_[0]) * cells_[1] * cells_[2];

    // Counting sort: each cell's count, then its first entry, then the points in place (ascending
    // within a cell), with a copy of their positions in the same order, so that the search below
    // reads a cell's positions one after another in memory.
    cellOf_.resize(n);
    cellStart_.assign(cellCount + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 offset = points[i] - origin_;
        const int cx = cellCoordinate(offset.x(), side_, cells_[0]);
        const int cy = cellCoordinate(offset.y(), side_, cells_[1]);
        const int cz = cellCoordinate(offset.z(), side_, cells_[2]);
        cellOf_[i] = static_cast<std::uint32_t>((cz * cells_[1] + cy) * cells_[0] + cx);
        ++cellStart_[cellOf_[i] + 1];
    }
    for (std::size_t c = 0; c < cellCount; ++c) cellStart_[c + 1] += cellStart_[c];
    sorted_.resize(n);
    sortedPoints_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t k = cellStart_[cellOf_[i]]++;
        sorted_[k] = static_cast<std::uint32_t>(i);
        sortedPoints_[k] = points[i];
    }
    // Placing moved each cell's start to its end, which is the next cell's start: shift back.
    for (std::size_t c = cellCount; c > 0; --c) cellStart_[c] = cellStart_[c - 1];
    cellStart_[0] = 0;

    // Each point's neighbours from its own cell and the 26 around it: on two threads, the second
    // half's into a list of its own, joined after the first half's.
    const std::size_t middle = second ? n / 2 : n;
    std::size_t used[2] = {0, 0};
    // Each half's function holds one reference, which std::function keeps without allocating.
    const auto half = [&](int which) {
        if (which == 0)
            used[0] = search(points, h, 0, middle, list_);
        else
            used[1] = search(points, h, middle, n, secondList_);
    };
    if (second) {
        second->run(
            true, [&half] { half(0); }, [&half] { half(1); });
        for (std::size_t i = middle; i < n; ++i) start_[i + 1] += static_cast<std::uint32_t>(used[0]);
        if (list_.size() < used[0] + used[1]) list_.resize(used[0] + used[1]);
        std::copy(secondList_.begin(), secondList_.begin() + static_cast<std::ptrdiff_t>(used[1]),
                  list_.begin() + static_cast<std::ptrdiff_t>(used[0]));
    } else {
        half(0);
    }
    total_ = used[0] + used[1];
}

std::size_t ParticleGrid::search(const std::vector<Vec3>& points, double h, std::size_t begin, std::size_t end,
                                 std::vector<std::uint32_t>& out) {
    const double h2 = h * h;
    // A cell is left out when the nearest of its points lies h or farther from the particle; the
    // margin keeps a cell whose points were filed across its face by rounding.
    const double margin =
        1e-9 * (side_ + origin_.cwiseAbs().maxCoeff() + side_ * cells_[0] + side_ * cells_[1] + side_ * cells_[2]);
    const auto squared = [](double gap) { return gap > 0.0 ? gap * gap : 0.0; };
    std::size_t used = 0;
    for (std::size_t i = begin; i < end; ++i) {
        const Vec3 q = points[i];
        const std::uint32_t cell = cellOf_[i];
        const int c[3] = {static_cast<int>(cell % cells_[0]), static_cast<int>(cell / cells_[0] % cells_[1]),
                          static_cast<int>(cell / cells_[0] / cells_[1])};
        // Per axis, the squared distance from q to the cell before its own and to the cell after it.
        double before[3], after[3];
        for (int a = 0; a < 3; ++a) {
            const double low = origin_[a] + side_ * c[a];
            before[a] = squared(q[a] - low - margin);
            after[a] = squared(low + side_ - q[a] - margin);
        }
        const auto gap = [&](int a, int k) { return k < c[a] ? before[a] : k > c[a] ? after[a] : 0.0; };
        // The runs of the rows (z, y) around the cell that come nearer than h: of each, the cells
        // from x0 to x1 that do (those of a row lie one after another in sorted_).
        std::uint32_t runBegin[9], runEnd[9];
        int runs = 0;
        std::size_t candidates = 0;
        for (int z = std::max(c[2] - 1, 0); z <= std::min(c[2] + 1, cells_[2] - 1); ++z) {
            for (int y = std::max(c[1] - 1, 0); y <= std::min(c[1] + 1, cells_[1] - 1); ++y) {
                const double across = gap(2, z) + gap(1, y);
                if (across >= h2) continue;
                const int x0 = c[0] > 0 && across + before[0] < h2 ? c[0] - 1 : c[0];
                const int x1 = c[0] < cells_[0] - 1 && across + after[0] < h2 ? c[0] + 1 : c[0];
                const std::size_t row = (static_cast<std::size_t>(z) * cells_[1] + y) * cells_[0];
                runBegin[runs] = cellStart_[row + x0];
                runEnd[runs] = cellStart_[row + x1 + 1];
                candidates += runEnd[runs] - runBegin[runs];
                ++runs;
            }
        }
        // Room for every candidate; each is written and kept when it is a neighbour.
        if (out.size() < used + candidates) out.resize(std::max(used + candidates, 2 * out.size()));
        std::uint32_t* row = out.data() + used;
        std::size_t found = 0;
        for (int r = 0; r < runs; ++r) {
            for (std::uint32_t k = runBegin[r]; k < runEnd[r]; ++k) {
                row[found] = sorted_[k];
                found += static_cast<std::size_t>((sortedPoints_[k] - q).squaredNorm() < h2) &
                         static_cast<std::size_t>(sorted_[k] != i);
            }
        }
        used += found;
        start_[i + 1] = static_cast<std::uint32_t>(used);
    }
    return used;
}

}  // namespace gpl
