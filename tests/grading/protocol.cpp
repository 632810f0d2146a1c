#include "protocol.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>

namespace gpl::grading {

const char* callName(Call call) {
    switch (call) {
        case Call::SimulationTimestep: return "simulationTimestep()";
        case Call::Integrator: return "integrator()";
        case Call::PositionVerlet: return "positionVerlet()";
        case Call::VelocityVerlet: return "velocityVerlet()";
        case Call::SphereSphere: return "sphereSphere()";
        case Call::SpherePlane: return "spherePlane()";
        case Call::RopeContact: return "ropeContact()";
        case Call::SphereBox: return "sphereBox()";
        case Call::BoxPlane: return "boxPlane()";
        case Call::BoxBox: return "boxBox()";
        case Call::ResolveInterpenetration: return "resolveInterpenetration()";
        case Call::ApplyCollisionImpulse: return "applyCollisionImpulse()";
        case Call::WorldInverseInertia: return "worldInverseInertia()";
        case Call::IntegrateRotation: return "integrateRotation()";
        case Call::ApplyImpulseAtPoint: return "applyImpulseAtPoint()";
        case Call::ApplyContactImpulse: return "applyContactImpulse()";
        case Call::PrepareContactPoint:
            return "prepareContactPoint()";
        case Call::ApplyNormalImpulse: return "applyNormalImpulse()";
        case Call::ApplyFrictionImpulse: return "applyFrictionImpulse()";
        case Call::ApplyWarmStart: return "applyWarmStart()";
        case Call::SolveDistanceConstraint: return "solveDistanceConstraint()";
        case Call::SolveVolumeConstraint: return "solveVolumeConstraint()";
        case Call::ProjectParticleSphere: return "projectParticleSphere()";
        case Call::ProjectParticleBox: return "projectParticleBox()";
        case Call::Poly6Kernel: return "poly6Kernel()";
        case Call::SpikyGradient: return "spikyGradient()";
        case Call::FluidDensity: return "fluidDensity()";
        case Call::DensityConstraintLambda: return "densityConstraintLambda()";
        case Call::DensityCorrection: return "densityCorrection()";
        case Call::XsphViscosity: return "xsphViscosity()";
        case Call::Steps: return "simulationTimestep()";
        case Call::IntegratorSteps: return "an integrator kernel";
        case Call::RotationSteps: return "integrateRotation()";
        case Call::End: break;
    }
    return "an unknown hook";
}

// ---- Writing ------------------------------------------------------------------------------------

void Writer::text(const std::string& s) {
    const std::size_t n = std::min<std::size_t>(s.size(), kMaxStringBytes);
    u32(static_cast<std::uint32_t>(n));
    raw(s.data(), n);
}

void Writer::vec3(const Vec3& v) {
    for (int i = 0; i < 3; ++i) number(v[i]);
}

void Writer::mat3(const Mat3& m) {
    for (int i = 0; i < 9; ++i) number(m.data()[i]);
}

void Writer::quat(const Quat& q) {
    for (int i = 0; i < 4; ++i) number(q.coeffs()[i]);
}

void Writer::body(const Body& b) {
    u8(static_cast<std::uint8_t>(b.shape));
    number(b.radius);
    vec3(b.position);
    vec3(b.velocity);
    vec3(b.acceleration);
    number(b.mass);
    number(b.invMass);
    vec3(b.angularVelocity);
    number(b.restitution);
    number(b.friction);
    number(b.staticFriction);
    quat(b.orientation);
    mat3(b.inertia);
    mat3(b.invInertia);
    vec3(b.halfExtents);
    vec3(b.normal);
    vec3(b.force);
    vec3(b.torque);
    text(b.name);
}

void Writer::contact(const Contact& c) {
    u64(c.a);
    u64(c.b);
    vec3(c.normal);
    number(c.depth);
    const int n = c.pointCount;
    i32(n);
    for (int k = 0; k < n && k < kMaxContactPoints; ++k) vec3(c.points[static_cast<std::size_t>(k)]);
    number(c.restitution);
    number(c.friction);
    number(c.staticFriction);
}

void Writer::optionalContact(const std::optional<Contact>& c) {
    u8(c ? 1 : 0);
    if (c) contact(*c);
}

void Writer::pointImpulse(const PointImpulse& p) {
    number(p.normal);
    vec3(p.tangent);
    number(p.approach);
}

void Writer::contactPoint(const ContactPoint& p) {
    for (const Vec3* v : {&p.p, &p.ra, &p.rb}) vec3(*v);
    for (const ContactAxis* axis : {&p.n, &p.t1, &p.t2}) {
        for (const Vec3* v : {&axis->d, &axis->raXd, &axis->rbXd, &axis->invIaRaXd, &axis->invIbRbXd}) vec3(*v);
        number(axis->K);
    }
    for (const double x : {p.target, p.staticFriction, p.friction}) number(x);
}

void Writer::distanceCorrection(const DistanceCorrection& c) {
    vec3(c.dx1);
    vec3(c.dx2);
    number(c.dlambda);
}

void Writer::volumeCorrection(const VolumeCorrection& c) {
    for (const Vec3& d : c.dx) vec3(d);
    number(c.dlambda);
}

void Writer::tensileCorrection(const TensileCorrection& t) {
    number(t.k);
    number(t.dq);
    i32(t.n);
}

void Writer::fluidNeighbours(const std::vector<FluidNeighbour>& list) {
    u32(static_cast<std::uint32_t>(list.size()));
    for (const FluidNeighbour& j : list) {
        vec3(j.x);
        vec3(j.v);
        number(j.density);
        number(j.lambda);
    }
}

void Writer::vec3s(const std::vector<Vec3>& v) {
    u32(static_cast<std::uint32_t>(v.size()));
    for (const Vec3& x : v) vec3(x);
}

void Writer::bodies(const std::vector<Body>& bodies) {
    u32(static_cast<std::uint32_t>(bodies.size()));
    for (const Body& b : bodies) body(b);
}

void Writer::contacts(const std::vector<Contact>& contacts) {
    u32(static_cast<std::uint32_t>(contacts.size()));
    for (const Contact& c : contacts) contact(c);
}

void Writer::particles(const ParticleState& s) {
    vec3s(s.x);
    vec3s(s.v);
    vec3s(s.a);
    vec3s(s.xPrev);
}

void Writer::texts(const std::vector<std::string>& list) {
    u32(static_cast<std::uint32_t>(list.size()));
    for (const std::string& s : list) text(s);
}

// ---- Reading ------------------------------------------------------------------------------------

std::size_t Reader::count(std::size_t itemBytes) {
    const std::uint32_t n = u32();
    if (static_cast<std::size_t>(end_ - p_) / std::max<std::size_t>(itemBytes, 1) < n) {
        throw ProtocolError("a message announces more items than it holds");
    }
    return n;
}

std::string Reader::text() {
    const std::size_t n = count(1);
    if (n > kMaxStringBytes) throw ProtocolError("a message holds a string that is too long");
    std::string s(p_, n);
    p_ += n;
    return s;
}

Vec3 Reader::vec3() {
    Vec3 v;
    for (int i = 0; i < 3; ++i) v[i] = number();
    return v;
}

Mat3 Reader::mat3() {
    Mat3 m;
    for (int i = 0; i < 9; ++i) m.data()[i] = number();
    return m;
}

Quat Reader::quat() {
    Quat q;
    for (int i = 0; i < 4; ++i) q.coeffs()[i] = number();
    return q;
}

Body Reader::body() {
    Body b;
    const std::uint8_t shape = u8();
    if (shape > static_cast<std::uint8_t>(Shape::Plane)) throw ProtocolError("a body of an unknown shape");
    b.shape = static_cast<Shape>(shape);
    b.radius = number();
    b.position = vec3();
    b.velocity = vec3();
    b.acceleration = vec3();
    b.mass = number();
    b.invMass = number();
    b.angularVelocity = vec3();
    b.restitution = number();
    b.friction = number();
    b.staticFriction = number();
    b.orientation = quat();
    b.inertia = mat3();
    b.invInertia = mat3();
    b.halfExtents = vec3();
    b.normal = vec3();
    b.force = vec3();
    b.torque = vec3();
    b.name = text();
    return b;
}

Contact Reader::contact() {
    Contact c;
    c.a = u64();
    c.b = u64();
    c.normal = vec3();
    c.depth = number();
    const std::int32_t n = i32();
    if (n < 0 || n > kMaxContactPoints) throw ProtocolError("a contact with " + std::to_string(n) + " points");
    c.pointCount = n;
    for (int k = 0; k < n; ++k) c.points[static_cast<std::size_t>(k)] = vec3();
    c.restitution = number();
    c.friction = number();
    c.staticFriction = number();
    return c;
}

std::optional<Contact> Reader::optionalContact() {
    const std::uint8_t has = u8();
    if (has > 1) throw ProtocolError("a contact that is neither there nor not");
    if (!has) return std::nullopt;
    return contact();
}

PointImpulse Reader::pointImpulse() {
    PointImpulse p;
    p.normal = number();
    p.tangent = vec3();
    p.approach = number();
    return p;
}

ContactPoint Reader::contactPoint() {
    ContactPoint p;
    for (Vec3* v : {&p.p, &p.ra, &p.rb}) *v = vec3();
    for (ContactAxis* axis : {&p.n, &p.t1, &p.t2}) {
        for (Vec3* v : {&axis->d, &axis->raXd, &axis->rbXd, &axis->invIaRaXd, &axis->invIbRbXd}) *v = vec3();
        axis->K = number();
    }
    for (double* x : {&p.target, &p.staticFriction, &p.friction}) *x = number();
    return p;
}

DistanceCorrection Reader::distanceCorrection() {
    DistanceCorrection c;
    c.dx1 = vec3();
    c.dx2 = vec3();
    c.dlambda = number();
    return c;
}

VolumeCorrection Reader::volumeCorrection() {
    VolumeCorrection c;
    for (Vec3& d : c.dx) d = vec3();
    c.dlambda = number();
    return c;
}

TensileCorrection Reader::tensileCorrection() {
    TensileCorrection t;
    t.k = number();
    t.dq = number();
    t.n = i32();
    return t;
}

std::vector<FluidNeighbour> Reader::fluidNeighbours() {
    const std::size_t n = count(8 * sizeof(double));
    if (n > kMaxFluidNeighbours) throw ProtocolError("a message holds more fluid neighbours than a particle can have");
    std::vector<FluidNeighbour> list(n);
    for (FluidNeighbour& j : list) {
        j.x = vec3();
        j.v = vec3();
        j.density = number();
        j.lambda = number();
    }
    return list;
}

std::vector<Vec3> Reader::vec3s() {
    std::vector<Vec3> v(count(3 * sizeof(double)));
    for (Vec3& x : v) x = vec3();
    return v;
}

std::vector<Body> Reader::bodies() {
    std::vector<Body> v(count(64));
    for (Body& b : v) b = body();
    return v;
}

std::vector<Contact> Reader::contacts() {
    std::vector<Contact> v(count(64));
    for (Contact& c : v) c = contact();
    return v;
}

ParticleState Reader::particles() {
    ParticleState s;
    s.x = vec3s();
    s.v = vec3s();
    s.a = vec3s();
    s.xPrev = vec3s();
    return s;
}

std::vector<std::string> Reader::texts() {
    std::vector<std::string> v(count(4));
    for (std::string& s : v) s = text();
    return v;
}

void Reader::end() const {
    if (p_ != end_) throw ProtocolError("a message holds more than it should");
}

// ---- Frames -------------------------------------------------------------------------------------

namespace {

bool writeAll(int fd, const char* p, std::size_t n) {
    while (n > 0) {
        const ssize_t w = ::write(fd, p, n);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return false;
        p += w;
        n -= static_cast<std::size_t>(w);
    }
    return true;
}

// Bytes read; fewer than n only at the end of the pipe.
std::size_t readAll(int fd, char* p, std::size_t n) {
    std::size_t got = 0;
    while (got < n) {
        const ssize_t r = ::read(fd, p + got, n - got);
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) break;
        got += static_cast<std::size_t>(r);
    }
    return got;
}

}  // namespace

bool sendFrame(int fd, const std::string& bytes) {
    const auto n = static_cast<std::uint32_t>(bytes.size());
    char head[sizeof n];
    std::memcpy(head, &n, sizeof n);
    return writeAll(fd, head, sizeof head) && writeAll(fd, bytes.data(), bytes.size());
}

bool receiveFrame(int fd, std::string& bytes) {
    std::uint32_t n = 0;
    const std::size_t got = readAll(fd, reinterpret_cast<char*>(&n), sizeof n);
    if (got == 0) return false;
    if (got < sizeof n) throw ProtocolError("a message was cut short");
    if (n > kMaxFrameBytes) throw ProtocolError("a message of " + std::to_string(n) + " bytes, more than allowed");
    bytes.resize(n);
    if (readAll(fd, bytes.data(), n) < n) throw ProtocolError("a message was cut short");
    return true;
}

}  // namespace gpl::grading
