// An engine's world as the checker sends it and the submission's engine answers it: what a step
// reads (settings, bodies, springs, constraints, ropes, the container, the clock, last positions,
// the contacts so far) and what it changes (bodies, last positions, contacts).
//
// The checker keeps its own engine (the "mirror") with the framework's code and no student code:
// it loads scenes, adds bodies, owns gravity and the time step, measures energies and checks that
// bodies stay finite. Only the student hooks run in the sandbox, on a copy of the mirror's world.
#pragma once

#include <cstddef>
#include <cstring>
#include <string>
#include <vector>

#include "gpl/engine.h"
#include "protocol.h"

namespace gpl {

struct EngineAccess {
    // ---- The world, checker to engine ---------------------------------------------------------

    /// Settings, links, the clock and contacts always; the bodies and last positions only when
    /// `withBodies` (they are what the engine has already otherwise).
    static void writeWorld(grading::Writer& w, const PhysicsEngine& e, bool withBodies) {
        w.vec3(e.gravity_);
        w.number(e.timeStep_);
        w.u32(stageBits(e.required_));
        w.u32(stageBits(e.disabled_));
        w.u8(static_cast<std::uint8_t>(e.integratorKind_));
        w.i32(e.constraintIterations_);
        w.i32(e.contactIterations_);
        w.i32(e.interpenetrationIterations_);
        w.i32(e.threads());
        w.u32(static_cast<std::uint32_t>(e.springs_.size()));
        for (const Spring& s : e.springs_) {
            w.u64(s.a);
            w.u64(s.b);
            w.number(s.stiffness);
            w.number(s.restLength);
            w.number(s.damping);
        }
        w.u32(static_cast<std::uint32_t>(e.distances_.size()));
        for (const DistanceConstraint& d : e.distances_) {
            w.u64(d.a);
            w.u64(d.b);
            w.number(d.length);
        }
        w.u32(static_cast<std::uint32_t>(e.ropes_.size()));
        for (const Rope& r : e.ropes_) {
            w.u64(r.a);
            w.u64(r.b);
            w.number(r.length);
        }
        w.u8(e.container_ ? 1 : 0);
        if (e.container_) {
            w.vec3(e.container_->centre);
            w.number(e.container_->radius);
        }
        w.number(e.time_);
        w.u64(e.steps_);
        w.contacts(e.contacts_);
        w.u8(withBodies ? 1 : 0);
        if (withBodies) {
            w.bodies(e.bodies_);
            w.vec3s(e.previousPositions_);
        }
    }

    /// The engine's side: applies a world written by writeWorld(). A new set of bodies (another
    /// number or other names) starts afresh, as a scene being loaded does.
    static void readWorld(grading::Reader& r, PhysicsEngine& e) {
        e.gravity_ = r.vec3();
        e.timeStep_ = r.number();
        e.required_ = stageSet(r.u32());
        e.disabled_ = stageSet(r.u32());
        const std::uint8_t kind = r.u8();
        if (kind > static_cast<std::uint8_t>(Integrator::RungeKutta4)) throw grading::ProtocolError("unknown integrator");
        e.integratorKind_ = static_cast<Integrator>(kind);
        e.constraintIterations_ = r.i32();
        e.contactIterations_ = r.i32();
        e.interpenetrationIterations_ = r.i32();
        const int threads = r.i32();
        if (threads >= 1 && threads != e.threads()) e.setThreads(threads);
        e.springs_.resize(r.count(40));
        for (Spring& s : e.springs_) {
            s.a = r.u64();
            s.b = r.u64();
            s.stiffness = r.number();
            s.restLength = r.number();
            s.damping = r.number();
        }
        e.distances_.resize(r.count(24));
        for (DistanceConstraint& d : e.distances_) {
            d.a = r.u64();
            d.b = r.u64();
            d.length = r.number();
        }
        e.ropes_.resize(r.count(24));
        for (Rope& rope : e.ropes_) {
            rope.a = r.u64();
            rope.b = r.u64();
            rope.length = r.number();
        }
        e.container_.reset();
        if (r.u8()) {
            Container c;
            c.centre = r.vec3();
            c.radius = r.number();
            e.container_ = c;
        }
        e.time_ = r.number();
        e.steps_ = r.u64();
        e.contacts_ = r.contacts();
        e.nearPairs_.clear();  // found anew by detectCollisions() in every step, as step() does
        if (r.u8()) {
            std::vector<Body> bodies = r.bodies();
            if (!sameNames(bodies, e.bodies_)) e.friction_.forget();
            e.bodies_ = std::move(bodies);
            e.previousPositions_ = r.vec3s();
        }
        r.end();
        const std::size_t n = e.bodies_.size();
        const auto inRange = [n](std::size_t a, std::size_t b) { return a < n && b < n; };
        for (const Spring& s : e.springs_) {
            if (!inRange(s.a, s.b)) throw grading::ProtocolError("a spring names a body that is not there");
        }
        for (const DistanceConstraint& d : e.distances_) {
            if (!inRange(d.a, d.b)) throw grading::ProtocolError("a constraint names a body that is not there");
        }
        for (const Rope& rope : e.ropes_) {
            if (!inRange(rope.a, rope.b)) throw grading::ProtocolError("a rope names a body that is not there");
        }
    }

    // ---- What a hook changed, engine to checker ------------------------------------------------

    static void writeChanges(grading::Writer& w, const PhysicsEngine& e) {
        w.u32(static_cast<std::uint32_t>(e.bodies_.size()));
        for (const Body& b : e.bodies_) writeMotion(w, b);
        w.vec3s(e.previousPositions_);
        w.contacts(e.contacts_);
    }

    /// The checker's side: the motion of every body as the hook left it, copied into the mirror
    /// (what the checker owns of a body, its mass, shape and material, stays the mirror's); the
    /// last positions and contacts, checked against the mirror's bodies. The hooks still open
    /// follow (parseAnswer() reads them).
    static void readChanges(grading::Reader& r, PhysicsEngine& mirror) {
        const std::size_t n = mirror.bodies_.size();
        if (r.count(kMotionBytes) != n) throw grading::ProtocolError("the engine answered for another number of bodies");
        for (Body& b : mirror.bodies_) readMotion(r, b);
        std::vector<Vec3> previous = r.vec3s();
        std::vector<Contact> contacts = r.contacts();
        if (!previous.empty() && previous.size() != n) {
            throw grading::ProtocolError("the engine answered with last positions for another number of bodies");
        }
        for (const Contact& c : contacts) {
            if (c.a >= n || c.b >= n) throw grading::ProtocolError("the engine answered with a contact of no body");
        }
        mirror.previousPositions_ = std::move(previous);
        mirror.contacts_ = std::move(contacts);
    }

    /// Bytes of a body's motion on the pipe.
    static constexpr std::size_t kMotionBytes = 22 * sizeof(double);
    static void writeMotion(grading::Writer& w, const Body& b) {
        double m[19];
        std::memcpy(m, b.position.data(), 3 * sizeof(double));
        std::memcpy(m + 3, b.velocity.data(), 3 * sizeof(double));
        std::memcpy(m + 6, b.acceleration.data(), 3 * sizeof(double));
        std::memcpy(m + 9, b.angularVelocity.data(), 3 * sizeof(double));
        std::memcpy(m + 12, b.orientation.coeffs().data(), 4 * sizeof(double));
        std::memcpy(m + 16, b.force.data(), 3 * sizeof(double));
        w.numbers(m, 19);
        w.numbers(b.torque.data(), 3);
    }
    static void readMotion(grading::Reader& r, Body& b) {
        double m[22];
        r.numbers(m, 22);
        std::memcpy(b.position.data(), m, 3 * sizeof(double));
        std::memcpy(b.velocity.data(), m + 3, 3 * sizeof(double));
        std::memcpy(b.acceleration.data(), m + 6, 3 * sizeof(double));
        std::memcpy(b.angularVelocity.data(), m + 9, 3 * sizeof(double));
        std::memcpy(b.orientation.coeffs().data(), m + 12, 4 * sizeof(double));
        std::memcpy(b.force.data(), m + 16, 3 * sizeof(double));
        std::memcpy(b.torque.data(), m + 19, 3 * sizeof(double));
    }

    /// True when the two engines' bodies and last positions are the same to the bit.
    static bool sameBodies(const std::vector<Body>& a, const std::vector<Vec3>& previousA, const PhysicsEngine& b) {
        if (a.size() != b.bodies_.size() || previousA.size() != b.previousPositions_.size()) return false;
        for (std::size_t i = 0; i < a.size(); ++i) {
            if (!sameBody(a[i], b.bodies_[i])) return false;
        }
        return previousA.empty() ||
               std::memcmp(previousA.data(), b.previousPositions_.data(), previousA.size() * sizeof(Vec3)) == 0;
    }

    /// Field by field, each to the bit (a NaN equals itself; the padding between fields is not compared).
    static bool sameBody(const Body& x, const Body& y) {
        const auto same = [](const auto& u, const auto& v) { return std::memcmp(&u, &v, sizeof u) == 0; };
        return same(x.shape, y.shape) && same(x.radius, y.radius) && same(x.position, y.position) &&
               same(x.velocity, y.velocity) && same(x.acceleration, y.acceleration) && same(x.mass, y.mass) &&
               same(x.invMass, y.invMass) && same(x.angularVelocity, y.angularVelocity) &&
               same(x.restitution, y.restitution) && same(x.friction, y.friction) &&
               same(x.staticFriction, y.staticFriction) && same(x.orientation.coeffs(), y.orientation.coeffs()) &&
               same(x.inertia, y.inertia) && same(x.invInertia, y.invInertia) && same(x.halfExtents, y.halfExtents) &&
               same(x.normal, y.normal) && same(x.force, y.force) && same(x.torque, y.torque) && x.name == y.name;
    }

    /// Copies what a hook may change of a body (its motion: position, velocity, the accumulators,
    /// orientation and angular velocity) and leaves what the checker owns (mass, shape, material).
    static void copyMotion(const Body& from, Body& to) {
        to.position = from.position;
        to.velocity = from.velocity;
        to.acceleration = from.acceleration;
        to.angularVelocity = from.angularVelocity;
        to.orientation = from.orientation;
        to.force = from.force;
        to.torque = from.torque;
    }

    /// What step() does before and after simulationTimestep().
    static void beginStep(PhysicsEngine& e) { e.beginStep(); }
    static void endStep(PhysicsEngine& e) { e.endStep(); }
    /// endStep() without its check: the clock alone (the engine's side; the checker checks).
    static void advanceClock(PhysicsEngine& e) {
        e.time_ += e.timeStep_;
        ++e.steps_;
    }

    static const std::vector<Body>& bodies(const PhysicsEngine& e) { return e.bodies_; }
    static const std::vector<Vec3>& previousPositions(const PhysicsEngine& e) { return e.previousPositions_; }

private:
    static std::uint32_t stageBits(const StageSet& s) {
        std::uint32_t bits = 0;
        for (std::size_t i = 0; i < kStageCount; ++i) {
            if (s.contains(static_cast<Stage>(i))) bits |= 1u << i;
        }
        return bits;
    }
    static StageSet stageSet(std::uint32_t bits) {
        StageSet s;
        for (std::size_t i = 0; i < kStageCount; ++i) {
            if (bits & (1u << i)) s.insert(static_cast<Stage>(i));
        }
        return s;
    }
    static bool sameNames(const std::vector<Body>& a, const std::vector<Body>& b) {
        if (a.size() != b.size()) return false;
        for (std::size_t i = 0; i < a.size(); ++i) {
            if (a[i].name != b[i].name) return false;
        }
        return true;
    }
};

}  // namespace gpl
