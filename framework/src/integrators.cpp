#include "gpl/integrators.h"

#include <cmath>
#include <stdexcept>

namespace gpl {
namespace {

struct IntegratorInfo {
    Integrator method;
    const char* id;
    const char* name;
    int order;
};

constexpr IntegratorInfo kInfo[] = {
    {Integrator::ExplicitEuler, "explicit-euler", "explicit Euler", 1},
    {Integrator::SemiImplicitEuler, "semi-implicit-euler", "semi-implicit Euler", 1},
    {Integrator::PositionVerlet, "position-verlet", "position Verlet", 2},
    {Integrator::VelocityVerlet, "velocity-verlet", "velocity Verlet", 2},
    {Integrator::RungeKutta4, "rk4", "RK4", 4},
};

const IntegratorInfo& info(Integrator method) {
    for (const IntegratorInfo& i : kInfo) {
        if (i.method == method) return i;
    }
    throw std::invalid_argument("unknown integrator");
}

}  // namespace

const char* integratorName(Integrator method) { return info(method).name; }
const char* integratorId(Integrator method) { return info(method).id; }
int theoreticalOrder(Integrator method) { return info(method).order; }

Integrator integratorFromId(const std::string& id) {
    std::string known;
    for (const IntegratorInfo& i : kInfo) {
        if (id == i.id || id == i.name) return i.method;
        known += known.empty() ? "" : ", ";
        known += i.id;
    }
    throw std::invalid_argument("unknown integrator '" + id + "'; known: " + known);
}

ParticleState startState(std::vector<Vec3> x, std::vector<Vec3> v, const AccelerationFunction& accel) {
    ParticleState s;
    s.x = std::move(x);
    s.v = std::move(v);
    accel(s.x, s.v, s.a);
    return s;
}

void checkStep(const ParticleState& s, double h) {
    if (!std::isfinite(h) || h <= 0.0) {
        throw std::invalid_argument("time step must be a positive finite number of seconds, got " + formatNumber(h));
    }
    if (s.v.size() != s.x.size() || s.a.size() != s.x.size()) {
        throw std::invalid_argument("state has " + std::to_string(s.x.size()) + " positions but " +
                                    std::to_string(s.v.size()) + " velocities and " + std::to_string(s.a.size()) +
                                    " accelerations");
    }
    for (std::size_t i = 0; i < s.x.size(); ++i) {
        const char* what = !isFinite(s.x[i]) ? "position" : !isFinite(s.v[i]) ? "velocity" : "acceleration";
        if (!isFinite(s.x[i]) || !isFinite(s.v[i]) || !isFinite(s.a[i])) {
            throw std::invalid_argument(std::string("particle ") + std::to_string(i) + ": " + what +
                                        " is not finite before the step");
        }
    }
}

void explicitEuler(ParticleState& s, const AccelerationFunction& accel, double h) {
    for (std::size_t i = 0; i < s.x.size(); ++i) {
        s.x[i] += h * s.v[i];
        s.v[i] += h * s.a[i];
    }
    accel(s.x, s.v, s.a);
}

void semiImplicitEuler(ParticleState& s, const AccelerationFunction& accel, double h) {
    for (std::size_t i = 0; i < s.x.size(); ++i) {
        s.v[i] += h * s.a[i];
        s.x[i] += h * s.v[i];
    }
    accel(s.x, s.v, s.a);
}

void rungeKutta4(ParticleState& s, const AccelerationFunction& accel, double h) {
    // Scratch kept between calls so that a step does not allocate (wall time is measured).
    thread_local std::vector<Vec3> x2, v2, a2, x3, v3, a3, x4, v4, a4;
    const std::size_t n = s.x.size();
    for (auto* w : {&x2, &v2, &x3, &v3, &x4, &v4}) w->resize(n);
    // Stage derivatives of (x, v): k1 = (v, a), k2 = (v2, a2), k3 = (v3, a3), k4 = (v4, a4).
    for (std::size_t i = 0; i < n; ++i) {
        x2[i] = s.x[i] + 0.5 * h * s.v[i];
        v2[i] = s.v[i] + 0.5 * h * s.a[i];
    }
    accel(x2, v2, a2);
    for (std::size_t i = 0; i < n; ++i) {
        x3[i] = s.x[i] + 0.5 * h * v2[i];
        v3[i] = s.v[i] + 0.5 * h * a2[i];
    }
    accel(x3, v3, a3);
    for (std::size_t i = 0; i < n; ++i) {
        x4[i] = s.x[i] + h * v3[i];
        v4[i] = s.v[i] + h * a3[i];
    }
    accel(x4, v4, a4);
    for (std::size_t i = 0; i < n; ++i) {
        s.x[i] += h / 6.0 * (s.v[i] + 2.0 * v2[i] + 2.0 * v3[i] + v4[i]);
        s.v[i] += h / 6.0 * (s.a[i] + 2.0 * a2[i] + 2.0 * a3[i] + a4[i]);
    }
    accel(s.x, s.v, s.a);
}

void integrate(Integrator method, ParticleState& s, const AccelerationFunction& accel, double h) {
    switch (method) {
        case Integrator::ExplicitEuler:
            return explicitEuler(s, accel, h);
        case Integrator::SemiImplicitEuler:
            return semiImplicitEuler(s, accel, h);
        case Integrator::PositionVerlet:
            return positionVerlet(s, accel, h);
        case Integrator::VelocityVerlet:
            return velocityVerlet(s, accel, h);
        case Integrator::RungeKutta4:
            return rungeKutta4(s, accel, h);
    }
    throw std::invalid_argument("unknown integrator");
}

}  // namespace gpl
