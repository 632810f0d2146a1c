#include "picking.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gpl::viewer {

std::optional<double> intersect(const Body& b, const Ray& ray) {
    if (b.shape == Shape::Sphere) {
        const Vec3 m = ray.origin - b.position;
        const double bq = m.dot(ray.direction);
        const double c = m.squaredNorm() - b.radius * b.radius;
        const double disc = bq * bq - c;
        if (disc < 0.0) return std::nullopt;
        const double t = -bq - std::sqrt(disc);
        if (t >= 0.0) return t;
        return c <= 0.0 ? std::optional<double>(0.0) : std::nullopt;  // inside: hit at once
    }
    if (b.shape == Shape::Box) {
        // Slabs in the box's frame.
        const Mat3 r = b.orientation.toRotationMatrix();
        const Vec3 o = r.transpose() * (ray.origin - b.position);
        const Vec3 d = r.transpose() * ray.direction;
        double tmin = 0.0, tmax = std::numeric_limits<double>::infinity();
        for (int i = 0; i < 3; ++i) {
            if (std::abs(d[i]) < 1e-12) {
                if (std::abs(o[i]) > b.halfExtents[i]) return std::nullopt;
                continue;
            }
            double t1 = (-b.halfExtents[i] - o[i]) / d[i];
            double t2 = (b.halfExtents[i] - o[i]) / d[i];
            if (t1 > t2) std::swap(t1, t2);
            tmin = std::max(tmin, t1);
            tmax = std::min(tmax, t2);
            if (tmin > tmax) return std::nullopt;
        }
        return tmin;
    }
    return std::nullopt;
}

std::optional<Hit> pick(const std::vector<Body>& bodies, const Ray& ray) {
    std::optional<Hit> best;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        const auto t = intersect(bodies[i], ray);
        if (t && (!best || *t < best->distance)) best = Hit{i, *t};
    }
    return best;
}

}  // namespace gpl::viewer
