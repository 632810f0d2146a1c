// The fluids study (./lab bench fluids, worksheet 9): how smoothed-particle fluids trade speed for
// accuracy. A fluid is stepped by the framework's Fluids (fluids.h) as the engine's stages call it:
// position-based fluids (predict(), findNeighbours(), project(), updateVelocities()) or weakly
// compressible SPH (stepSph()), with the hooks the program is linked with, inside a closed tank of
// static boxes (tankWalls(), fluid_experiments.h). fluids_main.cpp prints and plots these
// functions' figures; tests/study/fluids_study_test.cpp checks them.
#pragma once

#include <string>
#include <vector>

#include "gpl/body.h"
#include "gpl/fluids.h"

namespace gpl::study {

enum class FluidMethod { PBF, WCSPH };
const char* methodName(FluidMethod method);

/// The scenes' water: 1000 kg/m^3, particles `spacing` apart seeing kSmoothingRatio spacings, PBF's
/// and WCSPH's other parameters the defaults (FluidParameters).
FluidParameters studyWater(double spacing = 0.025);

/// A fluid and the walls of its closed tank.
struct FluidTank {
    Fluids fluid;
    std::vector<Body> walls;
};

/// A block of nx x ny x nz particles at rest on the floor of a closed tank as wide and deep as the
/// block and `headroom` times as tall; the block's lower corner at the origin.
void fillBlock(FluidTank& tank, const FluidParameters& water, int nx, int ny, int nz, double headroom = 1.5);

/// One step of h: PBF's four stages, or WCSPH's step in `substeps` substeps (0: as many as the
/// speed of sound asks for, Fluids::sphSubsteps()).
void step(FluidTank& tank, FluidMethod method, double h, int substeps = 0);

/// The column of parts 1 and 2: 8 x 16 x 8 particles (0.2 m square, 0.4 m tall) in a tank as wide,
/// 0.6 m tall, released at rest from the rest lattice.
struct Column {
    int nx = 8, ny = 16, nz = 8;
    double spacing = 0.025;  ///< m
    double height() const { return ny * spacing; }
};

/// 1. A PBF column's density error after `seconds` (s) at a time step h with `iterations`: the
/// mean over the particles of max(rho / rho0 - 1, 0) (Fluids::densityError()) and the largest
/// rho / rho0 - 1, measured anew at the positions after each step and averaged over the last
/// `average` seconds.
struct DensityError {
    double mean = 0.0, largest = 0.0;  ///< relative
    bool finite = true;
    double msPerStep = 0.0;  ///< median CPU time of a step
};
DensityError pbfColumnError(const Column& column, int iterations, double h, double seconds = 1.0,
                            double average = 0.25);

/// 2. A WCSPH column at rest stepped h at a time in one substep, for `seconds`: empty when every
/// particle stays finite and none moves faster than ten times a fall of the column's height
/// (10 sqrt(2 g H): the column's settling stays far below it, a blow-up passes it), else what failed
/// first ("not finite" or "speed").
std::string sphColumnUnstable(const Column& column, double soundSpeed, double h, double seconds = 0.5);
/// The largest such h: from `start` doubled while stable or halved while not, then bisected on log
/// h to a relative `precision`; NaN when even `low` fails. failure: what failed at the smallest
/// unstable h tried.
struct StableStep {
    double h = 0.0;  ///< s
    std::string failure;
    int runs = 0;
};
StableStep largestStableSphStep(const Column& column, double soundSpeed, double start, double low = 1e-6,
                                double precision = 0.02, double seconds = 0.5);
/// The CFL bound of WCSPH's substeps: h <= lambda h_smooth / c, lambda = kCourant (the factor
/// Fluids::sphSubsteps() takes).
constexpr double kCourant = 0.4;
double cflBound(double smoothingLength, double soundSpeed);

/// 3 and 4. What a step costs on a block of n x n x n particles at rest in its tank, all as the
/// thread's CPU time, the median over `steps` timed steps after `warmup` untimed ones: PBF's four
/// stages apart (with `iterations`, h = pbfStep), one WCSPH substep (its neighbours, densities,
/// forces and push) at the CFL bound, the neighbour search alone, and the bare loop: every
/// particle's poly6 density summed over the same neighbours and nothing else (bareNeighbourSum()).
struct FluidCost {
    int particles = 0;
    double neighbours = 0.0;  ///< per particle, mean
    int iterations = 0;
    double pbfPredictNs = 0, pbfNeighboursNs = 0, pbfProjectNs = 0, pbfVelocitiesNs = 0;
    double sphSubstepNs = 0;  ///< one substep
    int sphSubsteps = 0;      ///< substeps of a step of pbfStep at the speed of sound
    double searchNs = 0;      ///< ParticleGrid::find() alone
    double bareNs = 0;        ///< bareNeighbourSum() alone
    double barePbfNs = 0;     ///< barePbfIteration() alone; 0 where it is not built
    double pbfStepNs() const { return pbfPredictNs + pbfNeighboursNs + pbfProjectNs + pbfVelocitiesNs; }
    double sphStepNs() const { return sphSubstepNs * sphSubsteps; }
    /// PBF's step over its iterations: what one iteration costs with the step's other stages shared out.
    double pbfIterationNs() const { return pbfStepNs() / iterations; }
};
/// threads: the two fluids' (Fluids::setThreads()). With 1, every figure is the thread's CPU time;
/// with 2, the stages and the substep are timed by the wall clock (the caller's CPU time leaves out
/// the second thread's half), while the search alone and the bare loop stay on one thread and its
/// CPU time: the limit is the one-thread bare loop.
FluidCost measureCost(int n, int iterations = 4, double pbfStep = 0.005, int warmup = 2, int steps = 5,
                      int threads = 1);

/// The bare loop of the limit: rho_i = m sum_j W_poly6(|x_i - x_j|, h) over particle i and its
/// neighbours in `grid` (found at `x`), poly6 written out; returns the sum of the densities (so
/// that the loop is not optimised away).
double bareNeighbourSum(const ParticleGrid& grid, const std::vector<Vec3>& x, double mass, double h,
                        std::vector<double>& density);

/// Instructors' tree only (bench/instructor/bare_pbf.cpp; built with GPL_BARE_PBF, and barePbfNs
/// stays 0 without it). The same work as one of PBF's iterations without the hooks and the
/// framework: its three passes over the neighbours in `grid` (found at `x`) with the kernels
/// written out in place, as the reference hooks compute them (densities from max(rho_i, rho0) to
/// multipliers with eps, then the moves with s_corr), and every particle moved; the fluid's mass,
/// rest density, smoothing length, eps and tensile correction. No push out of walls. Writes the
/// moved positions to `moved` and returns the sum of their coordinates (so that the loop is not
/// optimised away).
double barePbfIteration(const ParticleGrid& grid, const std::vector<Vec3>& x, double mass, double restDensity, double h,
                        double epsilon, const TensileCorrection& tensile, std::vector<double>& lambda,
                        std::vector<Vec3>& moved);

/// 5. A dam-break scene (dam-break or dam-break-sph, scenes_worksheet9.cpp) stepped to T = Tend:
/// its surge front Z = z / a against T = t sqrt(2 g / a) at every step, and Z interpolated to each
/// of Martin and Moyce's T (kMartinMoyce, fluid_experiments.h).
struct FrontRun {
    std::vector<double> T, Z;        ///< every step
    std::vector<double> atMeasured;  ///< Z at each kMartinMoyce T
    bool finite = true;
};
FrontRun damBreakFront(const std::string& scene, double Tend = 4.2);
/// The dam-break scenes' column width a (m).
constexpr double kDamBreakWidth = 0.25;

/// Least-squares slope of log y against log x.
double logLogSlope(const std::vector<double>& x, const std::vector<double>& y);
double median(std::vector<double> values);
/// The calling thread's CPU time so far (ns).
double threadCpuNs();

}  // namespace gpl::study
