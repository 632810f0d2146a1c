#include "gpl/engine.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <mutex>

#include "gpl/broadphase.h"
#include "gpl/friction_stage.h"

namespace gpl {

// Here, where the contact stages' types are complete: their Owned<> are made, copied and ended.
PhysicsEngine::PhysicsEngine() = default;
PhysicsEngine::~PhysicsEngine() = default;
PhysicsEngine::PhysicsEngine(const PhysicsEngine&) = default;
PhysicsEngine& PhysicsEngine::operator=(const PhysicsEngine&) = default;
PhysicsEngine::PhysicsEngine(PhysicsEngine&&) = default;
PhysicsEngine& PhysicsEngine::operator=(PhysicsEngine&&) = default;

PhysicsEngine::State PhysicsEngine::state() const {
    return {bodies_, time_, steps_, previousPositions_, soft_.x, soft_.v, soft_.w, fluids_.x, fluids_.v};
}

int PhysicsEngine::threads() const { return broadPhase_->threads(); }

std::size_t PhysicsEngine::add(Body b) {
    validate(b);
    for (const Body& other : bodies_) {
        if (other.name == b.name) throw std::invalid_argument("a body named '" + b.name + "' already exists");
    }
    bodies_.push_back(std::move(b));
    return bodies_.size() - 1;
}

Body& PhysicsEngine::body(const std::string& name) {
    for (Body& b : bodies_) {
        if (b.name == name) return b;
    }
    throw std::out_of_range("no body named '" + name + "'");
}

const Body& PhysicsEngine::body(const std::string& name) const { return const_cast<PhysicsEngine*>(this)->body(name); }

void PhysicsEngine::remove(std::size_t index) {
    if (index >= bodies_.size()) throw std::out_of_range("no body number " + std::to_string(index));
    bodies_.erase(bodies_.begin() + static_cast<std::ptrdiff_t>(index));
    if (!previousPositions_.empty())
        previousPositions_.erase(previousPositions_.begin() + static_cast<std::ptrdiff_t>(index));
    // Springs and constraints on the body go with it; those on later bodies follow the new numbering.
    const auto dropAndRenumber = [index](auto& links) {
        links.erase(
            std::remove_if(links.begin(), links.end(), [index](const auto& l) { return l.a == index || l.b == index; }),
            links.end());
        for (auto& l : links) {
            if (l.a > index) --l.a;
            if (l.b > index) --l.b;
        }
    };
    dropAndRenumber(springs_);
    dropAndRenumber(distances_);
    dropAndRenumber(ropes_);
    contacts_.clear();
    nearPairs_.clear();
    friction_->forget();  // the friction stage's sums name bodies by index
    soft_.contacts.clear();  // so do the particles' contacts
}

void PhysicsEngine::restore(const State& s) {
    bodies_ = s.bodies;
    contacts_.clear();
    nearPairs_.clear();
    time_ = s.time;
    steps_ = s.steps;
    previousPositions_ = s.previousPositions;
    friction_->forget();
    soft_.x = s.particlePositions;
    soft_.v = s.particleVelocities;
    soft_.w = s.particleInverseMasses;
    soft_.p = s.particlePositions;
    soft_.contacts.clear();
    soft_.selfPairs.clear();
    fluids_.x = s.fluidPositions;
    fluids_.v = s.fluidVelocities;
    fluids_.p = s.fluidPositions;
    fluids_.density.resize(fluids_.x.size(), fluids_.parameters().restDensity);
    fluids_.lambda.resize(fluids_.x.size(), 0.0);
    fluids_.pressure.resize(fluids_.x.size(), 0.0);
}

void PhysicsEngine::clear() {
    bodies_.clear();
    springs_.clear();
    distances_.clear();
    ropes_.clear();
    contacts_.clear();
    nearPairs_.clear();
    container_.reset();
    previousPositions_.clear();
    friction_->forget();
    soft_.clear();
    fluids_.clear();
    time_ = 0.0;
    steps_ = 0;
}

std::size_t PhysicsEngine::bodyIndex(const std::string& name) const {
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
        if (bodies_[i].name == name) return i;
    }
    throw std::invalid_argument("no body named '" + name + "'");
}

namespace {

void requireTwoEnds(const std::vector<Body>& bodies, std::size_t a, std::size_t b, const char* what) {
    if (a == b)
        throw std::invalid_argument(std::string(what) + " needs two different bodies, got '" + bodies[a].name +
                                    "' twice");
    if (bodies[a].isStatic() && bodies[b].isStatic()) {
        throw std::invalid_argument(std::string(what) + " between '" + bodies[a].name + "' and '" + bodies[b].name +
                                    "': both are static, so it could never act");
    }
}

}  // namespace

std::size_t PhysicsEngine::addSpring(const std::string& a, const std::string& b, double stiffness, double damping,
                                     double restLength) {
    Spring s;
    s.a = bodyIndex(a);
    s.b = bodyIndex(b);
    requireTwoEnds(bodies_, s.a, s.b, "a spring");
    const std::string where = "spring '" + a + "'-'" + b + "': ";
    if (!std::isfinite(stiffness) || stiffness <= 0.0) {
        throw std::invalid_argument(where + "stiffness must be a positive finite number of N/m, got " +
                                    formatNumber(stiffness));
    }
    if (!std::isfinite(damping) || damping < 0.0) {
        throw std::invalid_argument(where + "damping must be a finite number >= 0 N s/m, got " + formatNumber(damping));
    }
    if (!std::isfinite(restLength)) {
        throw std::invalid_argument(where + "rest length must be finite, got " + formatNumber(restLength));
    }
    s.stiffness = stiffness;
    s.damping = damping;
    s.restLength = restLength < 0.0 ? (bodies_[s.a].position - bodies_[s.b].position).norm() : restLength;
    springs_.push_back(s);
    return springs_.size() - 1;
}

std::size_t PhysicsEngine::addDistanceConstraint(const std::string& a, const std::string& b) {
    DistanceConstraint c;
    c.a = bodyIndex(a);
    c.b = bodyIndex(b);
    requireTwoEnds(bodies_, c.a, c.b, "a distance constraint");
    c.length = (bodies_[c.a].position - bodies_[c.b].position).norm();
    if (c.length == 0.0) {
        throw std::invalid_argument("distance constraint '" + a + "'-'" + b + "': the bodies are at the same place");
    }
    distances_.push_back(c);
    return distances_.size() - 1;
}

std::size_t PhysicsEngine::addRope(const std::string& a, const std::string& b) {
    const double distance = (bodies_[bodyIndex(a)].position - bodies_[bodyIndex(b)].position).norm();
    return addRope(a, b, distance);
}

std::size_t PhysicsEngine::addRope(const std::string& a, const std::string& b, double length) {
    Rope r;
    r.a = bodyIndex(a);
    r.b = bodyIndex(b);
    requireTwoEnds(bodies_, r.a, r.b, "a rope");
    const std::string where = "rope '" + a + "'-'" + b + "': ";
    if (!std::isfinite(length) || length <= 0.0) {
        throw std::invalid_argument(where + "length must be a positive finite number of metres, got " +
                                    formatNumber(length));
    }
    const double distance = (bodies_[r.a].position - bodies_[r.b].position).norm();
    if (distance > length * (1.0 + 1e-12)) {  // rounding of the distance the caller measured
        throw std::invalid_argument(where + "length " + formatNumber(length) + " m is shorter than the bodies' distance " +
                                    formatNumber(distance) + " m: the rope would start stretched");
    }
    r.length = length;
    ropes_.push_back(r);
    return ropes_.size() - 1;
}

void PhysicsEngine::setContactIterations(int iterations) {
    if (iterations < 1) {
        throw std::invalid_argument("contact iterations must be at least 1, got " + std::to_string(iterations));
    }
    contactIterations_ = iterations;
}

void PhysicsEngine::setInterpenetrationIterations(int iterations) {
    if (iterations < 0) {
        throw std::invalid_argument("interpenetration iterations must be at least 1 (or 0: as many as the contact "
                                    "iterations), got " + std::to_string(iterations));
    }
    interpenetrationIterations_ = iterations;
}

void PhysicsEngine::setContactSolver(ContactSolver solver) {
    if (solver != contactSolver_) friction_->forget();  // the solvers keep impulses of different meaning
    contactSolver_ = solver;
}

void PhysicsEngine::setThreads(int threads) {
    if (threads < 1) throw std::invalid_argument("threads must be at least 1, got " + std::to_string(threads));
    broadPhase_->setThreads(threads);
    soft_.setThreads(threads);
    fluids_.setThreads(threads);
}

void PhysicsEngine::setContainer(const Vec3& centre, double radius) {
    if (!isFinite(centre)) throw std::invalid_argument("container centre must be finite");
    if (!std::isfinite(radius) || radius <= 0.0) {
        throw std::invalid_argument("container radius must be a positive finite number of metres, got " +
                                    formatNumber(radius));
    }
    container_ = Container{centre, radius};
}

void PhysicsEngine::setIntegratorKind(Integrator kind) {
    integratorKind_ = kind;
    previousPositions_.clear();
}

void PhysicsEngine::setConstraintIterations(int iterations) {
    if (iterations < 1) {
        throw std::invalid_argument("constraint iterations must be at least 1, got " + std::to_string(iterations));
    }
    constraintIterations_ = iterations;
}

void PhysicsEngine::setGravity(const Vec3& g) {
    if (!isFinite(g)) throw std::invalid_argument("gravity must be finite");
    gravity_ = g;
}

void PhysicsEngine::setTimeStep(double h) {
    if (!std::isfinite(h) || h <= 0.0) {
        throw std::invalid_argument("time step must be a positive finite number of seconds, got " + formatNumber(h));
    }
    timeStep_ = h;
    previousPositions_.clear();  // x_{n-1} belongs to the old step
}

void PhysicsEngine::setStageEnabled(Stage stage, bool on) {
    if (on) {
        disabled_.erase(stage);
    } else {
        disabled_.insert(stage);
    }
}

void PhysicsEngine::step() {
    beginStep();
    simulationTimestep();
    endStep();
}

void PhysicsEngine::beginStep() {
    contacts_.clear();
    nearPairs_.clear();
    // The gravity stage sets the accumulators anew each step; switched off, they start empty
    // instead, so that the springs' accelerations never pile up on last step's.
    if (!stageActive(Stage::ConstantAcceleration)) {
        for (Body& b : bodies_) b.acceleration = Vec3::Zero();
    }
}

void PhysicsEngine::endStep() {
    time_ += timeStep_;
    ++steps_;
    if (allFinite()) return;
    for (const Body& b : bodies_) {
        if (!isFinite(b.position) || !isFinite(b.velocity)) {
            throw SimulationError("body '" + b.name + "' is no longer finite after step " + std::to_string(steps_) +
                                  " (t = " + formatNumber(time_) + " s): check integrator()");
        }
    }
    const std::size_t i = soft_.firstNonFinite();
    if (i < soft_.x.size()) {
        const SoftMesh& mesh = soft_.meshes[soft_.meshOf[i]];
        throw SimulationError("particle " + std::to_string(i - mesh.first) + " of '" + mesh.name +
                              "' is no longer finite after step " + std::to_string(steps_) + " (t = " +
                              formatNumber(time_) + " s): check solveDistanceConstraint() and solveVolumeConstraint()");
    }
    const std::size_t f = fluids_.firstNonFinite();
    if (f < fluids_.size()) {
        throw SimulationError("fluid particle " + std::to_string(f) + " is no longer finite after step " +
                              std::to_string(steps_) + " (t = " + formatNumber(time_) +
                              " s): check fluidDensity(), densityConstraintLambda() and densityCorrection()");
    }
}

void PhysicsEngine::updateConstantAcceleration() {
    for (Body& b : bodies_) {
        b.acceleration = b.isStatic() ? Vec3::Zero() : gravity_;
    }
}

void PhysicsEngine::accelerations(const std::vector<Vec3>& x, const std::vector<Vec3>& v, std::vector<Vec3>& a) const {
    a.assign(x.size(), Vec3::Zero());
    if (stageActive(Stage::ConstantAcceleration)) {
        for (std::size_t i = 0; i < bodies_.size(); ++i) {
            if (!bodies_[i].isStatic()) a[i] = gravity_;
        }
    }
    if (stageActive(Stage::Springs)) {
        for (const Spring& s : springs_) {
            const Vec3 f = springForce(x[s.a], x[s.b], v[s.a], v[s.b], s.stiffness, s.restLength, s.damping);
            a[s.a] += bodies_[s.a].invMass * f;
            a[s.b] -= bodies_[s.b].invMass * f;
        }
    }
}

void PhysicsEngine::applySpringForces() {
    for (const Spring& s : springs_) {
        Body& a = bodies_[s.a];
        Body& b = bodies_[s.b];
        const Vec3 f =
            springForce(a.position, b.position, a.velocity, b.velocity, s.stiffness, s.restLength, s.damping);
        a.acceleration += a.invMass * f;
        b.acceleration -= b.invMass * f;
    }
}

void PhysicsEngine::integrate() {
    if (integratorKind_ == Integrator::SemiImplicitEuler) {
        integrator();  // the worksheet-1 hook
        return;
    }
    ParticleState s;
    for (const Body& b : bodies_) {
        s.x.push_back(b.position);
        s.v.push_back(b.velocity);
        s.a.push_back(b.acceleration);
    }
    if (integratorKind_ == Integrator::PositionVerlet) s.xPrev = std::move(previousPositions_);
    const AccelerationFunction accel = [this](const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                                              std::vector<Vec3>& a) { accelerations(x, v, a); };
    gpl::integrate(integratorKind_, s, accel, timeStep_);
    recordOpenKernels();
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
        Body& b = bodies_[i];
        if (b.isStatic()) continue;
        b.position = s.x[i];
        b.velocity = s.v[i];
        b.acceleration = s.a[i];
    }
    previousPositions_ = std::move(s.xPrev);
}

void PhysicsEngine::projectConstraints() {
    const bool constraints = stageActive(Stage::Constraints);
    const bool collisions = stageActive(Stage::ParticleCollisions);
    start_.clear();
    for (const Body& b : bodies_) start_.push_back(b.position);
    for (int sweep = 0; sweep < constraintIterations_; ++sweep) {
        if (collisions) {
            // Pairs anew every sweep, with a margin: this sweep's pushes may reach new neighbours.
            for (const BodyPair& pair : broadPhase_->findPairs(bodies_, kContactMargin, &second_)) {
                Body& a = bodies_[pair.a];
                Body& b = bodies_[pair.b];
                if (a.shape != Shape::Sphere || b.shape != Shape::Sphere) continue;
                separateSpheres(a.position, b.position, a.radius, b.radius, a.invMass, b.invMass);
            }
        }
        // Constraints last, so that the container and the rods have the final word in each sweep.
        if (constraints) {
            for (const DistanceConstraint& c : distances_) {
                Body& a = bodies_[c.a];
                Body& b = bodies_[c.b];
                projectDistance(a.position, b.position, a.invMass, b.invMass, c.length);
            }
            if (container_) {
                for (Body& b : bodies_) {
                    if (!b.isStatic() && b.shape == Shape::Sphere) keepInside(b.position, b.radius, *container_);
                }
            }
        }
    }
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
        bodies_[i].velocity += (bodies_[i].position - start_[i]) / timeStep_;
    }
}

void PhysicsEngine::predictParticles() { soft_.predict(timeStep_, gravity_, time_); }

void PhysicsEngine::findParticleContacts() { soft_.findContacts(bodies_, timeStep_); }

void PhysicsEngine::projectParticles() {
    soft_.project(timeStep_, constraintIterations_, bodies_);
    recordOpenKernels();
}

void PhysicsEngine::updateParticleVelocities() { soft_.updateVelocities(timeStep_); }

void PhysicsEngine::predictFluid() { fluids_.predict(timeStep_, gravity_); }

void PhysicsEngine::findFluidNeighbours() { fluids_.findNeighbours(); }

void PhysicsEngine::projectFluid() {
    fluids_.project(bodies_);
    recordOpenKernels();
}

void PhysicsEngine::updateFluidVelocities() {
    fluids_.updateVelocities(timeStep_);
    recordOpenKernels();
}

void PhysicsEngine::stepSph() {
    fluids_.stepSph(timeStep_, gravity_, bodies_);
    recordOpenKernels();
}

void PhysicsEngine::recordOpenKernels() {
    for (const std::string& hook : kernelsNotImplemented()) missing_.insert(hook);
}

void PhysicsEngine::notImplemented(const std::string& hook) {
    if (!missing_.insert(hook).second) return;
    static std::mutex mutex;
    static std::set<std::string> reported;
    const std::lock_guard<std::mutex> lock(mutex);
    if (reported.insert(hook).second) std::cerr << "not implemented: " << hook << '\n';
}

double PhysicsEngine::kineticEnergy() const {
    double e = 0.0;
    for (const Body& b : bodies_) e += gpl::kineticEnergy(b);
    if (!soft_.empty()) e += soft_.kineticEnergy();
    if (!fluids_.empty()) e += fluids_.kineticEnergy();
    return e;
}

double PhysicsEngine::potentialEnergy() const {
    double e = 0.0;
    if (stageActive(Stage::ConstantAcceleration)) {
        for (const Body& b : bodies_) e += gpl::potentialEnergy(b, gravity_);
    }
    return plusSoftEnergies(plusSpringEnergies(e));
}

double PhysicsEngine::plusSoftEnergies(double e) const {
    if (!fluids_.empty()) e += fluids_.potentialEnergy(gravity_);
    if (soft_.empty()) return e;
    return e + soft_.potentialEnergy(gravity_) + soft_.elasticEnergy();
}

double PhysicsEngine::plusSpringEnergies(double e) const {
    for (const Spring& s : springs_) {
        e += springEnergy(bodies_[s.a].position, bodies_[s.b].position, s.stiffness, s.restLength);
    }
    return e;
}

double PhysicsEngine::totalEnergy() const {
    // Both sums in one pass over the bodies, added up as kineticEnergy() + potentialEnergy() would.
    const bool gravity = stageActive(Stage::ConstantAcceleration);
    double kinetic = 0.0, potential = 0.0;
    for (const Body& b : bodies_) {
        kinetic += gpl::kineticEnergy(b);
        if (gravity) potential += gpl::potentialEnergy(b, gravity_);
    }
    if (!soft_.empty()) kinetic += soft_.kineticEnergy();
    if (!fluids_.empty()) kinetic += fluids_.kineticEnergy();
    return kinetic + plusSoftEnergies(plusSpringEnergies(potential));
}

Vec3 PhysicsEngine::linearMomentum() const {
    Vec3 p = Vec3::Zero();
    for (const Body& b : bodies_) p += gpl::linearMomentum(b);
    if (!fluids_.empty()) p += fluids_.linearMomentum();
    return p;
}

bool PhysicsEngine::allFinite() const {
    // One pass without a branch per number (step() calls this every step): a NaN or an infinity
    // anywhere makes the sum of every position and velocity NaN or infinite. Only when it is not
    // finite, body by body, since finite numbers can also add up to an overflow.
    Vec3 sum = Vec3::Zero();
    for (const Body& b : bodies_) sum += b.position + b.velocity;
    if (isFinite(sum)) return (soft_.empty() || soft_.allFinite()) && fluids_.firstNonFinite() == fluids_.size();
    for (const Body& b : bodies_) {
        if (!isFinite(b.position) || !isFinite(b.velocity)) return false;
    }
    return (soft_.empty() || soft_.allFinite()) && fluids_.firstNonFinite() == fluids_.size();
}

}  // namespace gpl
