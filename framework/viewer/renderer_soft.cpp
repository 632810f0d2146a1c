// The renderer's cloth, ropes and soft bodies (worksheet 8): each mesh one vertex array, its
// particles the vertices and its normals recomputed every frame (soft_shapes.h).
#include <GL/gl.h>

#include <algorithm>

#include "renderer.h"
#include "soft_shapes.h"

namespace gpl::viewer {
namespace {

constexpr int kTubeSides = 8;

// A colour per mesh, apart from the bodies' palette: a cloth or rope beside another shows which is which.
void meshColour(std::size_t mesh, std::uint8_t out[4]) {
    static const std::uint8_t palette[][3] = {{196, 58, 70},  {54, 112, 190}, {228, 178, 48},
                                              {72, 158, 98},  {148, 92, 186}, {222, 118, 52}};
    const std::uint8_t* c = palette[mesh % 6];
    out[0] = c[0], out[1] = c[1], out[2] = c[2], out[3] = 255;
}

// Towards white by `share` (0..1), alpha kept.
void paler(const std::uint8_t in[4], double share, std::uint8_t out[4]) {
    for (int k = 0; k < 3; ++k) out[k] = static_cast<std::uint8_t>(in[k] + (255 - in[k]) * share);
    out[3] = in[3];
}

}  // namespace

void Renderer::appendSoftMesh(Batch& batch, const SoftBodies& soft, std::size_t mi, const std::vector<Vec3>& x,
                              const std::uint8_t rgba[4]) {
    const SoftMesh& m = soft.meshes[mi];
    if (!m.triangles.empty()) {
        surfaceNormals(x, m, normals_);
        const auto base = static_cast<std::uint32_t>(batch.positions.size() / 3);
        for (std::uint32_t k = 0; k < m.count; ++k) batch.add(x[m.first + k], normals_[k], rgba);
        for (const auto& t : m.triangles) {
            for (std::uint32_t i : t) batch.indices.push_back(base + i - m.first);
        }
        return;
    }
    // A rope: a bead at every particle on a tube through them, its segments in two shades by turns.
    const double r = ropeDrawRadius(soft, mi);
    const std::vector<Vec3> chain(x.begin() + m.first, x.begin() + m.first + m.count);
    const TriangleMesh tube = ropeTube(chain, 0.6 * r, kTubeSides);
    std::uint8_t light[4];
    paler(rgba, 0.45, light);
    const auto base = static_cast<std::uint32_t>(batch.positions.size() / 3);
    for (std::size_t k = 0; k < tube.vertices.size(); ++k) {
        batch.add(tube.vertices[k], tube.normals[k], (k / (2 * kTubeSides)) % 2 ? light : rgba);
    }
    for (std::uint32_t i : tube.indices) batch.indices.push_back(base + i);
    for (const Vec3& p : chain) appendBall(batch, p, r, rgba, 2);
}

void Renderer::drawSoftBodies(const Session& session, const Options& options) {
    const SoftBodies& soft = session.engine().softBodies();
    if (soft.meshes.empty()) return;
    // Surfaces a little behind their lines and marks, so that those on the surface show.
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.0f, 1.0f);
    for (std::size_t mi = 0; mi < soft.meshes.size(); ++mi) {
        const SoftMesh& m = soft.meshes[mi];
        std::uint8_t rgba[4];
        meshColour(mi, rgba);
        solid_.clear();
        appendSoftMesh(solid_, soft, mi, soft.x, rgba);
        if (m.kind == SoftMesh::Kind::Cloth) {
            // Both sides lit, the back in a paler shade of the mesh's colour (the reverse of a fabric).
            std::uint8_t back[4];
            paler(rgba, 0.35, back);
            const float backColour[4] = {back[0] / 255.0f, back[1] / 255.0f, back[2] / 255.0f, 1.0f};
            glDisable(GL_CULL_FACE);
            glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_TRUE);
            glColorMaterial(GL_FRONT, GL_AMBIENT_AND_DIFFUSE);
            glMaterialfv(GL_BACK, GL_AMBIENT_AND_DIFFUSE, backColour);
            solid_.draw(GL_TRIANGLES);
            glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
            glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_FALSE);
            glEnable(GL_CULL_FACE);
        } else {
            solid_.draw(GL_TRIANGLES);
        }
    }
    glDisable(GL_POLYGON_OFFSET_FILL);

    glDisable(GL_LIGHTING);
    // The links on request: the grid's edges (stretch, a soft body's edges, a rope's segments) dark,
    // shear blue, bending green.
    if (options.softWire) {
        lines_.clear();
        const std::uint8_t edge[4] = {40, 40, 48, 255}, shear[4] = {60, 110, 230, 255}, bend[4] = {40, 170, 80, 255};
        for (const DistanceLink& l : soft.links) {
            const std::uint8_t* c = l.kind == LinkKind::Shear ? shear : l.kind == LinkKind::Bend ? bend : edge;
            lines_.add(soft.x[l.i], Vec3::UnitY(), c);
            lines_.add(soft.x[l.j], Vec3::UnitY(), c);
        }
        lines_.draw(GL_LINES);
    }
    // Pinned particles dark; the hovered one white, the selected one yellow with the drag's line.
    points_.clear();
    const std::uint8_t pin[4] = {30, 30, 36, 255}, white[4] = {255, 255, 255, 255}, yellow[4] = {255, 242, 51, 255};
    for (std::size_t i = 0; i < soft.x.size(); ++i) {
        if (soft.w[i] == 0.0) points_.add(soft.x[i], Vec3::UnitY(), pin);
    }
    glPointSize(7.0f);
    points_.draw(GL_POINTS);
    points_.clear();
    if (options.hoveredParticle && *options.hoveredParticle < soft.x.size()) {
        points_.add(soft.x[*options.hoveredParticle], Vec3::UnitY(), white);
    }
    if (const auto selected = session.selectedParticle(); selected && *selected < soft.x.size()) {
        points_.add(soft.x[*selected], Vec3::UnitY(), yellow);
        if (const auto target = session.dragTarget()) {
            lines_.clear();
            lines_.add(soft.x[*selected], Vec3::UnitY(), yellow);
            lines_.add(*target, Vec3::UnitY(), yellow);
            glLineWidth(2.0f);
            lines_.draw(GL_LINES);
            glLineWidth(1.0f);
        }
    }
    glPointSize(10.0f);
    points_.draw(GL_POINTS);
    glPointSize(1.0f);
    glEnable(GL_LIGHTING);
}

void Renderer::drawSoftGhost(const Session& session) {
    const SoftBodies& soft = session.engine().softBodies();
    const std::vector<Vec3>& x = session.ghostParticles();
    if (soft.meshes.empty() || x.size() != soft.x.size()) return;
    translucent_.clear();
    const std::uint8_t ghost[4] = {140, 190, 255, 90};
    for (std::size_t mi = 0; mi < soft.meshes.size(); ++mi) appendSoftMesh(translucent_, soft, mi, x, ghost);
    glDisable(GL_CULL_FACE);
    glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_TRUE);
    translucent_.drawTranslucent(GL_TRIANGLES);
    glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_FALSE);
    glEnable(GL_CULL_FACE);
}

}  // namespace gpl::viewer
