// What the worksheet-7 autograders share: a pair of turning bodies touching at one point, the
// effective mass along a direction written in the tests' own way, and the scenes of resting contact
// and friction built here (an incline, a floor) with the stages the friction stage needs.
#pragma once

#include <cmath>
#include <string>

#include "contacts.h"
#include "gpl/friction.h"
#include "gpl/response.h"
#include "gpl/scenes.h"
#include "turning.h"

namespace gpl::checks {

/// The inverse world inertia of a body (1/(kg m^2)), zero for a static one, from the tests' own R I R^T.
inline Mat3 inverseWorldInertia(const Body& b) {
    return b.isStatic() ? Mat3(Mat3::Zero()) : Mat3(worldInertia(b).inverse());
}

/// 1 / effective mass (1/kg) of the pair at p along the unit direction d: the change of the relative
/// velocity of the material points along d per unit impulse along d.
inline double inverseMassAlong(const Body& a, const Body& b, const Vec3& p, const Vec3& d) {
    double w = a.invMass + b.invMass;
    for (const Body* body : {&a, &b}) {
        const Vec3 r = p - body->position;
        w += d.dot((inverseWorldInertia(*body) * r.cross(d)).cross(r));
    }
    return w;
}

/// Relative velocity of the material points of b and a at p (m/s).
inline Vec3 relativeAt(const Body& a, const Body& b, const Vec3& p) { return pointVelocity(b, p) - pointVelocity(a, p); }

/// Two bodies touching at one point: b's side of the contact along `normal`.
struct Touch {
    Body a, b;
    Contact contact;
    PointImpulse sum;
};

inline std::string touchText(const Touch& t) {
    return "\n  a: " + turning(t.a) + "\n  b: " + turning(t.b) + "\n  normal " + str(t.contact.normal) + ", point " +
           str(t.contact.points[0]) + ", restitution " + formatNumber(t.contact.restitution) + ", mu_s " +
           formatNumber(t.contact.staticFriction) + ", mu_d " + formatNumber(t.contact.friction) +
           "\n  sums before: normal " + formatNumber(t.sum.normal) + " N s, tangent " + str(t.sum.tangent) +
           " N s, approach " + formatNumber(t.sum.approach) + " m/s";
}

/// A random pair of turning bodies (a static in every fifth) touching at a random point near both.
inline Touch randomTouch(Random& rnd, int i) {
    Touch t{turningBody(rnd, "a", i), turningBody(rnd, "b", i + 1), {}, {}};
    if (i % 5 == 3) t.a.makeStatic();
    t.contact.normal = rnd.direction();
    t.contact.pointCount = 1;
    t.contact.depth = 0.001;
    t.contact.points[0] = 0.5 * (t.a.position + t.b.position) + rnd.inBox(1.0);
    t.contact.restitution = rnd.uniform(0.0, 1.0);
    t.contact.friction = rnd.uniform(0.1, 0.8);
    t.contact.staticFriction = t.contact.friction * rnd.uniform(1.0, 1.5);
    return t;
}

/// The stages of a scene with friction: the worksheet-6 landing and the friction stage.
inline StageSet frictionStages() {
    return {Stage::ConstantAcceleration, Stage::Integration,      Stage::Rotation,          Stage::CollisionDetection,
            Stage::Interpenetration,     Stage::CollisionImpulses, Stage::Friction};
}

}  // namespace gpl::checks
