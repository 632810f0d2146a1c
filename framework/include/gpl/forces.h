// Forces beyond gravity, as pure kernels: positions and velocities in, force out.
#pragma once

#include <cstddef>

#include "gpl/math.h"

namespace gpl {

/// A linear (Hooke) spring between two bodies; a static body makes an anchor.
struct Spring {
    std::size_t a = 0;        ///< index of the first body
    std::size_t b = 0;        ///< index of the second body
    double stiffness = 0.0;   ///< k (N/m), > 0
    double restLength = 0.0;  ///< L0 (m), >= 0
    double damping = 0.0;     ///< c (N s/m), >= 0; acts on the relative velocity along the spring
};

/// Force on the first end (N); the second end feels its negative. With d = xa - xb and
/// u = d / |d|: F = -k (|d| - L0) u - c ((va - vb) . u) u. A spring of zero length has no
/// direction and exerts no force.
Vec3 springForce(const Vec3& xa, const Vec3& xb, const Vec3& va, const Vec3& vb, double stiffness, double restLength,
                 double damping);

/// Energy stored in the spring (J): k (|xa - xb| - L0)^2 / 2.
double springEnergy(const Vec3& xa, const Vec3& xb, double stiffness, double restLength);

}  // namespace gpl
