// Cloth, ropes and soft bodies (worksheet 8): particles held by position-based constraints, the
// stage state the engine's four soft-body stages share. The engine owns one SoftBodies (its
// softBodies()); a scene without soft bodies leaves it empty and never runs its stages.
//
// One step of h (PhysicsEngine::simulationTimestep() calls them in this order):
//   predict()          v += h (g + wind on the cloth's triangles / m); p = x + h v  (pinned: p = x)
//   findContacts()     which particles lie near the rigid bodies' planes, spheres and boxes, and
//                      which cloth particles lie near each other (a spatial hash)
//   project()          iterations sweeps: every constraint (distance, volume) with its kernel
//                      (soft_constraints.h), then the contacts; lambda starts at 0 each step
//   updateVelocities() v = (p - x) / h; x = p
// A mesh is PBD or XPBD (Method): XPBD uses each constraint's compliance; PBD ignores lambda and
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
};

/// A rectangular cloth of nx x ny particles (nx, ny >= 2), the grid spanning `origin` to
/// origin + (nx - 1) spacing u + (ny - 1) spacing v, u and v unit and perpendicular.
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
/// build the meshes the scenes use.
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

/// A cube of side `side` (m) centred at `centre`, cut into cells x cells x cells cubes of 5 or 6
/// tetrahedra each (cells >= 1).
TetMeshSpec makeSoftCube(const std::string& name, const Vec3& centre, double side, int cells);
/// A ball of radius (m) at centre from a lattice of tetrahedra: cells across its diameter (>= 2).
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
    /// Wind velocity (m/s) felt by cloth triangles, with a drag coefficient (kg/(m^2 s)) >= 0.
    void setWind(const Vec3& velocity, double drag);
    void clear();
    bool empty() const { return x.empty(); }

    // ---- The step's four parts (the engine's stages SoftPredict, SoftContacts, SoftProject,
    // SoftVelocities); bodies are the rigid engine's, read only ----------------------------------
    void predict(double h, const Vec3& gravity, double time);
    void findContacts(const std::vector<Body>& bodies, double h);
    void project(double h, int iterations, const std::vector<Body>& bodies);
    void updateVelocities(double h);

    // ---- Diagnostics --------------------------------------------------------------------------
    double kineticEnergy() const;                            ///< J
    double potentialEnergy(const Vec3& gravity) const;       ///< J, gravitational, zero at the origin
    double elasticEnergy() const;                            ///< J, XPBD constraints' C^2 / (2 alpha)
    /// Largest relative stretch (|x_i - x_j| - rest) / rest over the mesh's links of this kind.
    double largestStretch(std::size_t mesh, LinkKind kind) const;
    /// Volume of the mesh's tetrahedra over their rest volume (1 for a soft body at rest).
    double volumeRatio(std::size_t mesh) const;
    /// Deepest a particle's sphere lies inside a rigid body (m, 0 when none does).
    double deepestPenetration(const std::vector<Body>& bodies) const;
    bool allFinite() const;

    // ---- The particles (structure of arrays) and constraints, read by the viewer and the tests --
    std::vector<Vec3> x;       ///< positions at the end of the last step (m)
    std::vector<Vec3> p;       ///< predicted positions, projected during the step (m)
    std::vector<Vec3> v;       ///< velocities (m/s)
    std::vector<double> w;     ///< inverse masses (1/kg); 0 pinned
    std::vector<double> mass;  ///< masses (kg) as built, kept when pinned
    std::vector<std::uint32_t> meshOf;  ///< each particle's mesh
    std::vector<SoftMesh> meshes;
    std::vector<DistanceLink> links;
    std::vector<TetVolume> volumes;
};

}  // namespace gpl
