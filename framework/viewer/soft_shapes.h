// What the viewer draws of cloth, ropes and soft bodies (worksheet 8), as geometry without any GL:
// the surface normals of a mesh, the tube of a rope, the particle a ray picks, where each mesh lies.
// The renderer turns these into vertex arrays; the tests check them.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "camera.h"
#include "gpl/soft_bodies.h"
#include "scene_shapes.h"

namespace gpl::viewer {

/// Unit normals at the mesh's particles, normals[k] at particle first + k: the sum of the normals
/// of the triangles around the particle, each as long as twice its area (so a large triangle
/// counts more than a sliver), normalised; a particle on no triangle (or on triangles of no
/// area) gets zero. A triangle's normal is (b - a) x (c - a): outward for a soft body, whose
/// triangles are counter-clockwise seen from outside; a cloth is lit on both sides.
void surfaceNormals(const std::vector<Vec3>& x, const SoftMesh& mesh, std::vector<Vec3>& normals);

/// Triangles with a normal per vertex (m, unit).
struct TriangleMesh {
    std::vector<Vec3> vertices, normals;
    std::vector<std::uint32_t> indices;  ///< three per triangle, counter-clockwise seen from outside
};

/// A rope's chain as cylinders of this radius (m), one per segment between points[i] and
/// points[i + 1], each with `sides` vertices on either end ring: segment i's vertices are
/// [2 sides i, 2 sides (i + 1)), so each segment can take a colour of its own. The rings turn with
/// the chain (parallel transport), so that neighbouring cylinders meet without a twist.
TriangleMesh ropeTube(const std::vector<Vec3>& points, double radius, int sides);

/// Radius (m) a rope's particles are drawn and picked with: its contact radius, and at least a
/// fifth of its mean segment, so that a thin rope still shows as a chain.
double ropeDrawRadius(const SoftBodies& soft, std::size_t mesh);

/// The particle a ray picks and how far along the ray (m) it hits the mesh.
struct ParticleHit {
    std::uint32_t particle = 0;
    double distance = 0.0;
};

/// The particle under a ray: where the ray first crosses a cloth's or soft body's triangles (from
/// either side), that triangle's corner nearest the crossing, or the particle whose sphere (of its
/// radius) the ray enters first, whichever is nearer; a rope's particle whose sphere of
/// ropeDrawRadius() the ray enters first. Nothing when the ray misses every mesh.
std::optional<ParticleHit> pickParticle(const SoftBodies& soft, const Ray& ray);

/// A particle by its mesh's name and its index in the mesh ("flag#0"); nothing when there is no
/// such mesh or index.
std::optional<std::uint32_t> particleByName(const SoftBodies& soft, const std::string& meshHashIndex);
/// "flag#0": the particle's mesh and its index in the mesh.
std::string particleName(const SoftBodies& soft, std::uint32_t particle);

/// The mesh's distance links and tetrahedra.
std::size_t constraintCount(const SoftBodies& soft, std::size_t mesh);

/// The largest relative stretch a mesh shows: over its grid's edges for a cloth, its segments for
/// a rope, its edges for a soft body (SoftBodies::largestStretch() of that kind).
double meshStretch(const SoftBodies& soft, std::size_t mesh);

/// The box the mesh's particles fill, grown by their radius (m).
Bounds meshBounds(const SoftBodies& soft, std::size_t mesh);

/// The pixels each mesh with a particle free to move covers (every particle as a sphere of its
/// radius, a rope's of ropeDrawRadius()), in the meshes' order, as Camera::movingBodies() gives
/// the bodies'; false (and fewer boxes) when a particle lies behind the eye.
bool movingMeshes(const Camera& camera, const SoftBodies& soft, int width, int height, std::vector<PixelBox>& boxes);

/// True when some particle of the mesh is free to move (inverse mass > 0).
bool meshMoves(const SoftBodies& soft, std::size_t mesh);

}  // namespace gpl::viewer
