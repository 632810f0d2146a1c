#include "gpl/engine.h"

#include <cmath>
#include <iostream>
#include <mutex>

namespace gpl {

PhysicsEngine::PhysicsEngine() = default;

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
}

void PhysicsEngine::restore(const State& s) {
    bodies_ = s.bodies;
    time_ = s.time;
    steps_ = s.steps;
}

void PhysicsEngine::clear() {
    bodies_.clear();
    time_ = 0.0;
    steps_ = 0;
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
}

void PhysicsEngine::setStageEnabled(Stage stage, bool on) {
    if (on) {
        disabled_.erase(stage);
    } else {
        disabled_.insert(stage);
    }
}

void PhysicsEngine::step() {
    simulationTimestep();
    time_ += timeStep_;
    ++steps_;
    for (const Body& b : bodies_) {
        if (!isFinite(b.position) || !isFinite(b.velocity)) {
            throw SimulationError("body '" + b.name + "' is no longer finite after step " + std::to_string(steps_) +
                                  " (t = " + formatNumber(time_) + " s): check integrator()");
        }
    }
}

void PhysicsEngine::updateConstantAcceleration() {
    for (Body& b : bodies_) {
        b.acceleration = b.isStatic() ? Vec3::Zero() : gravity_;
    }
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
    return e;
}

double PhysicsEngine::potentialEnergy() const {
    double e = 0.0;
    for (const Body& b : bodies_) e += gpl::potentialEnergy(b, gravity_);
    return e;
}

double PhysicsEngine::totalEnergy() const { return kineticEnergy() + potentialEnergy(); }

Vec3 PhysicsEngine::linearMomentum() const {
    Vec3 p = Vec3::Zero();
    for (const Body& b : bodies_) p += gpl::linearMomentum(b);
    return p;
}

bool PhysicsEngine::allFinite() const {
    for (const Body& b : bodies_) {
        if (!isFinite(b.position) || !isFinite(b.velocity)) return false;
    }
    return true;
}

}  // namespace gpl
