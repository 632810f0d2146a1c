// An engine's world as the checker sends it and the submission's engine answers it: what a step
// reads (settings, bodies, springs, constraints, ropes, the container, the clock, last positions,
// the contacts so far, the soft bodies, the fluid) and what it changes (bodies, last positions,
// contacts, the soft and fluid particles' positions and velocities).
//
// The checker keeps its own engine (the "mirror") with the framework's code and no student code:
// it loads scenes, adds bodies, owns gravity and the time step, measures energies and checks that
// bodies stay finite. Only the student hooks run in the sandbox, on a copy of the mirror's world.
#pragma once

#include <cstddef>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "gpl/broadphase.h"
#include "gpl/engine.h"
#include "gpl/fluids.h"
#include "gpl/friction_stage.h"
#include "gpl/soft_bodies.h"
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
        writeSoft(w, e.soft_);
        writeFluid(w, e.fluids_);
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
        readSoft(r, e.soft_);
        readFluid(r, e.fluids_);
        if (r.u8()) {
            std::vector<Body> bodies = r.bodies();
            if (!sameNames(bodies, e.bodies_)) e.friction_->forget();
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
        w.vec3s(e.soft_.x);
        w.vec3s(e.soft_.v);
        w.vec3s(e.fluids_.x);
        w.vec3s(e.fluids_.v);
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
        // The particles' positions and velocities, as many as the mirror has; what they are is for
        // the tests (and the finiteness check of endStep()) to judge.
        SoftBodies& soft = mirror.soft_;
        std::vector<Vec3> x = r.vec3s(), v = r.vec3s();
        if (x.size() != soft.x.size() || v.size() != soft.x.size()) {
            throw grading::ProtocolError("the engine answered for another number of particles");
        }
        // The fluid's positions and velocities likewise: as many as the mirror has, finite (checked
        // by endStep(), which names the particle) before any test reads them.
        Fluids& fluid = mirror.fluids_;
        std::vector<Vec3> fx = r.vec3s(), fv = r.vec3s();
        if (fx.size() != fluid.x.size() || fv.size() != fluid.x.size()) {
            throw grading::ProtocolError("the engine answered for another number of fluid particles");
        }
        mirror.previousPositions_ = std::move(previous);
        mirror.contacts_ = std::move(contacts);
        soft.x = std::move(x);
        soft.v = std::move(v);
        soft.p = soft.x;
        fluid.x = std::move(fx);
        fluid.v = std::move(fv);
        fluid.p = fluid.x;
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

    /// Bytes of a particle's answer in a step (position and velocity).
    static constexpr std::size_t kParticleBytes = 6 * sizeof(double);

private:
    // ---- The soft bodies, checker to engine: meshes, particles, constraints and wind whole (a step
    // reads them all); the lambdas and this step's contacts start afresh in every step ------------

    static void writeSoft(grading::Writer& w, const SoftBodies& s) {
        w.u32(static_cast<std::uint32_t>(s.meshes.size()));
        for (const SoftMesh& m : s.meshes) {
            w.text(m.name);
            w.u8(static_cast<std::uint8_t>(m.kind));
            w.u8(static_cast<std::uint8_t>(m.method));
            for (const std::uint32_t u : {m.first, m.count, m.firstLink, m.linkCount, m.firstVolume, m.volumeCount}) w.u32(u);
            w.i32(m.nx);
            w.i32(m.ny);
            w.u32(static_cast<std::uint32_t>(m.triangles.size()));
            for (const auto& tri : m.triangles) {
                for (const std::uint32_t u : tri) w.u32(u);
            }
            w.number(m.radius);
            w.u8(m.selfCollision ? 1 : 0);
        }
        w.vec3s(s.x);
        w.vec3s(s.v);
        w.vec3s(s.x0);
        w.u32(static_cast<std::uint32_t>(s.w.size()));
        for (std::size_t i = 0; i < s.w.size(); ++i) {
            w.number(s.w[i]);
            w.number(i < s.mass.size() ? s.mass[i] : 0.0);
            w.u32(i < s.meshOf.size() ? s.meshOf[i] : 0);
        }
        w.u32(static_cast<std::uint32_t>(s.links.size()));
        for (const DistanceLink& l : s.links) {
            w.u32(l.i);
            w.u32(l.j);
            w.number(l.rest);
            w.number(l.compliance);
            w.number(l.stiffness);
            w.u8(static_cast<std::uint8_t>(l.kind));
        }
        w.u32(static_cast<std::uint32_t>(s.volumes.size()));
        for (const TetVolume& t : s.volumes) {
            for (const std::uint32_t u : t.v) w.u32(u);
            w.number(t.rest);
            w.number(t.compliance);
            w.number(t.stiffness);
        }
        w.vec3(s.wind());
        w.number(s.windDrag());
    }

    /// The engine's side of writeSoft(); every index and enumeration checked.
    static void readSoft(grading::Reader& r, SoftBodies& s) {
        using grading::ProtocolError;
        s.clear();
        s.meshes.resize(r.count(40));
        for (SoftMesh& m : s.meshes) {
            m.name = r.text();
            const std::uint8_t kind = r.u8(), method = r.u8();
            if (kind > static_cast<std::uint8_t>(SoftMesh::Kind::SoftBody)) throw ProtocolError("a mesh of an unknown kind");
            if (method > static_cast<std::uint8_t>(SoftMethod::XPBD)) throw ProtocolError("a mesh of an unknown method");
            m.kind = static_cast<SoftMesh::Kind>(kind);
            m.method = static_cast<SoftMethod>(method);
            for (std::uint32_t* u : {&m.first, &m.count, &m.firstLink, &m.linkCount, &m.firstVolume, &m.volumeCount}) *u = r.u32();
            m.nx = r.i32();
            m.ny = r.i32();
            m.triangles.resize(r.count(12));
            for (auto& tri : m.triangles) {
                for (std::uint32_t& u : tri) u = r.u32();
            }
            m.radius = r.number();
            m.selfCollision = r.u8() != 0;
        }
        s.x = r.vec3s();
        s.v = r.vec3s();
        s.x0 = r.vec3s();
        const std::size_t n = s.x.size();
        if (r.count(20) != n || s.v.size() != n || s.x0.size() != n) throw ProtocolError("particles of unequal counts");
        s.w.resize(n);
        s.mass.resize(n);
        s.meshOf.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            s.w[i] = r.number();
            s.mass[i] = r.number();
            s.meshOf[i] = r.u32();
            if (s.meshOf[i] >= s.meshes.size()) throw ProtocolError("a particle of no mesh");
        }
        s.p = s.x;
        s.links.resize(r.count(33));
        for (DistanceLink& l : s.links) {
            l.i = r.u32();
            l.j = r.u32();
            l.rest = r.number();
            l.compliance = r.number();
            l.stiffness = r.number();
            const std::uint8_t kind = r.u8();
            if (kind > static_cast<std::uint8_t>(LinkKind::Rope)) throw ProtocolError("a link of an unknown kind");
            l.kind = static_cast<LinkKind>(kind);
            if (l.i >= n || l.j >= n) throw ProtocolError("a link names a particle that is not there");
        }
        s.volumes.resize(r.count(40));
        for (TetVolume& t : s.volumes) {
            for (std::uint32_t& u : t.v) {
                u = r.u32();
                if (u >= n) throw ProtocolError("a tetrahedron names a particle that is not there");
            }
            t.rest = r.number();
            t.compliance = r.number();
            t.stiffness = r.number();
        }
        for (const SoftMesh& m : s.meshes) {
            const auto within = [](std::uint64_t first, std::uint64_t count, std::size_t size) { return first + count <= size; };
            if (!within(m.first, m.count, n) || !within(m.firstLink, m.linkCount, s.links.size()) ||
                !within(m.firstVolume, m.volumeCount, s.volumes.size())) {
                throw ProtocolError("a mesh names particles or constraints that are not there");
            }
            for (const auto& tri : m.triangles) {
                for (const std::uint32_t u : tri) {
                    if (u >= n) throw ProtocolError("a triangle names a particle that is not there");
                }
            }
        }
        const Vec3 wind = r.vec3();
        const double drag = r.number();
        s.setWind(wind, drag);
    }

    // ---- The fluid, checker to engine: parameters, container and particles whole (a step reads
    // them all); densities, multipliers and pressures start afresh in every step --------------------

    static void writeFluid(grading::Writer& w, const Fluids& f) {
        const FluidParameters& p = f.parameters();
        for (const double u : {p.restDensity, p.spacing, p.smoothingLength, p.relaxation, p.tensile.k, p.tensile.dq,
                               p.xsph, p.soundSpeed, p.artificialViscosity}) {
            w.number(u);
        }
        w.i32(p.tensile.n);
        w.i32(p.iterations);
        w.u8(f.container() ? 1 : 0);
        if (f.container()) {
            w.vec3(f.container()->lower);
            w.vec3(f.container()->upper);
        }
        w.vec3s(f.x);
        w.vec3s(f.v);
    }

    /// The engine's side of writeFluid(); the parameters checked as setParameters() checks them,
    /// every position and velocity finite.
    static void readFluid(grading::Reader& r, Fluids& f) {
        using grading::ProtocolError;
        FluidParameters p;
        for (double* u : {&p.restDensity, &p.spacing, &p.smoothingLength, &p.relaxation, &p.tensile.k, &p.tensile.dq,
                          &p.xsph, &p.soundSpeed, &p.artificialViscosity}) {
            *u = r.number();
        }
        p.tensile.n = r.i32();
        p.iterations = r.i32();
        f.clear();
        try {
            f.setParameters(p);
            if (r.u8()) {
                FluidBox box;
                box.lower = r.vec3();
                box.upper = r.vec3();
                f.setContainer(box);
            }
        } catch (const std::invalid_argument& e) {
            throw ProtocolError(std::string("the fluid: ") + e.what());
        }
        std::vector<Vec3> x = r.vec3s(), v = r.vec3s();
        if (v.size() != x.size()) throw ProtocolError("fluid positions and velocities of unequal counts");
        for (std::size_t i = 0; i < x.size(); ++i) {
            if (!x[i].allFinite() || !v[i].allFinite()) throw ProtocolError("a fluid particle that is not finite");
        }
        f.x = std::move(x);
        f.v = std::move(v);
        f.p = f.x;
        f.density.assign(f.x.size(), p.restDensity);
        f.lambda.assign(f.x.size(), 0.0);
        f.pressure.assign(f.x.size(), 0.0);
    }

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
