#include "gpl/body.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace gpl {
namespace {

void requirePositive(const std::string& name, const char* what, double value) {
    if (!std::isfinite(value) || value <= 0.0) {
        throw std::invalid_argument("body '" + name + "': " + what + " must be a positive finite number, got " +
                                    formatNumber(value));
    }
}

Body movable(const std::string& name, Shape shape, double mass, const Mat3& inertia) {
    Body b;
    b.name = name;
    b.shape = shape;
    b.mass = mass;
    b.invMass = 1.0 / mass;
    b.inertia = inertia;
    b.invInertia = inertia.inverse();
    return b;
}

}  // namespace

const char* shapeName(Shape shape) {
    switch (shape) {
        case Shape::Sphere:
            return "sphere";
        case Shape::Box:
            return "box";
        case Shape::Plane:
            return "plane";
    }
    return "unknown";
}

Body& Body::at(const Vec3& p) {
    position = p;
    return *this;
}
Body& Body::moving(const Vec3& v) {
    velocity = v;
    return *this;
}
Body& Body::spinning(const Vec3& w) {
    angularVelocity = w;
    return *this;
}
Body& Body::rotated(const Quat& q) {
    orientation = q.normalized();
    return *this;
}
Body& Body::bouncy(double e) {
    restitution = e;
    return *this;
}

Body& Body::rough(double staticMu, double slidingMu) {
    staticFriction = staticMu;
    friction = slidingMu;
    return *this;
}

Body& Body::makeStatic() {
    mass = std::numeric_limits<double>::infinity();
    invMass = 0.0;
    invInertia = Mat3::Zero();
    velocity = Vec3::Zero();
    angularVelocity = Vec3::Zero();
    return *this;
}

Body sphere(const std::string& name, double radius, double mass) {
    requirePositive(name, "radius", radius);
    requirePositive(name, "mass", mass);
    Body b = movable(name, Shape::Sphere, mass, Mat3::Identity() * (0.4 * mass * radius * radius));
    b.radius = radius;
    return b;
}

Body box(const std::string& name, const Vec3& halfExtents, double mass) {
    for (int i = 0; i < 3; ++i) requirePositive(name, "box half extent", halfExtents[i]);
    requirePositive(name, "mass", mass);
    const Vec3 sq = halfExtents.cwiseProduct(halfExtents);
    const Vec3 diag = Vec3(sq.y() + sq.z(), sq.x() + sq.z(), sq.x() + sq.y()) * (mass / 3.0);
    Body b = movable(name, Shape::Box, mass, diag.asDiagonal());
    b.halfExtents = halfExtents;
    return b;
}

Body plane(const std::string& name, const Vec3& normal) {
    if (!isFinite(normal) || normal.norm() == 0.0) {
        throw std::invalid_argument("plane '" + name + "': normal must be a finite, non-zero vector");
    }
    Body b;
    b.name = name;
    b.shape = Shape::Plane;
    b.normal = normal.normalized();
    b.restitution = 1.0;
    b.makeStatic();
    return b;
}

void validate(const Body& b) {
    const auto fail = [&](const std::string& what) { throw std::invalid_argument("body '" + b.name + "': " + what); };
    if (!isFinite(b.position)) fail("position is not finite");
    if (!isFinite(b.velocity)) fail("velocity is not finite");
    if (!isFinite(b.angularVelocity)) fail("angular velocity is not finite");
    if (!b.orientation.coeffs().allFinite()) fail("orientation is not finite");
    if (!std::isfinite(b.invMass) || b.invMass < 0.0) fail("inverse mass must be finite and >= 0");
    if (!b.isStatic() && !(std::isfinite(b.mass) && b.mass > 0.0)) fail("mass must be a positive finite number");
    if (!b.isStatic() && std::abs(b.mass * b.invMass - 1.0) > 1e-12) fail("mass and inverse mass disagree");
    if (b.shape == Shape::Sphere && !(std::isfinite(b.radius) && b.radius > 0.0))
        fail("radius must be a positive finite number of metres, got " + formatNumber(b.radius));
    if (b.shape == Shape::Plane && !(isFinite(b.normal) && b.normal.norm() > 0.0))
        fail("normal must be a finite, non-zero vector");
    if (!(b.restitution >= 0.0 && b.restitution <= 1.0))
        fail("restitution must lie in [0, 1], got " + formatNumber(b.restitution));
    if (!(b.friction >= 0.0 && std::isfinite(b.friction)))
        fail("friction must be a finite number >= 0, got " + formatNumber(b.friction));
    if (!(b.staticFriction >= 0.0 && std::isfinite(b.staticFriction)))
        fail("static friction must be a finite number >= 0, got " + formatNumber(b.staticFriction));
    if (b.staticFriction < b.friction)
        fail("static friction " + formatNumber(b.staticFriction) + " is below the sliding friction " +
             formatNumber(b.friction) + ": a body that sticks holds at least what it would slide with");
}

double rotationalEnergy(const Body& b) {
    if (b.isStatic()) return 0.0;
    // In the body frame, w_b . I w_b with w_b = R^T w: the same as w . (R I R^T) w without building
    // the world inertia.
    const Vec3 w = b.orientation.conjugate() * b.angularVelocity;
    return 0.5 * w.dot(b.inertia * w);
}

Vec3 linearMomentum(const Body& b) {
    if (b.isStatic()) return Vec3::Zero();
    return b.mass * b.velocity;
}

}  // namespace gpl
