// gpl-hooks-VARIANT --serve: a variant's hooks answering the checker's requests. This program holds
// the student's code and runs only in the grader's sandbox (tools/grading/sandbox.py), under the
// system-call filter the launcher (launch.cpp) puts in force before it starts. It reads requests
// from file descriptor 3 and writes answers to 4 (protocol.h); what the hooks print goes to its
// standard output and error, which the grader caps. It decides nothing: the checker, in another
// process, compares what it answers with physics.
#include <execinfo.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <array>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "engine_access.h"
#include "gpl/collision.h"
#include "gpl/engine.h"
#include "gpl/fluid_kernels.h"
#include "gpl/hooks.h"
#include "gpl/response.h"
#include "gpl/rotation.h"
#include "gpl/soft_constraints.h"
#include "protocol.h"

namespace gpl::grading {
namespace {

constexpr int kIn = 3;
constexpr int kOut = 4;

// ---- Where the hooks were when the process ended ---------------------------------------------------
// With GPL_GRADER_TRACE naming a file, a crash signal, the grader's SIGUSR1 at a limit it watches,
// or a signal of a limit the kernel keeps (SIGXCPU, SIGXFSZ, SIGSYS for a refused system call)
// writes the call stack there and ends the process as the signal would have. The grader reads the
// hook from it only within the call the checker was waiting for (the checker names that call).

int traceFd = -1;
// The engine's step in flight (its number since the scene was loaded, as step() counts), 0 outside
// one: a crash names it ("grader: in step N"), so the report can say which step a failed assertion ended.
volatile sig_atomic_t stepInFlight = 0;

/// Names the engine's next step as the one in flight for as long as it lives.
struct InStep {
    explicit InStep(const PhysicsEngine& e) { stepInFlight = static_cast<sig_atomic_t>(e.stepCount() + 1); }
    ~InStep() { stepInFlight = 0; }
    InStep(const InStep&) = delete;
    InStep& operator=(const InStep&) = delete;
};
char* stackLow = nullptr;   // the main thread's stack: a fault just below it is an overflow
char* stackHigh = nullptr;
constexpr int kTracedSignals[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGUSR1, SIGXCPU, SIGXFSZ, SIGSYS};

void writeText(const char* text) {
    if (write(traceFd, text, std::strlen(text)) < 0) return;  // nothing else to do in a handler
}

// What a refused system call tried, as the launcher's filter tags it (SECCOMP_RET_DATA, si_errno;
// launch.cpp's Tag).
const char* refusedKind(int tag) {
    switch (tag) {
        case 1: return "grader: forbidden system call: process\n";
        case 2: return "grader: forbidden system call: network\n";
        case 3: return "grader: forbidden system call: namespace\n";
        case 4: return "grader: forbidden system call: memory\n";
        case 5: return "grader: forbidden system call: kernel\n";
        case 6: return "grader: forbidden system call: signal\n";
        case 7: return "grader: forbidden system call: limit\n";
        default: return "grader: forbidden system call\n";
    }
}

void writeTrace(int signal, siginfo_t* info, void*) {
    // The grader's and the CPU limit's signals go to the whole process and any thread may take
    // them; the main thread's stack is the one that leads into the hooks.
    const long mainThread = getpid();
    if ((signal == SIGUSR1 || signal == SIGXCPU) && syscall(SYS_gettid) != mainThread) {
        syscall(SYS_tgkill, mainThread, mainThread, signal);
        return;
    }
    if (signal == SIGSYS && info) writeText(refusedKind(info->si_errno));
    if (signal == SIGSEGV && info && stackLow) {
        const char* at = static_cast<const char*>(info->si_addr);
        if (at < stackHigh && at >= stackLow - (1 << 20)) writeText("grader: stack overflow\n");
    }
    if (stepInFlight > 0 && signal != SIGUSR1) {
        char line[48] = "grader: in step ";
        char digits[24];
        int d = 0;
        for (long s = stepInFlight; s > 0 && d < 20; s /= 10) digits[d++] = static_cast<char>('0' + s % 10);
        std::size_t at = std::strlen(line);
        while (d > 0) line[at++] = digits[--d];
        line[at++] = '\n';
        line[at] = '\0';
        writeText(line);
    }
    void* frames[64];
    const int n = backtrace(frames, 64);
    backtrace_symbols_fd(frames, n, traceFd);
    ::signal(signal, SIG_DFL);
    raise(signal);
}

void installTraceHandlers() {
    const char* path = std::getenv("GPL_GRADER_TRACE");
    if (!path || !*path) return;
    traceFd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (traceFd < 0) return;
    void* warmUp[1];
    backtrace(warmUp, 1);  // loads what backtrace() needs now, not inside a signal handler
    pthread_attr_t attributes;
    if (pthread_getattr_np(pthread_self(), &attributes) == 0) {
        void* low = nullptr;
        std::size_t size = 0;
        if (pthread_attr_getstack(&attributes, &low, &size) == 0) {
            stackLow = static_cast<char*>(low);
            stackHigh = stackLow + size;
        }
        pthread_attr_destroy(&attributes);
    }
    // An endless recursion leaves no stack for the handler: it gets its own.
    static char altStack[1 << 16];
    stack_t stack{};
    stack.ss_sp = altStack;
    stack.ss_size = sizeof altStack;
    sigaltstack(&stack, nullptr);
    struct sigaction action {};
    action.sa_sigaction = writeTrace;
    action.sa_flags = SA_ONSTACK | SA_SIGINFO;
    sigemptyset(&action.sa_mask);
    for (int s : kTracedSignals) sigaction(s, &action, nullptr);
}

// ---- Answering -----------------------------------------------------------------------------------

/// The hooks still open: the engine's and the kernels' whose stubs ran.
std::vector<std::string> openHooks(const PhysicsEngine& engine) {
    std::vector<std::string> open(engine.missingHooks().begin(), engine.missingHooks().end());
    for (const std::string& h : kernelsNotImplemented()) open.push_back(h);
    return open;
}

/// The acceleration function of an integrator kernel: each evaluation asks the checker.
AccelerationFunction askChecker(std::size_t n) {
    return [n](const std::vector<Vec3>& x, const std::vector<Vec3>& v, std::vector<Vec3>& a) {
        Writer w;
        w.u8(static_cast<std::uint8_t>(Frame::AskAccelerations));
        w.vec3s(x);
        w.vec3s(v);
        if (!sendFrame(kOut, w.bytes())) std::_Exit(0);
        std::string frame;
        if (!receiveFrame(kIn, frame)) std::_Exit(0);
        Reader r(frame);
        if (r.u8() != static_cast<std::uint8_t>(Frame::Accelerations)) throw ProtocolError("expected accelerations");
        a = r.vec3s();
        r.end();
        if (x.size() != n) a.assign(x.size(), Vec3::Zero());
    };
}

Thrown kindOf(const std::exception& e) {
    if (dynamic_cast<const SimulationError*>(&e)) return Thrown::Simulation;
    if (dynamic_cast<const std::invalid_argument*>(&e)) return Thrown::InvalidArgument;
    if (dynamic_cast<const std::out_of_range*>(&e)) return Thrown::OutOfRange;
    if (dynamic_cast<const std::bad_alloc*>(&e)) return Thrown::BadAlloc;
    return Thrown::Other;
}

/// Answers a batched run: up to n steps, each made by `step` and answered by `write`, ended early
/// by the first exception (answered after the steps, with its kind and message) or by a state that
/// `finite` finds no longer finite. The count comes first, patched in once it is known.
template <class Step, class Write, class Finite>
void answerSteps(Writer& out, std::uint32_t n, Step step, Write write, Finite finite) {
    const std::size_t countAt = out.size();
    out.u32(0);
    std::uint32_t done = 0;
    Writer failure;
    failure.u8(0);
    for (; done < n; ++done) {
        try {
            step();
        } catch (const std::exception& ex) {
            failure.clear();
            failure.u8(1);
            failure.u8(static_cast<std::uint8_t>(kindOf(ex)));
            failure.text(ex.what());
            break;
        }
        write();
        if (!finite()) {
            ++done;
            break;
        }
    }
    out.patchU32(countAt, done);
    out.append(failure);
}

/// Calls the hook the request names with its inputs; writes its outputs.
void answer(Call call, Reader& in, Writer& out, std::unique_ptr<PhysicsEngine>& held) {
    switch (call) {
        case Call::SimulationTimestep:
        case Call::Integrator: {
            // A fresh engine for another of the checker's engines (or one loaded anew).
            if (in.u8()) held = std::make_unique<PhysicsEngine>();
            PhysicsEngine& e = *held;
            EngineAccess::readWorld(in, e);
            {
                const InStep named(e);
                if (call == Call::SimulationTimestep) {
                    e.simulationTimestep();
                } else {
                    e.integrator();
                }
            }
            EngineAccess::writeChanges(out, e);
            return;
        }
        case Call::Steps: {
            // Whole steps as step() makes them, each one's changes answered; the checker advances its
            // own clock and checks the bodies. The first exception, or a body no longer finite, ends them.
            if (in.u8()) held = std::make_unique<PhysicsEngine>();
            const std::uint32_t n = in.u32();
            PhysicsEngine& e = *held;
            EngineAccess::readWorld(in, e);
            out.reserve(out.size() + n * (180 * e.bodies().size() +
                                          EngineAccess::kParticleBytes * (e.softBodies().x.size() + e.fluids().size()) + 64));
            answerSteps(
                out, n,
                [&] {
                    EngineAccess::beginStep(e);
                    const InStep named(e);
                    e.simulationTimestep();
                    EngineAccess::advanceClock(e);
                },
                [&] {
                    EngineAccess::writeChanges(out, e);
                    out.texts(openHooks(e));
                },
                [&] { return e.allFinite(); });
            return;
        }
        case Call::IntegratorSteps: {
            // Steps of positionVerlet() or velocityVerlet() under a force evaluated here; each step's
            // state answered. The first exception, or a state no longer finite, ends them.
            const std::uint8_t which = in.u8();
            if (which != static_cast<std::uint8_t>(Call::PositionVerlet) &&
                which != static_cast<std::uint8_t>(Call::VelocityVerlet)) {
                throw ProtocolError("steps of an unknown integrator");
            }
            ParticleState s = in.particles();
            LinearForce force;
            force.g = in.vec3();
            force.k = in.number();
            force.c = in.number();
            const double h = in.number();
            const std::uint32_t n = in.u32();
            in.end();
            const AccelerationFunction accel = force;
            answerSteps(
                out, n,
                [&] {
                    if (which == static_cast<std::uint8_t>(Call::PositionVerlet)) {
                        positionVerlet(s, accel, h);
                    } else {
                        velocityVerlet(s, accel, h);
                    }
                },
                [&] { out.particles(s); },
                [&] {
                    bool finite = true;
                    for (const auto* list : {&s.x, &s.v, &s.a}) {
                        for (const Vec3& x : *list) finite = finite && x.allFinite();
                    }
                    return finite;
                });
            return;
        }
        case Call::RotationSteps: {
            // Steps of integrateRotation() of one body; each step's motion answered. The first
            // exception, or a state no longer finite, ends them.
            Body b = in.body();
            const double h = in.number();
            const std::uint32_t n = in.u32();
            in.end();
            answerSteps(
                out, n, [&] { integrateRotation(b, h); }, [&] { EngineAccess::writeMotion(out, b); },
                [&] { return b.orientation.coeffs().allFinite() && b.angularVelocity.allFinite(); });
            return;
        }
        case Call::PositionVerlet:
        case Call::VelocityVerlet: {
            ParticleState s = in.particles();
            const double h = in.number();
            in.end();
            const AccelerationFunction accel = askChecker(s.x.size());
            if (call == Call::PositionVerlet) {
                positionVerlet(s, accel, h);
            } else {
                velocityVerlet(s, accel, h);
            }
            out.particles(s);
            return;
        }
        case Call::SphereSphere:
        case Call::SpherePlane:
        case Call::SphereBox:
        case Call::BoxPlane:
        case Call::BoxBox: {
            const Body a = in.body(), b = in.body();
            in.end();
            std::optional<Contact> c;
            if (call == Call::SphereSphere) c = sphereSphere(a, b);
            if (call == Call::SpherePlane) c = spherePlane(a, b);
            if (call == Call::SphereBox) c = sphereBox(a, b);
            if (call == Call::BoxPlane) c = boxPlane(a, b);
            if (call == Call::BoxBox) c = boxBox(a, b);
            out.optionalContact(c);
            return;
        }
        case Call::RopeContact: {
            const Body a = in.body(), b = in.body();
            const double length = in.number();
            in.end();
            out.optionalContact(ropeContact(a, b, length));
            return;
        }
        case Call::ResolveInterpenetration:
        case Call::ApplyCollisionImpulse:
        case Call::ApplyContactImpulse: {
            const Contact c = in.contact();
            Body a = in.body(), b = in.body();
            in.end();
            if (call == Call::ResolveInterpenetration) resolveInterpenetration(c, a, b);
            if (call == Call::ApplyCollisionImpulse) applyCollisionImpulse(c, a, b);
            if (call == Call::ApplyContactImpulse) applyContactImpulse(c, a, b);
            out.body(a);
            out.body(b);
            return;
        }
        case Call::WorldInverseInertia: {
            const Body b = in.body();
            in.end();
            out.mat3(worldInverseInertia(b));
            return;
        }
        case Call::IntegrateRotation: {
            Body b = in.body();
            const double h = in.number();
            in.end();
            integrateRotation(b, h);
            out.body(b);
            return;
        }
        case Call::ApplyImpulseAtPoint: {
            Body a = in.body(), b = in.body();
            const Vec3 point = in.vec3(), impulse = in.vec3();
            in.end();
            applyImpulseAtPoint(a, b, point, impulse);
            out.body(a);
            out.body(b);
            return;
        }
        case Call::PrepareContactPoint: {
            const Contact c = in.contact();
            const int k = in.i32();
            const Body a = in.body(), b = in.body();
            const Mat3 invIa = in.mat3(), invIb = in.mat3();
            const double approach = in.number();
            in.end();
            if (k < 0 || k >= c.pointCount) throw ProtocolError("a contact point that the contact does not have");
            out.contactPoint(prepareContactPoint(c, k, a, b, invIa, invIb, approach));
            return;
        }
        case Call::ApplyNormalImpulse:
        case Call::ApplyFrictionImpulse:
        case Call::ApplyWarmStart: {
            const ContactPoint point = in.contactPoint();
            Body a = in.body(), b = in.body();
            PointImpulse sum = in.pointImpulse();
            in.end();
            if (call == Call::ApplyNormalImpulse) applyNormalImpulse(point, a, b, sum);
            if (call == Call::ApplyFrictionImpulse) applyFrictionImpulse(point, a, b, sum);
            if (call == Call::ApplyWarmStart) applyWarmStart(point, a, b, sum);
            out.body(a);
            out.body(b);
            out.pointImpulse(sum);
            return;
        }
        case Call::SolveDistanceConstraint: {
            const Vec3 x1 = in.vec3(), x2 = in.vec3();
            const double w1 = in.number(), w2 = in.number(), rest = in.number(), compliance = in.number();
            const double h = in.number(), lambda = in.number();
            in.end();
            out.distanceCorrection(solveDistanceConstraint(x1, x2, w1, w2, rest, compliance, h, lambda));
            return;
        }
        case Call::SolveVolumeConstraint: {
            std::array<Vec3, 4> x;
            for (Vec3& c : x) c = in.vec3();
            std::array<double, 4> w{};
            for (double& c : w) c = in.number();
            const double restVolume = in.number(), compliance = in.number(), h = in.number(), lambda = in.number();
            in.end();
            out.volumeCorrection(solveVolumeConstraint(x, w, restVolume, compliance, h, lambda));
            return;
        }
        case Call::ProjectParticleSphere: {
            const Vec3 p = in.vec3();
            const double r = in.number();
            const Vec3 centre = in.vec3();
            const double radius = in.number();
            in.end();
            out.vec3(projectParticleSphere(p, r, centre, radius));
            return;
        }
        case Call::ProjectParticleBox: {
            const Vec3 p = in.vec3();
            const double r = in.number();
            const Vec3 centre = in.vec3();
            const Quat orientation = in.quat();
            const Vec3 half = in.vec3();
            in.end();
            out.vec3(projectParticleBox(p, r, centre, orientation, half));
            return;
        }
        case Call::Poly6Kernel: {
            const double r = in.number(), h = in.number();
            in.end();
            out.number(poly6Kernel(r, h));
            return;
        }
        case Call::SpikyGradient: {
            const Vec3 r = in.vec3();
            const double h = in.number();
            in.end();
            out.vec3(spikyGradient(r, h));
            return;
        }
        case Call::FluidDensity: {
            const Vec3 x = in.vec3();
            const std::vector<FluidNeighbour> neighbours = in.fluidNeighbours();
            const double mass = in.number(), h = in.number();
            in.end();
            out.number(fluidDensity(x, neighbours, mass, h));
            return;
        }
        case Call::DensityConstraintLambda: {
            const Vec3 x = in.vec3();
            const std::vector<FluidNeighbour> neighbours = in.fluidNeighbours();
            const double density = in.number(), restDensity = in.number(), mass = in.number(), h = in.number();
            const double epsilon = in.number();
            in.end();
            out.number(densityConstraintLambda(x, neighbours, density, restDensity, mass, h, epsilon));
            return;
        }
        case Call::DensityCorrection: {
            const Vec3 x = in.vec3();
            const double lambda = in.number();
            const std::vector<FluidNeighbour> neighbours = in.fluidNeighbours();
            const double restDensity = in.number(), mass = in.number(), h = in.number();
            const TensileCorrection tensile = in.tensileCorrection();
            in.end();
            out.vec3(densityCorrection(x, lambda, neighbours, restDensity, mass, h, tensile));
            return;
        }
        case Call::XsphViscosity: {
            const Vec3 x = in.vec3(), v = in.vec3();
            const std::vector<FluidNeighbour> neighbours = in.fluidNeighbours();
            const double mass = in.number(), h = in.number(), c = in.number();
            in.end();
            out.vec3(xsphViscosity(x, v, neighbours, mass, h, c));
            return;
        }
        case Call::End:
            break;
    }
    throw ProtocolError("a request for an unknown hook");
}

void thrown(Writer& out, Thrown kind, const std::string& what, const PhysicsEngine& engine) {
    out.clear();
    out.u8(static_cast<std::uint8_t>(Frame::Thrown));
    out.u8(static_cast<std::uint8_t>(kind));
    out.text(what);
    out.texts(openHooks(engine));
}

int serve() {
    auto held = std::make_unique<PhysicsEngine>();
    std::string frame;  // the request and the answer keep their memory from one request to the next
    Writer out;
    while (true) {
        if (!receiveFrame(kIn, frame)) return 0;  // the checker is done
        Reader in(frame);
        if (in.u8() != static_cast<std::uint8_t>(Frame::Request)) throw ProtocolError("expected a request");
        const auto call = static_cast<Call>(in.u8());
        out.clear();
        try {
            out.u8(static_cast<std::uint8_t>(Frame::Answer));
            answer(call, in, out, held);
            out.texts(openHooks(*held));
            if (!sendFrame(kOut, out.bytes())) return 0;
            continue;
        } catch (const ProtocolError&) {
            throw;
        } catch (const SimulationError& e) {
            thrown(out, Thrown::Simulation, e.what(), *held);
        } catch (const std::invalid_argument& e) {
            thrown(out, Thrown::InvalidArgument, e.what(), *held);
        } catch (const std::out_of_range& e) {
            thrown(out, Thrown::OutOfRange, e.what(), *held);
        } catch (const std::bad_alloc& e) {
            thrown(out, Thrown::BadAlloc, e.what(), *held);
        } catch (const std::exception& e) {
            thrown(out, Thrown::Other, e.what(), *held);
        }
        if (!sendFrame(kOut, out.bytes())) return 0;
    }
}

}  // namespace
}  // namespace gpl::grading

int main(int argc, char** argv) {
    if (argc != 2 || std::strcmp(argv[1], "--serve") != 0) {
        std::cerr << "usage: " << argv[0] << " --serve (the grader starts it; requests on fd 3, answers on fd 4)\n";
        return 2;
    }
    if (fcntl(3, F_GETFD) < 0 || fcntl(4, F_GETFD) < 0) {
        std::cerr << argv[0] << ": file descriptors 3 and 4 must be the checker's pipes\n";
        return 2;
    }
    signal(SIGPIPE, SIG_IGN);
    gpl::grading::installTraceHandlers();
    try {
        return gpl::grading::serve();
    } catch (const gpl::grading::ProtocolError& e) {
        std::cerr << argv[0] << ": " << e.what() << '\n';
        return 3;
    }
}
