#include "gpl/runner.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace gpl {
namespace {

std::atomic<std::size_t> stepNow{0};  // the step run() is taking, for a signal handler

void writeRow(std::ostream& csv, const PhysicsEngine& e, const std::string& name, const Vec3& x, const Vec3& v,
              double kinetic, double potential) {
    csv << e.stepCount() << ',' << e.time() << ',' << name << ',' << x.x() << ',' << x.y() << ',' << x.z() << ','
        << v.x() << ',' << v.y() << ',' << v.z() << ',' << kinetic << ',' << potential << ',' << kinetic + potential
        << '\n';
}

void writeRows(std::ostream& csv, const PhysicsEngine& e) {
    double movableMass = 0.0;
    Vec3 weightedPosition = Vec3::Zero();
    // Gravity's potential only while its stage acts, as in PhysicsEngine::potentialEnergy().
    const Vec3 gravity = e.stageActive(Stage::ConstantAcceleration) ? e.gravity() : Vec3::Zero();
    for (const Body& b : e.bodies()) {
        writeRow(csv, e, b.name, b.position, b.velocity, kineticEnergy(b), potentialEnergy(b, gravity));
        if (b.isStatic()) continue;
        movableMass += b.mass;
        weightedPosition += b.mass * b.position;
    }
    const Vec3 centre = movableMass > 0.0 ? Vec3(weightedPosition / movableMass) : Vec3::Zero();
    const Vec3 centreVelocity = movableMass > 0.0 ? Vec3(e.linearMomentum() / movableMass) : Vec3::Zero();
    writeRow(csv, e, "world", centre, centreVelocity, e.kineticEnergy(), e.potentialEnergy());
}

// The soft bodies' measures of the summary, taken at one state.
void measureSoftBodies(const PhysicsEngine& e, RunSummary& s) {
    const SoftBodies& soft = e.softBodies();
    if (soft.empty()) return;
    for (std::size_t m = 0; m < soft.meshes.size(); ++m) {
        const SoftMesh& mesh = soft.meshes[m];
        switch (mesh.kind) {
            case SoftMesh::Kind::Cloth:
                s.largestStretch = std::max(s.largestStretch, soft.largestStretch(m, LinkKind::Stretch));
                break;
            case SoftMesh::Kind::Rope:
                s.largestStretch = std::max(s.largestStretch, soft.largestStretch(m, LinkKind::Rope));
                break;
            case SoftMesh::Kind::SoftBody: {
                s.largestStretch = std::max(s.largestStretch, soft.largestStretch(m, LinkKind::Edge));
                const double ratio = soft.volumeRatio(m);
                s.smallestVolumeRatio = std::min(s.smallestVolumeRatio, ratio);
                s.largestVolumeRatio = std::max(s.largestVolumeRatio, ratio);
                break;
            }
        }
    }
    s.deepestPenetration = std::max(s.deepestPenetration, soft.deepestPenetration(e.bodies()));
}

}  // namespace

void writeCsvHeader(std::ostream& csv) { csv << "step,time,body,x,y,z,vx,vy,vz,kinetic,potential,total\n"; }

RunSummary run(PhysicsEngine& engine, std::size_t steps, std::ostream* csv) {
    RunSummary s;
    s.initialEnergy = engine.totalEnergy();
    s.initialAngularMomentum = engine.angularMomentum();
    if (csv) {
        *csv << std::setprecision(17);
        writeRows(*csv, engine);
        csv->flush();
    }
    const double startTime = engine.time();
    // The summary's end is the last state that was finite: a step that ends in a NaN adds nothing.
    const auto atEnd = [&] {
        s.simulatedTime = engine.time() - startTime;
        s.finalEnergy = engine.totalEnergy();
        s.finalAngularMomentum = engine.angularMomentum();
        s.maxSpeed = 0.0;
        for (const Body& b : engine.bodies()) s.maxSpeed = std::max(s.maxSpeed, b.velocity.norm());
        for (const Vec3& v : engine.softBodies().v) s.maxSpeed = std::max(s.maxSpeed, v.norm());
    };
    atEnd();
    measureSoftBodies(engine, s);
    double previous = s.initialEnergy;
    try {
        for (std::size_t i = 0; i < steps; ++i) {
            stepNow = engine.stepCount() + 1;
            engine.step();
            ++s.steps;
            s.maxContacts = std::max(s.maxContacts, engine.contacts().size());
            for (const Contact& c : engine.contacts()) s.deepestContact = std::max(s.deepestContact, c.depth);
            const double energy = engine.totalEnergy();
            s.maxEnergyIncrease = std::max(s.maxEnergyIncrease, energy - previous);
            previous = energy;
            if (csv) {
                writeRows(*csv, engine);
                csv->flush();  // every finished step is in the file, whatever ends the program
            }
            atEnd();
            measureSoftBodies(engine, s);
        }
    } catch (const SimulationError& error) {
        s.error = error.what();
    }
    stepNow = 0;
    return s;
}

std::size_t stepInProgress() { return stepNow; }

std::string describe(const RunSummary& s, const PhysicsEngine& e) {
    std::ostringstream out;
    out << std::setprecision(6);
    // A run that stopped says why first; the rest describes the steps that ended finite.
    if (!s.error.empty()) out << "stopped early: " << s.error << '\n';
    const auto openHooks = [&] {
        if (e.missingHooks().empty()) return;
        out << "hooks not implemented yet:";
        for (const auto& h : e.missingHooks()) out << ' ' << h;
        out << '\n';
    };
    if (!s.error.empty() && s.steps == 0) {
        openHooks();
        return out.str();
    }
    if (!s.error.empty()) out << "the " << s.steps << " finite step" << (s.steps == 1 ? "" : "s") << ":\n";
    out << "steps: " << s.steps << " of h = " << e.timeStep() << " s (" << s.simulatedTime << " s simulated), "
        << e.bodies().size() << " bodies, stages: " << e.requiredStages().names()
        << ", integrator: " << integratorName(e.integratorKind()) << '\n';
    const double drift = s.finalEnergy - s.initialEnergy;
    out << "total energy: " << s.initialEnergy << " J -> " << s.finalEnergy << " J (drift " << std::showpos << drift
        << std::noshowpos << " J";
    if (s.initialEnergy != 0.0)
        out << ", " << std::showpos << 100.0 * drift / std::abs(s.initialEnergy) << std::noshowpos << " %";
    if (s.steps > 0)
        out << ", " << std::showpos << drift / static_cast<double>(s.steps) << std::noshowpos << " J per step";
    out << ")\n";
    if (s.maxEnergyIncrease > 0.0) {
        out << "largest energy increase in one step: " << s.maxEnergyIncrease << " J\n";
    }
    out << "largest speed at the end: " << s.maxSpeed << " m/s\n";
    if (e.requiredStages().contains(Stage::Rotation)) {
        const Vec3& l0 = s.initialAngularMomentum;
        const Vec3& l1 = s.finalAngularMomentum;
        out << "angular momentum about the origin: (" << l0.x() << ", " << l0.y() << ", " << l0.z() << ") -> ("
            << l1.x() << ", " << l1.y() << ", " << l1.z() << ") kg m^2/s (changed by " << (l1 - l0).norm();
        if (l0.norm() > 0.0) out << ", " << 100.0 * (l1 - l0).norm() / l0.norm() << " %";
        out << ")\n";
    }
    if (e.requiredStages().contains(Stage::CollisionDetection) || e.requiredStages().contains(Stage::Ropes)) {
        out << "contacts: at most " << s.maxContacts << " in one step, deepest " << s.deepestContact
            << " m (found before resolution)\n";
    }
    const SoftBodies& soft = e.softBodies();
    if (!soft.empty()) {
        bool anySoftBody = false;
        for (const SoftMesh& mesh : soft.meshes) anySoftBody = anySoftBody || mesh.kind == SoftMesh::Kind::SoftBody;
        out << "soft bodies: " << soft.x.size() << " particles in " << soft.meshes.size() << " mesh"
            << (soft.meshes.size() == 1 ? "" : "es") << ", " << soft.constraintCount() << " constraints; largest stretch "
            << 100.0 * s.largestStretch << " %";
        if (anySoftBody) out << ", volume ratio " << s.smallestVolumeRatio << " .. " << s.largestVolumeRatio;
        out << ", deepest penetration " << s.deepestPenetration << " m\n";
    }
    openHooks();
    return out.str();
}

}  // namespace gpl
