// The baseline contact solver (baumgarte.h). Each step:
//   1. prepares every point once: lever arms, a tangent basis, effective masses, and the normal
//      velocity it should leave with: e times its approach when it bounces, else the Baumgarte
//      bias kBias (d - slop) / h for an overlap d beyond the slop, or -gap / h across a gap (the
//      bodies may close it within the step, no more);
//   2. warm starts every point with last step's sums;
//   3. sweeps: at every point the normal impulse that brings its normal velocity to the target,
//      the sum kept >= 0, then the friction impulse that stops its slip, the sum kept in the
//      Coulomb cone of the normal sum.
#include "gpl/baumgarte.h"

#include <algorithm>
#include <cmath>

#include "gpl/contact_point.h"
#include "gpl/friction.h"

namespace gpl {

void BaumgarteImpulses::run(std::vector<Body>& bodies, const std::vector<Mat3>& invI,
                            const std::vector<Contact>& contacts, const std::vector<std::size_t>& first,
                            const std::vector<double>& depth, std::vector<PointImpulse>& sums, double slop, double h,
                            int sweeps) {
    // 1. The points.
    points_.clear();
    for (std::size_t c = 0; c < contacts.size(); ++c) {
        const Contact& con = contacts[c];
        const Body& a = bodies[con.a];
        const Body& b = bodies[con.b];
        for (int k = 0; k < con.pointCount; ++k) {
            const std::size_t i = first[c] + k;
            Point p{prepare(con, k, a, b, invI[con.a], invI[con.b], sums[i].normal, sums[i].tangent)};
            const double d = depth[i];
            const double bias = d > slop ? kBias * (d - slop) / h : d < 0.0 ? d / h : 0.0;  // m/s
            const double bounce = sums[i].approach < -kRestingSpeed ? -con.restitution * sums[i].approach : 0.0;
            p.target = std::max(bias, bounce);
            points_.push_back(p);
        }
    }

    // The impulse J (N s) on b at the point, -J on a.
    const auto push = [&](const Point& p, const Vec3& J) {
        Body& a = bodies[p.a];
        Body& b = bodies[p.b];
        a.velocity -= a.invMass * J;
        a.angularVelocity -= invI[p.a] * p.ra.cross(J);
        b.velocity += b.invMass * J;
        b.angularVelocity += invI[p.b] * p.rb.cross(J);
    };

    // 2. Warm start.
    for (const Point& p : points_) push(p, p.normal * p.n + p.tangent1 * p.t1 + p.tangent2 * p.t2);

    // 3. The sweeps.
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        for (Point& p : points_) {
            const Body& a = bodies[p.a];
            const Body& b = bodies[p.b];
            const auto relative = [&] {
                return Vec3(b.velocity + b.angularVelocity.cross(p.rb) - a.velocity - a.angularVelocity.cross(p.ra));
            };
            const double normal = std::max(0.0, p.normal + p.mn * (p.target - p.n.dot(relative())));
            push(p, (normal - p.normal) * p.n);
            p.normal = normal;

            const Vec3 u = relative();
            double f1 = p.tangent1 - p.mt1 * u.dot(p.t1);
            double f2 = p.tangent2 - p.mt2 * u.dot(p.t2);
            clampToCone(f1, f2, p.normal, p.staticFriction, p.friction);
            push(p, (f1 - p.tangent1) * p.t1 + (f2 - p.tangent2) * p.t2);
            p.tangent1 = f1;
            p.tangent2 = f2;
        }
    }
    for (std::size_t i = 0; i < points_.size(); ++i) {
        sums[i].normal = points_[i].normal;
        sums[i].tangent = points_[i].tangent1 * points_[i].t1 + points_[i].tangent2 * points_[i].t2;
    }
}

}  // namespace gpl
