// The soft step contact solver (soft_step.h). Each step:
//   1. prepares every point once: lever arms, a tangent basis, effective masses, the gap where the
//      bodies are now, and last step's impulses to start from;
//   2. takes every movable body back to the start of the step (the integration stage has moved it
//      by h v and sped it up by h a), as a displacement and a rotation from where it is now;
//   3. runs the substeps: each speeds the bodies up by its share of h a, applies the impulses of
//      the substep before (warm start), solves every point once with the contact spring, moves
//      and turns the bodies, and solves once more without the spring (relax), so the velocities
//      they leave with carry no push of the spring;
//   4. bounces the points that approached fast enough (restitution), once, after the substeps;
//   5. puts the bodies where the substeps took them.
// A point's gap in a substep is its gap now plus how far the two material points there have moved
// apart along the normal since (to first order in the rotation): no collision detection runs
// between substeps.
#include "gpl/soft_step.h"

#include <algorithm>
#include <cmath>

#include "gpl/contact_point.h"
#include "gpl/friction.h"

namespace gpl {
namespace {

// The soft constraint of a spring of frequency hertz and damping ratio zeta over a substep hs:
// the share of the overlap pushed out per second, and how much of a rigid constraint's impulse it
// takes (massScale) and of its own impulse so far it gives back (impulseScale).
struct Softness {
    double biasRate, massScale, impulseScale;
};
Softness softness(double hertz, double zeta, double hs) {
    const double omega = 2.0 * EIGEN_PI * hertz;
    const double a1 = 2.0 * zeta + hs * omega;
    const double a2 = hs * omega * a1;
    const double a3 = 1.0 / (1.0 + a2);
    return {omega / a1, a2 * a3, a3};
}

}  // namespace

Vec3 SoftStep::relativeVelocity(const Point& p) const {
    return v_[p.b] + w_[p.b].cross(p.rb) - v_[p.a] - w_[p.a].cross(p.ra);
}

void SoftStep::push(const Point& p, const Vec3& impulse, const std::vector<Body>& bodies,
                    const std::vector<Mat3>& invI) {
    v_[p.a] -= bodies[p.a].invMass * impulse;
    w_[p.a] -= invI[p.a] * p.ra.cross(impulse);
    v_[p.b] += bodies[p.b].invMass * impulse;
    w_[p.b] += invI[p.b] * p.rb.cross(impulse);
}

void SoftStep::run(std::vector<Body>& bodies, const std::vector<Mat3>& invI, const std::vector<Contact>& contacts,
                   const std::vector<std::size_t>& first, const std::vector<double>& depth,
                   std::vector<PointImpulse>& sums, double h, int substeps) {
    const double hs = h / substeps;

    // 1. The points.
    points_.clear();
    for (std::size_t c = 0; c < contacts.size(); ++c) {
        const Contact& con = contacts[c];
        const Body& a = bodies[con.a];
        const Body& b = bodies[con.b];
        for (int k = 0; k < con.pointCount; ++k) {
            const std::size_t i = first[c] + k;
            Point p{prepare(con, k, a, b, invI[con.a], invI[con.b], sums[i].normal, sums[i].tangent)};
            p.separation = -depth[i];
            p.approach = sums[i].approach;
            points_.push_back(p);
        }
    }

    // 2. Back to the start of the step.
    v_.resize(bodies.size());
    w_.resize(bodies.size());
    moved_.resize(bodies.size());
    turned_.resize(bodies.size());
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        const Body& b = bodies[i];
        const bool movable = !b.isStatic();
        v_[i] = movable ? Vec3(b.velocity - h * b.acceleration) : b.velocity;
        w_[i] = b.angularVelocity;
        moved_[i] = movable ? Vec3(-h * b.velocity) : Vec3::Zero();
        turned_[i] = movable ? Vec3(-h * b.angularVelocity) : Vec3::Zero();
    }

    // 3. The substeps.
    for (int s = 0; s < substeps; ++s) {
        for (std::size_t i = 0; i < bodies.size(); ++i) {
            if (!bodies[i].isStatic()) v_[i] += hs * bodies[i].acceleration;
        }
        for (const Point& p : points_) push(p, p.normal * p.n + p.tangent1 * p.t1 + p.tangent2 * p.t2, bodies, invI);
        solve(bodies, invI, hs, true);
        for (std::size_t i = 0; i < bodies.size(); ++i) {
            if (bodies[i].isStatic()) continue;
            moved_[i] += hs * v_[i];
            turned_[i] += hs * w_[i];
        }
        solve(bodies, invI, hs, false);
    }

    // 4. Restitution: a point that approached faster than kRestingSpeed and was pushed leaves with
    // e times its approach.
    for (Point& p : points_) {
        if (!(p.approach < -kRestingSpeed) || p.largestNormal == 0.0 || p.restitution == 0.0) continue;
        const double vn = p.n.dot(relativeVelocity(p));
        const double total = std::max(0.0, p.normal - p.mn * (vn + p.restitution * p.approach));
        push(p, (total - p.normal) * p.n, bodies, invI);
        p.normal = total;
    }

    // 5. Where the substeps took the bodies, and the impulses of the last substep for next step.
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        Body& b = bodies[i];
        if (b.isStatic()) continue;
        b.velocity = v_[i];
        b.angularVelocity = w_[i];
        b.position += moved_[i];
        const double angle = turned_[i].norm();
        if (angle > 0.0) b.orientation = (Quat(Eigen::AngleAxisd(angle, turned_[i] / angle)) * b.orientation).normalized();
    }
    for (std::size_t i = 0; i < points_.size(); ++i) {
        sums[i].normal = points_[i].normal;
        sums[i].tangent = points_[i].tangent1 * points_[i].t1 + points_[i].tangent2 * points_[i].t2;
    }
}

void SoftStep::solve(const std::vector<Body>& bodies, const std::vector<Mat3>& invI, double hs, bool soft) {
    const Softness spring = softness(kStiffness / hs, kDampingRatio, hs);
    for (Point& p : points_) {
        // Normal: the gap now, from the gap at the start and how the material points have moved.
        const Vec3 apart = moved_[p.b] + turned_[p.b].cross(p.rb) - moved_[p.a] - turned_[p.a].cross(p.ra);
        const double gap = p.separation + p.n.dot(apart);  // m
        double bias = 0.0, massScale = 1.0, impulseScale = 0.0;
        if (gap > 0.0) {
            bias = gap / hs;  // the bodies may close the gap within the substep, no more
        } else if (soft) {
            bias = std::max(spring.biasRate * gap, -kMaxPushSpeed);
            massScale = spring.massScale;
            impulseScale = spring.impulseScale;
        }
        const double vn = p.n.dot(relativeVelocity(p));
        const double total = std::max(0.0, p.normal - p.mn * massScale * (vn + bias) - impulseScale * p.normal);
        push(p, (total - p.normal) * p.n, bodies, invI);
        p.normal = total;
        p.largestNormal = std::max(p.largestNormal, total);

        // Friction: stop the slip along both tangents, within the Coulomb cone of this normal impulse.
        const Vec3 u = relativeVelocity(p);
        double f1 = p.tangent1 - p.mt1 * u.dot(p.t1);
        double f2 = p.tangent2 - p.mt2 * u.dot(p.t2);
        clampToCone(f1, f2, p.normal, p.staticFriction, p.friction);
        push(p, (f1 - p.tangent1) * p.t1 + (f2 - p.tangent2) * p.t2, bodies, invI);
        p.tangent1 = f1;
        p.tangent2 = f2;
    }
}

}  // namespace gpl
