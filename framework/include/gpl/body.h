// Rigid bodies: a plain struct grouped by role. Static means inverse mass zero; one rule, checked
// everywhere through Body::isStatic().
#pragma once

#include <string>

#include "gpl/math.h"

namespace gpl {

enum class Shape { Sphere, Box, Plane };

/// Name of a shape as shown to people ("sphere", "box", "plane").
const char* shapeName(Shape shape);

struct alignas(64) Body {
    // The fields are grouped by meaning; the groups are ordered by how often a time step reads them,
    // so that what integration and the sphere stages read (shape, radius, position, velocity,
    // acceleration, masses, angular velocity) fills the body's first two cache lines, which the
    // alignment to 64 bytes keeps apart from the neighbours'.
    Shape shape = Shape::Sphere;
    double radius = 0.0;  ///< sphere radius (m)

    // Pose and velocity.
    Vec3 position = Vec3::Zero();  ///< centre of mass in world coordinates (m)
    Vec3 velocity = Vec3::Zero();  ///< linear velocity of the centre of mass, world frame (m/s)

    // Accumulators, rebuilt every time step by the force stages.
    Vec3 acceleration = Vec3::Zero();  ///< constant acceleration such as gravity (m/s^2)

    // Mass properties. A static body has invMass 0, infinite mass and a zero inverse inertia.
    double mass = 1.0;     ///< kg
    double invMass = 1.0;  ///< 1/kg; 0 for static bodies

    // Read by kineticEnergy() with the velocity (rotation's other fields follow the material).
    Vec3 angularVelocity = Vec3::Zero();  ///< angular velocity, world frame (rad/s)

    // Material.
    double restitution = 0.5;  ///< coefficient of restitution, 0 (plastic) .. 1 (elastic)
    double friction = 0.5;        ///< Coulomb friction while sliding, mu_d (dimensionless, >= 0)
    double staticFriction = 0.5;  ///< Coulomb friction while sticking, mu_s (dimensionless, >= mu_d)

    // Rotation: pose, velocity and mass properties.
    Quat orientation = Quat::Identity();  ///< rotation from body to world frame (unit quaternion)
    Mat3 inertia = Mat3::Identity();      ///< inertia tensor about the centre of mass, body frame (kg m^2)
    Mat3 invInertia = Mat3::Identity();   ///< its inverse (1/(kg m^2)); zero for static bodies

    // Geometry of the other shapes, in the body's own frame.
    Vec3 halfExtents = Vec3::Zero();  ///< box half sizes along the body axes (m)
    Vec3 normal = Vec3::UnitY();      ///< plane normal (unit, body frame); the plane passes through position

    // Accumulators of forces and torques.
    Vec3 force = Vec3::Zero();   ///< sum of applied forces (N)
    Vec3 torque = Vec3::Zero();  ///< sum of applied torques about the centre of mass (N m)

    std::string name;  ///< unique within a scene; shown by the runner, the viewer and the grader

    bool isStatic() const { return invMass == 0.0; }

    // Builder-style helpers for scenes: sphere("ball", 0.5, 2.0).at({0, 10, 0}).moving({3, 0, 0}).
    Body& at(const Vec3& p);
    Body& moving(const Vec3& v);
    Body& spinning(const Vec3& w);
    Body& rotated(const Quat& q);
    Body& bouncy(double e);  ///< sets the restitution (checked by validate())
    /// Sets the friction coefficients, static mu_s and sliding mu_d (checked by validate()).
    Body& rough(double staticMu, double slidingMu);
    /// Makes the body static: it never moves and is not affected by forces.
    Body& makeStatic();
};

/// A solid sphere of the given radius (m) and mass (kg). Throws std::invalid_argument on a
/// non-positive or non-finite radius or mass.
Body sphere(const std::string& name, double radius, double mass);
/// A solid box with the given half extents (m) and mass (kg). Same checks as sphere().
Body box(const std::string& name, const Vec3& halfExtents, double mass);
/// An infinite static plane through the origin with the given normal (normalised here), the
/// side it points to free and the side behind it solid. Its restitution is 1, so that with the
/// product rule (combineRestitution()) a ball bounces off it with the ball's own coefficient.
Body plane(const std::string& name, const Vec3& normal);

/// Throws std::invalid_argument with a message naming the body and the field when the body's
/// state is not finite or its mass properties are inconsistent.
void validate(const Body& body);

// Diagnostics per body (static bodies have no kinetic or potential energy and no momentum). The
// energies are defined here, inline, because integrator checks call them for every body and step.

/// J, the rotational part of kineticEnergy().
double rotationalEnergy(const Body& body);
/// J, translational + rotational.
inline double kineticEnergy(const Body& b) {
    if (b.isStatic()) return 0.0;
    const double translation = 0.5 * b.mass * b.velocity.squaredNorm();
    // Not turning (every particle and sphere until worksheet 5): the rotational term is exactly 0.
    if (b.angularVelocity.isZero(0.0)) return translation;
    return translation + rotationalEnergy(b);
}
/// J, -m g.x (zero at the origin).
inline double potentialEnergy(const Body& b, const Vec3& gravity) {
    if (b.isStatic()) return 0.0;
    return -b.mass * gravity.dot(b.position);
}
Vec3 linearMomentum(const Body& body);  ///< kg m/s

}  // namespace gpl
