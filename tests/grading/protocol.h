// What the checker and a submission's engine say to each other. The checker (trusted: the graded
// tests, no submission code) sends a request, "call this hook with these inputs"; the submission's
// engine (gpl-hooks-VARIANT, in the sandbox) calls the hook and answers with its outputs. Each
// message is one frame on a pipe: its length (4 bytes), then its bytes, written field by field.
//
// The reader trusts nothing it reads: every count, size, index and enumeration is checked, and a
// frame that does not parse throws ProtocolError. A submission that answers nonsense fails the
// test it answered; it never crashes the checker, and it never decides what a test expects.
#pragma once

#include <cstddef>
#include <cstdint>
#include <algorithm>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "gpl/body.h"
#include "gpl/contact.h"
#include "gpl/fluid_kernels.h"
#include "gpl/friction.h"
#include "gpl/integrators.h"
#include "gpl/soft_constraints.h"

namespace gpl::grading {

/// A frame that cannot be read, or an answer that is not one.
class ProtocolError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// The hooks the checker can ask for: one per student hook that has inputs and outputs.
enum class Call : std::uint8_t {
    SimulationTimestep = 1,
    Integrator,
    PositionVerlet,
    VelocityVerlet,
    SphereSphere,
    SpherePlane,
    RopeContact,
    SphereBox,
    BoxPlane,
    BoxBox,
    ResolveInterpenetration,
    ApplyCollisionImpulse,
    WorldInverseInertia,
    IntegrateRotation,
    ApplyImpulseAtPoint,
    ApplyContactImpulse,
    PrepareContactPoint,
    ApplyNormalImpulse,
    ApplyFrictionImpulse,
    ApplyWarmStart,
    SolveDistanceConstraint,
    SolveVolumeConstraint,
    ProjectParticleSphere,
    ProjectParticleBox,
    Poly6Kernel,
    SpikyGradient,
    FluidDensity,
    DensityConstraintLambda,
    DensityCorrection,
    XsphViscosity,
    Steps,            ///< whole steps of the engine, simulationTimestep() in each (graded.h: grading::steps())
    IntegratorSteps,  ///< steps of an integrator kernel under a LinearForce (graded.h: grading::integratorSteps())
    RotationSteps,    ///< steps of integrateRotation() of one body (graded.h: grading::rotationSteps())
    End               ///< one past the last
};

/// The hook as a student knows it: "integrator()".
const char* callName(Call call);

/// The kinds of frame.
enum class Frame : std::uint8_t {
    Request = 1,       ///< checker: call a hook (the call, then its inputs)
    Answer,            ///< engine: the hook returned (its outputs, then the hooks still open)
    Thrown,            ///< engine: the hook threw (the kind, the message, the hooks still open)
    AskAccelerations,  ///< engine: the integrator kernel asks for a(x, v) (positions, velocities)
    Accelerations,     ///< checker: the accelerations asked for
};

/// What a hook threw, so that the checker throws the same kind.
enum class Thrown : std::uint8_t { Other = 1, Simulation, InvalidArgument, OutOfRange, BadAlloc, End };

/// A force the submission's engine can evaluate itself, a(x, v) = g - k x - c v for every particle
/// (gravity, a spring to the origin, damping), so that a run of integrator steps needs no request
/// per evaluation. Callable as an AccelerationFunction.
struct LinearForce {
    Vec3 g = Vec3::Zero();  ///< m/s^2
    double k = 0.0;         ///< 1/s^2
    double c = 0.0;         ///< 1/s
    void operator()(const std::vector<Vec3>& x, const std::vector<Vec3>& v, std::vector<Vec3>& a) const {
        a.resize(x.size());
        for (std::size_t i = 0; i < x.size(); ++i) a[i] = g - k * x[i] - c * (i < v.size() ? v[i] : Vec3::Zero());
    }
};

/// Largest frame either side accepts: a hundred thousand bodies.
constexpr std::uint32_t kMaxFrameBytes = 256u << 20;
/// Most neighbours a fluid kernel's request may hold: hundreds of times a particle's usual few
/// dozen, a bound that keeps a request's memory small whatever its count says.
constexpr std::uint32_t kMaxFluidNeighbours = 1u << 16;
/// Longest string (a body's name, an exception's message) either side accepts.
constexpr std::uint32_t kMaxStringBytes = 1u << 16;

/// Bytes of one frame, written field by field.
class Writer {
public:
    const std::string& bytes() const { return bytes_; }
    void append(const Writer& other) { bytes_ += other.bytes_; }
    std::size_t size() const { return bytes_.size(); }
    void reserve(std::size_t n) { bytes_.reserve(n); }
    /// Empties the frame, keeping its memory for the next.
    void clear() { bytes_.clear(); }
    /// n numbers at once.
    void numbers(const double* v, std::size_t n) { raw(v, n * sizeof(double)); }
    /// Writes v over the 4 bytes at `at`, a place kept with u32() for a count known later.
    void patchU32(std::size_t at, std::uint32_t v) { std::memcpy(bytes_.data() + at, &v, sizeof v); }
    void u8(std::uint8_t v) { raw(&v, sizeof v); }
    void u32(std::uint32_t v) { raw(&v, sizeof v); }
    void u64(std::uint64_t v) { raw(&v, sizeof v); }
    void i32(std::int32_t v) { raw(&v, sizeof v); }
    void number(double v) { raw(&v, sizeof v); }
    void text(const std::string& s);
    void vec3(const Vec3& v);
    void mat3(const Mat3& m);
    void quat(const Quat& q);
    void body(const Body& b);
    void contact(const Contact& c);
    void optionalContact(const std::optional<Contact>& c);
    void pointImpulse(const PointImpulse& p);
    void contactPoint(const ContactPoint& p);
    void distanceCorrection(const DistanceCorrection& c);
    void volumeCorrection(const VolumeCorrection& c);
    void tensileCorrection(const TensileCorrection& t);
    /// The count, then each neighbour's position, velocity, density and lambda.
    void fluidNeighbours(const std::vector<FluidNeighbour>& list);
    void vec3s(const std::vector<Vec3>& v);
    void bodies(const std::vector<Body>& bodies);
    void contacts(const std::vector<Contact>& contacts);
    void particles(const ParticleState& s);
    void texts(const std::vector<std::string>& list);

private:
    void raw(const void* p, std::size_t n) { bytes_.append(static_cast<const char*>(p), n); }
    std::string bytes_;
};

/// Reads one frame field by field; throws ProtocolError on anything that is not there or not valid.
class Reader {
public:
    /// Reads `bytes` from byte `from` on.
    explicit Reader(const std::string& bytes, std::size_t from = 0)
        : p_(bytes.data() + std::min(from, bytes.size())), end_(bytes.data() + bytes.size()) {}
    std::uint8_t u8() { return pod<std::uint8_t>(); }
    std::uint32_t u32() { return pod<std::uint32_t>(); }
    std::uint64_t u64() { return pod<std::uint64_t>(); }
    std::int32_t i32() { return pod<std::int32_t>(); }
    double number() { return pod<double>(); }
    /// n numbers at once.
    void numbers(double* v, std::size_t n) {
        if (static_cast<std::size_t>(end_ - p_) / sizeof(double) < n) throw ProtocolError("a message ends too early");
        std::memcpy(v, p_, n * sizeof(double));
        p_ += n * sizeof(double);
    }
    std::string text();
    Vec3 vec3();
    Mat3 mat3();
    Quat quat();
    Body body();
    /// A contact; its points beyond pointCount, which must be 0..kMaxContactPoints, are zero.
    Contact contact();
    std::optional<Contact> optionalContact();
    PointImpulse pointImpulse();
    ContactPoint contactPoint();
    DistanceCorrection distanceCorrection();
    VolumeCorrection volumeCorrection();
    TensileCorrection tensileCorrection();
    /// At most kMaxFluidNeighbours.
    std::vector<FluidNeighbour> fluidNeighbours();
    std::vector<Vec3> vec3s();
    std::vector<Body> bodies();
    std::vector<Contact> contacts();
    ParticleState particles();
    std::vector<std::string> texts();
    /// A count of items of at least `itemBytes` bytes each that the rest of the frame can hold.
    std::size_t count(std::size_t itemBytes);
    /// Throws unless every byte has been read.
    void end() const;

private:
    template <class T>
    T pod() {
        if (static_cast<std::size_t>(end_ - p_) < sizeof(T)) throw ProtocolError("a message ends too early");
        T v;
        std::memcpy(&v, p_, sizeof v);
        p_ += sizeof v;
        return v;
    }
    const char* p_;
    const char* end_;
};

/// Writes one frame (length, then bytes); false when the other side is gone.
bool sendFrame(int fd, const std::string& bytes);
/// Reads one frame into `bytes` (its memory kept from frame to frame); false when the other side
/// closed the pipe before it began. Throws ProtocolError on a frame longer than kMaxFrameBytes or
/// cut short.
bool receiveFrame(int fd, std::string& bytes);

}  // namespace gpl::grading
