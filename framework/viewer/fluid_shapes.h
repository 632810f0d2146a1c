// What the viewer draws of a fluid (worksheet 9), as geometry and colours without any GL: each
// particle's colour by its density error or its speed, the tank walls around the fluid's container
// (drawn as the container's glass box, not as the boxes that would hide the fluid), the particle a
// ray picks, the particles whose sprites can show, and the benchmark's fill of a container. The
// renderer turns these into one vertex array of points; the tests check them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "camera.h"
#include "gpl/engine.h"
#include "gpl/fluids.h"
#include "soft_shapes.h"

namespace gpl::viewer {

/// What a fluid particle's colour shows.
enum class FluidColouring { DensityError, Speed };
const char* fluidColouringName(FluidColouring colouring);  ///< "density error", "speed"

/// The default ranges of the colour maps: +-2 % of the rest density (PBF's iterations hold the
/// compression to about a per cent; a free surface's particles, short of neighbours, read tens of
/// per cent below and saturate blue), and 0 .. 2 m/s (the scenes' flows: a dam break's front runs
/// at about sqrt(2 g a) ~ 2.2 m/s).
constexpr double kDefaultDensityRange = 0.02;
constexpr double kDefaultSpeedRange = 2.0;  ///< m/s

/// A diverging map centred on 0 for t in [-1, 1] (clamped): blue below, white at 0, red above.
void divergingColour(double t, std::uint8_t rgba[4]);
/// A sequential map for t in [0, 1] (clamped): dark blue through teal and green to yellow, its
/// lightness rising with t.
void sequentialColour(double t, std::uint8_t rgba[4]);

/// rho_i / rho0 - 1 from the fluid's last density computation (0 before there is one).
double densityErrorOf(const Fluids& fluid, std::size_t i);

/// Four bytes of particle i's colour, as fluidColours() gives it.
void fluidColour(const Fluids& fluid, std::size_t i, FluidColouring colouring, double range, std::uint8_t rgba[4]);
/// Four bytes per particle: density error over +-range (diverging) or speed over 0 .. range
/// (sequential, range in m/s); range > 0.
void fluidColours(const Fluids& fluid, FluidColouring colouring, double range, std::vector<std::uint8_t>& rgba);

/// "PBF" or "WCSPH": the method the engine's required stages step the fluid with.
const char* fluidMethodName(const PhysicsEngine& engine);

/// True for a static, unturned box outside the container that touches it (within a millimetre): a
/// wall, the floor or the lid of the tank the scene builds around the fluid.
bool isTankWall(const Body& body, const FluidBox& container);

/// The fluid particle whose sphere (of the fluid's radius()) the ray enters first, and how far
/// along the ray; nothing when it misses every one.
std::optional<ParticleHit> pickFluidParticle(const Fluids& fluid, const Ray& ray);

/// How wide (pixels) a particle's sprite is drawn: its sphere's width at the depth of its centre
/// (m along the view), at least kSmallestSprite; pixelsPerMetre is at unit depth, the viewport's
/// height / (2 tan(fovy / 2)). The renderer's point shader computes the same.
constexpr double kSmallestSprite = 2.0;
double spriteWidth(double radius, double depth, double pixelsPerMetre);

/// A coarse depth buffer over the viewport, in square cells of a few pixels, each holding the
/// depth (m along the view) of the nearest sprite known to cover the whole cell: the work space of
/// visibleSprites(), kept from frame to frame so that its memory is reused.
struct SpriteDepths {
    int cell = 1;  ///< pixels on a side
    int columns = 0, rows = 0;
    std::vector<float> nearest;  ///< columns x rows, row 0 at the bottom
    /// Blocks of kBlock x kBlock cells: the farthest of their cells' depths (infinite while a cell
    /// of the block is uncovered), brought up to date when a test needs it after a block changed.
    static constexpr int kBlock = 4;
    int blockColumns = 0, blockRows = 0;
    std::vector<float> farthest;
    std::vector<std::uint8_t> changed;
};

/// The particles of `order` whose sprites can show in a width x height viewport, in the order
/// given; the others are left out. A sprite is drawn as the renderer's point sprites are: a disc
/// as wide as spriteWidth(), every fragment at the depth of the particle's centre. A particle is
/// left out when its disc lies wholly outside the viewport, or when every cell of `work` it touches
/// is covered by a sprite kept before it that is strictly nearer: the depth test would then reject
/// all of its fragments, so leaving it out changes no pixel. Nearest first leaves out the most (a
/// block of fluid shows little more than its outer layers).
void visibleSprites(const Camera& camera, const Fluids& fluid, int width, int height,
                    const std::vector<std::uint32_t>& order, SpriteDepths& work, std::vector<std::uint32_t>& visible);

/// The box the fluid's particles fill, grown by their radius (m); empty without particles.
Bounds fluidBounds(const Fluids& fluid);

/// The pixels the fluid covers (every particle as a sphere of its radius), appended to boxes as
/// movingMeshes() appends a mesh's; false (and nothing appended) when a particle lies behind the eye.
/// Nothing without particles.
bool fluidPixels(const Camera& camera, const Fluids& fluid, int width, int height, std::vector<PixelBox>& boxes);

/// Replaces the fluid's particles by `count` at rest on a cubic lattice at its rest spacing, filling
/// its container layer by layer from the floor and leaving out lattice points inside a static
/// sphere or box; returns how many it placed (fewer when the container is full). Without a
/// container, nothing changes and it returns 0.
std::size_t fillContainer(Fluids& fluid, const std::vector<Body>& bodies, std::size_t count);

}  // namespace gpl::viewer
