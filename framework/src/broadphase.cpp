#include "gpl/broadphase.h"

#include <algorithm>
#include <cmath>
#include <thread>

#include "gpl/pair_order.h"

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

// The body's bounding ball grown by `margin` times its size, as boundingBox() grows its box: a
// sphere's radius (1 + margin) r, a box's the distance of its corners |h| plus margin times its
// smallest half extent; a radius below zero for a plane.
Ball ballOf(const Body& b, double margin) {
    if (b.shape == Shape::Sphere) return {b.position, (1.0 + margin) * b.radius};
    if (b.shape == Shape::Box) return {b.position, b.halfExtents.norm() + margin * b.halfExtents.minCoeff()};
    return {b.position, -1.0};
}

// Two balls meet (touching counts).
bool meet(const Ball& p, const Ball& q) {
    const double reach = p.radius + q.radius;
    return (p.centre - q.centre).squaredNorm() <= reach * reach;
}

// Two bounding volumes overlap: both the boxes and the balls of two finite bodies.
bool overlap(const Aabb& boxP, const Aabb& boxQ, const Ball& ballP, const Ball& ballQ) {
    return meet(ballP, ballQ) && overlap(boxP, boxQ);
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

std::uint64_t packCell(long x, long y, long z) {
    const auto bits = [](long c) { return static_cast<std::uint64_t>(c + kCellRange); };
    return bits(x) << (2 * kCellBits) | bits(y) << kCellBits | bits(z);
}

// What to add to a packed cell to get its neighbour dx, dy cells away on the first two axes.
constexpr std::uint64_t rowOffset(long dx, long dy) {
    return static_cast<std::uint64_t>(dx * (1L << (2 * kCellBits)) + dy * (1L << kCellBits));
}

// What the kept pairs depend on besides the boxes: a plane (static by construction), a static
// finite body or a movable one.
constexpr char kMovable = 0, kStatic = 1, kPlane = 2;
char kindOf(const Body& b) { return b.shape == Shape::Plane ? kPlane : b.isStatic() ? kStatic : kMovable; }

}  // namespace

Aabb BroadPhase::grownBox(const Body& body, double margin, double ahead) {
    Aabb box = boundingBox(body, margin + kSkin);
    const Vec3 reach = ahead * body.velocity;  // m, where the velocity carries it
    box.min += reach.cwiseMin(Vec3::Zero());
    box.max += reach.cwiseMax(Vec3::Zero());
    return box;
}

bool BroadPhase::sameScene(const std::vector<Body>& bodies, double margin) {
    now_.resize(bodies.size());
    balls_.resize(bodies.size());
    out_.clear();
    bool same = margin == grownMargin_ && bodies.size() == grown_.size();
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        const Body& b = bodies[i];
        const char kind = kindOf(b);
        if (kind == kPlane) {
            same = same && kind_[i] == kPlane && b.position == grown_[i].min && planeNormal(b) == grown_[i].max;
            continue;
        }
        now_[i] = boundingBox(b, margin);
        balls_[i] = ballOf(b, margin);
        same = same && kind == kind_[i];
        if (same && !((grown_[i].min.array() <= now_[i].min.array()).all() &&
                      (now_[i].max.array() <= grown_[i].max.array()).all())) {
            out_.push_back(i);
        }
    }
    return same;
}

void BroadPhase::update(const std::vector<Body>& bodies, double margin, double ahead) {
    // The bodies out of their grown boxes get new ones and lose their kept pairs.
    left_.assign(bodies.size(), 0);
    for (const std::size_t i : out_) {
        grown_[i] = grownBox(bodies[i], margin, ahead);
        left_[i] = 1;
    }
    kept_.erase(std::remove_if(kept_.begin(), kept_.end(), [this](const BodyPair& p) { return left_[p.a] || left_[p.b]; }),
                kept_.end());
    // Their pairs with every other body's grown box (two that both left, once: from the first).
    fresh_.clear();
    for (const std::size_t i : out_) {
        for (std::size_t j = 0; j < bodies.size(); ++j) {
            if (j == i || (left_[j] && j < i)) continue;
            bool touch = false;
            if (kind_[j] == kPlane) {
                touch = kind_[i] == kMovable && reachesPlane(grown_[i], grown_[j].min, grown_[j].max);
            } else {
                touch = !(kind_[i] == kStatic && kind_[j] == kStatic) && overlap(grown_[i], grown_[j]);
            }
            if (touch) fresh_.push_back({std::min(i, j), std::max(i, j)});
        }
    }
    std::sort(fresh_.begin(), fresh_.end());
    placed_.resize(kept_.size() + fresh_.size());
    std::merge(kept_.begin(), kept_.end(), fresh_.begin(), fresh_.end(), placed_.begin());
    kept_.swap(placed_);
}

void BroadPhase::filterKept() {
    pairs_.clear();
    for (const BodyPair& p : kept_) {
        bool touch = false;
        if (kind_[p.a] == kPlane) {
            touch = reachesPlane(now_[p.b], grown_[p.a].min, grown_[p.a].max);
        } else if (kind_[p.b] == kPlane) {
            touch = reachesPlane(now_[p.a], grown_[p.b].min, grown_[p.b].max);
        } else {
            touch = overlap(now_[p.a], now_[p.b], balls_[p.a], balls_[p.b]);
        }
        if (touch) pairs_.push_back(p);
    }
}

const std::vector<BodyPair>& BroadPhase::findPairs(const std::vector<Body>& bodies, double margin,
                                                   SecondThread* second, double ahead) {
    if (sameScene(bodies, margin) && out_.size() <= kUpdateAtMost) {
        if (!out_.empty()) {
            update(bodies, margin, ahead);
            ++updates_;
        }
        filterKept();
        return pairs_;
    }
    ++searches_;
    if (threads_ < 2) second = nullptr;
    if (second != nullptr && bodies.size() >= kGridFrom) second->wake();  // up by the time the boxes are made
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
        const Aabb box = grownBox(bodies[i], margin, ahead);
        entries_.push_back({box, i, bodies[i].isStatic()});
        sizes_.push_back((box.max - box.min).maxCoeff());
    }

    if (entries_.size() < kGridFrom) {
        sweep();
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

    // Kept, with the grown boxes, for the next calls; this call's answer from them.
    grown_.resize(bodies.size());
    kind_.resize(bodies.size());
    for (const Entry& e : entries_) grown_[e.index] = e.box;
    for (const std::size_t plane : planes_) grown_[plane] = {bodies[plane].position, planeNormal(bodies[plane])};
    for (std::size_t i = 0; i < bodies.size(); ++i) kind_[i] = kindOf(bodies[i]);
    grownMargin_ = margin;
    kept_.swap(pairs_);
    filterKept();
    return pairs_;
}

void BroadPhase::sortPairs(std::size_t bodies) {
    orderByPair(pairs_.size(), bodies, [this](std::size_t i) { return pairs_[i].a; },
                [this](std::size_t i) { return pairs_[i].b; }, pairOrder_, firsts_, cursor_);
    placed_.resize(pairs_.size());
    for (std::size_t m = 0; m < pairOrder_.size(); ++m) placed_[m] = pairs_[pairOrder_[m]];
    pairs_.swap(placed_);
}

void BroadPhase::sweep() {
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
    sweepFrom(axis, 0, swept_.size(), pairs_);
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
    // Cells as wide as the largest box that is not large (kLargeSizes median boxes): two boxes that
    // overlap then have their centres in the same cell or in neighbouring ones.
    double median = 0.0;
    if (!sizes_.empty()) {
        std::nth_element(sizes_.begin(), sizes_.begin() + sizes_.size() / 2, sizes_.end());
        median = sizes_[sizes_.size() / 2];
    }
    const auto size = [](const Entry& e) { return (e.box.max - e.box.min).maxCoeff(); };
    const auto large = [&](const Entry& e) { return median > 0.0 && size(e) > kLargeSizes * median; };
    double cell = 0.0;
    for (const Entry& e : entries_) {
        if (!large(e)) cell = std::max(cell, size(e));
    }
    if (!(cell > 0.0) || !std::isfinite(cell)) cell = 1.0;
    // Each box filed under the cell of its centre; a large one, or one outside the grid's range
    // (with a cell to spare on every side), is tested against every other box instead.
    for (std::size_t k = 0; k < entries_.size(); ++k) {
        const Entry& e = entries_[k];
        const Vec3 at = (0.5 * (e.box.min + e.box.max) / cell).array().floor();
        const bool inRange = (at.array() > -kCellRange + 1.0).all() && (at.array() < kCellRange - 2.0).all();
        if (!inRange || large(e)) {
            large_.push_back(k);
            continue;
        }
        filed_.push_back({packCell(static_cast<long>(at.x()), static_cast<long>(at.y()), static_cast<long>(at.z())),
                          static_cast<std::uint32_t>(k)});
    }
    std::sort(filed_.begin(), filed_.end());
    // The boxes packed in the cells' order, for the inner loop.
    swept_.clear();
    for (const Filed& f : filed_) {
        const Entry& e = entries_[f.entry];
        swept_.push_back({e.box, e.index, e.isStatic});
    }

    if (second != nullptr && second->helps()) {
        // Two halves of the boxes, each tested against its neighbours after it; sortPairs() orders
        // the pairs.
        const std::size_t half = filed_.size() / 2;
        secondHalf_.clear();
        second->run(true, [this, half] { testNeighbours(0, half, pairs_); },
                    [this, half] { testNeighbours(half, filed_.size(), secondHalf_); });
        pairs_.insert(pairs_.end(), secondHalf_.begin(), secondHalf_.end());
    } else {
        testNeighbours(0, filed_.size(), pairs_);
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

void BroadPhase::testNeighbours(std::size_t first, std::size_t last, std::vector<BodyPair>& pairs) const {
    // Each pair of neighbours is tested once, by the box whose cell comes first in the order of
    // filed_ (by the earlier of the two in one cell): against the boxes after it in its own row of
    // cells along the third axis (its cell and the next), and in the four rows that come after that
    // row (each three cells long).
    constexpr std::uint64_t kRows[] = {rowOffset(0, 1), rowOffset(1, -1), rowOffset(1, 0), rowOffset(1, 1)};
    std::size_t from[4];  // per row, the first box not before the row's first cell
    for (int r = 0; r < 4 && first < last; ++r) {
        const Filed lowest{filed_[first].cell + kRows[r] - 1, 0};
        from[r] = static_cast<std::size_t>(std::lower_bound(filed_.begin(), filed_.end(), lowest) - filed_.begin());
    }
    const auto test = [this, &pairs](const Swept& p, std::size_t v) {
        const Swept& q = swept_[v];
        if (overlap(p.box, q.box) && !(p.isStatic && q.isStatic)) {
            pairs.push_back({std::min(p.index, q.index), std::max(p.index, q.index)});
        }
    };
    for (std::size_t u = first; u < last; ++u) {
        const Swept& p = swept_[u];
        const std::uint64_t cell = filed_[u].cell;
        for (std::size_t v = u + 1; v < filed_.size() && filed_[v].cell <= cell + 1; ++v) test(p, v);
        for (int r = 0; r < 4; ++r) {
            std::size_t v = from[r];
            while (v < filed_.size() && filed_[v].cell < cell + kRows[r] - 1) ++v;
            from[r] = v;
            for (; v < filed_.size() && filed_[v].cell <= cell + kRows[r] + 1; ++v) test(p, v);
        }
    }
}

int BroadPhase::defaultThreads() { return std::thread::hardware_concurrency() >= 2 ? 2 : 1; }

std::vector<BodyPair> bruteForcePairs(const std::vector<Body>& bodies, double margin) {
    // Every body's bounding volumes once, then every pair of bodies.
    std::vector<Aabb> boxes;
    std::vector<Ball> balls;
    boxes.reserve(bodies.size());
    balls.reserve(bodies.size());
    for (const Body& b : bodies) {
        boxes.push_back(boundingBox(b, margin));
        balls.push_back(ballOf(b, margin));
    }
    std::vector<BodyPair> pairs;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        for (std::size_t j = i + 1; j < bodies.size(); ++j) {
            const Body& p = bodies[i];
            const Body& q = bodies[j];
            const bool planeP = p.shape == Shape::Plane, planeQ = q.shape == Shape::Plane;
            if (planeP && planeQ) continue;
            if (planeP || planeQ) {
                const Body& plane = planeP ? p : q;
                const std::size_t other = planeP ? j : i;
                if (!bodies[other].isStatic() && reachesPlane(boxes[other], plane.position, planeNormal(plane)))
                    pairs.push_back({i, j});
                continue;
            }
            if (p.isStatic() && q.isStatic()) continue;
            if (overlap(boxes[i], boxes[j], balls[i], balls[j])) pairs.push_back({i, j});
        }
    }
    return pairs;
}

}  // namespace gpl
