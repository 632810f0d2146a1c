#include "fluid_shapes.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gpl::viewer {
namespace {

// Piecewise linear through evenly spaced stops (r, g, b) at t = 0, 1 / (n - 1), ..., 1.
template <std::size_t N>
void throughStops(const std::uint8_t (&stops)[N][3], double t, std::uint8_t rgba[4]) {
    t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0) * (N - 1);
    const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(t), N - 2);
    const double f = t - k;
    for (int c = 0; c < 3; ++c) {
        rgba[c] = static_cast<std::uint8_t>(std::lround(stops[k][c] + f * (stops[k + 1][c] - stops[k][c])));
    }
    rgba[3] = 255;
}

}  // namespace

const char* fluidColouringName(FluidColouring colouring) {
    return colouring == FluidColouring::Speed ? "speed" : "density error";
}

void divergingColour(double t, std::uint8_t rgba[4]) {
    // Blue, white, red: equal steps of lightness either side of the white centre.
    static const std::uint8_t stops[5][3] = {{40, 70, 170}, {120, 160, 225}, {245, 245, 245}, {235, 140, 110}, {180, 30, 40}};
    throughStops(stops, 0.5 * ((std::isfinite(t) ? t : 0.0) + 1.0), rgba);
}

void sequentialColour(double t, std::uint8_t rgba[4]) {
    // Dark blue, blue, teal, green, yellow (after viridis): lighter with every stop.
    static const std::uint8_t stops[5][3] = {{50, 30, 110}, {55, 90, 160}, {35, 145, 140}, {95, 195, 90}, {250, 230, 40}};
    throughStops(stops, t, rgba);
}

double densityErrorOf(const Fluids& fluid, std::size_t i) {
    if (i >= fluid.density.size()) return 0.0;
    return fluid.density[i] / fluid.parameters().restDensity - 1.0;
}

void fluidColour(const Fluids& fluid, std::size_t i, FluidColouring colouring, double range, std::uint8_t rgba[4]) {
    const double inverse = 1.0 / std::max(range, 1e-12);
    if (colouring == FluidColouring::Speed) {
        sequentialColour(fluid.v[i].norm() * inverse, rgba);
    } else {
        divergingColour(densityErrorOf(fluid, i) * inverse, rgba);
    }
}

void fluidColours(const Fluids& fluid, FluidColouring colouring, double range, std::vector<std::uint8_t>& rgba) {
    const std::size_t n = fluid.size();
    rgba.resize(4 * n);
    for (std::size_t i = 0; i < n; ++i) fluidColour(fluid, i, colouring, range, &rgba[4 * i]);
}

const char* fluidMethodName(const PhysicsEngine& engine) {
    return engine.requiredStages().contains(Stage::FluidSph) ? "WCSPH" : "PBF";
}

bool isTankWall(const Body& body, const FluidBox& container) {
    constexpr double kTouch = 1e-3;  // m: walls laid against the container, within a millimetre
    if (!body.isStatic() || body.shape != Shape::Box) return false;
    if (!body.orientation.toRotationMatrix().isIdentity(1e-9)) return false;
    const Vec3 lower = body.position - body.halfExtents, upper = body.position + body.halfExtents;
    // Outside: some axis where the box lies beyond a face of the container (to the tolerance) ...
    bool outside = false;
    // ... and touching: within the tolerance of the container on every axis.
    bool near = true;
    for (int k = 0; k < 3; ++k) {
        outside = outside || upper[k] <= container.lower[k] + kTouch || lower[k] >= container.upper[k] - kTouch;
        near = near && upper[k] >= container.lower[k] - kTouch && lower[k] <= container.upper[k] + kTouch;
    }
    return outside && near;
}

std::optional<ParticleHit> pickFluidParticle(const Fluids& fluid, const Ray& ray) {
    const double r = fluid.radius();
    const Vec3 d = ray.direction.normalized();
    std::optional<ParticleHit> best;
    for (std::size_t i = 0; i < fluid.size(); ++i) {
        // |o + t d - x|^2 = r^2: t = b - sqrt(b^2 - c) with b = (x - o) . d, c = |x - o|^2 - r^2.
        const Vec3 to = fluid.x[i] - ray.origin;
        const double b = to.dot(d), c = to.squaredNorm() - r * r;
        const double disc = b * b - c;
        if (disc < 0.0) continue;
        const double t = c <= 0.0 ? 0.0 : b - std::sqrt(disc);  // from inside: at once
        if (t < 0.0) continue;
        if (!best || t < best->distance) best = ParticleHit{static_cast<std::uint32_t>(i), t};
    }
    return best;
}

double spriteWidth(double radius, double depth, double pixelsPerMetre) {
    return std::max(kSmallestSprite, 2.0 * radius * pixelsPerMetre / std::max(depth, 1e-3));
}

void visibleSprites(const Camera& camera, const Fluids& fluid, int width, int height,
                    const std::vector<std::uint32_t>& order, SpriteDepths& work, std::vector<std::uint32_t>& visible) {
    constexpr double kPi = 3.14159265358979323846;
    // A sprite marks the cells it covers only up to this width (pixels): far below the largest point
    // a GL implementation draws, so that no sprite is drawn smaller than it is marked.
    constexpr double kLargestOccluder = 64.0;
    // A fragment is drawn where a pixel's centre lies in the disc. A cell counts as covered when its
    // pixels' centres lie kSlack inside a disc, and a disc is looked up in every cell with a pixel's
    // centre within kSlack beyond its edge: room for the rasteriser's rounding of a sprite's place.
    constexpr double kSlack = 0.25;  // pixels
    visible.clear();
    width = std::max(width, 1), height = std::max(height, 1);
    const double pixelsPerMetre = 0.5 * height / std::tan(Camera::kFieldOfViewY * kPi / 360.0);
    const Vec3 eye = camera.eye(), forward = camera.forward(), right = camera.right(), up = camera.up();
    const double radius = fluid.radius();
    // Cells about a fifth of a sprite at the camera's target: a few to a sprite, whatever the zoom.
    work.cell = static_cast<int>(std::clamp(spriteWidth(radius, camera.distance(), pixelsPerMetre) / 5.0, 2.0, 16.0));
    work.columns = (width + work.cell - 1) / work.cell, work.rows = (height + work.cell - 1) / work.cell;
    work.nearest.assign(static_cast<std::size_t>(work.columns) * work.rows, HUGE_VALF);
    constexpr int kBlock = SpriteDepths::kBlock;
    work.blockColumns = (work.columns + kBlock - 1) / kBlock, work.blockRows = (work.rows + kBlock - 1) / kBlock;
    work.farthest.assign(static_cast<std::size_t>(work.blockColumns) * work.blockRows, HUGE_VALF);
    work.changed.assign(work.farthest.size(), 0);
    // A block's farthest depth, brought up to date.
    const auto blockFarthest = [&](int bc, int br) {
        const std::size_t b = static_cast<std::size_t>(br) * work.blockColumns + bc;
        if (work.changed[b]) {
            work.changed[b] = 0;
            float far = 0.0f;
            const int cEnd = std::min(work.columns, (bc + 1) * kBlock), rEnd = std::min(work.rows, (br + 1) * kBlock);
            for (int r = br * kBlock; r < rEnd; ++r) {
                const float* row = &work.nearest[static_cast<std::size_t>(r) * work.columns];
                for (int c = bc * kBlock; c < cEnd; ++c) far = std::max(far, row[c]);
            }
            work.farthest[b] = far;
        }
        return work.farthest[b];
    };
    // In cells from here on (single precision: a few thousand cells across); a pixel's centre lies
    // half a pixel inside its cell's edge.
    const float perCell = 1.0f / static_cast<float>(work.cell), margin = 0.5f * perCell;
    const float span = 1.0f - 2.0f * margin;  // from a cell's first pixel centre to its last
    // floor() of a number above -kOffset, by truncation.
    constexpr float kOffset = 4096.0f;
    const auto floorOf = [](float v) { return static_cast<int>(v + kOffset) - static_cast<int>(kOffset); };
    const auto ceilOf = [&](float v) { return -floorOf(-v); };
    for (std::uint32_t i : order) {
        const Vec3 d = fluid.x[i] - eye;
        const double depth = d.dot(forward);
        if (!(depth > Camera::kNear)) {  // near the eye or behind it: left to GL's clipping
            visible.push_back(i);
            continue;
        }
        const double half = 0.5 * spriteWidth(radius, depth, pixelsPerMetre);
        const double px = 0.5 * width + pixelsPerMetre * d.dot(right) / depth;  // pixels from the left
        const double py = 0.5 * height + pixelsPerMetre * d.dot(up) / depth;    // pixels from the bottom
        if (px + half + kSlack < 0.0 || py + half + kSlack < 0.0 || px - half - kSlack > width ||
            py - half - kSlack > height) {
            continue;
        }
        const auto x = static_cast<float>(px) * perCell, y = static_cast<float>(py) * perCell;
        const auto reach = static_cast<float>(half + kSlack) * perCell;
        const int r0 = std::max(0, floorOf(y - reach)), r1 = std::min(work.rows - 1, floorOf(y + reach));
        const auto f = static_cast<float>(depth);
        // At once when the blocks around the disc are covered by nearer sprites throughout.
        const int b0 = std::max(0, floorOf(x - reach)) / kBlock;
        const int b1 = std::min(work.columns - 1, floorOf(x + reach)) / kBlock;
        bool hidden = true;
        for (int br = r0 / kBlock; br <= r1 / kBlock && hidden; ++br) {
            for (int bc = b0; bc <= b1 && hidden; ++bc) hidden = blockFarthest(bc, br) < f;
        }
        if (hidden) continue;
        // Row by row, the cells with a pixel's centre within `reach` of the disc's centre (cell c's
        // centres span c + margin .. c + 1 - margin): shows when one is not covered by a nearer sprite.
        bool shows = false;
        for (int r = r0; r <= r1 && !shows; ++r) {
            const float dy = std::max(std::max(r + margin - y, y - (r + 1 - margin)), 0.0f);
            if (dy > reach) continue;
            const float w = std::sqrt(reach * reach - dy * dy);
            const int c0 = std::max(0, ceilOf(x - w - 1.0f + margin));
            const int c1 = std::min(work.columns - 1, floorOf(x + w - margin));
            const float* row = &work.nearest[static_cast<std::size_t>(r) * work.columns];
            bool covered = true;
            for (int c = c0; c <= c1; ++c) covered &= row[c] < f;  // no branch per cell
            shows = !covered;
        }
        if (!shows) continue;
        visible.push_back(i);
        if (2.0 * half > kLargestOccluder) continue;
        // Mark the cells whose every pixel's centre lies inside the disc (less the slack).
        const auto inner = static_cast<float>(half - kSlack) * perCell;
        for (int r = r0; r <= r1; ++r) {
            const float dy = std::max(std::abs(r + margin - y), std::abs(r + 1 - margin - y));
            if (dy > inner) continue;
            const float w = std::sqrt(inner * inner - dy * dy);
            const int c0 = std::max(0, ceilOf(x - w - margin));
            const int c1 = std::min(work.columns - 1, floorOf(x + w - margin - span));
            float* row = &work.nearest[static_cast<std::size_t>(r) * work.columns];
            for (int c = c0; c <= c1; ++c) row[c] = std::min(row[c], f);
            if (c0 <= c1) {
                for (int bc = c0 / kBlock; bc <= c1 / kBlock; ++bc) {
                    work.changed[static_cast<std::size_t>(r / kBlock) * work.blockColumns + bc] = 1;
                }
            }
        }
    }
}

Bounds fluidBounds(const Fluids& fluid) {
    Bounds box;
    for (const Vec3& q : fluid.x) box.extend(q);
    if (!box.isEmpty()) box.min() -= Vec3::Constant(fluid.radius()), box.max() += Vec3::Constant(fluid.radius());
    return box;
}

bool fluidPixels(const Camera& camera, const Fluids& fluid, int width, int height, std::vector<PixelBox>& boxes) {
    if (fluid.empty()) return true;
    constexpr double kPi = 3.14159265358979323846;
    const double pixelsPerRadian = 0.5 * std::max(1, height) / std::tan(Camera::kFieldOfViewY * kPi / 360.0);
    const double inf = std::numeric_limits<double>::infinity();
    PixelBox box{inf, inf, -inf, -inf};
    for (const Vec3& q : fluid.x) {
        double x, y;
        if (!camera.project(q, width, height, x, y)) return false;
        // A particle's sphere spans about its radius over its depth, as a mesh's in movingMeshes().
        const double r = fluid.radius() * pixelsPerRadian / (q - camera.eye()).dot(camera.forward());
        box = {std::min(box.left, x - r), std::min(box.top, y - r), std::max(box.right, x + r), std::max(box.bottom, y + r)};
    }
    boxes.push_back(box);
    return true;
}

std::size_t fillContainer(Fluids& fluid, const std::vector<Body>& bodies, std::size_t count) {
    if (!fluid.container()) return 0;
    const FluidBox tank = *fluid.container();
    const FluidParameters parameters = fluid.parameters();
    const double s = parameters.spacing;
    fluid.clear();  // removes the container too: set again below
    fluid.setContainer(tank);
    // A tank a whole number of spacings wide holds that many, whatever the rounding of the quotient.
    const auto cells = [&](int k) { return static_cast<int>(std::floor((tank.upper[k] - tank.lower[k]) / s + 1e-9)); };
    const int nx = cells(0), ny = cells(1), nz = cells(2);
    const auto inside = [&](const Vec3& q) {
        for (const Body& b : bodies) {
            if (!b.isStatic() || isTankWall(b, tank)) continue;
            if (b.shape == Shape::Sphere && (q - b.position).norm() < b.radius + 0.5 * s) return true;
            if (b.shape == Shape::Box) {
                const Vec3 local = b.orientation.conjugate() * (q - b.position);
                if ((local.cwiseAbs().array() < (b.halfExtents + Vec3::Constant(0.5 * s)).array()).all()) return true;
            }
        }
        return false;
    };
    for (int j = 0; j < ny && fluid.size() < count; ++j) {
        for (int k = 0; k < nz && fluid.size() < count; ++k) {
            for (int i = 0; i < nx && fluid.size() < count; ++i) {
                const Vec3 q = tank.lower + s * Vec3(i + 0.5, j + 0.5, k + 0.5);
                if (!inside(q)) fluid.addParticle(q);
            }
        }
    }
    return fluid.size();
}

}  // namespace gpl::viewer
