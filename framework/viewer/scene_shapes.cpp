#include "scene_shapes.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gpl::viewer {
namespace {

constexpr double kGroundCosine = 0.99;  // cos 8 degrees

Vec3 worldNormal(const Body& plane) { return (plane.orientation * plane.normal).normalized(); }

// Sutherland-Hodgman: the part of a convex polygon where n . (x - p) >= 0.
std::vector<Vec3> clip(const std::vector<Vec3>& polygon, const Vec3& p, const Vec3& n) {
    std::vector<Vec3> out;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
        const Vec3& s = polygon[i];
        const Vec3& e = polygon[(i + 1) % polygon.size()];
        const double ds = n.dot(s - p), de = n.dot(e - p);
        if (ds >= 0.0) out.push_back(s);
        if ((ds >= 0.0) != (de >= 0.0)) out.push_back(s + ds / (ds - de) * (e - s));
    }
    return out;
}

// A square of half size `half` on the plane, centred where `near` projects onto it, counter-clockwise
// seen from the free side.
std::vector<Vec3> square(const Body& plane, const Vec3& near, double half) {
    const Vec3 n = worldNormal(plane);
    const Vec3 u = (std::abs(n.y()) < 0.9 ? n.cross(Vec3::UnitY()) : n.cross(Vec3::UnitX())).normalized();
    const Vec3 v = n.cross(u);  // u x v = n
    const Vec3 o = near - n.dot(near - plane.position) * n;
    return {o - half * (u + v), o + half * (u - v), o + half * (u + v), o - half * (u - v)};
}

// The polygon outside every plane other than `self` (and other than grounds, when `skipGround`).
std::vector<Vec3> outsideOthers(std::vector<Vec3> polygon, const std::vector<Body>& bodies, std::size_t self,
                                bool skipGround) {
    for (std::size_t j = 0; j < bodies.size() && polygon.size() >= 3; ++j) {
        const Body& other = bodies[j];
        if (j == self || other.shape != Shape::Plane || (skipGround && isGround(other))) continue;
        polygon = clip(polygon, other.position, worldNormal(other));
    }
    return polygon;
}

}  // namespace

bool isGround(const Body& b) { return b.shape == Shape::Plane && worldNormal(b).y() >= kGroundCosine; }

Bounds sceneBounds(const std::vector<Body>& bodies) {
    Bounds box;
    double margin = 0.01;
    for (const Body& b : bodies) {
        box.extend(b.position);
        if (b.shape == Shape::Sphere) {
            box.extend(b.position - Vec3::Constant(b.radius));
            box.extend(b.position + Vec3::Constant(b.radius));
            margin = std::max(margin, b.radius);
        } else if (b.shape == Shape::Box) {
            const double r = b.halfExtents.norm();
            box.extend(b.position - Vec3::Constant(r));
            box.extend(b.position + Vec3::Constant(r));
        }
    }
    if (box.isEmpty()) return box;
    box.min() -= Vec3::Constant(margin);
    box.max() += Vec3::Constant(margin);
    return box;
}

std::vector<PlanePatch> wallPatches(const std::vector<Body>& bodies, const Bounds& bounds) {
    std::vector<PlanePatch> patches;
    if (bounds.isEmpty()) return patches;
    const double half = bounds.diagonal().norm() + 1.0;  // covers the bounds wherever the plane cuts them
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        const Body& b = bodies[i];
        if (b.shape != Shape::Plane || isGround(b)) continue;
        std::vector<Vec3> polygon = outsideOthers(square(b, bounds.center(), half), bodies, i, false);
        for (int axis = 0; axis < 3 && polygon.size() >= 3; ++axis) {
            polygon = clip(polygon, bounds.min(), Vec3::Unit(axis));
            if (polygon.size() >= 3) polygon = clip(polygon, bounds.max(), -Vec3::Unit(axis));
        }
        if (polygon.size() >= 3) patches.push_back({i, worldNormal(b), std::move(polygon)});
    }
    return patches;
}

std::optional<PlanePatch> enclosedGround(const std::vector<Body>& bodies) {
    // The highest ground (the one the renderer tiles), cut by the other planes from a square far
    // larger than any scene: enclosed when nothing is left of the square's edges.
    std::optional<std::size_t> ground;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        if (isGround(bodies[i]) && (!ground || bodies[i].position.y() > bodies[*ground].position.y())) ground = i;
    }
    if (!ground) return std::nullopt;
    const double half = 1e4;  // m
    const Body& g = bodies[*ground];
    std::vector<Vec3> polygon = outsideOthers(square(g, g.position, half), bodies, *ground, true);
    if (polygon.size() < 3) return std::nullopt;
    for (const Vec3& p : polygon) {
        if ((p - g.position).cwiseAbs().maxCoeff() > 0.5 * half) return std::nullopt;
    }
    return PlanePatch{*ground, worldNormal(g), std::move(polygon)};
}

bool ropeTaut(const Rope& rope, const std::vector<Body>& bodies, const std::vector<Contact>& contacts) {
    const Vec3 d = bodies[rope.a].position - bodies[rope.b].position;
    if (d.norm() >= (1.0 - 1e-3) * rope.length) return true;
    return std::any_of(contacts.begin(), contacts.end(),
                       [&](const Contact& c) { return c.a == rope.a && c.b == rope.b && c.normal.dot(d) > 0.0; });
}

std::vector<Vec3> ropeCurve(const Vec3& a, const Vec3& b, double length, const Vec3& down, int segments) {
    segments = std::max(1, segments);
    const Vec3 chord = b - a;
    const double c = chord.norm();
    // The sag s of a parabola over a chord c whose arc is as long as the rope: the arc of
    // y = 4 s t (1 - t) is c/2 (sqrt(1 + k^2) + asinh(k) / k) with k = 4 s / c; bisection on s.
    double sag = 0.0;
    Vec3 across = Vec3::Zero();
    if (c < length && c > 1e-9) {
        const Vec3 along = chord / c;
        across = down - down.dot(along) * along;
        if (across.norm() < 1e-6) across = along.cross(std::abs(along.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitZ());
        across.normalize();
        const auto arc = [c](double s) {
            const double k = 4.0 * s / c;
            return k < 1e-9 ? c : 0.5 * c * (std::sqrt(1.0 + k * k) + std::asinh(k) / k);
        };
        double lo = 0.0, hi = 0.5 * length;
        for (int i = 0; i < 50; ++i) {
            const double mid = 0.5 * (lo + hi);
            (arc(mid) < length ? lo : hi) = mid;
        }
        sag = 0.5 * (lo + hi);
    } else if (c < length) {
        // Both ends at one point: the rope hangs down, doubled.
        across = down.norm() > 1e-9 ? down.normalized() : Vec3(-Vec3::UnitY());
        sag = 0.5 * length;
    }
    std::vector<Vec3> points;
    for (int i = 0; i <= segments; ++i) {
        const double t = double(i) / segments;
        points.push_back(a + t * chord + 4.0 * sag * t * (1.0 - t) * across);
    }
    return points;
}

double normalLength(const Contact& contact, const std::vector<Body>& bodies) {
    double size = std::numeric_limits<double>::infinity();
    for (std::size_t i : {contact.a, contact.b}) {
        if (i >= bodies.size()) continue;
        const Body& b = bodies[i];
        if (b.shape == Shape::Sphere) size = std::min(size, b.radius);
        if (b.shape == Shape::Box) size = std::min(size, b.halfExtents.minCoeff());
    }
    return std::isfinite(size) ? 0.8 * size : 0.1;
}

}  // namespace gpl::viewer
