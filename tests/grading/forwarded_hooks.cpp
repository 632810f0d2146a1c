// The student hooks as the checker has them: every one is a request to the submission's engine
// (submission.h). The checker's own engine (the mirror a graded test steps) runs the framework's
// code here, trusted: step() clears the contacts, advances the clock and checks that every body is
// finite; gravity and the time step are the mirror's. Only simulationTimestep() and integrator()
// cross to the submission, with the mirror's world; they bring back the motion of its bodies.
#include <algorithm>
#include <cstring>
#include <functional>
#include <string>

#include "engine_access.h"
#include "gpl/collision.h"
#include "gpl/integrators.h"
#include "gpl/engine.h"
#include "gpl/fluid_kernels.h"
#include "gpl/response.h"
#include "gpl/rotation.h"
#include "gpl/scenes.h"
#include "gpl/soft_constraints.h"
#include "submission.h"
#include "../autograder/graded.h"

namespace gpl {
namespace {

using grading::Call;
using grading::Reader;
using grading::Writer;

// What the submission's engine holds now: whose world (the mirror it last answered), and that
// mirror's bodies and last positions as they were after the answer. A request sends the bodies only
// when the mirror's differ (a test changed them), so that a run of steps sends each state once.
const PhysicsEngine* heldFor = nullptr;
std::vector<Body> heldBodies;
std::vector<Vec3> heldPrevious;
std::size_t heldSteps = 0;

/// The hooks a step of the mirror's world may run, stage by stage.
std::vector<std::string> hooksOfStep(const PhysicsEngine& e) {
    std::vector<std::string> hooks{"simulationTimestep()"};
    const auto add = [&](std::initializer_list<Call> calls) {
        for (Call c : calls) {
            if (std::find(hooks.begin(), hooks.end(), callName(c)) == hooks.end()) hooks.emplace_back(callName(c));
        }
    };
    const bool turning = e.stageActive(Stage::Rotation);
    if (e.stageActive(Stage::Integration)) {
        switch (e.integratorKind()) {
            case Integrator::PositionVerlet: add({Call::PositionVerlet}); break;
            case Integrator::VelocityVerlet: add({Call::VelocityVerlet}); break;
            case Integrator::SemiImplicitEuler: add({Call::Integrator}); break;
            default: break;
        }
    }
    if (turning) add({Call::IntegrateRotation, Call::WorldInverseInertia});
    if (e.stageActive(Stage::CollisionDetection)) {
        add({Call::SphereSphere, Call::SpherePlane, Call::SphereBox, Call::BoxPlane, Call::BoxBox});
    }
    if (e.stageActive(Stage::Ropes)) add({Call::RopeContact});
    if (e.stageActive(Stage::Interpenetration)) add({Call::ResolveInterpenetration});
    if (e.stageActive(Stage::CollisionImpulses)) {
        if (turning) {
            add({Call::ApplyContactImpulse, Call::ApplyImpulseAtPoint, Call::WorldInverseInertia});
        } else {
            add({Call::ApplyCollisionImpulse});
        }
    }
    if (e.stageActive(Stage::Friction)) {
        add({Call::PrepareContactPoint, Call::ApplyWarmStart, Call::ApplyNormalImpulse, Call::ApplyFrictionImpulse,
             Call::ApplyImpulseAtPoint, Call::WorldInverseInertia});
    }
    if (e.stageActive(Stage::SoftProject)) {
        add({Call::SolveDistanceConstraint, Call::SolveVolumeConstraint, Call::ProjectParticleSphere,
             Call::ProjectParticleBox});
    }
    if (e.stageActive(Stage::FluidProject)) {
        add({Call::Poly6Kernel, Call::FluidDensity, Call::SpikyGradient, Call::DensityConstraintLambda,
             Call::DensityCorrection});
    }
    if (e.stageActive(Stage::FluidVelocities)) add({Call::Poly6Kernel, Call::XsphViscosity});
    if (e.stageActive(Stage::FluidSph)) add({Call::Poly6Kernel, Call::FluidDensity, Call::SpikyGradient});
    return hooks;
}

/// The status lines name the step's hooks while its request is in flight.
struct StepHooks {
    explicit StepHooks(const PhysicsEngine& e) { grading::setStepHooks(hooksOfStep(e)); }
    ~StepHooks() { grading::setStepHooks({}); }
};

void engineCall(Call call, PhysicsEngine& mirror) {
    const StepHooks named(mirror);
    // Another engine (or this one, loaded anew): the submission starts from a fresh engine too.
    const bool fresh = heldFor != &mirror || mirror.stepCount() < heldSteps;
    const bool send = fresh || !EngineAccess::sameBodies(heldBodies, heldPrevious, mirror);
    Writer w;
    w.u8(fresh ? 1 : 0);
    EngineAccess::writeWorld(w, mirror, send);
    heldFor = nullptr;  // until the answer is read whole: a hook that throws leaves its engine as it was then
    const std::string& answer = grading::request(call, w.bytes());
    grading::parseAnswer(call, answer, [&](Reader& r) { EngineAccess::readChanges(r, mirror); });
    for (const std::string& hook : grading::openHooksOfLastAnswer()) mirror.notImplemented(hook);
    heldBodies = EngineAccess::bodies(mirror);
    heldPrevious = EngineAccess::previousPositions(mirror);
    heldFor = &mirror;
    heldSteps = mirror.stepCount();
}

}  // namespace

namespace grading {

namespace {

/// Reads a batched answer: its count of steps (at most `asked`), each step's record read by `step`
/// (which returns false when the test's checks failed: the rest is not read), then whether a hook
/// threw and the hooks still open. False when `step` stopped the run; rethrows what a hook threw;
/// an answer that does not parse ends the submission for this test.
bool readSteps(Call call, Reader& r, std::uint32_t asked, const std::function<bool()>& step) {
    std::uint8_t threw = 0, kind = 0;
    std::string message;
    try {
        const std::uint32_t done = r.u32();
        if (done > asked) throw ProtocolError("more steps than were asked for");
        for (std::uint32_t s = 0; s < done; ++s) {
            if (!step()) return false;
        }
        threw = r.u8();
        if (threw > 1) throw ProtocolError("an answer that neither threw nor did not");
        if (threw) {
            kind = r.u8();
            if (kind < 1 || kind >= static_cast<std::uint8_t>(Thrown::End)) throw ProtocolError("an unknown exception");
            message = r.text();
        }
        r.texts();
        r.end();
        if (done == 0 && !threw) throw ProtocolError("no step was made");
    } catch (const ProtocolError& e) {
        endNow(call, e.what());
    }
    if (threw) rethrow(static_cast<Thrown>(kind), message);
    return true;
}

}  // namespace

void steps(PhysicsEngine& mirror, int n, const std::function<void(int)>& each) {
    // Steps of one request: as many as about a megabyte of answers holds (a thousand bodies: six),
    // which stays in the processor's caches.
    const StepHooks named(mirror);
    const std::size_t perStep = 180 * std::max<std::size_t>(1, EngineAccess::bodies(mirror).size()) +
                                EngineAccess::kParticleBytes * (mirror.softBodies().x.size() + mirror.fluids().size()) +
                                64;
    const int batch = static_cast<int>(std::clamp<std::size_t>((1u << 20) / perStep, 1, 1000));
    int k = 0;
    std::string answer;  // a copy of each answer, its memory kept from batch to batch: each(k) may ask for hooks too
    while (k < n) {
        const auto asked = static_cast<std::uint32_t>(std::min(batch, n - k));
        const bool fresh = heldFor != &mirror || mirror.stepCount() < heldSteps;
        const bool send = fresh || !EngineAccess::sameBodies(heldBodies, heldPrevious, mirror);
        Writer w;
        w.u8(fresh ? 1 : 0);
        w.u32(asked);
        EngineAccess::writeWorld(w, mirror, send);
        heldFor = nullptr;  // until every step of the answer has been taken
        answer = request(Call::Steps, w.bytes());
        Reader r(answer, 1);
        const bool whole = readSteps(Call::Steps, r, asked, [&] {
            EngineAccess::beginStep(mirror);
            EngineAccess::readChanges(r, mirror);
            for (const std::string& hook : r.texts()) {
                for (int c = 1; c < static_cast<int>(Call::End); ++c) {
                    if (hook == callName(static_cast<Call>(c))) mirror.notImplemented(hook);
                }
            }
            EngineAccess::endStep(mirror);  // the checker's clock and its check that bodies are finite
            each(++k);
            return !::testing::Test::HasFailure();
        });
        if (!whole) return;  // the submission's engine is ahead of the mirror now: a later request starts afresh
        heldBodies = EngineAccess::bodies(mirror);
        heldPrevious = EngineAccess::previousPositions(mirror);
        heldFor = &mirror;
        heldSteps = mirror.stepCount();
    }
}

void integratorSteps(IntegratorKernel kernel, ParticleState& state, const LinearForce& force, double h, int n,
                     const std::function<void(int)>& each) {
    const Call which = kernel == &positionVerlet ? Call::PositionVerlet : Call::VelocityVerlet;
    if (kernel != &positionVerlet && kernel != &velocityVerlet) {
        throw std::invalid_argument("integratorSteps(): positionVerlet or velocityVerlet");
    }
    const std::size_t particles = state.x.size();
    const std::size_t perStep = 100 * std::max<std::size_t>(1, particles) + 16;
    const int batch = static_cast<int>(std::clamp<std::size_t>((1u << 20) / perStep, 1, 5000));
    int k = 0;
    std::string answer;  // a copy of each answer, its memory kept from batch to batch: each(k) may ask for hooks too
    while (k < n) {
        const auto asked = static_cast<std::uint32_t>(std::min(batch, n - k));
        Writer w;
        w.u8(static_cast<std::uint8_t>(which));
        w.particles(state);
        w.vec3(force.g);
        w.number(force.k);
        w.number(force.c);
        w.number(h);
        w.u32(asked);
        answer = request(Call::IntegratorSteps, w.bytes());
        Reader r(answer, 1);
        const bool whole = readSteps(which, r, asked, [&] {
            ParticleState next = r.particles();
            if (next.x.size() != particles || next.v.size() != particles || next.a.size() != particles ||
                (!next.xPrev.empty() && next.xPrev.size() != particles)) {
                throw ProtocolError("the kernel answered with another number of particles");
            }
            state = std::move(next);
            // A NaN slips through any check written as "fail when x > tol": a non-finite state fails here,
            // before the test's checks see it.
            const auto finite = [](const std::vector<Vec3>& xs) {
                return std::all_of(xs.begin(), xs.end(), [](const Vec3& x) { return x.allFinite(); });
            };
            if (!finite(state.x) || !finite(state.v) || !finite(state.a) || !finite(state.xPrev)) {
                ADD_FAILURE() << "step " << k + 1 << ": the kernel answered a position, velocity or acceleration that "
                              << "is not a finite number";
                return false;
            }
            each(++k);
            return !::testing::Test::HasFailure();
        });
        if (!whole) return;
    }
}

void rotationSteps(Body& body, double h, int n, const std::function<void(int)>& each) {
    const int batch = 5000;  // about a megabyte of answers
    int k = 0;
    std::string answer;  // a copy of each answer, its memory kept from batch to batch: each(k) may ask for hooks too
    while (k < n) {
        const auto asked = static_cast<std::uint32_t>(std::min(batch, n - k));
        Writer w;
        w.body(body);
        w.number(h);
        w.u32(asked);
        answer = request(Call::RotationSteps, w.bytes());
        Reader r(answer, 1);
        const bool whole = readSteps(Call::RotationSteps, r, asked, [&] {
            EngineAccess::readMotion(r, body);
            if (!body.orientation.coeffs().allFinite() || !body.angularVelocity.allFinite() ||
                !body.position.allFinite() || !body.velocity.allFinite() || !body.acceleration.allFinite() ||
                !body.force.allFinite() || !body.torque.allFinite()) {
                ADD_FAILURE() << "step " << k + 1 << ": the kernel left the body with a number that is not finite "
                              << "(its orientation, angular velocity, position, velocity, forces or torque)";
                return false;
            }
            each(++k);
            return !::testing::Test::HasFailure();
        });
        if (!whole) return;
    }
}

}  // namespace grading

namespace {

std::optional<Contact> contactCall(Call call, const Body& a, const Body& b) {
    Writer w;
    w.body(a);
    w.body(b);
    std::optional<Contact> c;
    grading::parseAnswer(call, grading::request(call, w.bytes()), [&](Reader& r) { c = r.optionalContact(); });
    return c;
}

/// A kernel that changes two bodies: their motion comes back, the rest stays the checker's.
void twoBodies(Call call, const Writer& inputs, Body& a, Body& b, PointImpulse* sum = nullptr) {
    grading::parseAnswer(call, grading::request(call, inputs.bytes()), [&](Reader& r) {
        const Body na = r.body(), nb = r.body();
        EngineAccess::copyMotion(na, a);
        EngineAccess::copyMotion(nb, b);
        if (sum) *sum = r.pointImpulse();
    });
}

/// A kernel of a contact and its two bodies (interpenetration, the impulses of worksheets 4 and 6).
void contactImpulse(Call call, const Contact& contact, Body& a, Body& b) {
    Writer w;
    w.contact(contact);
    w.body(a);
    w.body(b);
    twoBodies(call, w, a, b);
}

void particleCall(Call call, ParticleState& state, const AccelerationFunction& accel, double h) {
    Writer w;
    w.particles(state);
    w.number(h);
    const std::size_t particles = state.x.size();
    grading::parseAnswer(call, grading::request(call, w.bytes(), &accel, particles), [&](Reader& r) {
        ParticleState s = r.particles();
        if (s.x.size() != particles || s.v.size() != particles || s.a.size() != particles ||
            (!s.xPrev.empty() && s.xPrev.size() != particles)) {
            throw grading::ProtocolError("the kernel answered with another number of particles");
        }
        state = std::move(s);
    });
}

}  // namespace

// ---- Worksheet 1: the engine's hooks ------------------------------------------------------------

void PhysicsEngine::simulationTimestep() { engineCall(Call::SimulationTimestep, *this); }
void PhysicsEngine::integrator() { engineCall(Call::Integrator, *this); }

// ---- Worksheet 2 --------------------------------------------------------------------------------

void positionVerlet(ParticleState& state, const AccelerationFunction& accel, double h) {
    particleCall(Call::PositionVerlet, state, accel, h);
}
void velocityVerlet(ParticleState& state, const AccelerationFunction& accel, double h) {
    particleCall(Call::VelocityVerlet, state, accel, h);
}

// ---- Worksheets 3, 4, 5: contacts ---------------------------------------------------------------

std::optional<Contact> sphereSphere(const Body& a, const Body& b) { return contactCall(Call::SphereSphere, a, b); }
std::optional<Contact> spherePlane(const Body& s, const Body& p) { return contactCall(Call::SpherePlane, s, p); }
std::optional<Contact> sphereBox(const Body& s, const Body& b) { return contactCall(Call::SphereBox, s, b); }
std::optional<Contact> boxPlane(const Body& b, const Body& p) { return contactCall(Call::BoxPlane, b, p); }
std::optional<Contact> boxBox(const Body& a, const Body& b) { return contactCall(Call::BoxBox, a, b); }

std::optional<Contact> ropeContact(const Body& a, const Body& b, double length) {
    Writer w;
    w.body(a);
    w.body(b);
    w.number(length);
    std::optional<Contact> c;
    grading::parseAnswer(Call::RopeContact, grading::request(Call::RopeContact, w.bytes()),
                         [&](Reader& r) { c = r.optionalContact(); });
    return c;
}

void resolveInterpenetration(const Contact& contact, Body& a, Body& b) {
    contactImpulse(Call::ResolveInterpenetration, contact, a, b);
}

void applyCollisionImpulse(const Contact& contact, Body& a, Body& b) {
    contactImpulse(Call::ApplyCollisionImpulse, contact, a, b);
}

// ---- Worksheet 6: rotation ----------------------------------------------------------------------

Mat3 worldInverseInertia(const Body& body) {
    Writer w;
    w.body(body);
    Mat3 m;
    grading::parseAnswer(Call::WorldInverseInertia, grading::request(Call::WorldInverseInertia, w.bytes()),
                         [&](Reader& r) { m = r.mat3(); });
    return m;
}

void integrateRotation(Body& body, double h) {
    Writer w;
    w.body(body);
    w.number(h);
    grading::parseAnswer(Call::IntegrateRotation, grading::request(Call::IntegrateRotation, w.bytes()),
                         [&](Reader& r) { EngineAccess::copyMotion(r.body(), body); });
}

void applyImpulseAtPoint(Body& a, Body& b, const Vec3& point, const Vec3& impulse) {
    Writer w;
    w.body(a);
    w.body(b);
    w.vec3(point);
    w.vec3(impulse);
    twoBodies(Call::ApplyImpulseAtPoint, w, a, b);
}

void applyContactImpulse(const Contact& contact, Body& a, Body& b) {
    contactImpulse(Call::ApplyContactImpulse, contact, a, b);
}

// ---- Worksheet 7: friction ----------------------------------------------------------------------

namespace {
Writer pointInputs(const ContactPoint& point, const Body& a, const Body& b, const PointImpulse& sum) {
    Writer w;
    w.contactPoint(point);
    w.body(a);
    w.body(b);
    w.pointImpulse(sum);
    return w;
}
}  // namespace

ContactPoint prepareContactPoint(const Contact& contact, int k, const Body& a, const Body& b, const Mat3& invIa,
                                 const Mat3& invIb, double approach) {
    Writer w;
    w.contact(contact);
    w.i32(k);
    w.body(a);
    w.body(b);
    w.mat3(invIa);
    w.mat3(invIb);
    w.number(approach);
    ContactPoint prepared;
    grading::parseAnswer(Call::PrepareContactPoint, grading::request(Call::PrepareContactPoint, w.bytes()),
                         [&](Reader& r) { prepared = r.contactPoint(); });
    return prepared;
}

void applyWarmStart(const ContactPoint& point, Body& a, Body& b, const PointImpulse& sum) {
    PointImpulse unchanged = sum;
    twoBodies(Call::ApplyWarmStart, pointInputs(point, a, b, sum), a, b, &unchanged);
}

void applyNormalImpulse(const ContactPoint& point, Body& a, Body& b, PointImpulse& sum) {
    twoBodies(Call::ApplyNormalImpulse, pointInputs(point, a, b, sum), a, b, &sum);
}

void applyFrictionImpulse(const ContactPoint& point, Body& a, Body& b, PointImpulse& sum) {
    twoBodies(Call::ApplyFrictionImpulse, pointInputs(point, a, b, sum), a, b, &sum);
}

// ---- Worksheet 8: cloth and soft bodies -----------------------------------------------------------
// The answers are read as they come, NaN or huge included: the tests compare them with physics, so
// that nonsense fails the test it answered.

DistanceCorrection solveDistanceConstraint(const Vec3& x1, const Vec3& x2, double w1, double w2, double rest,
                                           double compliance, double h, double lambda) {
    Writer w;
    w.vec3(x1);
    w.vec3(x2);
    for (const double v : {w1, w2, rest, compliance, h, lambda}) w.number(v);
    DistanceCorrection c;
    grading::parseAnswer(Call::SolveDistanceConstraint, grading::request(Call::SolveDistanceConstraint, w.bytes()),
                         [&](Reader& r) { c = r.distanceCorrection(); });
    return c;
}

VolumeCorrection solveVolumeConstraint(const std::array<Vec3, 4>& x, const std::array<double, 4>& w, double restVolume,
                                       double compliance, double h, double lambda) {
    Writer out;
    for (const Vec3& c : x) out.vec3(c);
    for (const double c : w) out.number(c);
    for (const double v : {restVolume, compliance, h, lambda}) out.number(v);
    VolumeCorrection c;
    grading::parseAnswer(Call::SolveVolumeConstraint, grading::request(Call::SolveVolumeConstraint, out.bytes()),
                         [&](Reader& r) { c = r.volumeCorrection(); });
    return c;
}

Vec3 projectParticleSphere(const Vec3& p, double r, const Vec3& centre, double radius) {
    Writer w;
    w.vec3(p);
    w.number(r);
    w.vec3(centre);
    w.number(radius);
    Vec3 moved = p;
    grading::parseAnswer(Call::ProjectParticleSphere, grading::request(Call::ProjectParticleSphere, w.bytes()),
                         [&](Reader& r) { moved = r.vec3(); });
    return moved;
}

Vec3 projectParticleBox(const Vec3& p, double r, const Vec3& centre, const Quat& orientation, const Vec3& half) {
    Writer w;
    w.vec3(p);
    w.number(r);
    w.vec3(centre);
    w.quat(orientation);
    w.vec3(half);
    Vec3 moved = p;
    grading::parseAnswer(Call::ProjectParticleBox, grading::request(Call::ProjectParticleBox, w.bytes()),
                         [&](Reader& r) { moved = r.vec3(); });
    return moved;
}

// ---- Worksheet 9: fluids --------------------------------------------------------------------------
// The answers are read as they come, NaN or huge included: the graded tests compare them with
// physics in comparisons that a number not finite fails, so that nonsense fails the test it answered.

double poly6Kernel(double r, double h) {
    Writer w;
    w.number(r);
    w.number(h);
    double W = 0.0;
    grading::parseAnswer(Call::Poly6Kernel, grading::request(Call::Poly6Kernel, w.bytes()),
                         [&](Reader& in) { W = in.number(); });
    return W;
}

Vec3 spikyGradient(const Vec3& r, double h) {
    Writer w;
    w.vec3(r);
    w.number(h);
    Vec3 g = Vec3::Zero();
    grading::parseAnswer(Call::SpikyGradient, grading::request(Call::SpikyGradient, w.bytes()),
                         [&](Reader& in) { g = in.vec3(); });
    return g;
}

double fluidDensity(const Vec3& x, const std::vector<FluidNeighbour>& neighbours, double mass, double h) {
    Writer w;
    w.vec3(x);
    w.fluidNeighbours(neighbours);
    w.number(mass);
    w.number(h);
    double density = 0.0;
    grading::parseAnswer(Call::FluidDensity, grading::request(Call::FluidDensity, w.bytes()),
                         [&](Reader& in) { density = in.number(); });
    return density;
}

double densityConstraintLambda(const Vec3& x, const std::vector<FluidNeighbour>& neighbours, double density,
                               double restDensity, double mass, double h, double epsilon) {
    Writer w;
    w.vec3(x);
    w.fluidNeighbours(neighbours);
    for (const double v : {density, restDensity, mass, h, epsilon}) w.number(v);
    double lambda = 0.0;
    grading::parseAnswer(Call::DensityConstraintLambda, grading::request(Call::DensityConstraintLambda, w.bytes()),
                         [&](Reader& in) { lambda = in.number(); });
    return lambda;
}

Vec3 densityCorrection(const Vec3& x, double lambda, const std::vector<FluidNeighbour>& neighbours,
                       double restDensity, double mass, double h, const TensileCorrection& tensile) {
    Writer w;
    w.vec3(x);
    w.number(lambda);
    w.fluidNeighbours(neighbours);
    for (const double v : {restDensity, mass, h}) w.number(v);
    w.tensileCorrection(tensile);
    Vec3 dp = Vec3::Zero();
    grading::parseAnswer(Call::DensityCorrection, grading::request(Call::DensityCorrection, w.bytes()),
                         [&](Reader& in) { dp = in.vec3(); });
    return dp;
}

Vec3 xsphViscosity(const Vec3& x, const Vec3& v, const std::vector<FluidNeighbour>& neighbours, double mass, double h,
                   double c) {
    Writer w;
    w.vec3(x);
    w.vec3(v);
    w.fluidNeighbours(neighbours);
    for (const double value : {mass, h, c}) w.number(value);
    Vec3 blended = v;
    grading::parseAnswer(Call::XsphViscosity, grading::request(Call::XsphViscosity, w.bytes()),
                         [&](Reader& in) { blended = in.vec3(); });
    return blended;
}

// ---- The student's own scenes -------------------------------------------------------------------

void addStudentScenes(SceneRegistry&) {}  // the checker grades the course's scenes

}  // namespace gpl
