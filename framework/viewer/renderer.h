// Draws a session with fixed-function OpenGL (GL 2, as Mesa's llvmpipe runs it well): shaded
// spheres (in two shades by octant, so that their spin shows) and boxes with their orientation, the
// ground as tiles (a scene without a floor has none), other planes as translucent walls around the
// scene, blob shadows and fog as depth cues, static bodies in grey and movable ones in colour,
// springs, rods and ropes, the selection, the drag spring, the reference ghost and, on request, the
// contacts. Bodies are batched into one vertex array per frame: a thousand bodies cost a few draw
// calls, not thousands. Cloth, ropes and soft bodies (renderer_soft.cpp) are a vertex array per
// mesh: a cloth a lit surface, both sides, a soft body its outer surface, a rope a chain of beads.
// A fluid (renderer_fluid.cpp) is one array of points, each a shaded sprite of the particle's size,
// in its container's glass box (the tank's walls are not drawn: they would hide it).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "camera.h"
#include "fluid_shapes.h"
#include "session.h"

namespace gpl::viewer {

class Renderer {
public:
    Renderer();
    /// What is drawn besides the scene.
    struct Options {
        std::optional<std::size_t> hovered;            ///< the body under the cursor, drawn lighter
        std::optional<std::uint32_t> hoveredParticle;  ///< the particle under the cursor, marked
        bool contacts = false;                         ///< the contacts of the last step
        bool softWire = false;                         ///< the soft bodies' links over their surfaces
        std::optional<std::uint32_t> hoveredFluidParticle;  ///< the fluid particle under the cursor, marked
        FluidColouring fluidColouring = FluidColouring::DensityError;  ///< what a fluid particle's colour shows
        double fluidRange = kDefaultDensityRange;      ///< the colour map's range (fluidColours())
    };
    /// Draws into the viewport (0, 0, width, height) of the window: the part the side panel leaves.
    void draw(const Session& session, const Camera& camera, int width, int height, const Options& options);

    /// Indexed vertices (llvmpipe shades each vertex once however many triangles share it).
    struct Mesh {
        std::vector<Vec3> vertices, normals;
        std::vector<std::uint8_t> marks;     ///< per vertex, 1 where a sphere's marked octants are
        std::vector<std::uint32_t> indices;  ///< triangles
    };
    struct Batch {
        std::vector<float> positions, normals;
        std::vector<std::uint8_t> colours;
        std::vector<std::uint32_t> indices;
        void clear() { positions.clear(), normals.clear(), colours.clear(), indices.clear(); }
        std::uint32_t add(const Vec3& p, const Vec3& n, const std::uint8_t rgba[4]);
        void draw(unsigned mode) const;  ///< indexed when it has indices
        /// Drawn blended by alpha over what is already drawn, without writing depth (glass, ghosts).
        void drawTranslucent(unsigned mode) const;
    };

private:
    /// Appends a sphere or a box to the batch, turned as the body is; the sphere's detail follows its
    /// size on screen.
    void append(Batch& batch, const Body& body, const std::uint8_t rgba[4], const Camera& camera, int height) const;
    /// Appends a ball of this centre and radius (m), from the sphere mesh of this detail (0 fine .. 2 coarse).
    void appendBall(Batch& batch, const Vec3& centre, double radius, const std::uint8_t rgba[4], int detail) const;
    /// Appends one mesh's surface (a cloth's or a soft body's) or a rope's beads and tube, at the
    /// particle positions x.
    void appendSoftMesh(Batch& batch, const SoftBodies& soft, std::size_t mesh, const std::vector<Vec3>& x,
                        const std::uint8_t rgba[4]);
    /// The soft bodies: each mesh's surface or chain, lit; its links on request; pinned, hovered and
    /// selected particles marked; the drag's line to the cursor.
    void drawSoftBodies(const Session& session, const Options& options);
    /// The reference ghost's soft bodies, translucent.
    void drawSoftGhost(const Session& session);
    /// The fluid's particles in one call, coloured by options; the hovered and selected particle
    /// marked, the drag's line to the cursor.
    void drawFluid(const Session& session, const Camera& camera, int width, int height, const Options& options);
    /// The fluid's container: its edges, and its far faces as glass.
    void drawFluidContainer(const Session& session, const Camera& camera);
    /// The sprite program, compiled at the first use; false where GLSL is not available.
    bool fluidProgramReady();
    /// fluidOrder_ := the particles' indices from the nearest to the farthest from the eye.
    void depthOrder(const Fluids& fluid, const Camera& camera);

    Mesh sphere_[3];  ///< unit spheres with marked octants, fine to coarse
    Mesh cube_;       ///< the cube [-1, 1]^3
    Mesh disc_;       ///< unit disc in the x-z plane
    Batch solid_, translucent_, shadows_, lines_, points_;
    std::vector<Vec3> normals_;  ///< a soft mesh's, per particle
    struct FluidVertex {
        float position[3];
        std::uint8_t colour[4];
    };
    std::vector<FluidVertex> fluidVertices_;    ///< the particles drawn, in fluidShown_'s order
    std::vector<std::uint32_t> fluidOrder_;     ///< the particles front to back (depthOrder())
    std::vector<std::uint32_t> fluidShown_;     ///< those of fluidOrder_ that can show (visibleSprites())
    SpriteDepths fluidDepths_;                  ///< visibleSprites()'s work space
    std::vector<float> fluidKeys_;              ///< depthOrder()'s work space
    std::vector<std::size_t> fluidBuckets_;     ///< depthOrder()'s work space
    unsigned fluidProgram_ = 0;                 ///< GL program name, 0 when none
    bool fluidProgramTried_ = false;
};

}  // namespace gpl::viewer
