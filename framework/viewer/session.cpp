#include "session.h"

#include <algorithm>
#include <cmath>

namespace gpl::viewer {

void EnergySeries::push(double k, double p) {
    for (auto* s : {&kinetic, &potential, &total}) {
        if (s->size() == kCapacity) s->pop_front();
    }
    kinetic.push_back(static_cast<float>(k));
    potential.push_back(static_cast<float>(p));
    total.push_back(static_cast<float>(k + p));
}

Session::Session(const Scene& scene) : scene_(&scene), reference_(gplref::makeReferenceWorld()) { load(scene); }

void Session::load(const Scene& scene) {
    scene_ = &scene;
    gpl::load(engine_, scene);
    bounds_ = sceneBounds(engine_.bodies());
    tick_ = scene.timeStep;
    engine_.setTimeStep(tick_ / substeps_);
    history_.clear();
    clock_.reset();
    selected_.reset();
    selectedParticle_.reset();
    selectedFluid_.reset();
    drag_.reset();
    error_.clear();
    edited_ = false;
    shots_ = 0;
    energies_.clear();
    energies_.initialTotal = engine_.totalEnergy();
    energies_.push(engine_.kineticEnergy(), engine_.potentialEnergy());
    restartGhost();
}

void Session::frame(double realSeconds) {
    if (paused_) return;
    const int n = clock_.advance(realSeconds, speed_, tick_, kMaxStepsPerFrame);
    for (int i = 0; i < n && !paused_; ++i) tickOnce();
}

void Session::stepOnce() { tickOnce(); }

void Session::tickOnce() {
    history_.push(engine_.state());
    try {
        for (int i = 0; i < substeps_; ++i) {
            if (drag_ && !drag_->particle && !drag_->fluid) {
                // A critically damped spring to the cursor (omega = 12 rad/s), whatever the mass.
                Body& b = engine_.bodies()[drag_->index];
                const double w = 12.0, h = engine_.timeStep();
                b.velocity += h * (w * w * (drag_->target - b.position) - 2.0 * w * b.velocity);
            }
            stepEngine();
            if (ghostOn()) reference_->step();
        }
    } catch (const std::exception& e) {
        error_ = e.what();
        paused_ = true;
    }
    if (ghostOn()) takeGhostState();
    energies_.push(engine_.kineticEnergy(), engine_.potentialEnergy());
}

void Session::stepEngine() {
    if (drag_ && drag_->fluid) {
        // The particle leads with the velocity that takes it toward the cursor; after the step it is
        // put exactly there (its neighbours moved around where it went).
        Fluids& fluid = engine_.fluids();
        const std::size_t i = drag_->index;
        const double h = engine_.timeStep();
        Vec3 to = fluid.x[i] + (1.0 - std::exp(-kParticleDragRate * h)) * (drag_->target - fluid.x[i]);
        if (const auto& box = fluid.container()) {
            const Vec3 margin = Vec3::Constant(fluid.radius());
            to = to.cwiseMax(box->lower + margin).cwiseMin(box->upper - margin);
        }
        drag_->particleVelocity = (to - fluid.x[i]) / h;
        fluid.v[i] = drag_->particleVelocity;
        engine_.step();
        fluid.x[i] = fluid.p[i] = to;
        fluid.v[i] = drag_->particleVelocity;
        return;
    }
    if (!drag_ || !drag_->particle) {
        engine_.step();
        return;
    }
    // The particle is pinned for the step alone, so that no state the history keeps holds it pinned.
    SoftBodies& soft = engine_.softBodies();
    const auto i = static_cast<std::uint32_t>(drag_->index);
    const double h = engine_.timeStep(), w = soft.w[i];
    const Vec3 to = soft.x[i] + (1.0 - std::exp(-kParticleDragRate * h)) * (drag_->target - soft.x[i]);
    drag_->particleVelocity = (to - soft.x[i]) / h;
    soft.x[i] = soft.p[i] = to;
    soft.w[i] = 0.0;
    try {
        engine_.step();
    } catch (...) {
        soft.w[i] = w;
        throw;
    }
    soft.w[i] = w;
    soft.v[i] = w > 0.0 ? drag_->particleVelocity : Vec3::Zero();
}

bool Session::stepBack() {
    PhysicsEngine::State s;
    if (!history_.pop(s)) return false;
    engine_.restore(s);
    if (selected_ && *selected_ >= engine_.bodies().size()) selected_.reset();
    if (selectedParticle_ && *selectedParticle_ >= engine_.softBodies().x.size()) selectedParticle_.reset();
    if (selectedFluid_ && *selectedFluid_ >= engine_.fluids().size()) selectedFluid_.reset();
    drag_.reset();
    error_.clear();
    // The ghost cannot step back; it follows again after a reset.
    edited_ = true;
    if (!energies_.total.empty()) {
        energies_.kinetic.pop_back(), energies_.potential.pop_back(), energies_.total.pop_back();
    }
    return true;
}

void Session::setSpeed(double s) { speed_ = std::clamp(s, kMinSpeed, kMaxSpeed); }

void Session::setTick(double tick) {
    engine_.setTimeStep(tick / substeps_);  // validates first
    tick_ = tick;
    settingsChanged();
}

void Session::setSubsteps(int n) {
    n = std::clamp(n, 1, 64);
    engine_.setTimeStep(tick_ / n);
    substeps_ = n;
    settingsChanged();
}

void Session::setIntegrator(Integrator kind) {
    engine_.setIntegratorKind(kind);
    settingsChanged();
}

void Session::setContactSolver(ContactSolver solver) {
    engine_.setContactSolver(solver);
    settingsChanged();
}

void Session::setStageEnabled(Stage stage, bool on) {
    engine_.setStageEnabled(stage, on);
    settingsChanged();
}

void Session::setContactIterations(int n) {
    engine_.setContactIterations(std::clamp(n, 1, kMaxContactIterations));
    settingsChanged();
}

void Session::setConstraintIterations(int n) {
    engine_.setConstraintIterations(std::clamp(n, 1, kMaxConstraintIterations));
    settingsChanged();
}

void Session::setFluidIterations(int n) {
    FluidParameters parameters = engine_.fluids().parameters();
    parameters.iterations = std::clamp(n, 1, kMaxFluidIterations);
    engine_.fluids().setParameters(parameters);
    settingsChanged();
}

void Session::setRestitution(std::size_t index, double e) {
    engine_.bodies().at(index).restitution = std::clamp(e, 0.0, 1.0);
    settingsChanged();
}

void Session::toggleGravity() { setGravity(gravityOn() ? Vec3::Zero() : standardGravity()); }

void Session::setGravity(const Vec3& g) {
    engine_.setGravity(g);
    settingsChanged();
}

void Session::settingsChanged() {
    // Before the first step the ghost can start over with the new settings; later it would
    // compare two different histories, so it stops until the next reset.
    if (engine_.stepCount() == 0) {
        restartGhost();
    } else {
        edited_ = true;
    }
}

Session::Picked Session::pickAt(const Ray& ray) const {
    const auto& tank = engine_.fluids().container();
    std::optional<Hit> body;
    if (!tank) {
        body = pick(engine_.bodies(), ray);
    } else {
        for (std::size_t i = 0; i < engine_.bodies().size(); ++i) {
            if (isTankWall(engine_.bodies()[i], *tank)) continue;
            const auto t = intersect(engine_.bodies()[i], ray);
            if (t && (!body || *t < body->distance)) body = Hit{i, *t};
        }
    }
    const auto particle = pickParticle(engine_.softBodies(), ray);
    const auto fluid = pickFluidParticle(engine_.fluids(), ray);
    const double bodyAt = body ? body->distance : HUGE_VAL;
    const double particleAt = particle ? particle->distance : HUGE_VAL;
    if (fluid && fluid->distance < bodyAt && fluid->distance < particleAt) return {std::nullopt, std::nullopt, fluid->particle};
    if (particle && particleAt < bodyAt) return {std::nullopt, particle->particle, std::nullopt};
    if (body) return {body->index, std::nullopt, std::nullopt};
    return {};
}

std::optional<std::size_t> Session::pickAndSelect(const Ray& ray) {
    const Picked hit = pickAt(ray);
    selected_ = hit.body;
    selectedParticle_ = hit.particle;
    selectedFluid_ = hit.fluidParticle;
    return selected_;
}

bool Session::beginDrag(const Ray& ray, const Vec3& viewDirection) {
    const Picked hit = pickAt(ray);
    if (hit.fluidParticle) {
        selectFluidParticle(hit.fluidParticle);
        const Vec3 at = engine_.fluids().x[*hit.fluidParticle];
        drag_ = Drag{*hit.fluidParticle, at, at, viewDirection.normalized()};
        drag_->fluid = true;
        edited_ = true;
        return true;
    }
    if (hit.particle) {
        selectParticle(hit.particle);
        const Vec3 at = engine_.softBodies().x[*hit.particle];
        drag_ = Drag{*hit.particle, at, at, viewDirection.normalized(), true};
        edited_ = true;
        return true;
    }
    if (!hit.body) return false;
    const auto distance = intersect(engine_.bodies()[*hit.body], ray);
    if (!distance || engine_.bodies()[*hit.body].isStatic()) return false;
    select(hit.body);
    const Vec3 grab = ray.origin + *distance * ray.direction;
    drag_ = Drag{*hit.body, grab, grab, viewDirection.normalized()};
    edited_ = true;
    return true;
}

void Session::dragTo(const Ray& ray) {
    if (!drag_) return;
    const double denom = ray.direction.dot(drag_->planeNormal);
    if (std::abs(denom) < 1e-9) return;
    const double t = (drag_->planePoint - ray.origin).dot(drag_->planeNormal) / denom;
    if (t > 0.0) drag_->target = ray.origin + t * ray.direction;
}

std::string Session::uniqueName(const std::string& stem) const {
    for (int i = 1;; ++i) {
        const std::string name = stem + "-" + std::to_string(i);
        const auto& bodies = engine_.bodies();
        if (std::none_of(bodies.begin(), bodies.end(), [&](const Body& b) { return b.name == name; })) return name;
    }
}

void Session::shoot(const Ray& from, double speed) {
    engine_.add(
        sphere(uniqueName("shot"), 0.3, 1.0).at(from.origin + 1.0 * from.direction).moving(speed * from.direction));
    ++shots_;
    edited_ = true;
}

void Session::addBox(const Vec3& at) {
    engine_.add(box(uniqueName("box"), {0.5, 0.5, 0.5}, 1.0).at(at));
    edited_ = true;
}

bool Session::removeSelected() {
    if (!selected_) return false;
    engine_.remove(*selected_);
    // The states before hold the body, while the springs, rods and ropes left are numbered without
    // it: stepping back into them would tie the wrong bodies together.
    history_.clear();
    selected_.reset();
    drag_.reset();
    edited_ = true;
    return true;
}

void Session::setGhost(bool on) {
    ghostOn_ = on;
    restartGhost();
}

void Session::restartGhost() {
    ghostPoses_.clear();
    ghostParticles_.clear();
    if (!ghostOn_ || !reference_) return;
    try {
        gplref::ReferenceWorld::Settings settings;
        settings.timeStep = engine_.timeStep();
        const Vec3 g = engine_.gravity();
        settings.gravity = {g.x(), g.y(), g.z()};
        settings.integrator = integratorId(engine_.integratorKind());
        settings.contactIterations = engine_.contactIterations();
        settings.constraintIterations = engine_.constraintIterations();
        for (std::size_t i = 0; i < kStageCount; ++i) {
            if (!engine_.stageEnabled(static_cast<Stage>(i))) settings.disabledStages.push_back(static_cast<int>(i));
        }
        // The ghost shows and compares bodies and soft particles only; a fluid pushes neither (the
        // rigid bodies push it, one way), so the reference steps none.
        for (const Stage fluid : {Stage::FluidPredict, Stage::FluidNeighbours, Stage::FluidProject,
                                  Stage::FluidVelocities, Stage::FluidSph}) {
            settings.disabledStages.push_back(static_cast<int>(fluid));
        }
        for (const Body& b : engine_.bodies()) settings.restitution.push_back(b.restitution);
        reference_->load(scene_->name, settings);
        takeGhostState();
    } catch (const std::exception& e) {
        error_ = std::string("reference ghost: ") + e.what();
        ghostOn_ = false;
    }
}

void Session::takeGhostState() {
    ghostPoses_ = reference_->poses();
    const auto particles = reference_->particles();
    ghostParticles_.resize(particles.size());
    for (std::size_t i = 0; i < particles.size(); ++i) {
        ghostParticles_[i] = Vec3(particles[i][0], particles[i][1], particles[i][2]);
    }
}

double Session::ghostDifference(std::string* name) const {
    double worst = 0.0;
    if (!ghostOn()) return worst;
    const auto& bodies = engine_.bodies();
    for (std::size_t i = 0; i < std::min(bodies.size(), ghostPoses_.size()); ++i) {
        const auto& p = ghostPoses_[i];
        const double d = (bodies[i].position - Vec3(p[0], p[1], p[2])).norm();
        if (d >= worst) {
            worst = d;
            if (name) *name = bodies[i].name;
        }
    }
    const SoftBodies& soft = engine_.softBodies();
    for (std::size_t i = 0; i < std::min(soft.x.size(), ghostParticles_.size()); ++i) {
        const double d = (soft.x[i] - ghostParticles_[i]).norm();
        if (d > worst) {
            worst = d;
            if (name) *name = particleName(soft, static_cast<std::uint32_t>(i));
        }
    }
    return worst;
}

}  // namespace gpl::viewer
