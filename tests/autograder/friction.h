// What the worksheet-7 autograders share: a pair of turning bodies touching at one point, its point
// prepared for the sweeps and the effective mass along a direction written in the tests' own way,
// and the stages the friction stage needs.
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

/// Two bodies touching at one point: b's side of the contact along `normal`, the first tangent of the
/// point's basis (unit, across the normal; the second is normal x tangent) and the sums so far.
struct Touch {
    Body a, b;
    Contact contact;
    Vec3 tangent = Vec3::UnitX();
    PointImpulse sum;
};

/// The axis of a point at p along the unit direction d, in the tests' own way: the lever arms'
/// cross products with d, the world inverse inertias (the tests' own R I R^T, inverted) applied to
/// them, and the inverse effective mass in worksheet 6's triple-product form.
inline ContactAxis axisOf(const Body& a, const Body& b, const Vec3& p, const Vec3& d) {
    ContactAxis x;
    x.d = d;
    x.raXd = (p - a.position).cross(d);
    x.rbXd = (p - b.position).cross(d);
    x.invIaRaXd = inverseWorldInertia(a) * x.raXd;
    x.invIbRbXd = inverseWorldInertia(b) * x.rbXd;
    x.K = inverseMassAlong(a, b, p, d);
    return x;
}

/// The touch's point as the sweeps read it, prepared in the tests' own way: lever arms, the axes of
/// the touch's tangent basis (axisOf()), and the target of the contract: -e approach above
/// kRestingSpeed, else 0.
inline ContactPoint pointOf(const Touch& t) {
    ContactPoint c;
    c.p = t.contact.points[0];
    c.ra = c.p - t.a.position;
    c.rb = c.p - t.b.position;
    const Vec3& n = t.contact.normal;
    c.n = axisOf(t.a, t.b, c.p, n);
    c.t1 = axisOf(t.a, t.b, c.p, t.tangent);
    c.t2 = axisOf(t.a, t.b, c.p, n.cross(t.tangent));
    c.target = t.sum.approach < -kRestingSpeed ? -t.contact.restitution * t.sum.approach : 0.0;
    c.staticFriction = t.contact.staticFriction;
    c.friction = t.contact.friction;
    return c;
}

inline std::string touchText(const Touch& t) {
    const ContactPoint c = pointOf(t);
    return "\n  a: " + turning(t.a) + "\n  b: " + turning(t.b) + "\n  point p " + str(c.p) + ", n " + str(c.n.d) +
           ", t1 " + str(c.t1.d) + ", t2 " + str(c.t2.d) + "\n  K_n " + formatNumber(c.n.K) + ", K_t1 " +
           formatNumber(c.t1.K) + ", K_t2 " + formatNumber(c.t2.K) + " 1/kg, target " + formatNumber(c.target) +
           " m/s, mu_s " + formatNumber(c.staticFriction) + ", mu_d " + formatNumber(c.friction) +
           "\n  sums before: normal " + formatNumber(t.sum.normal) + " N s, tangent " + str(t.sum.tangent) +
           " N s, approach " + formatNumber(t.sum.approach) + " m/s";
}

/// A random pair of turning bodies (a static in every fifth) touching at a random point near both,
/// with a random tangent basis.
inline Touch randomTouch(Random& rnd, int i) {
    Touch t{turningBody(rnd, "a", i), turningBody(rnd, "b", i + 1), {}, {}, {}};
    if (i % 5 == 3) t.a.makeStatic();
    t.contact.normal = rnd.direction();
    t.contact.pointCount = 1;
    t.contact.depth = 0.001;
    t.contact.points[0] = 0.5 * (t.a.position + t.b.position) + rnd.inBox(1.0);
    t.contact.restitution = rnd.uniform(0.0, 1.0);
    t.contact.friction = rnd.uniform(0.1, 0.8);
    t.contact.staticFriction = t.contact.friction * rnd.uniform(1.0, 1.5);
    t.tangent = rnd.perpendicular(t.contact.normal);
    return t;
}

/// Two balls touching (a static one in every fifth, a ball on a fixed ground): the point on the line
/// of their centres, so that both lever arms lie along the normal and the inverse effective mass is
/// the same along every tangent.
inline Touch ballsTouching(Random& rnd, int i) {
    Touch t = randomTouch(rnd, i);
    const Vec3 n = t.contact.normal;
    for (Body* ball : {&t.a, &t.b}) {
        const std::string name = ball->name;
        *ball = sphere(name, rnd.uniform(0.1, 1.0), rnd.uniform(0.1, 10.0))
                    .rotated(rnd.rotation())
                    .moving(rnd.inBox(5.0))
                    .spinning(rnd.inBox(5.0));
    }
    if (i % 5 == 3) t.a.makeStatic();
    t.a.position = rnd.inBox(5.0);
    t.contact.points[0] = t.a.position + t.a.radius * n;
    t.b.position = t.contact.points[0] + t.b.radius * n;
    return t;
}

/// The stages of a scene with friction: the worksheet-6 landing and the friction stage.
inline StageSet frictionStages() {
    return {Stage::ConstantAcceleration, Stage::Integration,      Stage::Rotation,          Stage::CollisionDetection,
            Stage::Interpenetration,     Stage::CollisionImpulses, Stage::Friction};
}

}  // namespace gpl::checks
