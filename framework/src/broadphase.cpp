#include "gpl/broadphase.h"

#include <algorithm>
#include <cmath>

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

// The pair test both the sweep and the brute force use (the sweep has checked one axis already).
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
    order_.clear();
    planes_.clear();
    boxes_.resize(bodies.size());
    Vec3 sum = Vec3::Zero(), sumSquares = Vec3::Zero();
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        if (bodies[i].shape == Shape::Plane) {
            planes_.push_back(i);
            continue;
        }
        boxes_[i] = boundingBox(bodies[i], margin);
        order_.push_back(i);
        sum += bodies[i].position;
        sumSquares += bodies[i].position.cwiseProduct(bodies[i].position);
    }

    // Sweep along the axis on which the centres spread most.
    const double n = static_cast<double>(std::max<std::size_t>(order_.size(), 1));
    const Vec3 variance = sumSquares / n - (sum / n).cwiseProduct(sum / n);
    int axis = 0;
    variance.maxCoeff(&axis);
    std::sort(order_.begin(), order_.end(),
              [&](std::size_t p, std::size_t q) { return boxes_[p].min[axis] < boxes_[q].min[axis]; });
    for (std::size_t k = 0; k < order_.size(); ++k) {
        const std::size_t i = order_[k];
        for (std::size_t m = k + 1; m < order_.size(); ++m) {
            const std::size_t j = order_[m];
            if (boxes_[j].min[axis] > boxes_[i].max[axis]) break;
            if (mayTouch(bodies[i], bodies[j], boxes_[i], boxes_[j])) pairs_.push_back({std::min(i, j), std::max(i, j)});
        }
    }

    for (std::size_t p : planes_) {
        const Vec3 normal = planeNormal(bodies[p]);
        for (std::size_t i : order_) {
            if (bodies[i].isStatic() || !reachesPlane(boxes_[i], bodies[p].position, normal)) continue;
            pairs_.push_back({std::min(i, p), std::max(i, p)});
        }
    }
    std::sort(pairs_.begin(), pairs_.end());
    return pairs_;
}

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
