#include "cloth_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>

#include "report.h"

namespace gpl::study {

namespace {

using Clock = std::chrono::steady_clock;

double nsSince(Clock::time_point begin) {
    return std::chrono::duration<double, std::nano>(Clock::now() - begin).count();
}

void applyMethod(ClothSpec& spec, const ClothMethod& m) {
    spec.method = m.method;
    spec.stiffness = m.stiffness;
    const double alpha = m.method == SoftMethod::XPBD ? m.compliance : 0.0;
    spec.stretchCompliance = alpha;
    spec.shearCompliance = spec.bendCompliance = kShearBendSofter * alpha;
}

// The cloth's stretch links (each of the study's runs steps one cloth).
std::vector<DistanceLink> stretchLinks(const SoftBodies& soft) {
    std::vector<DistanceLink> out;
    for (const DistanceLink& l : soft.links) {
        if (l.kind == LinkKind::Stretch) out.push_back(l);
    }
    return out;
}

const Vec3 kGravity(0.0, -9.81, 0.0);
const double kPi = std::acos(-1.0);

// One step of the soft bodies, the four parts in the engine's order.
void step(SoftBodies& soft, const std::vector<Body>& bodies, double h, int iterations, const Vec3& g, double time) {
    soft.predict(h, g, time);
    soft.findContacts(bodies, h);
    soft.project(h, iterations, bodies);
    soft.updateVelocities(h);
}

}  // namespace

std::vector<ClothMethod> clothMethods() {
    return {{"PBD k=1", SoftMethod::PBD, 1.0, 0.0},
            {"PBD k=0.5", SoftMethod::PBD, 0.5, 0.0},
            {"XPBD a=0", SoftMethod::XPBD, 1.0, 0.0},
            {"XPBD a=" + sci(kSoftCompliance, 0), SoftMethod::XPBD, 1.0, kSoftCompliance}};
}

ClothSpec hangingClothSpec(int n, double side, double mass, const ClothMethod& m) {
    ClothSpec spec;
    spec.name = "hanging";
    spec.nx = spec.ny = n;
    spec.spacing = side / (n - 1);
    spec.origin = Vec3::Zero();
    spec.u = Vec3::UnitX();
    spec.v = -Vec3::UnitY();
    spec.mass = mass;
    spec.radius = 0.25 * spec.spacing;
    applyMethod(spec, m);
    for (int i = 0; i < n; ++i) spec.pinned.push_back({i, 0});
    return spec;
}

ChainStretch chainStretch(int n, double side, double mass, double compliance, double g) {
    const double particle = mass / (static_cast<double>(n) * n);
    const double rest = side / (n - 1);
    // The vertical link below row j carries the n - 1 - j particles under it; the horizontal links
    // carry nothing, as every column hangs alike. Vertical and horizontal links are n (n - 1) each.
    ChainStretch out;
    out.largest = (n - 1) * particle * g * compliance / rest;
    out.mean = 0.5 * (0.5 * n * particle * g * compliance / rest);
    return out;
}

Settled settleHanging(const ClothSpec& spec, double h, int iterations, const SettleTimes& times) {
    SoftBodies soft;
    soft.addCloth(spec);
    const std::vector<DistanceLink> links = stretchLinks(soft);
    const std::vector<Body> none;
    const auto rampSteps = static_cast<long>(std::llround(times.ramp / h));
    const auto holdSteps = static_cast<long>(std::llround(times.hold / h));
    const auto averageSteps = std::max(1L, static_cast<long>(std::llround(times.average / h)));
    std::vector<double> sum(links.size(), 0.0), ms;
    ms.reserve(rampSteps + holdSteps + averageSteps);
    Settled out;
    const long total = rampSteps + holdSteps + averageSteps;
    for (long s = 0; s < total; ++s) {
        // Gravity's smooth ramp, (1 - cos(pi t / ramp)) / 2, starts and ends with zero slope.
        const double t = (s + 1) * h;
        const double load = t >= times.ramp ? 1.0 : 0.5 * (1.0 - std::cos(kPi * t / times.ramp));
        const auto begin = Clock::now();
        step(soft, none, h, iterations, load * kGravity, s * h);
        ms.push_back(nsSince(begin) * 1e-6);
        if (!soft.allFinite()) {
            out.finite = false;
            break;
        }
        if (s >= rampSteps + holdSteps) {
            for (std::size_t k = 0; k < links.size(); ++k) {
                sum[k] += ((soft.x[links[k].i] - soft.x[links[k].j]).norm() - links[k].rest) / links[k].rest;
            }
        }
    }
    out.msPerStep = median(ms);
    if (!out.finite) {
        out.largest = out.mean = std::numeric_limits<double>::infinity();
        return out;
    }
    double total_ = 0.0;
    out.largest = -std::numeric_limits<double>::infinity();
    for (double s : sum) {
        out.largest = std::max(out.largest, s / averageSteps);
        total_ += s / averageSteps;
    }
    out.mean = total_ / static_cast<double>(sum.size());
    return out;
}

StepCost measureStepCost(const ClothSpec& spec, double h, int iterations, int steps) {
    SoftBodies soft;
    soft.setThreads(1);  // each part's time is this thread's
    soft.addCloth(spec);
    const std::vector<Body> none;
    StepCost cost;
    cost.particles = static_cast<int>(soft.x.size());
    cost.links = static_cast<int>(soft.links.size());
    cost.iterations = iterations;
    std::vector<double> predict, contacts, project, velocities;
    const auto ns = [](double fromMs) { return (threadCpuMs() - fromMs) * 1e6; };
    for (int s = 0; s < steps; ++s) {
        double begin = threadCpuMs();
        soft.predict(h, kGravity, s * h);
        predict.push_back(ns(begin));
        begin = threadCpuMs();
        soft.findContacts(none, h);
        contacts.push_back(ns(begin));
        begin = threadCpuMs();
        soft.project(h, iterations, none);
        project.push_back(ns(begin));
        begin = threadCpuMs();
        soft.updateVelocities(h);
        velocities.push_back(ns(begin));
    }
    cost.predictNs = median(predict);
    cost.contactsNs = median(contacts);
    cost.projectNs = median(project);
    cost.velocitiesNs = median(velocities);
    return cost;
}

ClothSpec flagSpec(const Flag& flag, const ClothMethod& m) {
    ClothSpec spec;
    spec.name = "flag";
    spec.nx = flag.nx;
    spec.ny = flag.ny;
    spec.spacing = flag.spacing;
    // Hanging from a vertical pole along -y at x = 0, the cloth spanning +x: row 0 is the top.
    spec.origin = Vec3(0.0, 2.95, 0.0);
    spec.u = Vec3::UnitX();
    spec.v = -Vec3::UnitY();
    spec.mass = flag.mass;
    spec.method = m.method;
    spec.stiffness = m.stiffness;
    spec.stretchCompliance = m.method == SoftMethod::XPBD ? m.compliance : 0.0;
    spec.shearCompliance = flag.shearCompliance;
    spec.bendCompliance = flag.bendCompliance;
    spec.pinned = {{0, 0}, {0, flag.ny - 1}};
    return spec;
}

std::string flagUnstable(const Flag& flag, const ClothMethod& m, double h, int iterations, const Stability& s) {
    SoftBodies soft;
    soft.addCloth(flagSpec(flag, m));
    soft.setWind(flag.wind, flag.drag);
    const double diagonal = std::hypot(flag.nx - 1, flag.ny - 1) * flag.spacing;
    const double speedBound =
        s.speedBound > 0.0 ? s.speedBound : 10.0 * (flag.wind.norm() + std::sqrt(2.0 * 9.81 * diagonal));
    const std::vector<Body> none;
    const auto steps = static_cast<long>(std::ceil(s.seconds / h));
    for (long k = 0; k < steps; ++k) {
        step(soft, none, h, iterations, kGravity, k * h);
        if (!soft.allFinite()) return "not finite";
        for (const Vec3& v : soft.v) {
            if (!(v.norm() <= speedBound)) return "speed";
        }
        if (!(soft.largestStretch(0, LinkKind::Stretch) <= s.stretchBound)) return "stretch";
    }
    return "";
}

StableStep largestStableStep(const Flag& flag, const ClothMethod& m, int iterations, const Stability& s, double start,
                             double low, double high, double precision) {
    StableStep out;
    const auto stableAt = [&](double h) {
        const std::string why = flagUnstable(flag, m, h, iterations, s);
        if (!why.empty()) out.failure = why;
        return why.empty();
    };
    out.h = largestStable(start, low, high, precision, stableAt);
    return out;
}

ClothSpec sphereDropSpec(const SphereDrop& d) {
    ClothSpec spec;
    spec.name = "drop";
    spec.nx = spec.ny = d.n;
    spec.spacing = d.side / (d.n - 1);
    spec.origin = Vec3(-0.5 * d.side, d.sphereRadius + d.drop, -0.5 * d.side);
    spec.u = Vec3::UnitX();
    spec.v = Vec3::UnitZ();
    spec.mass = d.mass;
    spec.method = SoftMethod::XPBD;
    spec.stretchCompliance = spec.shearCompliance = spec.bendCompliance = 0.0;
    spec.radius = d.radius;
    return spec;
}

Body dropSphere(const SphereDrop& d) {
    return sphere("ball", d.sphereRadius, 1.0).makeStatic().rough(d.friction, d.friction);
}

double penetration(const std::vector<Vec3>& x, const SphereDrop& d) {
    double deepest = 0.0;
    for (const Vec3& p : x) deepest = std::max(deepest, d.sphereRadius + d.radius - p.norm());
    return deepest;
}

void linkStretch(const std::vector<Vec3>& x, const std::vector<DistanceLink>& links, double& largest, double& mean) {
    largest = 0.0;
    double sum = 0.0;
    for (const DistanceLink& l : links) {
        const double s = ((x[l.i] - x[l.j]).norm() - l.rest) / l.rest;
        largest = std::max(largest, s);
        sum += s;
    }
    mean = links.empty() ? 0.0 : sum / static_cast<double>(links.size());
}

double threadCpuMs() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

double processCpuMs() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

double median(std::vector<double> values) {
    if (values.empty()) return std::nan("");
    const auto mid = values.begin() + static_cast<long>(values.size() / 2);
    std::nth_element(values.begin(), mid, values.end());
    return *mid;
}

DropRun dropOnSphere(const SphereDrop& d) {
    SoftBodies soft;
    soft.setThreads(d.threads);
    soft.addCloth(sphereDropSpec(d));
    const std::vector<Body> bodies{dropSphere(d)};
    const std::vector<DistanceLink> links = stretchLinks(soft);
    const auto steps = static_cast<long>(std::llround(d.seconds / d.h));
    DropRun run;
    run.stepMs.reserve(steps);
    for (long s = 0; s < steps; ++s) {
        const double cpu = processCpuMs();
        const auto begin = Clock::now();
        step(soft, bodies, d.h, d.iterations, kGravity, s * d.h);
        run.stepMs.push_back(nsSince(begin) * 1e-6);
        run.cpuMs.push_back(processCpuMs() - cpu);
        run.deepest = std::max(run.deepest, penetration(soft.x, d));
    }
    run.finite = soft.allFinite();
    run.medianMs = median(run.stepMs);
    run.medianCpuMs = median(run.cpuMs);
    linkStretch(soft.x, links, run.largestStretch, run.meanStretch);
    return run;
}

double bareSweepsMs([[maybe_unused]] const SphereDrop& d, [[maybe_unused]] int repeats) {
#ifdef GPL_BARE_XPBD
    SoftBodies soft;
    soft.setThreads(1);
    soft.addCloth(sphereDropSpec(d));
    const std::vector<Body> bodies{dropSphere(d)};
    // The cloth draped over the sphere half way through the drop, and its next step's prediction.
    const auto steps = static_cast<long>(std::llround(0.5 * d.seconds / d.h));
    for (long s = 0; s < steps; ++s) step(soft, bodies, d.h, d.iterations, kGravity, s * d.h);
    soft.predict(d.h, kGravity, steps * d.h);
    std::vector<double> ms;
    for (int r = 0; r < repeats; ++r) {
        std::vector<Vec3> p = soft.p;
        std::vector<DistanceLink> links = soft.links;
        const auto begin = Clock::now();
        bareXpbdSweeps(p, soft.w, links, d.h, d.iterations);
        ms.push_back(nsSince(begin) * 1e-6);
    }
    return median(ms);
#else
    return 0.0;
#endif
}

}  // namespace gpl::study
