// Integrators as pure kernels: a particle state and an acceleration function in, the state one
// time step later out. No engine, no globals: the engine, the study (./lab bench accuracy) and the
// tests call the same functions.
//
// Contract shared by every kernel: on entry state.a holds the accelerations at (state.x, state.v);
// on return x, v and a have all moved on by h, so that the next step starts from current
// accelerations without evaluating them again. Counting calls of `accel` therefore counts force
// evaluations: one per step for the Euler and Verlet methods, four for RK4.
//
// Student hooks (worksheet 2; bodies in assignments/, reference bodies in solutions/):
//   positionVerlet()  x_{n+1} = 2 x_n - x_{n-1} + h^2 a_n, the velocity derived from positions
//   velocityVerlet()  x_{n+1} = x_n + h v_n + h^2/2 a_n, v_{n+1} = v_n + h/2 (a_n + a_{n+1})
// Framework kernels: explicitEuler(), semiImplicitEuler(), rungeKutta4().
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "gpl/hooks.h"
#include "gpl/math.h"

namespace gpl {

/// The integrators the engine offers, in the order the viewer and the study list them.
enum class Integrator { ExplicitEuler, SemiImplicitEuler, PositionVerlet, VelocityVerlet, RungeKutta4 };

/// Every integrator, in display order.
constexpr std::array<Integrator, 5> kIntegrators = {Integrator::ExplicitEuler, Integrator::SemiImplicitEuler,
                                                    Integrator::PositionVerlet, Integrator::VelocityVerlet,
                                                    Integrator::RungeKutta4};

/// Name for people ("semi-implicit Euler").
const char* integratorName(Integrator method);
/// Name for the command line and CSV files ("semi-implicit-euler").
const char* integratorId(Integrator method);
/// The integrator with this id or name; throws std::invalid_argument listing the known ids.
Integrator integratorFromId(const std::string& id);
/// Global order of accuracy in theory (1, 1, 2, 2, 4).
int theoreticalOrder(Integrator method);

/// N particles moving under x'' = a(x, v).
struct ParticleState {
    std::vector<Vec3> x;      ///< positions (m)
    std::vector<Vec3> v;      ///< velocities (m/s)
    std::vector<Vec3> a;      ///< accelerations at (x, v) (m/s^2)
    std::vector<Vec3> xPrev;  ///< positions one step earlier (m); position Verlet only, empty until its first step
};

/// The forces of a system as accelerations: fills a (resized to x.size()) with a(x, v) in m/s^2.
using AccelerationFunction =
    std::function<void(const std::vector<Vec3>& x, const std::vector<Vec3>& v, std::vector<Vec3>& a)>;

/// A state at rest-or-moving with a filled in by one call of accel: the start of every run.
ParticleState startState(std::vector<Vec3> x, std::vector<Vec3> v, const AccelerationFunction& accel);

/// Throws std::invalid_argument with a clear message unless h is a positive finite number of
/// seconds and every position, velocity and acceleration is finite and the sizes agree.
void checkStep(const ParticleState& state, double h);

// ---- Kernels: one time step of h seconds -----------------------------------------------------
/// x += h v; v += h a (both with the old values). First order; adds energy every step.
void explicitEuler(ParticleState& state, const AccelerationFunction& accel, double h);
/// v += h a; x += h v (the new velocity). First order, symplectic: the worksheet-1 method.
void semiImplicitEuler(ParticleState& state, const AccelerationFunction& accel, double h);
/// Student hook (worksheet 2), solutions/position_verlet.cpp.
void positionVerlet(ParticleState& state, const AccelerationFunction& accel, double h);
/// Student hook (worksheet 2), solutions/velocity_verlet.cpp.
void velocityVerlet(ParticleState& state, const AccelerationFunction& accel, double h);
/// Classical fourth-order Runge-Kutta on (x, v); four force evaluations per step.
void rungeKutta4(ParticleState& state, const AccelerationFunction& accel, double h);

/// One step with the chosen kernel.
void integrate(Integrator method, ParticleState& state, const AccelerationFunction& accel, double h);

}  // namespace gpl
