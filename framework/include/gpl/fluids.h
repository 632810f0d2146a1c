// Fluids (worksheet 9): particles of one rest density, stepped by position-based fluids (PBF,
// Macklin and Mueller 2013: the students' method) or by weakly compressible SPH (WCSPH, Becker and
// Teschner 2007: the framework's comparison). The engine owns one Fluids (its fluids()); a scene
// without fluid leaves it empty and never runs its stages. Every field at a particle is a sum over
// its neighbours (ParticleGrid) with the students' kernels (fluid_kernels.h).
//
// One PBF step of h (PhysicsEngine::simulationTimestep() calls them in this order):
//   predict()          v += h g; p = x + h v
//   findNeighbours()   every particle's neighbours nearer than the smoothing length, once per step
//   project()          iterations times: densities (fluidDensity()) and multipliers
//                      (densityConstraintLambda(), one-sided: only rho_i > rho0 pushes), moves
//                      (densityCorrection()), then every particle pushed out of the rigid engine's
//                      planes, boxes and spheres
//   updateVelocities() v = (p - x) / h; XSPH (xsphViscosity()); x = p
// One WCSPH step (stepSph()), in substeps short enough for the speed of sound: neighbours,
// densities (fluidDensity()), Tait's pressure, the symmetric pressure force and Monaghan's
// artificial viscosity along spikyGradient(), semi-implicit Euler, the rigid bodies' push.
// Rigid bodies push particles (one way): a particle of radius spacing / 2 moves out of the body.
//
// Every pass over the particles computes each particle's value from fields no particle of the
// pass writes (a density pass writes the next densities and multipliers beside those its
// neighbours are read from), so a pass may run in two halves at once: with two threads
// (setThreads(), the default where the machine has two cores) and a fluid of kThreadedParticles
// or more, the second half of the particles runs on a SecondThread. Each particle's sums are the
// same code in the same order either way: the results are the same to the bit.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "gpl/body.h"
#include "gpl/fluid_kernels.h"
#include "gpl/math.h"
#include "gpl/particle_grid.h"
#include "gpl/second_thread.h"

namespace gpl {

/// The smoothing length the scenes use, in particle spacings: poly6 summed over a cubic lattice at
/// the rest spacing gives the rest density within about one per cent at this ratio (the 26 nearest
/// lattice neighbours inside h; at 1.5 spacings the sum falls 5 per cent short).
constexpr double kSmoothingRatio = 2.0;

struct FluidParameters {
    double restDensity = 1000.0;    ///< rho0 (kg/m^3, > 0)
    double spacing = 0.02;          ///< rest spacing of the particles (m, > 0); each has m = rho0 spacing^3
    double smoothingLength = 0.04;  ///< h (m, >= spacing): how far a particle sees
    /// PBF's relaxation eps in units of 1 / spacing^2 (dimensionless, > 0). A particle inside the rest
    /// lattice has sum_k |grad_k C|^2 of about 0.37 / spacing^2 (h = 2 spacings): eps small beside it
    /// barely softens the constraint there, and keeps a surface particle with few neighbours from
    /// being flung.
    double relaxation = 0.01;
    /// PBF's s_corr, here with k in units of spacing^2 and dq a share of h (0 < dq < 1). s_corr is
    /// added to the multipliers, which are m^2 (lambda = -C / (sum |grad C|^2 + eps), grad C in 1/m):
    /// a particle inside the lattice compressed by C has lambda of about -C spacing^2 / 0.37, so k
    /// in spacing^2 keeps s_corr's weight beside the multipliers the same at every spacing.
    TensileCorrection tensile{0.1, 0.2, 4};
    double xsph = 0.01;                 ///< XSPH's c after each PBF step (0 <= c <= 1)
    int iterations = 4;                 ///< PBF's sweeps of the density constraints per step (>= 1)
    double soundSpeed = 20.0;           ///< WCSPH's speed of sound c (m/s, > 0): about 10 times the fastest flow
    double artificialViscosity = 0.05;  ///< WCSPH: Monaghan's alpha (dimensionless, >= 0)
};

/// An axis-aligned box (m): the inside of a tank.
struct FluidBox {
    Vec3 lower = Vec3::Zero();
    Vec3 upper = Vec3::Zero();
    bool contains(const Vec3& q) const {
        return (q.array() >= lower.array()).all() && (q.array() <= upper.array()).all();
    }
};

class Fluids {
public:
    // ---- Building (each throws std::invalid_argument with one line naming the field before
    // anything steps) ----------------------------------------------------------------------------
    /// Sets the parameters: a rest density, spacing or smoothing length <= 0 or not finite, a
    /// smoothing length below the spacing, a relaxation <= 0, a tensile k < 0, dq outside (0, 1),
    /// n < 1, an XSPH c outside [0, 1], iterations < 1, a speed of sound <= 0 or a viscosity < 0
    /// are refused. Particles already added keep their places.
    void setParameters(const FluidParameters& parameters);
    const FluidParameters& parameters() const { return parameters_; }
    /// A box the fluid must stay inside (the inside of a closed tank that the scene builds of static
    /// bodies): every particle added must lie in it, at least half a spacing from its faces. Refused
    /// when a corner is not finite, the box is empty, or a particle already added lies outside.
    void setContainer(const FluidBox& box);
    const std::optional<FluidBox>& container() const { return container_; }
    /// Fills the box [lower, upper] with a cubic lattice at the rest spacing, the particles' centres
    /// half a spacing inside its faces, all moving at `velocity`; returns how many were added
    /// (refused: a corner or the velocity not finite, a box thinner than a spacing, a particle outside
    /// the container).
    std::size_t addBlock(const Vec3& lower, const Vec3& upper, const Vec3& velocity = Vec3::Zero());
    /// Adds one particle (refused: not finite, or outside the container).
    void addParticle(const Vec3& position, const Vec3& velocity = Vec3::Zero());
    /// Removes every particle and the container; the parameters stay.
    void clear();
    bool empty() const { return x.empty(); }
    std::size_t size() const { return x.size(); }

    double mass() const;                                         ///< m = rho0 spacing^3 (kg), every particle's
    double radius() const { return 0.5 * parameters_.spacing; }  ///< m, for the rigid bodies' push
    double epsilon() const;                                      ///< PBF's eps (1/m^2)
    TensileCorrection tensile() const;                           ///< s_corr as the kernel takes it: k in m^2, dq in m

    // ---- PBF's step: the engine's stages FluidPredict, FluidNeighbours, FluidProject,
    // FluidVelocities --------------------------------------------------------------------------
    /// v += h gravity; p = x + h v.
    void predict(double h, const Vec3& gravity);
    /// The neighbours of every predicted position p, kept for the rest of the step.
    void findNeighbours();
    /// parameters().iterations times: every density and, from it, every multiplier (from max(rho_i, rho0):
    /// without particles beyond a free surface or a wall, the particles there read as less dense
    /// than they are, and the two-sided constraint would pull them in), then every move (all
    /// computed before any particle moves: each pair's moves are equal and opposite), then the
    /// rigid bodies' push. bodies: the rigid engine's, read only.
    void project(const std::vector<Body>& bodies);
    /// v = (p - x) / h, then XSPH's blend of every velocity with its neighbours' (from the
    /// velocities before the blend), then x = p.
    void updateVelocities(double h);

    // ---- WCSPH's step: the engine's stage FluidSph ---------------------------------------------
    /// One step of h in sphSubsteps(h) substeps of h / n, each: neighbours, densities, pressures
    /// p = B ((rho / rho0)^7 - 1) with B = rho0 c^2 / 7 (0 where rho < rho0, a free surface's
    /// deficit), accelerations g - sum_j m (p_i / rho_i^2 + p_j / rho_j^2 + Pi_ij) grad W(x_i - x_j)
    /// with Monaghan's viscosity Pi_ij, v += hs a, x += hs v, the rigid bodies' push (a pushed
    /// particle keeps no velocity into the body). p is left equal to x. substeps: 0 takes
    /// sphSubsteps(h); a number >= 1 takes that many whatever the speed of sound says (the fluids
    /// study's search for the largest stable step).
    void stepSph(double h, const Vec3& gravity, const std::vector<Body>& bodies, int substeps = 0);
    /// Substeps of stepSph(): the fewest with h / n <= 0.4 smoothing length / speed of sound (CFL).
    int sphSubsteps(double h) const;

    // ---- Diagnostics ----------------------------------------------------------------------------
    /// Neighbours anew at x and every density from them (density; in WCSPH also pressure).
    void measureDensities();
    /// The mean over the particles of max(rho_i / rho0 - 1, 0) from density: the compression the
    /// constraints fight (a particle at a free surface or a wall, short of neighbours, reads as
    /// less dense without being stretched).
    double densityError() const;
    double largestDensityError() const;                 ///< the largest rho_i / rho0 - 1 (0 when none is above)
    double kineticEnergy() const;                       ///< J
    double potentialEnergy(const Vec3& gravity) const;  ///< J, gravitational, zero at the origin
    Vec3 linearMomentum() const;                        ///< kg m/s
    /// The first particle whose position or velocity is not finite, or none (size()).
    std::size_t firstNonFinite() const;
    const ParticleGrid& grid() const { return grid_; }

    // ---- Threads --------------------------------------------------------------------------------
    /// 1: every pass on the calling thread; 2: the passes of a fluid of kThreadedParticles or more
    /// in two halves on two threads (the same results). Throws std::invalid_argument below 1.
    void setThreads(int threads);
    int threads() const { return threads_; }
    /// The fewest particles whose passes two threads share: below, a hand-over costs more than
    /// half a pass saves.
    static constexpr std::size_t kThreadedParticles = 2000;

    // ---- The particles (structure of arrays), read by the viewer and the tests ----------------
    std::vector<Vec3> x;           ///< positions at the end of the last step (m)
    std::vector<Vec3> p;           ///< predicted positions, projected during a PBF step (m)
    std::vector<Vec3> v;           ///< velocities (m/s)
    std::vector<double> density;   ///< rho_i of the last density computation (kg/m^3)
    std::vector<double> lambda;    ///< PBF's multipliers of the last iteration
    std::vector<double> pressure;  ///< WCSPH's pressures of the last substep (Pa)

private:
    FluidParameters parameters_;
    std::optional<FluidBox> container_;
    ParticleGrid grid_;
    int threads_ = defaultThreads();
    SecondThread second_;  ///< runs the second half of each pass (threads_ 2)
    // Buffers kept from step to step, so that a step allocates nothing once they have grown.
    /// One particle's neighbours as the kernels see them: one buffer for each half of a pass.
    std::vector<FluidNeighbour> neighbours_[2];
    std::vector<Vec3> delta_;          ///< PBF's moves, or WCSPH's accelerations
    std::vector<Vec3> blended_;        ///< XSPH's velocities
    std::vector<double> nextDensity_;  ///< a density pass's densities, then swapped into density
    std::vector<double> nextLambda_;   ///< a density pass's multipliers, then swapped into lambda
    /// Per rigid body of this step's push: its world bounds grown by radius() and a margin for
    /// rounding. A sphere or box cannot push a particle outside them, so its kernel is not asked.
    std::vector<FluidBox> reach_;

    static int defaultThreads();
    /// pass(begin, end, neighbours) for the particles [begin, end) with a neighbour buffer of their
    /// own: over all of them here, or in two halves on two threads (see the top of this file).
    template <class Pass>
    void eachParticle(const Pass& pass);
    /// `into` := particle i's neighbours at `positions`, with their velocities, densities and
    /// multipliers.
    void gather(std::size_t i, const std::vector<Vec3>& positions, std::vector<FluidNeighbour>& into) const;
    /// The thread that searches for the second half of the particles' neighbours, or nullptr.
    SecondThread* searchThread() { return threads_ > 1 && x.size() >= kThreadedParticles ? &second_ : nullptr; }
    /// The densities at `positions` (fluidDensity()) into density, and Tait's pressures from them
    /// into pressure.
    void densities(const std::vector<Vec3>& positions);
    /// reach_ for `bodies`.
    void boundBodies(const std::vector<Body>& bodies);
    /// q pushed out of every rigid plane, box and sphere in turn (a particle of radius()); with a
    /// velocity, each body that pushes also takes the velocity's part into it. reach_: bodies'.
    void pushOut(Vec3& q, const std::vector<Body>& bodies, Vec3* velocity) const;
    void requireInside(const Vec3& q, const char* what) const;
};

}  // namespace gpl
