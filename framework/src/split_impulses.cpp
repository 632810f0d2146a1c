// Split impulses: the friction stage's position correction (split_impulses.h).
#include "gpl/split_impulses.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

namespace gpl {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// The stretch [lo, hi] of the line p + s n (s in metres) that lies inside a body; lo > hi when the
/// line misses it.
struct Stretch {
    double lo = -kInfinity;
    double hi = kInfinity;
};

Stretch stretchInside(const Body& body, const Vec3& p, const Vec3& n, double grow) {
    Stretch s;
    switch (body.shape) {
        case Shape::Sphere: {
            // |p + s n - c|^2 <= r^2: s = -d.n +- sqrt(r^2 - |d|^2 + (d.n)^2), with d = p - c.
            const Vec3 d = p - body.position;
            const double along = d.dot(n);
            const double r = body.radius + grow;
            const double square = r * r - d.squaredNorm() + along * along;
            if (square < 0.0) return {kInfinity, -kInfinity};
            const double half = std::sqrt(square);
            return {-along - half, -along + half};
        }
        case Shape::Box: {
            // The slabs |x_i| <= e_i of the box frame, one axis at a time.
            const Vec3 o = body.orientation.conjugate() * (p - body.position);
            const Vec3 d = body.orientation.conjugate() * n;
            for (int i = 0; i < 3; ++i) {
                const double e = body.halfExtents[i] + grow;
                if (std::abs(d[i]) < 1e-12) {
                    if (std::abs(o[i]) > e) return {kInfinity, -kInfinity};
                    continue;
                }
                const double t1 = (-e - o[i]) / d[i], t2 = (e - o[i]) / d[i];
                s.lo = std::max(s.lo, std::min(t1, t2));
                s.hi = std::min(s.hi, std::max(t1, t2));
            }
            return s;
        }
        case Shape::Plane: {
            // The solid side: (p + s n - x) . m <= 0, with m the plane's normal.
            const Vec3 m = body.orientation * body.normal;
            const double height = (p - body.position).dot(m), rate = n.dot(m);
            if (std::abs(rate) < 1e-12) return height <= 0.0 ? s : Stretch{kInfinity, -kInfinity};
            const double at = -height / rate;
            return rate > 0.0 ? Stretch{-kInfinity, at} : Stretch{at, kInfinity};
        }
    }
    return s;
}

}  // namespace

// The share of a margin that a grows by; b grows by the rest (as collide() grows them).
double shareOf(const Body& a, const Body& b, double margin) {
    return b.shape == Shape::Plane ? margin : a.shape == Shape::Plane ? 0.0 : 0.5 * margin;
}

Vec3 betweenSurfaces(const Body& a, const Body& b, const Vec3& p, const Vec3& n, double margin) {
    const double share = shareOf(a, b, margin);
    const Stretch sa = stretchInside(a, p, n, share), sb = stretchInside(b, p, n, margin - share);
    if (!(sa.lo <= sa.hi) || !(sb.lo <= sb.hi)) return p;
    // Where a's surface ends and b's begins, without the growth: a's stretch ends share further on,
    // b's begins margin - share earlier.
    return p + 0.5 * ((sa.hi - share) + (sb.lo + (margin - share))) * n;
}

double depthAlong(const Body& a, const Body& b, const Vec3& p, const Vec3& n, double margin) {
    const double share = shareOf(a, b, margin);
    const Stretch sa = stretchInside(a, p, n, share), sb = stretchInside(b, p, n, margin - share);
    if (!(sa.lo <= sa.hi) || !(sb.lo <= sb.hi)) return std::numeric_limits<double>::quiet_NaN();
    return sa.hi - sb.lo - margin;
}

void SplitImpulses::set(std::size_t k, std::size_t a, std::size_t b, const Vec3& p, const Vec3& n, double depth,
                        const std::vector<Body>& bodies, const Mat3& invIa, const Mat3& invIb) {
    Point q{a, b, p - bodies[a].position, p - bodies[b].position, n, bodies[a].invMass, bodies[b].invMass, 0.0, depth};
    const Vec3 ran = q.ra.cross(n), rbn = q.rb.cross(n);
    q.wn = q.ma + q.mb + ran.dot(invIa * ran) + rbn.dot(invIb * rbn);
    points_[k] = q;
}

void SplitImpulses::sweep(std::vector<Point>& points, const std::vector<Mat3>& invI) {
    for (Point& q : points) {
        Vec3& va = pseudo_[q.a].v;
        Vec3& vb = pseudo_[q.b].v;
        Vec3& wa = pseudo_[q.a].w;
        Vec3& wb = pseudo_[q.b].w;
        const double vn = q.n.dot(vb + wb.cross(q.rb) - va - wa.cross(q.ra));  // m/s, > 0 separating
        const double sum = std::max(0.0, q.sum + (q.target - vn) / q.wn);
        const Vec3 impulse = (sum - q.sum) * q.n;  // N s, on b; -impulse on a
        q.sum = sum;
        // A static body's pseudo velocities stay zero (its inverse mass and inertia are zero): they
        // are not written, so the two halves never write the same body.
        if (q.ma != 0.0) {
            va -= q.ma * impulse;
            wa -= invI[q.a] * q.ra.cross(impulse);
        }
        if (q.mb != 0.0) {
            vb += q.mb * impulse;
            wb += invI[q.b] * q.rb.cross(impulse);
        }
    }
}

void SplitImpulses::run(std::vector<Body>& bodies, const std::vector<Mat3>& invI, double slop, double h, int sweeps,
                        const Halves* halves, SecondThread* second) {
    bool any = false;
    for (Point& q : points_) {
        q.target = q.depth > slop ? kShare * (q.depth - slop) / h : 0.0;  // m/s
        q.sum = 0.0;
        any |= q.target > 0.0 && q.wn > 0.0;
    }
    if (!any) return;
    pseudo_.assign(bodies.size(), Pseudo{});
    // The points to sweep, by part (all in the middle without a cut). A point of two static bodies
    // (wn = 0) has nothing to move.
    const bool cut = halves != nullptr && halves->cutInTwo();
    for (std::vector<Point>& part : parts_) part.clear();
    for (const Point& q : points_) {
        if (q.wn > 0.0) parts_[cut ? halves->part(q.a, q.b) : Halves::kMiddle].push_back(q);
    }
    const auto part = [this, &invI](int p) { sweep(parts_[p], invI); };
    const std::function<void()> left = [&part] { part(Halves::kLeft); };
    const std::function<void()> right = [&part] { part(Halves::kRight); };
    for (int s = 0; s < sweeps; ++s) {
        if (cut && second != nullptr) {
            second->run(true, left, right);
        } else if (cut) {
            left();
            right();
        }
        part(Halves::kMiddle);
    }
    inHalves(cut ? second : nullptr, bodies.size(), [&](std::size_t i) {
        Body& body = bodies[i];
        if (body.isStatic()) return;
        body.position += h * pseudo_[i].v;
        const Vec3 turn = h * pseudo_[i].w;  // rad, world frame
        if (!turn.isZero(0.0)) {
            const double angle = turn.norm();
            body.orientation = (Quat(Eigen::AngleAxisd(angle, turn / angle)) * body.orientation).normalized();
        }
    });
}

}  // namespace gpl
