// The speed-versus-accuracy study behind ./lab bench accuracy: problems with exact answers and
// the measurements taken on them. The ctest suite (tests/study) checks the same functions against
// theory, so the numbers the study prints are the numbers that are tested.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "gpl/integrators.h"

namespace gpl::study {

/// A problem x'' = a(x, v) with a known state at its end time.
struct Problem {
    std::string id;                  ///< "oscillator", used in file names
    std::string title;               ///< for people
    std::string unit;                ///< of positions and errors ("m", "rad")
    std::vector<Vec3> x0, v0;        ///< initial positions and velocities
    double endTime = 1.0;            ///< s
    std::vector<Vec3> exactX;        ///< exact positions at endTime
    std::vector<Vec3> exactV;        ///< exact velocities at endTime
    double timeScale = 1.0;          ///< tau (s): the error is sqrt(|dx|^2 + tau^2 |dv|^2)
    double omega = 0.0;              ///< fastest angular frequency (rad/s), for h*omega
    double scale = 1.0;              ///< size of the positions, in unit: errors below 1e-2 scale are "asymptotic"
    std::vector<std::size_t> steps;  ///< the sweep: numbers of steps to endTime
    AccelerationFunction accel;
    std::function<double(const std::vector<Vec3>& x, const std::vector<Vec3>& v)> energy;  ///< J/kg (or J)
};

// End times avoid whole and half periods: there the O(h) shape error of semi-implicit Euler on a
// linear oscillator cancels and it would look second order.
Problem freeFall();                ///< thrown ball, g = 9.81 m/s^2, 2 s
Problem oscillator(double omega);  ///< x'' = -omega^2 x from (1 m, 0), 1.3 periods
Problem pendulum(
    double amplitude);  ///< theta'' = -(g/L) sin theta, L = 1 m, from rest to the bottom (a quarter period, exact)
Problem kepler();       ///< e = 0.6, GM = 1, a = 1, perihelion to aphelion (pi s)
/// Springs of 100 N/m in a line from a fixed anchor, masses in kg (each > 0 and finite, else
/// std::invalid_argument), small longitudinal motion; no exact end state (only for stability).
Problem springChain(const std::vector<double>& masses);
/// Largest angular frequency of the spring chain's normal modes (rad/s), from its mass and stiffness matrices.
double springChainOmegaMax(const std::vector<double>& masses);

/// The result of one run.
struct Run {
    std::size_t steps = 0;
    double h = 0.0;            ///< s
    double error = 0.0;        ///< state error at endTime in the problem's unit (inf when the run blew up)
    double energyMax = 0.0;    ///< max over steps of |E - E0| / |E0|
    double energyDrift = 0.0;  ///< (E(T) - E0) / |E0|
    double evaluationsPerStep = 0.0;
    double secondsPerStep = 0.0;  ///< wall time, measured on a run without energy bookkeeping
    bool finite = true;           ///< false when the state stopped being finite (it then stopped)
};

/// Runs `steps` steps of endTime/steps. Throws std::invalid_argument (clear message) on zero
/// steps or a non-finite start, before stepping. `timed`: also measure the wall time per step.
Run simulate(const Problem& p, Integrator method, std::size_t steps, bool timed = false);
/// Runs `steps` steps of h from the problem's start; the error is measured against the exact
/// end state only when steps * h equals endTime (otherwise it is NaN). Throws
/// std::invalid_argument on a non-positive or non-finite h or a non-finite start, before stepping.
Run simulateWithStep(const Problem& p, Integrator method, double h, std::size_t steps, bool timed = false);

/// The student hook the integrator steps with ("positionVerlet()", worksheet 2); empty for the
/// framework's kernels (explicit and semi-implicit Euler, RK4).
std::string hookOf(Integrator method);
/// The integrators whose hook is still a stub in this program, found by one step of each on the
/// oscillator (a stub records itself, gpl/hooks.h). In display order; empty when all are written.
std::vector<Integrator> openIntegrators();

/// Relative energy error (E - E0)/|E0| after every step, `steps` steps of h (for plots).
std::vector<double> energyHistory(const Problem& p, Integrator method, double h, std::size_t steps);

/// Order of convergence: least-squares slope of log(error) over log(h) on the finest runs whose
/// error lies in the asymptotic window (below 1e-2 scale, above the rounding floor). points == 0
/// when fewer than three runs qualify (for example an exact method).
struct Order {
    double slope = 0.0;
    std::size_t points = 0;
};
Order measuredOrder(const Problem& p, const std::vector<Run>& sweep);

/// True when `steps` steps of h from the problem's start stay bounded: the largest energy in the
/// second half exceeds the largest in the first half by less than 1 % (a growing mode would), and
/// no energy exceeds 1e4 times the initial one.
bool boundedRun(const Problem& p, Integrator method, double h, std::size_t steps);

/// Largest stable h*omega of the problem (a linear one: oscillator or spring chain): a sweep of
/// h*omega on a grid, then bisection between the last stable and the first unstable value.
/// Returns 0 when even the smallest value tried (minHOmega) is unstable.
double stabilityLimit(const Problem& p, Integrator method, double minHOmega = 1e-3);
/// Theory for the undamped oscillator: 0 (explicit Euler), 2, 2, 2, 2 sqrt 2 (RK4).
double theoreticalStabilityLimit(Integrator method);

/// Largest position error over one period of an oscillator centred `offset` metres from the
/// origin, computed in float or double (velocity Verlet written for the scalar type), h = 1e-3 s.
double offsetError(double offset, bool singlePrecision);

}  // namespace gpl::study
