// The heap of `./lab bench engine` in this engine, and what both engines share: the lattice, the
// statistics of step times and the quality of the settled heap.
#include "heap.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <random>
#include <unordered_map>

#include "gpl/body.h"
#include "gpl/collision.h"
#include "gpl/engine.h"

namespace gpl::bench {

std::vector<Vec3> heapPositions(std::size_t n) {
    const int side = std::max(1, static_cast<int>(std::ceil(std::cbrt(static_cast<double>(n)) - 1e-9)));
    std::mt19937 random(1);  // fixed seed: the same heap every time, in both engines
    const auto jitter = [&random] { return 0.1 * (static_cast<double>(random()) / 4294967296.0 - 0.5); };  // m
    std::vector<Vec3> at;
    at.reserve(n);
    const double centre = 0.5 * (side - 1);
    for (int y = 0; at.size() < n; ++y) {
        for (int z = 0; z < side && at.size() < n; ++z) {
            for (int x = 0; x < side && at.size() < n; ++x) {
                const double jx = jitter(), jy = jitter(), jz = jitter();
                at.emplace_back(kSpacing * (x - centre) + jx, 1.0 + kSpacing * y + jy, kSpacing * (z - centre) + jz);
            }
        }
    }
    return at;
}

std::vector<Quat> heapOrientations(std::size_t n) {
    std::mt19937 random(2);  // fixed seed, as the lattice's
    std::normal_distribution<double> normal;
    std::vector<Quat> q;
    q.reserve(n);
    // Four normal numbers, normalised: a direction uniform on the sphere of unit quaternions.
    while (q.size() < n) q.push_back(Quat(normal(random), normal(random), normal(random), normal(random)).normalized());
    return q;
}

std::vector<HeapRun> runInTurns(HeapShape shape, std::size_t n, double seconds,
                                const std::vector<std::pair<std::string, HeapSim*>>& engines) {
    const auto steps = static_cast<std::size_t>(std::ceil(seconds / kTimeStep));
    std::vector<std::vector<double>> stepMs(engines.size());
    std::vector<double> points(engines.size(), 0.0);
    // The states of the last second, measured after the run: measuring between the timed steps
    // made this engine's next step slower (its second thread had gone to sleep meanwhile).
    std::vector<std::vector<std::vector<HeapBody>>> lastSecond(engines.size());
    for (std::size_t done = 0; done < steps; done += kTurn) {
        for (std::size_t e = 0; e < engines.size(); ++e) {
            for (std::size_t s = done; s < std::min(steps, done + kTurn); ++s) {
                const auto start = std::chrono::steady_clock::now();
                engines[e].second->step();
                stepMs[e].push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
                points[e] += engines[e].second->contactPoints();
                if (s + kQualitySteps >= steps) lastSecond[e].push_back(engines[e].second->state());
            }
        }
    }
    std::vector<HeapRun> runs(engines.size());
    for (std::size_t e = 0; e < engines.size(); ++e) {
        HeapRun& run = runs[e];
        run.engine = engines[e].first;
        run.shape = shape;
        run.bodies = n;
        run.steps = steps;
        if (steps > 0) {
            run.contactsPerStep = points[e] / static_cast<double>(steps);
            std::vector<double>& ms = stepMs[e];
            std::sort(ms.begin(), ms.end());
            run.medianMs = ms[ms.size() / 2];
            run.p90Ms = ms[std::min(ms.size() - 1, ms.size() * 9 / 10)];
        }
        // The last state kept is the one at the end: its height and kinetic energy stay in run.
        if (lastSecond[e].empty()) lastSecond[e].push_back(engines[e].second->state());
        double deepest = 0.0;
        for (const std::vector<HeapBody>& state : lastSecond[e]) {
            measureQuality(state, run);
            deepest = std::max(deepest, run.deepest);
        }
        run.deepest = deepest;
    }
    return runs;
}

namespace {

// The cells of a grid `cell` wide that hold each body's centre: bodies that may overlap are in the
// same or neighbouring cells when the cell is at least the largest distance of two touching centres.
template <class Visit>
void nearPairs(const std::vector<HeapBody>& bodies, double cell, Visit visit) {
    const auto key = [](long x, long y, long z) { return (x * 73856093) ^ (y * 19349663) ^ (z * 83492791); };
    const auto cellOf = [cell](double u) { return std::lround(std::floor(u / cell)); };
    std::unordered_multimap<long, std::size_t> grid;
    grid.reserve(bodies.size());
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        const Vec3& p = bodies[i].position;
        grid.emplace(key(cellOf(p.x()), cellOf(p.y()), cellOf(p.z())), i);
    }
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        const Vec3& p = bodies[i].position;
        const long cx = cellOf(p.x()), cy = cellOf(p.y()), cz = cellOf(p.z());
        for (long dx = -1; dx <= 1; ++dx) {
            for (long dy = -1; dy <= 1; ++dy) {
                for (long dz = -1; dz <= 1; ++dz) {
                    const auto [first, last] = grid.equal_range(key(cx + dx, cy + dy, cz + dz));
                    for (auto it = first; it != last; ++it) {
                        if (it->second > i) visit(i, it->second);
                    }
                }
            }
        }
    }
}

}  // namespace

void measureQuality(const std::vector<HeapBody>& bodies, HeapRun& run) {
    run.deepest = 0.0;
    run.height = 0.0;
    run.kinetic = 0.0;
    run.fastest = 0.0;
    for (const HeapBody& b : bodies) run.fastest = std::max(run.fastest, b.velocity.norm());
    if (run.shape == HeapShape::Spheres) {
        for (const HeapBody& b : bodies) {
            run.deepest = std::max(run.deepest, kRadius - b.position.y());
            run.height = std::max(run.height, b.position.y() + kRadius);
            // Translation only, in both engines: this engine does not step a sphere's rotation.
            run.kinetic += 0.5 * kMass * b.velocity.squaredNorm();
        }
        nearPairs(bodies, 2.0 * kRadius, [&](std::size_t i, std::size_t j) {
            run.deepest = std::max(run.deepest, 2.0 * kRadius - (bodies[i].position - bodies[j].position).norm());
        });
        return;
    }
    // Cubes, as this engine's bodies, measured by its reference kernels.
    const Vec3 half = Vec3::Constant(kHalfSide);
    const Body ground = plane("ground", Vec3::UnitY());
    std::vector<Body> cubes;
    cubes.reserve(bodies.size());
    const double inertia = kMass * (2.0 * kHalfSide) * (2.0 * kHalfSide) / 6.0;  // kg m^2, about any axis
    for (const HeapBody& b : bodies) {
        cubes.push_back(box("cube", half, kMass).at(b.position).rotated(b.orientation));
        if (const std::optional<Contact> c = boxPlane(cubes.back(), ground)) run.deepest = std::max(run.deepest, c->depth);
        for (int k = 0; k < 8; ++k) {
            const Vec3 corner((k & 1 ? 1 : -1) * kHalfSide, (k & 2 ? 1 : -1) * kHalfSide, (k & 4 ? 1 : -1) * kHalfSide);
            run.height = std::max(run.height, (b.position + b.orientation * corner).y());
        }
        run.kinetic += 0.5 * kMass * b.velocity.squaredNorm() + 0.5 * inertia * b.angularVelocity.squaredNorm();
    }
    nearPairs(bodies, 2.0 * std::sqrt(3.0) * kHalfSide, [&](std::size_t i, std::size_t j) {
        if (const std::optional<Contact> c = boxBox(cubes[i], cubes[j])) run.deepest = std::max(run.deepest, c->depth);
    });
}

double settleTime(std::size_t n) {
    const std::vector<Vec3> at = heapPositions(n);
    double top = 0.0;
    for (const Vec3& p : at) top = std::max(top, p.y());
    return std::sqrt(2.0 * top / 9.81) + 3.0;
}

namespace {

class OurHeap final : public HeapSim {
public:
    OurHeap(HeapShape shape, std::size_t n, int threads, int interpenetration) {
        e_.setThreads(threads);
        StageSet stages{Stage::ConstantAcceleration, Stage::Integration, Stage::CollisionDetection,
                        Stage::Interpenetration, Stage::CollisionImpulses, Stage::Friction};
        if (shape == HeapShape::Boxes) stages.insert(Stage::Rotation);
        e_.setRequiredStages(stages);
        e_.setTimeStep(kTimeStep);
        e_.setContactIterations(kIterations);
        e_.setInterpenetrationIterations(interpenetration);
        e_.add(plane("ground", Vec3::UnitY()).rough(kFriction, kFriction));
        const std::vector<Vec3> at = heapPositions(n);
        const std::vector<Quat> turn = heapOrientations(n);
        for (std::size_t i = 0; i < n; ++i) {
            const std::string name = "body" + std::to_string(i);
            Body b = shape == HeapShape::Spheres ? sphere(name, kRadius, kMass)
                                                 : box(name, Vec3::Constant(kHalfSide), kMass).rotated(turn[i]);
            e_.add(b.at(at[i]).bouncy(0.0).rough(kFriction, kFriction));
        }
    }
    void step() override { e_.step(); }
    double contactPoints() const override {
        double count = 0.0;
        for (const Contact& c : e_.contacts()) count += c.pointCount;
        return count;
    }
    std::vector<HeapBody> state() const override {
        std::vector<HeapBody> bodies;
        for (const Body& b : e_.bodies()) {
            if (!b.isStatic()) bodies.push_back({b.position, b.orientation, b.velocity, b.angularVelocity});
        }
        return bodies;
    }
    std::pair<double, double> pairFriction() const override {
        double ground = std::nan(""), between = std::nan("");
        for (const Contact& c : e_.contacts()) {
            (e_.bodies()[c.a].isStatic() || e_.bodies()[c.b].isStatic() ? ground : between) = c.friction;
        }
        return {ground, between};
    }

private:
    PhysicsEngine e_;
};

}  // namespace

std::unique_ptr<HeapSim> ourHeap(HeapShape shape, std::size_t n, int threads, int interpenetration) {
    return std::make_unique<OurHeap>(shape, n, threads, interpenetration);
}

}  // namespace gpl::bench
