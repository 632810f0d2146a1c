#include "study.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "gpl/forces.h"
#include "gpl/hooks.h"

namespace gpl::study {
namespace {

constexpr double kG = 9.81;  // m/s^2

double norm2(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) sum += (a[i] - b[i]).squaredNorm();
    return sum;
}

std::vector<std::size_t> doublings(std::size_t first, std::size_t last) {
    std::vector<std::size_t> out;
    for (std::size_t n = first; n <= last; n *= 2) out.push_back(n);
    return out;
}

bool finiteState(const ParticleState& s) {
    for (std::size_t i = 0; i < s.x.size(); ++i) {
        if (!isFinite(s.x[i]) || !isFinite(s.v[i])) return false;
    }
    return true;
}

}  // namespace

Problem freeFall() {
    Problem p;
    p.id = "free-fall";
    p.title = "free fall (thrown ball, 2 s)";
    p.unit = "m";
    p.x0 = {Vec3(0.0, 10.0, 0.0)};
    p.v0 = {Vec3(3.0, 4.0, 0.0)};
    p.endTime = 2.0;
    const Vec3 g(0.0, -kG, 0.0);
    p.exactX = {p.x0[0] + p.v0[0] * p.endTime + 0.5 * g * p.endTime * p.endTime};
    p.exactV = {p.v0[0] + g * p.endTime};
    p.scale = 10.0;
    p.steps = doublings(8, 4096);
    p.accel = [g](const std::vector<Vec3>& x, const std::vector<Vec3>&, std::vector<Vec3>& a) {
        a.assign(x.size(), g);
    };
    p.energy = [g](const std::vector<Vec3>& x, const std::vector<Vec3>& v) {
        return 0.5 * v[0].squaredNorm() - g.dot(x[0]);
    };
    return p;
}

Problem oscillator(double omega) {
    Problem p;
    p.id = "oscillator";
    p.title = "harmonic oscillator (1.3 periods)";
    p.unit = "m";
    p.x0 = {Vec3(1.0, 0.0, 0.0)};
    p.v0 = {Vec3::Zero()};
    p.endTime = 1.3 * 2.0 * M_PI / omega;
    p.exactX = {Vec3(std::cos(omega * p.endTime), 0.0, 0.0)};
    p.exactV = {Vec3(-omega * std::sin(omega * p.endTime), 0.0, 0.0)};
    p.omega = omega;
    p.timeScale = 1.0 / omega;
    p.scale = 1.0;
    p.steps = doublings(16, 16384);
    const double w2 = omega * omega;
    p.accel = [w2](const std::vector<Vec3>& x, const std::vector<Vec3>&, std::vector<Vec3>& a) {
        a.resize(x.size());
        for (std::size_t i = 0; i < x.size(); ++i) a[i] = -w2 * x[i];
    };
    p.energy = [w2](const std::vector<Vec3>& x, const std::vector<Vec3>& v) {
        return 0.5 * v[0].squaredNorm() + 0.5 * w2 * x[0].squaredNorm();
    };
    return p;
}

Problem pendulum(double amplitude) {
    const double length = 1.0;  // m
    const double w0 = std::sqrt(kG / length);
    Problem p;
    p.id = amplitude < 0.5 ? "pendulum-small" : "pendulum-large";
    p.title = "pendulum, " + formatNumber(amplitude) + " rad, from rest to the bottom";
    p.unit = "rad";
    p.x0 = {Vec3(amplitude, 0.0, 0.0)};
    p.v0 = {Vec3::Zero()};
    // A quarter of the exact period 4 K(k) / w0 with k = sin(amplitude / 2); at the bottom
    // theta = 0 and energy gives the angular velocity.
    p.endTime = std::comp_ellint_1(std::sin(0.5 * amplitude)) / w0;
    p.exactX = {Vec3::Zero()};
    p.exactV = {Vec3(-std::sqrt(2.0 * kG * (1.0 - std::cos(amplitude)) / length) / length, 0.0, 0.0)};
    p.omega = w0;
    p.timeScale = 1.0 / w0;
    p.scale = amplitude;
    p.steps = doublings(8, 8192);
    p.accel = [w0](const std::vector<Vec3>& x, const std::vector<Vec3>&, std::vector<Vec3>& a) {
        a.assign(x.size(), Vec3::Zero());
        for (std::size_t i = 0; i < x.size(); ++i) a[i].x() = -w0 * w0 * std::sin(x[i].x());
    };
    p.energy = [length](const std::vector<Vec3>& x, const std::vector<Vec3>& v) {
        return 0.5 * length * length * v[0].x() * v[0].x() + kG * length * (1.0 - std::cos(x[0].x()));
    };
    return p;
}

Problem kepler() {
    const double e = 0.6;
    Problem p;
    p.id = "kepler";
    p.title = "Kepler orbit, e = 0.6, perihelion to aphelion";
    p.unit = "m";
    // GM = 1, semi-major axis 1: perihelion 1 - e, speed there sqrt((1 + e) / (1 - e)).
    p.x0 = {Vec3(1.0 - e, 0.0, 0.0)};
    p.v0 = {Vec3(0.0, std::sqrt((1.0 + e) / (1.0 - e)), 0.0)};
    p.endTime = M_PI;
    p.exactX = {Vec3(-(1.0 + e), 0.0, 0.0)};
    p.exactV = {Vec3(0.0, -std::sqrt((1.0 - e) / (1.0 + e)), 0.0)};
    p.omega = p.v0[0].norm() / p.x0[0].norm();  // angular rate at perihelion
    p.scale = 1.0;
    p.steps = doublings(64, 32768);
    p.accel = [](const std::vector<Vec3>& x, const std::vector<Vec3>&, std::vector<Vec3>& a) {
        a.resize(x.size());
        for (std::size_t i = 0; i < x.size(); ++i) {
            const double r = x[i].norm();
            a[i] = -x[i] / (r * r * r);
        }
    };
    p.energy = [](const std::vector<Vec3>& x, const std::vector<Vec3>& v) {
        return 0.5 * v[0].squaredNorm() - 1.0 / x[0].norm();
    };
    return p;
}

namespace {
constexpr double kChainStiffness = 100.0;  // N/m
constexpr double kChainRest = 1.0;         // m

void checkMasses(const std::vector<double>& masses) {
    if (masses.empty()) throw std::invalid_argument("a spring chain needs at least one mass");
    for (std::size_t i = 0; i < masses.size(); ++i) {
        if (!std::isfinite(masses[i]) || masses[i] <= 0.0) {
            throw std::invalid_argument("spring chain: mass " + std::to_string(i) +
                                        " must be a positive finite number of kg, got " + formatNumber(masses[i]));
        }
    }
}
}  // namespace

Problem springChain(const std::vector<double>& masses) {
    checkMasses(masses);
    const std::size_t n = masses.size();
    Problem p;
    p.id = "spring-chain";
    p.title = "spring chain, " + std::to_string(n) + " masses";
    p.unit = "m";
    // Body i rests at x = i + 1 (anchor at 0); displaced by a tenth of a millimetre in a pattern
    // that excites every mode, at rest. So small that an unstable mode grows by 1e8 in energy
    // before the bodies could pass each other and the motion stop being linear.
    for (std::size_t i = 0; i < n; ++i) {
        const double sign = i % 2 == 0 ? 1.0 : -1.0;
        p.x0.push_back(Vec3(kChainRest * static_cast<double>(i + 1) + 1e-4 * sign * (1.0 + 0.3 * i), 0.0, 0.0));
        p.v0.push_back(Vec3::Zero());
    }
    p.omega = springChainOmegaMax(masses);
    p.timeScale = 1.0 / p.omega;
    p.accel = [masses](const std::vector<Vec3>& x, const std::vector<Vec3>& v, std::vector<Vec3>& a) {
        a.assign(x.size(), Vec3::Zero());
        for (std::size_t i = 0; i < x.size(); ++i) {
            const Vec3 left = i == 0 ? Vec3::Zero() : x[i - 1];
            const Vec3 leftV = i == 0 ? Vec3::Zero() : v[i - 1];
            const Vec3 f = springForce(x[i], left, v[i], leftV, kChainStiffness, kChainRest, 0.0);
            a[i] += f / masses[i];
            if (i > 0) a[i - 1] -= f / masses[i - 1];
        }
    };
    p.energy = [masses](const std::vector<Vec3>& x, const std::vector<Vec3>& v) {
        double e = 0.0;
        for (std::size_t i = 0; i < x.size(); ++i) {
            e += 0.5 * masses[i] * v[i].squaredNorm();
            e += springEnergy(x[i], i == 0 ? Vec3::Zero() : x[i - 1], kChainStiffness, kChainRest);
        }
        return e;
    };
    return p;
}

double springChainOmegaMax(const std::vector<double>& masses) {
    checkMasses(masses);
    const auto n = static_cast<Eigen::Index>(masses.size());
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
    Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n);
    for (Eigen::Index i = 0; i < n; ++i) {
        m(i, i) = masses[static_cast<std::size_t>(i)];
        k(i, i) += kChainStiffness;  // spring to the left neighbour (or the anchor)
        if (i > 0) {
            k(i - 1, i - 1) += kChainStiffness;
            k(i, i - 1) -= kChainStiffness;
            k(i - 1, i) -= kChainStiffness;
        }
    }
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(k, m);
    return std::sqrt(modes.eigenvalues().maxCoeff());
}

Run simulateWithStep(const Problem& p, Integrator method, double h, std::size_t steps, bool timed) {
    std::size_t evaluations = 0;
    const AccelerationFunction counted = [&](const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                                             std::vector<Vec3>& a) {
        ++evaluations;
        p.accel(x, v, a);
    };
    ParticleState s = startState(p.x0, p.v0, counted);
    checkStep(s, h);
    Run run;
    run.steps = steps;
    run.h = h;
    const double e0 = p.energy(s.x, s.v);
    const double energyScale = e0 != 0.0 ? std::abs(e0) : 1.0;
    const std::size_t startEvaluations = evaluations;
    std::size_t done = 0;
    for (; done < steps; ++done) {
        integrate(method, s, counted, h);
        if (!finiteState(s)) {
            run.finite = false;
            break;
        }
        const double de = (p.energy(s.x, s.v) - e0) / energyScale;
        run.energyMax = std::max(run.energyMax, std::abs(de));
        run.energyDrift = de;
    }
    run.evaluationsPerStep =
        static_cast<double>(evaluations - startEvaluations) / static_cast<double>(std::max<std::size_t>(done, 1));
    const double inf = std::numeric_limits<double>::infinity();
    if (!run.finite) {
        run.error = run.energyMax = run.energyDrift = inf;
    } else if (std::abs(static_cast<double>(steps) * h - p.endTime) <= 1e-9 * p.endTime && !p.exactX.empty()) {
        const double tau = p.timeScale;
        run.error = std::sqrt(norm2(s.x, p.exactX) + tau * tau * norm2(s.v, p.exactV));
    } else {
        run.error = std::numeric_limits<double>::quiet_NaN();
    }
    if (timed && run.finite) {
        // The same run without energy bookkeeping, repeated for at least 0.5 ms; the best of five
        // such rounds, so that other work on the machine does not count against a method.
        using Clock = std::chrono::steady_clock;
        double best = std::numeric_limits<double>::infinity();
        for (int round = 0; round < 5; ++round) {
            const auto begin = Clock::now();
            std::size_t reps = 0;
            double seconds = 0.0;
            do {
                ParticleState t = startState(p.x0, p.v0, p.accel);
                for (std::size_t i = 0; i < steps; ++i) integrate(method, t, p.accel, h);
                ++reps;
                seconds = std::chrono::duration<double>(Clock::now() - begin).count();
            } while (seconds < 5e-4);
            best = std::min(best, seconds / static_cast<double>(reps * steps));
        }
        run.secondsPerStep = best;
    }
    return run;
}

Run simulate(const Problem& p, Integrator method, std::size_t steps, bool timed) {
    if (steps == 0) throw std::invalid_argument("the number of steps must be at least 1");
    return simulateWithStep(p, method, p.endTime / static_cast<double>(steps), steps, timed);
}

std::string hookOf(Integrator method) {
    switch (method) {
        case Integrator::PositionVerlet:
            return "positionVerlet()";
        case Integrator::VelocityVerlet:
            return "velocityVerlet()";
        case Integrator::ExplicitEuler:
        case Integrator::SemiImplicitEuler:
        case Integrator::RungeKutta4:
            return "";
    }
    return "";
}

std::vector<Integrator> openIntegrators() {
    const Problem p = oscillator(1.0);
    for (Integrator m : kIntegrators) {
        ParticleState s = startState(p.x0, p.v0, p.accel);
        try {
            integrate(m, s, p.accel, 0.01);
        } catch (const std::exception&) {
            // Written but broken: the study says so when it runs the method.
        }
    }
    const std::vector<std::string> stubs = kernelsNotImplemented();
    std::vector<Integrator> open;
    for (Integrator m : kIntegrators) {
        if (!hookOf(m).empty() && std::find(stubs.begin(), stubs.end(), hookOf(m)) != stubs.end()) open.push_back(m);
    }
    return open;
}

std::vector<double> energyHistory(const Problem& p, Integrator method, double h, std::size_t steps) {
    ParticleState s = startState(p.x0, p.v0, p.accel);
    checkStep(s, h);
    const double e0 = p.energy(s.x, s.v);
    std::vector<double> out;
    out.reserve(steps);
    for (std::size_t i = 0; i < steps; ++i) {
        integrate(method, s, p.accel, h);
        out.push_back((p.energy(s.x, s.v) - e0) / std::abs(e0));
    }
    return out;
}

Order measuredOrder(const Problem& p, const std::vector<Run>& sweep) {
    std::vector<const Run*> window;
    for (const Run& r : sweep) {
        // Below 1e-2 of the scale the leading error term dominates; above 100 N eps of the scale
        // the rounding accumulated over N steps is under 1 % of the error.
        const double floor = 100.0 * std::numeric_limits<double>::epsilon() * static_cast<double>(r.steps) * p.scale;
        if (r.finite && r.error < 1e-2 * p.scale && r.error > floor) window.push_back(&r);
    }
    std::sort(window.begin(), window.end(), [](const Run* a, const Run* b) { return a->h < b->h; });
    if (window.size() > 4) window.resize(4);  // the four finest: the most asymptotic
    Order order;
    if (window.size() < 3) return order;
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (const Run* r : window) {
        const double x = std::log(r->h), y = std::log(r->error);
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    const double n = static_cast<double>(window.size());
    order.slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    order.points = window.size();
    return order;
}

bool boundedRun(const Problem& p, Integrator method, double h, std::size_t steps) {
    ParticleState s = startState(p.x0, p.v0, p.accel);
    checkStep(s, h);
    const double e0 = p.energy(s.x, s.v);
    double firstHalf = e0, secondHalf = 0.0;
    for (std::size_t i = 0; i < steps; ++i) {
        integrate(method, s, p.accel, h);
        if (!finiteState(s)) return false;
        double& half = i < steps / 2 ? firstHalf : secondHalf;
        half = std::max(half, p.energy(s.x, s.v));
    }
    // Growth within the run, or growth far beyond what a bounded orbit shows: a stable method's
    // energy (with its own velocities) stays within a factor 1/(1 - (h omega / 2)^2) of E0, which
    // is 1e4 only within 5e-5 of the limit.
    return secondHalf <= 1.01 * firstHalf && std::max(firstHalf, secondHalf) <= 1e4 * e0;
}

double stabilityLimit(const Problem& p, Integrator method, double minHOmega) {
    // At least 4000 steps and 20 periods of the fastest mode: at h*omega = 1e-3 explicit Euler's
    // energy grows by exp(10 * 2 pi * h omega) - 1 = 6.5 % over the second half, well above 1 %.
    const auto stable = [&](double hOmega) {
        const double h = hOmega / p.omega;
        const auto steps = static_cast<std::size_t>(std::max(4000.0, std::ceil(20.0 * 2.0 * M_PI / hOmega)));
        return boundedRun(p, method, h, steps);
    };
    if (!stable(minHOmega)) return 0.0;
    double lo = minHOmega, hi = 0.0;
    for (double hOmega = 0.05; hOmega <= 4.0 + 1e-12; hOmega += 0.05) {
        if (!stable(hOmega)) {
            hi = hOmega;
            break;
        }
        lo = hOmega;
    }
    if (hi == 0.0) return lo;  // stable everywhere tried
    while (hi - lo > 1e-6 * hi) {
        const double mid = 0.5 * (lo + hi);
        (stable(mid) ? lo : hi) = mid;
    }
    return lo;
}

double theoreticalStabilityLimit(Integrator method) {
    switch (method) {
        case Integrator::ExplicitEuler:
            return 0.0;
        case Integrator::SemiImplicitEuler:
        case Integrator::PositionVerlet:
        case Integrator::VelocityVerlet:
            return 2.0;
        case Integrator::RungeKutta4:
            return 2.0 * std::sqrt(2.0);
    }
    return 0.0;
}

namespace {
template <class Real>
double offsetErrorIn(Real offset) {
    using V = Eigen::Matrix<Real, 3, 1>;
    const Real omega = Real(2.0 * M_PI);
    const Real h = Real(1e-3);
    const V centre(offset, Real(0), Real(0));
    V x = centre + V(Real(1), Real(0), Real(0));
    V v = V::Zero();
    V a = -omega * omega * (x - centre);
    double worst = 0.0;
    for (int i = 1; i <= 1000; ++i) {  // one period
        x += h * v + Real(0.5) * h * h * a;
        v += Real(0.5) * h * a;
        a = -omega * omega * (x - centre);
        v += Real(0.5) * h * a;
        // Exact: centre + cos(omega t); compared in double, relative to the centre.
        const double displacement = static_cast<double>(x.x()) - static_cast<double>(centre.x());
        worst = std::max(worst, std::abs(displacement - std::cos(2.0 * M_PI * 1e-3 * i)));
    }
    return worst;
}
}  // namespace

double offsetError(double offset, bool singlePrecision) {
    return singlePrecision ? offsetErrorIn<float>(static_cast<float>(offset)) : offsetErrorIn<double>(offset);
}

}  // namespace gpl::study
