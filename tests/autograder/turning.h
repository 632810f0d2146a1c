// What the worksheet-6 autograders share: turning bodies drawn from a fixed seed, the closed forms
// of rigid-body mechanics the tests compare with (written here once, in the tests' own way), and
// messages that show a body's rotation.
#pragma once

#include <cmath>
#include <string>

#include "contacts.h"
#include "gpl/rotation.h"

namespace gpl::checks {

/// The world inertia tensor R I R^T of a movable body (kg m^2), built from the rotation matrix.
inline Mat3 worldInertia(const Body& b) {
    const Mat3 r = b.orientation.toRotationMatrix();
    return r * b.inertia * r.transpose();
}

/// Angular momentum about the point `about` (kg m^2/s): (x - about) × m v + R I R^T omega.
inline Vec3 momentAbout(const Body& b, const Vec3& about) {
    if (b.isStatic()) return Vec3::Zero();
    return (b.position - about).cross(b.mass * b.velocity) + worldInertia(b) * b.angularVelocity;
}

/// Kinetic energy, translation and rotation (J), from the world inertia tensor.
inline double energyOf(const Body& b) {
    if (b.isStatic()) return 0.0;
    return 0.5 * b.mass * b.velocity.squaredNorm() + 0.5 * b.angularVelocity.dot(worldInertia(b) * b.angularVelocity);
}

/// Velocity of the material point of b at p (m/s).
inline Vec3 pointVelocity(const Body& b, const Vec3& p) { return b.velocity + b.angularVelocity.cross(p - b.position); }

/// A movable body that turns: a box of half extents 0.1 .. 1 m or a sphere (every third), 0.1 .. 10 kg,
/// at a random place and orientation, moving at up to 5 m/s and turning at up to 5 rad/s.
inline Body turningBody(Random& rnd, const std::string& name, int i) {
    Body b = i % 3 == 2 ? sphere(name, rnd.uniform(0.1, 1.0), rnd.uniform(0.1, 10.0))
                        : box(name, {rnd.uniform(0.1, 1.0), rnd.uniform(0.1, 1.0), rnd.uniform(0.1, 1.0)},
                              rnd.uniform(0.1, 10.0));
    return b.at(rnd.inBox(5.0)).rotated(rnd.rotation()).moving(rnd.inBox(5.0)).spinning(rnd.inBox(5.0));
}

/// Angle (rad) of the rotation that takes q to r: 0 when they are the same orientation (q and -q
/// are the same orientation).
inline double angleBetween(const Quat& q, const Quat& r) {
    // From the quaternion of the difference, atan2 rather than acos: exact near 0, where acos loses half the digits.
    const Quat d = q.normalized().conjugate() * r.normalized();
    return 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
}

inline std::string str(const Quat& q) {
    std::ostringstream out;
    out.precision(12);
    out << "(w " << q.w() << ", x " << q.x() << ", y " << q.y() << ", z " << q.z() << ")";
    return out.str();
}

/// A body with its rotation, for messages.
inline std::string turning(const Body& b) {
    std::string s = str(b);
    if (b.shape == Shape::Box) s += ", half extents " + str(b.halfExtents);
    if (!b.isStatic()) s += ", orientation " + str(b.orientation) + ", angular velocity " + str(b.angularVelocity);
    return s;
}

}  // namespace gpl::checks
