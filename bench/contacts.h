// The speed-versus-accuracy study of contacts behind ./lab bench contacts: the engine with the
// contact stages of worksheets 3 and 4, stepped through the hooks of the program's variant, and
// measured with a ruler of its own (geometry, not the hooks). The ctest suite
// (tests/study/contacts_study_test.cpp) checks the same functions against theory, so the numbers
// the study prints are the numbers that are tested.
#pragma once

#include <string>
#include <vector>

#include "gpl/engine.h"

namespace gpl::study {

/// How contacts are answered: worksheet 3 moves positions and the velocities follow the
/// displacement (Δx/h); worksheet 4 adds impulses with restitution, which then own the velocities.
enum class Response { Positions, Impulses };
const char* responseName(Response r);  ///< "positions", "impulses" (used in file names)

// ---- Hooks ---------------------------------------------------------------------------------------

/// The hooks the contact study steps through (simulationTimestep(), integrator(), sphereSphere(),
/// spherePlane(), resolveInterpenetration(), applyCollisionImpulse()) that are still stubs in this
/// program, found by calling each once on a small case. Sorted; empty when all are written.
std::vector<std::string> openContactHooks();
/// The hooks an experiment with this response needs.
std::vector<std::string> hooksNeeded(Response r);

// ---- The ruler ----------------------------------------------------------------------------------

/// Overlap of two bodies (m) from their geometry alone: r_a + r_b - |x_b - x_a| for two spheres,
/// r - n.(x - p) for a sphere and a plane; 0 when they do not overlap or no shape pair applies.
double overlap(const Body& a, const Body& b);
/// Largest overlap over every pair of bodies (m).
double largestOverlap(const std::vector<Body>& bodies);

// ---- 1. Resolution iterations on a pile ----------------------------------------------------------

/// The balls-in-a-box scene (45 balls, five planes, h = 0.01 s) with this response and number of
/// contact iterations, stepped for 3 s to settle and measured over the next second, after every step.
struct PileRun {
    int iterations = 0;
    double contactsPerStep = 0.0;  ///< contacts the detection found, mean per step
    double foundDepth = 0.0;       ///< mean depth of those contacts as found, before the stages (m)
    double meanDepth = 0.0;        ///< mean overlap left in the step's contacts after the step (m)
    double largestDepth = 0.0;     ///< largest overlap left in one of the step's contacts (m)
    /// Largest overlap of any pair after the step (m), whether among the step's contacts or not.
    double largestAnyPair = 0.0;
    double meanApproach = 0.0;     ///< mean approach speed left in the step's contacts (m/s; 0 when separating)
    double largestApproach = 0.0;  ///< largest approach speed left in one of them (m/s)
    double nsPerStep = 0.0;        ///< wall time of a whole step, median of the fastest of 3 rounds (ns); never tested
};
PileRun pileWithIterations(Response r, int iterations);

// ---- 2. Time step against the largest speed that does not tunnel ---------------------------------

/// One head-on shot without gravity: a ball of radius ra at speed v (m/s) at a static sphere of
/// radius rb, both of restitution 1, contacts answered with this response, step h. The ball starts
/// so that its centre is phase * v h short of touching after its first step (phase in [0, 1)).
/// True when the ball ends up beyond the target's centre: it passed through.
bool tunnels(Response r, double ra, double rb, double v, double h, double phase);
/// Fraction of the start phases (j + 1/2)/phases, j = 0..phases-1, whose shot tunnels.
double tunnelFraction(Response r, double ra, double rb, double v, double h, int phases);
/// Theory for tunnelFraction(): a shot is turned back only when a step ends with the ball's centre
/// less than R = r_a + r_b short of the target's (a step that ends past the target's centre turns
/// the contact normal forwards and sends the ball out on the far side). With stride s = v h and
/// start phase p, the first step that reaches the target ends (1 - p) s beyond touching, so the
/// shot tunnels when (1 - p) s > R. Impulses turn the ball back there; positions only take the
/// overlap away and leave it the speed p v (Δx/h), so it tunnels also when that next step p s
/// exceeds R. The fraction of the discrete phases for which that holds: for dense phases
/// 1 - R/s (impulses) and min(1, 2 (1 - R/s)) (positions), above s = R.
double theoreticalTunnelFraction(Response r, double ra, double rb, double v, double h, int phases);
/// Largest speed (m/s) at which no start phase tunnels: bisection on the speed to 1e-9 relative.
double largestSafeSpeed(Response r, double ra, double rb, double h, int phases);
/// Theory for largestSafeSpeed(), either response: the worst phases, 1/(2 phases) from either end,
/// tunnel from v h = R/(1 - 1/(2 phases)); as the phases grow dense, v_max -> (r_a + r_b)/h.
double theoreticalSafeSpeed(double ra, double rb, double h, int phases);

// ---- 3. Resting contact: a column against iterations -----------------------------------------------

/// A column of spheres (restitution 0) placed exactly at rest on a plane, stepped at h = 0.01 s;
/// the top sphere measured over the second half of the run.
struct Column {
    int spheres = 0;
    int iterations = 0;
    double jitter = 0.0;          ///< peak-to-peak height of the top sphere (m)
    double sink = 0.0;            ///< its exact resting height minus its mean height (m; > 0: sunk)
    double largestOverlap = 0.0;  ///< largest overlap of any pair after a step (m)
    double largestSpeed = 0.0;    ///< largest speed of any sphere (m/s)
    bool passedThrough = false;   ///< some sphere ended a step below the one under it: the column collapsed
};
/// masses: one per sphere, bottom to top (kg); radius (m) of every sphere; seconds simulated.
Column restingColumn(Response r, const std::vector<double>& masses, int iterations, double radius = 0.25,
                     double seconds = 10.0);
/// The study's columns: `spheres` spheres of 0.25 m and 1 kg for 10 s.
Column restingColumn(Response r, int spheres, int iterations);
/// Theory for the sink of a column of equal spheres with one sweep and positions only, at
/// h = 0.01 s: working the sweep through from the floor up, the steady overlaps are (n - 1),
/// (n - 2), ..., 0 times g h^2 from the floor to the top, so the top sinks g h^2 n (n - 1)/2 (m).
double theoreticalOneSweepSink(int spheres);

// ---- 4. Mass ratios ------------------------------------------------------------------------------

/// One contact stage alone (no gravity, no integration) on a two-sphere stack on a plane: the
/// lower sphere of mass `bottom` reaches 1 mm into the plane and 1 mm into the upper one of mass
/// `top` (kg); for impulses instead both fall at 1 m/s onto the plane. Returns what is left after
/// the stage: the lower sphere's overlap with the plane (m) or its approach speed (m/s).
double twoSphereResidual(Response r, double bottom, double top, int iterations);
/// Theory: each Gauss-Seidel sweep (plane first, then the pair) leaves the fraction
/// rho = m_top / (m_bottom + m_top) of the correction with the plane, so the residual is
/// rho^k times 2 mm (positions) or 1 m/s (impulses) after k sweeps.
double theoreticalTwoSphereResidual(Response r, double bottom, double top, int iterations);
/// Theory for a two-sphere stack resting on a plane (restingColumn() with masses {bottom, top}),
/// h = 0.01 s, q = rho^k: the steady floor overlap, which is the top sphere's sink (m):
/// q g h^2/(1 - q) with positions, q g h^2/(1 - q)^2 with impulses; and with impulses the speed
/// the stack carries down at the end of every step, q g h/(1 - q) (m/s; 0 with positions). Valid
/// while the overlap is small against the radius.
double theoreticalStackSink(Response r, double bottom, double top, int iterations);
double theoreticalStackSpeed(Response r, double bottom, double top, int iterations);

// ---- 5. Very fast, very small ------------------------------------------------------------------

/// A ball of radius r at speed v (h = 0.01 s) at a static sphere of the same radius and, head on,
/// at a plane; every start phase of tunnelFraction(). Robust: nothing stopped being finite and no
/// shot left with more kinetic energy than it came with (restitution 1).
struct Extreme {
    double radius = 0.0;              ///< m
    double speed = 0.0;               ///< m/s
    double stepOverR = 0.0;           ///< v h / (r_a + r_b)
    double sphereFraction = 0.0;      ///< of the phases, shots through the sphere
    double theoryFraction = 0.0;      ///< theoreticalTunnelFraction()
    double planeFraction = 0.0;       ///< shots through the plane (theory: 0, a half-space)
    double largestEnergyRatio = 0.0;  ///< largest final / initial kinetic energy over all shots
    bool finite = true;
};
Extreme fastSmall(double radius, double speed, int phases);

}  // namespace gpl::study
