// Draws a session with fixed-function OpenGL (GL 2, as Mesa's llvmpipe runs it well): shaded
// spheres (in two shades by octant, so that their spin shows) and boxes with their orientation, the
// ground as tiles (a scene without a floor has none), other planes as translucent walls around the
// scene, blob shadows and fog as depth cues, static bodies in grey and movable ones in colour,
// springs, rods and ropes, the selection, the drag spring, the reference ghost and, on request, the
// contacts. Bodies are batched into one vertex array per frame: a thousand bodies cost a few draw
// calls, not thousands.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "camera.h"
#include "session.h"

namespace gpl::viewer {

class Renderer {
public:
    Renderer();
    /// Draws into the viewport (0, 0, width, height) of the window: the part the side panel leaves.
    void draw(const Session& session, const Camera& camera, int width, int height, std::optional<std::size_t> hovered,
              bool showContacts);

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
    };

private:
    /// Appends a sphere or a box to the batch, turned as the body is; the sphere's detail follows its
    /// size on screen.
    void append(Batch& batch, const Body& body, const std::uint8_t rgba[4], const Camera& camera, int height) const;

    Mesh sphere_[3];  ///< unit spheres with marked octants, fine to coarse
    Mesh cube_;       ///< the cube [-1, 1]^3
    Mesh disc_;       ///< unit disc in the x-z plane
    Batch solid_, translucent_, shadows_, lines_, points_;
};

}  // namespace gpl::viewer
