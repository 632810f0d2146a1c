// Cloth, ropes and soft bodies (worksheet 8): particles held by position-based constraints, the
// stage state the engine's four soft-body stages share. The engine owns one SoftBodies (its
// softBodies()); a scene without soft bodies leaves it empty and never runs its stages.
//
// One step of h (PhysicsEngine::simulationTimestep() calls them in this order):
//   predict()          v += h (g + wind on the cloth's triangles / m); p = x + h v  (pinned: p = x)
//   findContacts()     which particles lie near the rigid bodies' planes, spheres and boxes, and
//                      which cloth particles lie near each other (a spatial hash)
//   project()          iterations sweeps: every constraint (distance, volume) with its kernel
//                      (soft_constraints.h), then the contacts, each pushed out and held by
//                      friction; lambda starts at 0 each step; then a particle the sweeps pulled
//                      into a body that findContacts() did not find near it is pushed out
//   updateVelocities() v = (p - x) / h; x = p
// A mesh is PBD or XPBD (SoftMethod): XPBD uses each constraint's compliance; PBD ignores lambda and
// scales each projection with alpha = 0 by the per-iteration stiffness 1 - (1 - k)^(1/n), so what
// stiffness a mesh shows depends on the iteration count n and the step, as the worksheet teaches.
// Rigid bodies push particles (one way): a particle in contact moves out of the body and keeps
// no velocity into it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "gpl/body.h"
#include "gpl/math.h"
#include "gpl/second_thread.h"

namespace gpl {

/// How a mesh's constraints are projected.
enum class SoftMethod {
    PBD,   ///< Mueller et al. 2007: per-iteration stiffness k in [0, 1], no multiplier
    XPBD,  ///< Macklin, Mueller, Chentanez 2016: compliance and a multiplier per constraint
};

/// What a distance constraint holds (the viewer colours and the study counts them apart).
enum class LinkKind { Stretch, Shear, Bend, Edge, Rope };

/// Two particles held at a rest distance.
struct DistanceLink {
    std::uint32_t i = 0, j = 0;  ///< particle indices
    double rest = 0.0;           ///< m, >= 0
    double compliance = 0.0;     ///< m/N, >= 0 (XPBD)
    double stiffness = 1.0;      ///< in [0, 1] (PBD)
    LinkKind kind = LinkKind::Stretch;
    double lambda = 0.0;         ///< multiplier summed over this step's iterations
};

/// A tetrahedron held at its rest volume.
struct TetVolume {
    std::array<std::uint32_t, 4> v{};  ///< particle indices, ordered so that the rest volume is > 0
    double rest = 0.0;                 ///< m^3, > 0
    double compliance = 0.0;           ///< 1/(N m), >= 0 (XPBD)
    double stiffness = 1.0;            ///< in [0, 1] (PBD)
    double lambda = 0.0;
};

/// One cloth, rope or soft body: a range of the particles and what the viewer draws of it.
struct SoftMesh {
    enum class Kind { Cloth, Rope, SoftBody };
    std::string name;
    Kind kind = Kind::Cloth;
    SoftMethod method = SoftMethod::XPBD;
    std::uint32_t first = 0, count = 0;  ///< its particles: [first, first + count)
    /// Triangles of the drawn surface (particle indices, counter-clockwise seen from outside for a
    /// soft body); a rope has none and is drawn as its chain of particles.
    std::vector<std::array<std::uint32_t, 3>> triangles;
    double radius = 0.0;        ///< m, each particle's radius for contacts (a cloth's half thickness)
    bool selfCollision = false;  ///< cloth: particles of this mesh push each other apart
    /// Its constraints: links [firstLink, firstLink + linkCount), volumes [firstVolume, +volumeCount).
    std::uint32_t firstLink = 0, linkCount = 0;
    std::uint32_t firstVolume = 0, volumeCount = 0;
    /// A large mesh's links are stored as two halves and the rest (soft_sweeps.h): the halves' link
    /// counts, the first's from firstLink on, then the second's; 0 and 0 when it is not cut.
    std::uint32_t firstHalfLinks = 0, secondHalfLinks = 0;
    /// Of each half's links, how many at its end wait for the rest of the sweep before them: those
    /// that share a particle with the rest's links and volumes, or with an earlier such link.
    std::uint32_t firstHalfWaiting = 0, secondHalfWaiting = 0;
    int nx = 0, ny = 0;  ///< cloth: the grid's size; particle (i, j) is first + j nx + i
};

/// A particle near a rigid body this step (found once per step by findContacts()).
struct ParticleContact {
    std::uint32_t particle = 0;
    std::uint32_t body = 0;          ///< index into the rigid engine's bodies
    Vec3 normal = Vec3::UnitY();     ///< the direction of the last push out of the body (unit)
    Vec3 bodyVelocity = Vec3::Zero();  ///< the body's velocity at the particle then (m/s)
    double depth = 0.0;              ///< how far the body pushed the particle in this step's sweeps (m)
    Vec3 friction = Vec3::Zero();    ///< the friction's moves of the particle in this step's sweeps, summed (m)
    bool pushed = false;             ///< the body pushed the particle out during this step
};

/// The order in which a mesh's links are swept (a large mesh stores them in an order that gives
/// the same result, halvesOrder() in soft_sweeps.h): order[k] is the index among `links`
/// (as built) of the link stored at k. Links that share a particle keep the order they were built
/// in, so a sweep gives the same result to the bit as in the built order; and they come in waves of
/// links that share no particle (each link in the first wave after those of the earlier links it
/// shares a particle with), so that one projection need not wait for the move the one before made.
/// A grid's rows, swept one link after the other, then lie side by side and the processor projects
/// several links at once; a chain keeps its order. `particles`: more than any index in links.
std::vector<std::uint32_t> sweepOrder(const std::vector<DistanceLink>& links, std::size_t particles);

/// A rectangular cloth of nx x ny particles (nx, ny >= 2), the grid spanning `origin` to
/// origin + (nx - 1) spacing u + (ny - 1) spacing v, u and v unit and perpendicular. Particle (i, j)
/// starts at origin + spacing (i u + j v). Its constraints, built in this order (and stored in
/// sweepOrder()):
///   stretch  the grid's edges: (nx - 1) ny + nx (ny - 1) links
///   shear    both diagonals of every cell: 2 (nx - 1)(ny - 1) links
///   bend     for every inner edge of the grid (an edge between two cells), the two corners
///            opposite it in the two triangles that share it: (nx - 1)(ny - 2) + (nx - 2)(ny - 1)
///            links. A cell's own diagonal is shared by its two triangles too, but their opposite
///            corners are the cell's other diagonal, which shear holds already, so it adds none.
/// Each kind row by row, top (j = 0) to bottom; in a cloth of kHalvesFrom links or more (cut in
/// halves, soft_sweeps.h), the rows from both edges towards the middle (j = 0, ny - 2, 1, ...), the
/// bend links by their inner edge's row. Each cell is drawn as two triangles, split along alternate
/// diagonals (a checkerboard), counter-clockwise seen from the side u x v points to.
struct ClothSpec {
    std::string name = "cloth";
    int nx = 16, ny = 16;
    double spacing = 0.1;                  ///< m between neighbours, > 0
    Vec3 origin = Vec3::Zero();
    Vec3 u = Vec3::UnitX(), v = Vec3::UnitZ();
    double mass = 1.0;                     ///< kg of the whole cloth, > 0, shared equally
    SoftMethod method = SoftMethod::XPBD;
    double stretchCompliance = 0.0;        ///< m/N, >= 0: the grid's edges
    double shearCompliance = 1e-4;         ///< m/N, >= 0: the cells' diagonals
    double bendCompliance = 1e-2;          ///< m/N, >= 0: across every inner edge, the opposite corners
    double stiffness = 1.0;                ///< PBD only, in [0, 1]
    double radius = 0.01;                  ///< m, > 0
    bool selfCollision = false;
    std::vector<std::array<int, 2>> pinned;  ///< grid cells (i, j) held where they start
};

/// A chain of `segments` + 1 particles from `start` to `end`; `pinStart` holds the first.
struct RopeSpec {
    std::string name = "rope";
    int segments = 50;                     ///< >= 1
    Vec3 start = Vec3::Zero(), end = Vec3::UnitX();
    double mass = 1.0;                     ///< kg, > 0, shared equally
    SoftMethod method = SoftMethod::XPBD;
    double compliance = 0.0;               ///< m/N, >= 0
    double stiffness = 1.0;                ///< PBD only, in [0, 1]
    double radius = 0.02;                  ///< m, > 0
    bool pinStart = true;
};

/// A soft body from a tetrahedral mesh: particle positions, tetrahedra (each of positive volume
/// as given), edges and volumes held with their compliances. makeSoftCube() and makeSoftBall()
/// build the meshes the scenes use. Its constraints: every edge of the tetrahedra once (Edge
/// links), then one volume per tetrahedron; its surface: the tetrahedra's faces that no other
/// tetrahedron shares, counter-clockwise seen from outside. Every position must be a corner of a
/// tetrahedron (it takes its mass from them).
struct TetMeshSpec {
    std::string name = "soft";
    std::vector<Vec3> positions;
    std::vector<std::array<int, 4>> tets;
    double density = 100.0;                ///< kg/m^3, > 0: each tet's mass shared by its corners
    SoftMethod method = SoftMethod::XPBD;
    double edgeCompliance = 1e-5;          ///< m/N, >= 0
    double volumeCompliance = 0.0;         ///< 1/(N m), >= 0
    double stiffness = 1.0;                ///< PBD only, in [0, 1]
    double radius = 0.01;                  ///< m, > 0
};

/// A cube of side `side` (m) centred at `centre`, cut into cells x cells x cells cubes of 6
/// tetrahedra each (cells >= 1), all around one diagonal of the cell (Kuhn's split), mirrored from
/// cell to cell along each axis so that neighbours share their faces' diagonals and an even number
/// of cells is symmetric like the cube; every tetrahedron of positive volume.
/// Throws std::invalid_argument naming the mesh on cells < 1 or a side that is not positive.
TetMeshSpec makeSoftCube(const std::string& name, const Vec3& centre, double side, int cells);
/// A ball of radius (m) at centre from a lattice of tetrahedra: cells x cells x cells cubes across
/// its diameter (>= 2), split as in makeSoftCube(), keeping the tetrahedra whose centroid lies in
/// the ball; each vertex on the surface then moves out onto the sphere unless that would leave one
/// of its tetrahedra with less than a tenth of its lattice volume.
TetMeshSpec makeSoftBall(const std::string& name, const Vec3& centre, double radius, int cells);

class SoftBodies {
public:
    // ---- Building (each throws std::invalid_argument with one line naming the mesh and the field
    // before anything steps: nx or ny < 2, a spacing, mass or radius <= 0 or not finite, a
    // compliance < 0, a stiffness outside [0, 1], a pinned cell or tet index out of range, a
    // tetrahedron of zero or negative volume, a name already used) -------------------------------
    std::size_t addCloth(const ClothSpec& spec);
    std::size_t addRope(const RopeSpec& spec);
    std::size_t addSoftBody(const TetMeshSpec& spec);
    /// Pins (inverse mass 0) or frees a particle; throws std::out_of_range on a bad index.
    void setPinned(std::uint32_t particle, bool pinned);
    /// Wind velocity (m/s) felt by cloth triangles, with a drag coefficient (kg/(m^2 s)) >= 0; throws
    /// std::invalid_argument when either is not finite or the drag is negative. Each triangle
    /// feels drag ((wind(t) - v_tri) . n) n area, shared by its three corners, where wind(t) is the
    /// velocity with a gust (windAt()).
    void setWind(const Vec3& velocity, double drag);
    /// The wind at time t (s) at point q (m): the set velocity, stronger and weaker by up to a
    /// quarter in waves that travel downwind, and turned sideways (horizontally, across it) by up to
    /// a fifth of its speed: deterministic, so that a replay is the same.
    Vec3 windAt(double t, const Vec3& q) const;
    const Vec3& wind() const { return wind_; }
    double windDrag() const { return windDrag_; }
    /// Removes every particle, mesh and constraint, and the wind.
    void clear();
    bool empty() const { return x.empty(); }
    /// The mesh with this name; throws std::out_of_range when there is none.
    std::size_t meshIndex(const std::string& name) const;

    // ---- The step's four parts (the engine's stages SoftPredict, SoftContacts, SoftProject,
    // SoftVelocities); bodies are the rigid engine's, read only ----------------------------------
    /// v += h (gravity + wind force / m) and p = x + h v for every free particle; a pinned one
    /// keeps p = x and v = 0. time (s) is the step's start, for the wind's gusts.
    void predict(double h, const Vec3& gravity, double time);
    /// Once per step, after predict(): contacts holds every particle-body pair (planes, spheres,
    /// boxes) nearer than the particle's radius plus how far the particle and the body travel in
    /// this step plus one radius more (for the constraints' moves); selfPairs holds the pairs of a
    /// self-colliding cloth nearer than two radii plus twice the farthest travel relative to the
    /// cloth's mean move, from a spatial hash, leaving out pairs whose rest distance is below two
    /// radii (neighbours in the cloth).
    void findContacts(const std::vector<Body>& bodies, double h);
    /// Lambdas to 0, then `iterations` sweeps, each: every mesh's links with
    /// solveDistanceConstraint() and volumes with solveVolumeConstraint(); the self-collision
    /// pairs pushed to two radii apart (shared by inverse mass); every contact pushed out of its
    /// body with projectParticleSphere(), projectParticleBox() or the plane's projection, and
    /// while it touches the body (pushed in this sweep, or earlier in this step and still on the
    /// surface) held by positional friction: its slide along the surface in this step so far,
    /// relative to the body's, is stopped when the step's friction moves, summed, then stay within
    /// mu_s times the step's pushes, summed; otherwise the summed friction is mu_d times the pushes,
    /// against the slide (mu_s, mu_d: the body's staticFriction and friction; the Coulomb cone of
    /// worksheet 7's sequential impulses, on moves). Friction inside the sweeps lets the next
    /// sweep's links answer it, and each contact ends a sweep outside its body: the friction moves
    /// along the plane of the last push, which touches the (convex) body, or is followed by a push.
    /// After the sweeps, a free particle that the constraints pulled more than a millionth of its
    /// radius into a body that findContacts() did not expect near it is pushed out and kept as a
    /// contact: no particle ends the step inside a body.
    void project(double h, int iterations, const std::vector<Body>& bodies);
    /// v = (p - x) / h and x = p; a particle a body pushed keeps no velocity into it (relative to the
    /// body's at that point).
    void updateVelocities(double h);
    /// Threads of project(), 1 or 2 (2 where the machine has two cores): a mesh cut in halves
    /// (soft_sweeps.h) has them swept at once on two; the result is the same to the bit on one.
    /// Throws std::invalid_argument when threads < 1.
    void setThreads(int threads);
    int threads() const { return threads_; }

    // ---- Diagnostics --------------------------------------------------------------------------
    double kineticEnergy() const;                            ///< J
    double potentialEnergy(const Vec3& gravity) const;       ///< J, gravitational, zero at the origin
    double elasticEnergy() const;                            ///< J, XPBD constraints' C^2 / (2 alpha)
    /// Largest relative stretch (|x_i - x_j| - rest) / rest over the mesh's links of this kind.
    double largestStretch(std::size_t mesh, LinkKind kind) const;
    /// Volume of the mesh's tetrahedra over their rest volume (1 for a soft body at rest).
    double volumeRatio(std::size_t mesh) const;
    /// Deepest a particle's sphere lies inside a rigid plane, sphere or box (m, 0 when none does).
    double deepestPenetration(const std::vector<Body>& bodies) const;
    bool allFinite() const;
    /// The first free particle whose position or velocity is not finite, else the first pinned one
    /// (a pinned particle turns NaN only through a neighbour's constraint, 0 times NaN), or none
    /// (std::size_t(-1)).
    std::size_t firstNonFinite() const;
    /// Links and volumes of every mesh.
    std::size_t constraintCount() const { return links.size() + volumes.size(); }

    // ---- The particles (structure of arrays) and constraints, read by the viewer and the tests --
    std::vector<Vec3> x;       ///< positions at the end of the last step (m)
    std::vector<Vec3> p;       ///< predicted positions, projected during the step (m)
    std::vector<Vec3> v;       ///< velocities (m/s)
    std::vector<double> w;     ///< inverse masses (1/kg); 0 pinned
    std::vector<double> mass;  ///< masses (kg) as built, kept when pinned
    std::vector<std::uint32_t> meshOf;  ///< each particle's mesh
    std::vector<SoftMesh> meshes;
    std::vector<Vec3> x0;      ///< positions as built (m): rest shapes, for self-collision's neighbours
    std::vector<DistanceLink> links;
    std::vector<TetVolume> volumes;
    std::vector<ParticleContact> contacts;  ///< this step's particle-body pairs (findContacts())
    std::vector<std::array<std::uint32_t, 2>> selfPairs;  ///< this step's self-collision pairs

private:
    Vec3 wind_ = Vec3::Zero();
    double windDrag_ = 0.0;
    // Buffers kept from step to step, so that a step allocates nothing once they have grown.
    std::vector<Vec3> force_;                 ///< wind force per particle (N)
    std::vector<std::uint32_t> cellStart_;    ///< the spatial hash: each cell's first entry
    std::vector<std::uint32_t> cellEntries_;  ///< particles sorted by cell
    std::vector<std::uint32_t> nearby_;       ///< one particle's neighbours while they are collected
    int threads_ = defaultThreads();
    // For two threads only (projectInHalves(), soft_sweeps.cpp).
    SecondThread second_;  ///< sweeps a cut mesh's second half (threads_ 2)
    /// Per particle: a link or volume of a cut mesh's rest moves it (soft_sweeps.h), so its contacts
    /// wait for the rest; set as the meshes are built.
    std::vector<char> movedByRest_;
    std::vector<char> selfPaired_;  ///< per particle: in a self-collision pair this step (while grouping)
    /// This step's contact groups (soft_sweeps.h): mesh m's halves' contacts from contactGroups_[2 m]
    /// and [2 m + 1] to the next group's start, the rest from contactGroups_[2 M] (M meshes) on, of
    /// which those of cut meshes' second halves from contactGroups_[2 M + 1] on.
    std::vector<std::size_t> contactGroups_;
    std::vector<std::size_t> groupEnds_;    ///< each group's end while the contacts are grouped
    std::vector<ParticleContact> grouped_;  ///< the contacts while they are grouped
    static int defaultThreads();

    std::size_t addMesh(SoftMesh mesh);
    void collectSelfPairs(const SoftMesh& mesh, double travel);
    /// One sweep of the mesh's links from firstLink on, then of its volumes, with their kernels.
    void sweepMesh(const SoftMesh& mesh, std::uint32_t firstLink, double h, int iterations);
    void pushSelfPairs();
    /// Contacts [begin, end) pushed out of their bodies, with friction.
    void pushOutOfBodies(double h, const std::vector<Body>& bodies, std::size_t begin, std::size_t end);
    /// project() where a mesh is cut in halves and threads_ is 2 (soft_sweeps.cpp).
    void projectInHalves(double h, int iterations, const std::vector<Body>& bodies);
    /// Groups the contacts by the halves of their particles (soft_sweeps.h) into contactGroups_.
    void groupContacts();
    Vec3 pushedOut(const Body& body, const Vec3& q, double r) const;
    /// Moves the contact's particle (radius r) to `moved` and counts the push; false when it moves
    /// no more than the rounding of a particle on the surface.
    bool push(ParticleContact& contact, const Vec3& moved, double r);
    /// The contact's friction in one sweep; false when it moves nothing.
    bool applyFriction(ParticleContact& contact, double h, const Body& body);
    void catchMissedContacts(const std::vector<Body>& bodies);
};

}  // namespace gpl
