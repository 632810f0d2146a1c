// Worksheet 8, assignment 3: a particle pushed out of a rigid box.
//
// Inputs:  p            the particle's predicted position (m, world frame)
//          r            its radius (m, >= 0)
//          centre       the box's centre (m), orientation its rotation from box to world frame
//          half         its half extents along the box's axes (m, > 0)
// Outputs: in the box's frame, q = R^T (p - centre), and the point of the box nearest to q,
//          c = clamp(q, -half, half):
//          - q outside the box (c != q): when |q - c| < r the particle moves away from c to
//            distance r: q' = c + r (q - c) / |q - c|; otherwise it stays;
//          - q inside the box (c = q): it leaves through the nearest face: along the axis k where
//            half_k - |q_k| is smallest, q'_k = sign(q_k) (half_k + r), the other coordinates kept.
//          p' = centre + R q'.
#include <cassert>
#include <cmath>

#include "gpl/hooks.h"
#include "gpl/soft_constraints.h"

namespace gpl {

Vec3 projectParticleBox([[maybe_unused]] const Vec3& p, [[maybe_unused]] double r, [[maybe_unused]] const Vec3& centre,
                        [[maybe_unused]] const Quat& orientation, [[maybe_unused]] const Vec3& half) {
    // BEGIN SOLUTION
    assert(r >= 0.0 && (half.array() > 0.0).all());
    const Vec3 q = orientation.conjugate() * (p - centre);
    const Vec3 nearest = q.cwiseMax(-half).cwiseMin(half);
    Vec3 moved = q;
    if (nearest != q) {
        const Vec3 d = q - nearest;
        const double distance = d.norm();
        if (distance >= r) return p;
        moved = nearest + r * d / distance;
    } else {
        int k = 0;  // the axis of the nearest face
        for (int i = 1; i < 3; ++i)
            if (half[i] - std::abs(q[i]) < half[k] - std::abs(q[k])) k = i;
        moved[k] = (q[k] < 0.0 ? -1.0 : 1.0) * (half[k] + r);
    }
    return centre + orientation * moved;
    // ELSE STUB
    // kernelNotImplemented("projectParticleBox()");
    // return p;
    // END SOLUTION
}

}  // namespace gpl
