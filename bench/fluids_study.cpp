#include "fluids_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>

#include "gpl/engine.h"
#include "gpl/fluid_experiments.h"
#include "gpl/scenes.h"
#include "report.h"

namespace gpl::study {

namespace {

const Vec3 kGravity(0.0, -9.81, 0.0);

void fillColumn(FluidTank& tank, const Column& column) {
    fillBlock(tank, studyWater(column.spacing), column.nx, column.ny, column.nz, 0.6 / column.height());
}

}  // namespace

const char* methodName(FluidMethod method) { return method == FluidMethod::PBF ? "PBF" : "WCSPH"; }

FluidParameters studyWater(double spacing) {
    FluidParameters f;
    f.restDensity = 1000.0;
    f.spacing = spacing;
    f.smoothingLength = kSmoothingRatio * spacing;
    return f;
}

void fillBlock(FluidTank& tank, const FluidParameters& water, int nx, int ny, int nz, double headroom) {
    const double s = water.spacing;
    const Vec3 block(nx * s, ny * s, nz * s);
    const FluidBox inside{Vec3::Zero(), Vec3(block.x(), headroom * block.y(), block.z())};
    tank.fluid.clear();
    tank.fluid.setParameters(water);
    tank.fluid.setThreads(1);  // the study's times are the thread's CPU time
    tank.fluid.setContainer(inside);
    tank.fluid.addBlock(Vec3::Zero(), block);
    tank.walls = tankWalls(inside);
}

void step(FluidTank& tank, FluidMethod method, double h, int substeps) {
    Fluids& f = tank.fluid;
    if (method == FluidMethod::PBF) {
        f.predict(h, kGravity);
        f.findNeighbours();
        f.project(tank.walls);
        f.updateVelocities(h);
    } else {
        f.stepSph(h, kGravity, tank.walls, substeps);
    }
}

// ---- 1. PBF's density error ----------------------------------------------------------------------

DensityError pbfColumnError(const Column& column, int iterations, double h, double seconds, double average) {
    FluidTank tank;
    fillColumn(tank, column);
    FluidParameters water = tank.fluid.parameters();
    water.iterations = iterations;
    tank.fluid.setParameters(water);
    const auto steps = static_cast<long>(std::llround(seconds / h));
    const auto averaged = std::max(1L, std::min(steps, static_cast<long>(std::llround(average / h))));
    DensityError out;
    std::vector<double> ns;
    for (long s = 0; s < steps; ++s) {
        const double begin = threadCpuNs();
        step(tank, FluidMethod::PBF, h);
        ns.push_back(threadCpuNs() - begin);
        if (tank.fluid.firstNonFinite() < tank.fluid.size()) {
            out.finite = false;
            break;
        }
        if (s >= steps - averaged) {
            tank.fluid.measureDensities();
            out.mean += tank.fluid.densityError() / static_cast<double>(averaged);
            out.largest += tank.fluid.largestDensityError() / static_cast<double>(averaged);
        }
    }
    out.msPerStep = median(ns) * 1e-6;
    if (!out.finite) out.mean = out.largest = std::numeric_limits<double>::infinity();
    return out;
}

// ---- 2. WCSPH's largest stable step --------------------------------------------------------------

std::string sphColumnUnstable(const Column& column, double soundSpeed, double h, double seconds) {
    FluidTank tank;
    fillColumn(tank, column);
    FluidParameters water = tank.fluid.parameters();
    water.soundSpeed = soundSpeed;
    tank.fluid.setParameters(water);
    // Ten times a fall of the column's height: the column's first settling stays far below it, and a
    // step that blows up passes it within a few steps.
    const double fastest = 10.0 * std::sqrt(2.0 * 9.81 * column.height());
    const auto steps = static_cast<long>(std::ceil(seconds / h));
    for (long s = 0; s < steps; ++s) {
        step(tank, FluidMethod::WCSPH, h, 1);
        if (tank.fluid.firstNonFinite() < tank.fluid.size()) return "not finite";
        for (const Vec3& v : tank.fluid.v) {
            if (!(v.norm() <= fastest)) return "speed";
        }
    }
    return "";
}

StableStep largestStableSphStep(const Column& column, double soundSpeed, double start, double low, double precision,
                                double seconds) {
    StableStep out;
    const auto stableAt = [&](double h) {
        ++out.runs;
        const std::string why = sphColumnUnstable(column, soundSpeed, h, seconds);
        if (!why.empty()) out.failure = why;
        return why.empty();
    };
    out.h = largestStable(start, low, std::numeric_limits<double>::infinity(), precision, stableAt);
    return out;
}

double cflBound(double smoothingLength, double soundSpeed) { return kCourant * smoothingLength / soundSpeed; }

// ---- 3 and 4. Cost ---------------------------------------------------------------------------------

double bareNeighbourSum(const ParticleGrid& grid, const std::vector<Vec3>& x, double mass, double h,
                        std::vector<double>& density) {
    const double h2 = h * h;
    const double scale = mass * 315.0 / (64.0 * 3.14159265358979323846 * std::pow(h, 9));
    density.resize(x.size());
    double total = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        double sum = h2 * h2 * h2;  // the particle itself, r = 0
        const std::uint32_t first = grid.start(i), last = first + grid.count(i);
        for (std::uint32_t k = first; k < last; ++k) {
            const double q = h2 - (x[i] - x[grid.list()[k]]).squaredNorm();
            sum += q * q * q;
        }
        density[i] = scale * sum;
        total += density[i];
    }
    return total;
}

FluidCost measureCost(int n, int iterations, double pbfStep, int warmup, int steps, int threads) {
    FluidCost cost;
    FluidParameters water = studyWater();
    water.iterations = iterations;
    FluidTank pbf, sph;
    fillBlock(pbf, water, n, n, n);
    fillBlock(sph, water, n, n, n);
    pbf.fluid.setThreads(threads);
    sph.fluid.setThreads(threads);
    cost.particles = static_cast<int>(pbf.fluid.size());
    cost.iterations = iterations;
    const double dt = cflBound(water.smoothingLength, water.soundSpeed);
    cost.sphSubsteps = sph.fluid.sphSubsteps(pbfStep);
    std::vector<double> predict, neighbours, project, velocities, substep, search, bare, barePbf;
    ParticleGrid grid;
    std::vector<double> density, lambda;
    std::vector<Vec3> moved;
    volatile double sink = 0.0;  // the bare loop's result, kept so that the loop is not optimised away
    const auto timed = [](std::vector<double>& into, bool keep, const auto& run) {
        const double begin = threadCpuNs();
        run();
        if (keep) into.push_back(threadCpuNs() - begin);
    };
    const auto wallNs = [] {
        return static_cast<double>(
            std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
                .count());
    };
    // The fluids' stages: on two threads by the wall clock.
    const auto stage = [&](std::vector<double>& into, bool keep, const auto& run) {
        if (threads < 2) return timed(into, keep, run);
        const double begin = wallNs();
        run();
        if (keep) into.push_back(wallNs() - begin);
    };
    Fluids& f = pbf.fluid;
    for (int s = 0; s < warmup + steps; ++s) {
        const bool keep = s >= warmup;
        // The four PBF stages, then one WCSPH substep, then the search and the bare loop over the
        // PBF fluid's positions: taking turns, so that a busy moment of the machine falls on all.
        stage(predict, keep, [&] { f.predict(pbfStep, kGravity); });
        stage(neighbours, keep, [&] { f.findNeighbours(); });
        stage(project, keep, [&] { f.project(pbf.walls); });
        stage(velocities, keep, [&] { f.updateVelocities(pbfStep); });
        stage(substep, keep, [&] { sph.fluid.stepSph(dt, kGravity, sph.walls, 1); });
        timed(search, keep, [&] { grid.find(f.x, water.smoothingLength); });
        timed(bare, keep, [&] { sink = sink + bareNeighbourSum(grid, f.x, f.mass(), water.smoothingLength, density); });
#ifdef GPL_BARE_PBF
        timed(barePbf, keep, [&] {
            sink = sink + barePbfIteration(grid, f.x, f.mass(), water.restDensity, water.smoothingLength, f.epsilon(),
                                           f.tensile(), lambda, moved);
        });
#endif
    }
    cost.neighbours = static_cast<double>(grid.total()) / cost.particles;
    cost.pbfPredictNs = median(predict);
    cost.pbfNeighboursNs = median(neighbours);
    cost.pbfProjectNs = median(project);
    cost.pbfVelocitiesNs = median(velocities);
    cost.sphSubstepNs = median(substep);
    cost.searchNs = median(search);
    cost.bareNs = median(bare);
    if (!barePbf.empty()) cost.barePbfNs = median(barePbf);
    return cost;
}

// ---- 5. The dam break -------------------------------------------------------------------------------

FrontRun damBreakFront(const std::string& scene, double Tend) {
    PhysicsEngine e;
    load(e, scenes().find(scene));
    const double a = kDamBreakWidth;
    const double scale = std::sqrt(2.0 * 9.81 / a);  // T per second
    FrontRun run;
    run.T.push_back(0.0);
    run.Z.push_back(surgeFront(e.fluids()) / a);
    while (run.T.back() < Tend) {
        e.step();
        if (e.fluids().firstNonFinite() < e.fluids().size()) {
            run.finite = false;
            break;
        }
        run.T.push_back(e.time() * scale);
        run.Z.push_back(surgeFront(e.fluids()) / a);
    }
    for (const FrontPoint& m : kMartinMoyce) {
        double z = std::nan("");
        for (std::size_t k = 1; k < run.T.size(); ++k) {
            if (run.T[k] >= m.T) {
                z = run.Z[k - 1] + (run.Z[k] - run.Z[k - 1]) * (m.T - run.T[k - 1]) / (run.T[k] - run.T[k - 1]);
                break;
            }
        }
        run.atMeasured.push_back(z);
    }
    return run;
}

// ---- Helpers ---------------------------------------------------------------------------------------

double logLogSlope(const std::vector<double>& x, const std::vector<double>& y) {
    double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (std::size_t k = 0; k < x.size() && k < y.size(); ++k) {
        const double u = std::log(x[k]), w = std::log(y[k]);
        n += 1;
        sx += u;
        sy += w;
        sxx += u * u;
        sxy += u * w;
    }
    if (n < 2) return std::nan("");
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

double median(std::vector<double> values) {
    if (values.empty()) return std::nan("");
    const auto mid = values.begin() + static_cast<long>(values.size() / 2);
    std::nth_element(values.begin(), mid, values.end());
    return *mid;
}

double threadCpuNs() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) * 1e9 + static_cast<double>(t.tv_nsec);
}

}  // namespace gpl::study
