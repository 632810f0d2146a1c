// The heap both engines of `./lab bench engine` simulate: N spheres (radius 0.5 m, 1 kg) or N cubes
// (half side 0.3 m, 1 kg, each turned at random) on a jittered cubic lattice of spacing 1.2 m (fixed
// seed), dropped on a static plane y = 0, restitution 0, friction 0.5 in both (this engine: the
// friction stage of worksheet 7), fixed steps of 1/60 s, 10 solver iterations.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "gpl/math.h"

namespace gpl::bench {

enum class HeapShape { Spheres, Boxes };

constexpr double kRadius = 0.5;       // m, of a sphere
constexpr double kHalfSide = 0.3;     // m, of a cube: its corners (0.52 m out) stay clear of the
                                      // neighbours' at any turn (centres 1.1 m apart at least)
constexpr double kMass = 1.0;         // kg
constexpr double kSpacing = 1.2;      // m between lattice points
constexpr double kFriction = 0.5;
constexpr double kTimeStep = 1.0 / 60.0;  // s
constexpr int kIterations = 10;       // sweeps of the contact solver per step
/// This engine's sweeps of interpenetration per step (its position iterations): fewer than the
/// solver's, as Box2D's 3 position iterations beside 8 velocity iterations. Bullet has no such
/// sweeps (it pushes overlaps apart through its solver's velocities); the overlaps each engine
/// leaves are in the table. `--interpenetration N` sets it (10: as many as the solver's).
constexpr int kInterpenetrationIterations = 3;

/// The lattice points of the heap: side = ceil(cbrt(n)) along x and z, as many layers as it takes,
/// centred on the y axis, the lowest 1 m above the plane, each jittered by up to 0.05 m.
std::vector<Vec3> heapPositions(std::size_t n);
/// The orientations of the cubes: uniformly random unit quaternions (fixed seed).
std::vector<Quat> heapOrientations(std::size_t n);

/// The state of one body of the heap at the end, world frame.
struct HeapBody {
    Vec3 position;
    Quat orientation = Quat::Identity();
    Vec3 velocity;
    Vec3 angularVelocity;
};

/// What one engine did on one heap: time per step and the quality of the answer.
struct HeapRun {
    std::string engine;
    HeapShape shape = HeapShape::Spheres;
    std::size_t bodies = 0;
    std::size_t steps = 0;
    double medianMs = 0.0;       ///< per step
    double p90Ms = 0.0;          ///< per step
    double contactsPerStep = 0.0;  ///< mean over the steps
    double deepest = 0.0;        ///< m: largest overlap between bodies or with the plane in the last second
    double height = 0.0;         ///< m: the top of the settled heap (highest sphere's top, cube's corner)
    double kinetic = 0.0;        ///< J: kinetic energy at the end, translation and rotation (settled: near 0)
    double fastest = 0.0;        ///< m/s: the largest speed of a body's centre at the end
};

/// One engine's heap, stepped from outside, so that two engines can take turns on the machine.
class HeapSim {
public:
    virtual ~HeapSim() = default;
    virtual void step() = 0;
    /// Contact points after the last step, as Bullet's manifolds count them (a sphere's contact has
    /// one, a cube's up to 4).
    virtual double contactPoints() const = 0;
    /// The movable bodies now.
    virtual std::vector<HeapBody> state() const = 0;
    /// The friction coefficient of a contact with the plane and of one between two bodies, as the
    /// engine's contacts hold it after the last step (NaN where there is no such contact).
    virtual std::pair<double, double> pairFriction() const = 0;
};

/// This engine (the hooks it is linked with) on the heap, its broad phase and friction stage with
/// this many threads, `interpenetration` sweeps of interpenetration a step; cubes with the rotation
/// stage (worksheet 6).
std::unique_ptr<HeapSim> ourHeap(HeapShape shape, std::size_t n, int threads,
                                 int interpenetration = kInterpenetrationIterations);
/// Bullet's default pipeline on the same heap; only when built with Bullet (hasBullet()).
std::unique_ptr<HeapSim> bulletHeap(HeapShape shape, std::size_t n);
bool hasBullet();

/// Steps of one engine in a turn of runInTurns().
constexpr std::size_t kTurn = 10;
/// The last steps whose overlaps count in HeapRun::deepest: one second.
constexpr std::size_t kQualitySteps = 60;

/// Steps each engine through `seconds` of simulated time, the engines taking turns of kTurn steps
/// (A's first ten, B's first ten, A's next ten, ...), each step timed: a busy moment of the machine
/// then slows both engines' steps of the same stretch of the fall, not one engine's whole run, so
/// their ratio holds from run to run. Per engine, in the order given: the step times (median, 90th
/// percentile), contact points per step (mean) and the quality of the heap: its height and kinetic
/// energy at the end, its deepest overlap over the last kQualitySteps steps (their states kept, and
/// measured after the run), so that one lucky or unlucky last step does not decide it.
std::vector<HeapRun> runInTurns(HeapShape shape, std::size_t n, double seconds,
                                const std::vector<std::pair<std::string, HeapSim*>>& engines);

/// The quality figures of a state of the heap, into run (run.shape says what the bodies are). Both
/// engines' states are measured alike: the overlaps of cubes by this engine's reference
/// kernels boxBox() and boxPlane() (worksheet 5), of spheres by their distances.
void measureQuality(const std::vector<HeapBody>& bodies, HeapRun& run);

/// Simulated time (s) the heap of n bodies needs to fall and settle: the fall from the top layer
/// plus 3 s.
double settleTime(std::size_t n);

}  // namespace gpl::bench
