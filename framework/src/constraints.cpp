#include "gpl/constraints.h"
#include "gpl/soft_constraints.h"

namespace gpl {

void projectDistance(Vec3& xa, Vec3& xb, double wa, double wb, double length) {
    const double w = wa + wb;
    const Vec3 d = xa - xb;
    const double current = d.norm();
    if (w == 0.0 || current == 0.0) return;
    const Vec3 correction = (current - length) / (current * w) * d;
    xa -= wa * correction;
    xb += wb * correction;
}

void keepInside(Vec3& x, double r, const Container& container) {
    const Vec3 d = x - container.centre;
    const double distance = d.norm();
    const double limit = container.radius - r;
    if (distance > limit) x = container.centre + d * (limit / distance);
}

void separateSpheres(Vec3& xa, Vec3& xb, double ra, double rb, double wa, double wb) {
    const Vec3 d = xa - xb;
    const double distanceSquared = d.squaredNorm();
    const double contact = ra + rb;
    if (distanceSquared >= contact * contact || distanceSquared == 0.0 || wa + wb == 0.0) return;
    const double distance = std::sqrt(distanceSquared);
    const Vec3 push = (contact - distance) / (distance * (wa + wb)) * d;
    xa += wa * push;
    xb -= wb * push;
}

}  // namespace gpl

namespace gpl {

double tetrahedronVolume(const std::array<Vec3, 4>& x) {
    return (x[1] - x[0]).cross(x[2] - x[0]).dot(x[3] - x[0]) / 6.0;
}

}  // namespace gpl
