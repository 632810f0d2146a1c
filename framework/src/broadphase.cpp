#include "gpl/broadphase.h"

#include <algorithm>
#include <cmath>
#include <thread>

namespace gpl {
namespace {

bool overlap(const Aabb& p, const Aabb& q) {
    return (p.min.array() <= q.max.array()).all() && (q.min.array() <= p.max.array()).all();
}

// True when some point of the box lies on or behind the plane through `origin` with unit normal n.
bool reachesPlane(const Aabb& box, const Vec3& origin, const Vec3& n) {
    const Vec3 centre = 0.5 * (box.min + box.max);
    const Vec3 half = 0.5 * (box.max - box.min);
    return n.dot(centre - origin) - n.cwiseAbs().dot(half) <= 0.0;
}

Vec3 planeNormal(const Body& plane) { return plane.orientation * plane.normal; }

// The brute force's pair test (the sweep makes the same two checks on its packed entries).
bool mayTouch(const Body& p, const Body& q, const Aabb& boxP, const Aabb& boxQ) {
    if (p.isStatic() && q.isStatic()) return false;
    return overlap(boxP, boxQ);
}

}  // namespace

Aabb boundingBox(const Body& b, double margin) {
    Vec3 half = Vec3::Zero();
    if (b.shape == Shape::Sphere) {
        half = Vec3::Constant((1.0 + margin) * b.radius);
    } else if (b.shape == Shape::Box) {
        half = b.orientation.toRotationMatrix().cwiseAbs() * b.halfExtents +
               Vec3::Constant(margin * b.halfExtents.minCoeff());
    }
    return {b.position - half, b.position + half};
}

namespace {

constexpr int kCellBits = 21;                          // per axis in a packed cell
constexpr long kCellRange = 1L << (kCellBits - 1);     // cells -kCellRange .. kCellRange - 1 per axis
constexpr int kLargeCells = 4;                         // more cells than this on an axis: a large body

std::uint64_t packCell(long x, long y, long z) {
    const auto bits = [](long c) { return static_cast<std::uint64_t>(c + kCellRange); };
    return bits(x) << (2 * kCellBits) | bits(y) << kCellBits | bits(z);
}

}  // namespace

const std::vector<BodyPair>& BroadPhase::findPairs(const std::vector<Body>& bodies, double margin,
                                                   SecondThread* second) {
    if (threads_ < 2) second = nullptr;
    pairs_.clear();
    entries_.clear();
    filed_.clear();
    large_.clear();
    planes_.clear();
    sizes_.clear();
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        if (bodies[i].shape == Shape::Plane) {
            planes_.push_back(i);
            continue;
        }
        const Aabb box = boundingBox(bodies[i], margin);
        entries_.push_back({box, i, bodies[i].isStatic(), Eigen::Vector3i::Zero(), Eigen::Vector3i::Zero()});
        sizes_.push_back((box.max - box.min).maxCoeff());
    }

    if (entries_.size() < kGridFrom) {
        sweep(second);
    } else {
        grid(second);
    }

    for (std::size_t plane : planes_) {
        const Vec3 normal = planeNormal(bodies[plane]);
        for (const Entry& e : entries_) {
            if (e.isStatic || !reachesPlane(e.box, bodies[plane].position, normal)) continue;
            pairs_.push_back({std::min(e.index, plane), std::max(e.index, plane)});
        }
    }
    sortPairs(bodies.size());
    return pairs_;
}

void BroadPhase::sortPairs(std::size_t bodies) {
    // Counted by the first body, placed in its range, then each body's few pairs by the second:
    // linear in bodies and pairs, where a comparison sort is not.
    firsts_.assign(bodies + 1, 0);
    for (const BodyPair& p : pairs_) ++firsts_[p.a + 1];
    for (std::size_t i = 0; i < bodies; ++i) firsts_[i + 1] += firsts_[i];
    placed_.resize(pairs_.size());
    for (const BodyPair& p : pairs_) placed_[firsts_[p.a]++] = p;  // firsts_[i] ends as the end of i's range
    for (std::size_t i = 0, begin = 0; i < bodies; begin = firsts_[i++]) {
        std::sort(placed_.begin() + static_cast<std::ptrdiff_t>(begin), placed_.begin() + static_cast<std::ptrdiff_t>(firsts_[i]));
    }
    pairs_.swap(placed_);
}

void BroadPhase::sweep(SecondThread* second) {
    // Along the axis on which the boxes spread most, sorted by their lower ends: each box is tested
    // only against the boxes that begin before it ends.
    Vec3 sum = Vec3::Zero(), sumSquares = Vec3::Zero();
    for (const Entry& e : entries_) {
        const Vec3 centre = 0.5 * (e.box.min + e.box.max);
        sum += centre;
        sumSquares += centre.cwiseProduct(centre);
    }
    const double n = static_cast<double>(entries_.size());
    const Vec3 variance = sumSquares / n - (sum / n).cwiseProduct(sum / n);
    int axis = 0;
    variance.maxCoeff(&axis);
    sortAlong(axis);

    // The boxes packed in that order, for the inner loop.
    swept_.clear();
    for (const std::uint32_t k : order_) swept_.push_back({entries_[k].box, entries_[k].index, entries_[k].isStatic});
    if (second != nullptr && swept_.size() >= kTwoThreadsFrom) {
        // Two halves of the boxes, each tested against those after it; sortPairs() orders the pairs.
        const std::size_t half = swept_.size() / 2;
        secondHalf_.clear();
        second->run(true, [this, axis, half] { sweepFrom(axis, 0, half, pairs_); },
                    [this, axis, half] { sweepFrom(axis, half, swept_.size(), secondHalf_); });
        pairs_.insert(pairs_.end(), secondHalf_.begin(), secondHalf_.end());
    } else {
        sweepFrom(axis, 0, swept_.size(), pairs_);
    }
}

void BroadPhase::sweepFrom(int axis, std::size_t first, std::size_t last, std::vector<BodyPair>& pairs) const {
    const int u = (axis + 1) % 3, w = (axis + 2) % 3;  // the other two axes
    for (std::size_t k = first; k < last; ++k) {
        const Swept& p = swept_[k];
        for (std::size_t m = k + 1; m < swept_.size(); ++m) {
            const Swept& q = swept_[m];
            if (q.box.min[axis] > p.box.max[axis]) break;
            // On the sweep's axis the two overlap already: q begins within p.
            if (q.box.min[u] > p.box.max[u] || p.box.min[u] > q.box.max[u] || q.box.min[w] > p.box.max[w] ||
                p.box.min[w] > q.box.max[w] || (p.isStatic && q.isStatic)) {
                continue;
            }
            pairs.push_back({std::min(p.index, q.index), std::max(p.index, q.index)});
        }
    }
}

void BroadPhase::sortAlong(int axis) {
    // Bodies move little in a step, so the last call's order is nearly sorted: insertion sort puts
    // it right in about one pass. A new scene (another number of boxes) or another axis starts from
    // the bodies' order and is sorted from scratch, as is an order that insertion sort finds far
    // from sorted.
    const auto lower = [this, axis](std::uint32_t k) { return entries_[k].box.min[axis]; };
    const bool warm = order_.size() == entries_.size() && axis == orderAxis_;
    orderAxis_ = axis;
    if (!warm) {
        order_.resize(entries_.size());
        for (std::size_t k = 0; k < order_.size(); ++k) order_[k] = static_cast<std::uint32_t>(k);
    }
    std::size_t shifts = 0;
    const std::size_t maxShifts = 8 * order_.size();
    for (std::size_t k = 1; warm && k < order_.size() && shifts <= maxShifts; ++k) {
        const std::uint32_t moving = order_[k];
        const double key = lower(moving);
        std::size_t m = k;
        for (; m > 0 && lower(order_[m - 1]) > key; --m) order_[m] = order_[m - 1];
        order_[m] = moving;
        shifts += k - m;
    }
    if (!warm || shifts > maxShifts) {
        std::sort(order_.begin(), order_.end(), [&lower](std::uint32_t p, std::uint32_t q) { return lower(p) < lower(q); });
    }
}

void BroadPhase::grid(SecondThread* second) {
    // Cells twice as wide as the median box (a metre when there is nothing to go by).
    double cell = 1.0;
    if (!sizes_.empty()) {
        std::nth_element(sizes_.begin(), sizes_.begin() + sizes_.size() / 2, sizes_.end());
        if (sizes_[sizes_.size() / 2] > 0.0) cell = 2.0 * sizes_[sizes_.size() / 2];
    }
    for (std::size_t k = 0; k < entries_.size(); ++k) {
        Entry& e = entries_[k];
        const Vec3 lo = (e.box.min / cell).array().floor(), hi = (e.box.max / cell).array().floor();
        const bool inRange = (lo.array() >= -kCellRange).all() && (hi.array() < kCellRange).all();
        if (!inRange || ((hi - lo).array() >= kLargeCells).any()) {
            large_.push_back(k);
            continue;
        }
        e.cellLo = lo.cast<int>();
        e.cellHi = hi.cast<int>();
        for (int x = e.cellLo.x(); x <= e.cellHi.x(); ++x) {
            for (int y = e.cellLo.y(); y <= e.cellHi.y(); ++y) {
                for (int z = e.cellLo.z(); z <= e.cellHi.z(); ++z) {
                    filed_.push_back({packCell(x, y, z), static_cast<std::uint32_t>(k)});
                }
            }
        }
    }
    std::sort(filed_.begin(), filed_.end());

    if (second != nullptr) {
        // Two halves, each starting at the beginning of a cell.
        std::size_t half = filed_.size() / 2;
        while (half > 0 && half < filed_.size() && filed_[half].cell == filed_[half - 1].cell) ++half;
        secondHalf_.clear();
        second->run(true, [this, half] { testCells(0, half, pairs_); },
                    [this, half] { testCells(half, filed_.size(), secondHalf_); });
        pairs_.insert(pairs_.end(), secondHalf_.begin(), secondHalf_.end());
    } else {
        testCells(0, filed_.size(), pairs_);
    }

    // Large bodies against every other body (each pair of large bodies once).
    for (std::size_t l = 0; l < large_.size(); ++l) {
        const Entry& p = entries_[large_[l]];
        for (std::size_t k = 0; k < entries_.size(); ++k) {
            const Entry& q = entries_[k];
            const bool qLarge = std::binary_search(large_.begin(), large_.end(), k);
            if (k == large_[l] || (qLarge && k < large_[l])) continue;
            if (p.isStatic && q.isStatic) continue;
            if (overlap(p.box, q.box)) pairs_.push_back({std::min(p.index, q.index), std::max(p.index, q.index)});
        }
    }

}

void BroadPhase::testCells(std::size_t first, std::size_t last, std::vector<BodyPair>& pairs) const {
    for (std::size_t begin = first, end = first; begin < last; begin = end) {
        while (end < last && filed_[end].cell == filed_[begin].cell) ++end;
        const std::uint64_t cell = filed_[begin].cell;
        for (std::size_t u = begin; u < end; ++u) {
            const Entry& p = entries_[filed_[u].entry];
            for (std::size_t v = u + 1; v < end; ++v) {
                const Entry& q = entries_[filed_[v].entry];
                if (p.isStatic && q.isStatic) continue;
                // Reported only by the lowest cell the two cover together.
                const Eigen::Vector3i shared = p.cellLo.cwiseMax(q.cellLo);
                if (packCell(shared.x(), shared.y(), shared.z()) != cell) continue;
                if (overlap(p.box, q.box)) pairs.push_back({std::min(p.index, q.index), std::max(p.index, q.index)});
            }
        }
    }
}

int BroadPhase::defaultThreads() { return std::thread::hardware_concurrency() >= 2 ? 2 : 1; }

std::vector<BodyPair> bruteForcePairs(const std::vector<Body>& bodies, double margin) {
    std::vector<BodyPair> pairs;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        for (std::size_t j = i + 1; j < bodies.size(); ++j) {
            const Body& p = bodies[i];
            const Body& q = bodies[j];
            const bool planeP = p.shape == Shape::Plane, planeQ = q.shape == Shape::Plane;
            if (planeP && planeQ) continue;
            if (planeP || planeQ) {
                const Body& plane = planeP ? p : q;
                const Body& other = planeP ? q : p;
                if (!other.isStatic() && reachesPlane(boundingBox(other, margin), plane.position, planeNormal(plane)))
                    pairs.push_back({i, j});
                continue;
            }
            if (mayTouch(p, q, boundingBox(p, margin), boundingBox(q, margin))) pairs.push_back({i, j});
        }
    }
    return pairs;
}

}  // namespace gpl
