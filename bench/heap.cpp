// The heap of `./lab bench engine` in this engine, and what both engines share: the lattice, the
// statistics of step times and the quality of the settled heap.
#include "heap.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <unordered_map>

#include "gpl/body.h"
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

void timeSteps(double seconds, const std::function<void()>& step, const std::function<double()>& contacts,
               HeapRun& run) {
    const auto steps = static_cast<std::size_t>(std::ceil(seconds / kTimeStep));
    std::vector<double> stepMs;
    stepMs.reserve(steps);
    double total = 0.0;
    for (std::size_t s = 0; s < steps; ++s) {
        const auto start = std::chrono::steady_clock::now();
        step();
        stepMs.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
        total += contacts();
    }
    run.contactsPerStep = steps ? total / static_cast<double>(steps) : 0.0;
    run.steps = stepMs.size();
    if (stepMs.empty()) return;
    std::sort(stepMs.begin(), stepMs.end());
    run.medianMs = stepMs[stepMs.size() / 2];
    run.p90Ms = stepMs[std::min(stepMs.size() - 1, stepMs.size() * 9 / 10)];
}

void measureQuality(const std::vector<Vec3>& positions, const std::vector<Vec3>& velocities, HeapRun& run) {
    run.deepest = 0.0;
    run.height = 0.0;
    run.kinetic = 0.0;
    // A grid of cells one diameter wide: overlapping spheres are in the same or neighbouring cells.
    const double cell = 2.0 * kRadius;
    const auto key = [](long x, long y, long z) { return (x * 73856093) ^ (y * 19349663) ^ (z * 83492791); };
    std::unordered_multimap<long, std::size_t> grid;
    grid.reserve(positions.size());
    for (std::size_t i = 0; i < positions.size(); ++i) {
        const Vec3& p = positions[i];
        grid.emplace(key(std::lround(std::floor(p.x() / cell)), std::lround(std::floor(p.y() / cell)),
                         std::lround(std::floor(p.z() / cell))),
                     i);
        run.deepest = std::max(run.deepest, kRadius - p.y());
        run.height = std::max(run.height, p.y() + kRadius);
        run.kinetic += 0.5 * kMass * velocities[i].squaredNorm();
    }
    for (std::size_t i = 0; i < positions.size(); ++i) {
        const Vec3& p = positions[i];
        const long cx = std::lround(std::floor(p.x() / cell)), cy = std::lround(std::floor(p.y() / cell)),
                   cz = std::lround(std::floor(p.z() / cell));
        for (long dx = -1; dx <= 1; ++dx) {
            for (long dy = -1; dy <= 1; ++dy) {
                for (long dz = -1; dz <= 1; ++dz) {
                    const auto [first, last] = grid.equal_range(key(cx + dx, cy + dy, cz + dz));
                    for (auto it = first; it != last; ++it) {
                        if (it->second <= i) continue;
                        const double d = (positions[it->second] - p).norm();
                        run.deepest = std::max(run.deepest, 2.0 * kRadius - d);
                    }
                }
            }
        }
    }
}

double settleTime(std::size_t n) {
    const std::vector<Vec3> at = heapPositions(n);
    double top = 0.0;
    for (const Vec3& p : at) top = std::max(top, p.y());
    return std::sqrt(2.0 * top / 9.81) + 3.0;
}

HeapRun runOurs(std::size_t n, double seconds, int threads) {
    PhysicsEngine e;
    e.setThreads(threads);
    e.setRequiredStages({Stage::ConstantAcceleration, Stage::Integration, Stage::CollisionDetection,
                         Stage::Interpenetration, Stage::CollisionImpulses});
    e.setTimeStep(kTimeStep);
    e.setContactIterations(kIterations);
    e.add(plane("ground", Vec3::UnitY()));
    std::size_t i = 0;
    for (const Vec3& p : heapPositions(n)) {
        e.add(sphere("sphere" + std::to_string(i++), kRadius, kMass).at(p).bouncy(0.0));
    }
    HeapRun run;
    run.engine = "ours";
    run.bodies = n;
    timeSteps(seconds, [&e] { e.step(); }, [&e] { return static_cast<double>(e.contacts().size()); }, run);
    std::vector<Vec3> x, v;
    for (const Body& b : e.bodies()) {
        if (b.shape != Shape::Sphere) continue;
        x.push_back(b.position);
        v.push_back(b.velocity);
    }
    measureQuality(x, v, run);
    return run;
}

}  // namespace gpl::bench
