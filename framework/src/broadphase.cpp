#include "gpl/broadphase.h"

#include <algorithm>
#include <cmath>
#include <future>
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

const std::vector<BodyPair>& BroadPhase::findPairs(const std::vector<Body>& bodies, double margin) {
    pairs_.clear();
    entries_.clear();
    planes_.clear();
    Vec3 sum = Vec3::Zero(), sumSquares = Vec3::Zero();
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        if (bodies[i].shape == Shape::Plane) {
            planes_.push_back(i);
            continue;
        }
        entries_.push_back({0.0, 0.0, boundingBox(bodies[i], margin), i, bodies[i].isStatic()});
        sum += bodies[i].position;
        sumSquares += bodies[i].position.cwiseProduct(bodies[i].position);
    }

    // Sweep along the axis on which the centres spread most.
    const double n = static_cast<double>(std::max<std::size_t>(entries_.size(), 1));
    const Vec3 variance = sumSquares / n - (sum / n).cwiseProduct(sum / n);
    int axis = 0;
    variance.maxCoeff(&axis);
    for (Entry& e : entries_) {
        e.lo = e.box.min[axis];
        e.hi = e.box.max[axis];
    }
    std::sort(entries_.begin(), entries_.end(), [](const Entry& p, const Entry& q) { return p.lo < q.lo; });
    if (threads_ > 1 && entries_.size() >= kParallelFrom) {
        const std::size_t half = entries_.size() / 2;
        secondHalf_.clear();
        auto second = std::async(std::launch::async, [this, half] { sweep(half, entries_.size(), secondHalf_); });
        sweep(0, half, pairs_);
        second.get();
        pairs_.insert(pairs_.end(), secondHalf_.begin(), secondHalf_.end());
    } else {
        sweep(0, entries_.size(), pairs_);
    }

    for (std::size_t plane : planes_) {
        const Vec3 normal = planeNormal(bodies[plane]);
        for (const Entry& e : entries_) {
            if (e.isStatic || !reachesPlane(e.box, bodies[plane].position, normal)) continue;
            pairs_.push_back({std::min(e.index, plane), std::max(e.index, plane)});
        }
    }
    std::sort(pairs_.begin(), pairs_.end());
    return pairs_;
}

void BroadPhase::sweep(std::size_t first, std::size_t last, std::vector<BodyPair>& pairs) const {
    for (std::size_t k = first; k < last; ++k) {
        const Entry& p = entries_[k];
        for (std::size_t m = k + 1; m < entries_.size(); ++m) {
            const Entry& q = entries_[m];
            if (q.lo > p.hi) break;
            if (p.isStatic && q.isStatic) continue;
            if (overlap(p.box, q.box)) pairs.push_back({std::min(p.index, q.index), std::max(p.index, q.index)});
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
