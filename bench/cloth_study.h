// The cloth study (./lab bench cloth, worksheet 8): how position-based cloth trades speed for
// accuracy. A cloth is stepped by the soft bodies' four parts (SoftBodies::predict(),
// findContacts(), project(), updateVelocities(): what the engine's soft-body stages call), with the
// hooks the program is linked with. cloth_main.cpp prints and plots these functions' figures,
// tests/study/cloth_study_test.cpp checks them against theory.
#pragma once

#include <string>
#include <vector>

#include "gpl/body.h"
#include "gpl/soft_bodies.h"

namespace gpl::study {

/// How a cloth's constraints are projected: PBD with a stiffness, or XPBD with a compliance. PBD
/// gives every link (stretch, shear, bend) the stiffness; XPBD gives the stretch links the compliance
/// and the shear and bend links kShearBendSofter times it, so that the stretch links alone carry
/// the hanging cloth's weight (a chain of springs per column, whose stretch theory gives) and XPBD
/// with compliance 0 is PBD with stiffness 1.
struct ClothMethod {
    std::string name;
    SoftMethod method = SoftMethod::XPBD;
    double stiffness = 1.0;   ///< PBD, in [0, 1]
    double compliance = 0.0;  ///< XPBD, m/N
};

/// The four methods of the study: PBD with stiffness 1 and 0.5, XPBD with compliance 0 and
/// kSoftCompliance.
std::vector<ClothMethod> clothMethods();
/// The compliance of the soft XPBD cloth's stretch links (m/N): under the study's hanging cloth's
/// weight its top links stretch by about a sixth (chainStretch()), a property of the material that
/// neither the step nor the iterations change.
constexpr double kSoftCompliance = 2e-2;
constexpr double kShearBendSofter = 100.0;

/// A square cloth of n x n particles, side (m) and mass (kg), in the x-y plane with its top edge
/// (row 0) along the x axis at the origin and pinned there, hanging down -y.
ClothSpec hangingClothSpec(int n, double side, double mass, const ClothMethod& m);

/// What a hanging cloth's stretch links do once it has settled: gravity grows smoothly from 0 to g
/// over the first `ramp` seconds (so that the cloth is loaded without a jolt and hardly swings),
/// stays on for `hold` seconds, and each link's relative stretch (|x_i - x_j| - rest) / rest is
/// averaged over the last `average` seconds; then the largest and the mean over the links.
struct Settled {
    double largest = 0.0;  ///< relative stretch, the most-stretched link
    double mean = 0.0;     ///< relative stretch, mean over the stretch links
    bool finite = true;
    double msPerStep = 0.0;  ///< median wall time of a step
};
struct SettleTimes {
    double ramp = 1.0, hold = 1.0, average = 1.0;  ///< s
};
Settled settleHanging(const ClothSpec& spec, double h, int iterations, const SettleTimes& times = {});

/// The hanging cloth's settled stretch as theory gives it for XPBD once the iterations converge:
/// every column hangs as a chain of springs (the shear and bend links, kShearBendSofter times softer,
/// carry a few per cent of the load), the vertical link below row j carries the weight of
/// the n - 1 - j particles under it and stretches by tension x compliance, the horizontal links not
/// at all. largest: the top links; mean: over all stretch links.
struct ChainStretch {
    double largest = 0.0, mean = 0.0;
};
ChainStretch chainStretch(int n, double side, double mass, double compliance, double g = 9.81);

/// What a step costs on one thread: the thread's CPU time in each of the four parts (median over the steps, ns;
/// the time other programs had the core is left out), the constraints projected (links), and the
/// ns per projection: the projection part's time over iterations x links.
struct StepCost {
    int particles = 0, links = 0, iterations = 0;
    double predictNs = 0, contactsNs = 0, projectNs = 0, velocitiesNs = 0;
    double stepNs() const { return predictNs + contactsNs + projectNs + velocitiesNs; }
    double nsPerProjection() const { return projectNs / (static_cast<double>(iterations) * links); }
};
StepCost measureStepCost(const ClothSpec& spec, double h, int iterations, int steps);

/// The flag of the scene `flag` (scenes_worksheet8.cpp), without its pole and floor: a cloth pinned
/// at the two corners of its pole side, hanging in the x-y plane, in the scene's gusty wind. PBD
/// gives every link the stiffness; XPBD gives the stretch links the method's compliance and the
/// shear and bend links the scene's.
struct Flag {
    int nx = 30, ny = 20;
    double spacing = 0.05;                                ///< m
    double mass = 0.3;                                    ///< kg
    double shearCompliance = 1e-3, bendCompliance = 1.0;  ///< m/N, XPBD
    Vec3 wind{6.0, 0.0, 0.0};                             ///< m/s
    double drag = 1.0;                                    ///< kg/(m^2 s)
};
ClothSpec flagSpec(const Flag& flag, const ClothMethod& m);

/// When the flag counts as stable over `seconds`: every particle finite, no particle faster than
/// `speedBound` (m/s, which bounds the kinetic energy), and no stretch link longer than
/// (1 + stretchBound) times its rest length, at every step.
struct Stability {
    double seconds = 2.0;
    double speedBound = 0.0;    ///< m/s; 0: 10 (|wind| + sqrt(2 g L)), L the flag's diagonal
    double stretchBound = 0.5;  ///< relative: a cloth within it holds together
};
/// Empty when the flag is stable for h, else what failed first: "not finite", "speed" or "stretch".
std::string flagUnstable(const Flag& flag, const ClothMethod& m, double h, int iterations, const Stability& s);
/// The largest stable time step: from `start` (s), h doubled while the flag is stable or halved
/// while it is not, within [low, high], then bisected on log h to a relative `precision`. h is NaN
/// when even `low` is unstable, infinity when `high` is stable; `failure` names what failed at the
/// smallest unstable step tried.
struct StableStep {
    double h = 0.0;  ///< s
    std::string failure;
};
StableStep largestStableStep(const Flag& flag, const ClothMethod& m, int iterations, const Stability& s,
                             double start = 1.0 / 60.0, double low = 1e-3, double high = 0.25, double precision = 0.02);

/// A cloth of n x n particles, side x side (m), mass (kg), lying flat (x-z) and centred `drop` (m)
/// above a static sphere of radius R at the origin, dropped on it under gravity; nothing pinned.
/// Every link rigid (XPBD, compliance 0: PBD with stiffness 1), no self-collision, the particles'
/// radius `radius` (m); the sphere's friction coefficient (static and sliding) `friction`, which
/// keeps the cloth draped over it rather than sliding off. Both engines (bullet_cloth.h) run this.
struct SphereDrop {
    int n = 64;
    double side = 2.0, mass = 1.0;
    double sphereRadius = 0.5, drop = 0.1, radius = 0.01;
    double friction = 0.5;
    double h = 1.0 / 60.0;
    int iterations = 10;
    double seconds = 2.0;
    int threads = 1;  ///< this engine's, SoftBodies::setThreads(); Bullet's soft bodies run on one
};
ClothSpec sphereDropSpec(const SphereDrop& d);
Body dropSphere(const SphereDrop& d);

/// What one engine did with the drop: step times and, measured alike on both engines' particles,
/// the stretch of the grid's links at the end and the deepest a particle's sphere of `radius` lay
/// inside the rigid sphere over the run.
struct DropRun {
    std::vector<double> stepMs;  ///< wall time of each step
    std::vector<double> cpuMs;   ///< the program's CPU time of each step, every thread's: not what other programs took
    double medianMs = 0.0, medianCpuMs = 0.0;
    double largestStretch = 0.0;  ///< relative, stretch links, at the end
    double meanStretch = 0.0;
    double deepest = 0.0;  ///< m, over every step
    bool finite = true;
};
DropRun dropOnSphere(const SphereDrop& d);

/// The median wall time (ms) of `iterations` bare XPBD sweeps of the drop's cloth (bareXpbdSweeps(),
/// on one thread), from its predicted positions half way through the drop, over `repeats` runs; 0
/// where the bare sweeps are not built. What the method's own work on the links costs a step.
double bareSweepsMs(const SphereDrop& d, int repeats);

#ifdef GPL_BARE_XPBD
/// Instructors' tree only (bench/instructor/bare_xpbd.cpp; built with GPL_BARE_XPBD, and
/// bareSweepsMs() is 0 without it). `iterations` sweeps of `links` in their order, each link's
/// multiplier from 0, moving `p` (inverse masses `w`) by XPBD's projection as the reference
/// solveDistanceConstraint() computes it, written out in place: no hook calls, no contacts, no
/// threads. The links' share of a step's projection, and all of it for a cloth that touches nothing.
void bareXpbdSweeps(std::vector<Vec3>& p, const std::vector<double>& w, std::vector<DistanceLink>& links, double h,
                    int iterations);
#endif

/// The measures of a DropRun from particle positions (both engines use them): `links` are the
/// stretch links' particle pairs and rest lengths.
double penetration(const std::vector<Vec3>& x, const SphereDrop& d);
void linkStretch(const std::vector<Vec3>& x, const std::vector<DistanceLink>& links, double& largest, double& mean);
double median(std::vector<double> values);
/// The calling thread's CPU time so far (ms).
double threadCpuMs();
/// This program's CPU time so far, all its threads' (ms).
double processCpuMs();

}  // namespace gpl::study
