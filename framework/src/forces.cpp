#include "gpl/forces.h"

namespace gpl {

Vec3 springForce(const Vec3& xa, const Vec3& xb, const Vec3& va, const Vec3& vb, double stiffness, double restLength,
                 double damping) {
    const Vec3 d = xa - xb;
    const double length = d.norm();
    if (length == 0.0) return Vec3::Zero();
    const Vec3 u = d / length;
    return (-stiffness * (length - restLength) - damping * (va - vb).dot(u)) * u;
}

double springEnergy(const Vec3& xa, const Vec3& xb, double stiffness, double restLength) {
    const double stretch = (xa - xb).norm() - restLength;
    return 0.5 * stiffness * stretch * stretch;
}

}  // namespace gpl
