#include "renderer.h"

#include <GL/gl.h>
#include <GL/glu.h>

#include <algorithm>
#include <cmath>

#include "scene_shapes.h"
#include "soft_shapes.h"

namespace gpl::viewer {
namespace {

constexpr double kPi = 3.14159265358979323846;
const float kSky[4] = {0.80f, 0.85f, 0.90f, 1.0f};
constexpr double kShadowHeight = 15.0;  // m above the ground where blob shadows have faded out

void colourOf(const Body& b, std::size_t index, std::uint8_t out[4]) {
    static const std::uint8_t palette[][3] = {{242, 140, 51}, {51, 166, 178},  {217, 77, 77},
                                              {102, 184, 89}, {153, 115, 204}, {235, 199, 64}};
    static const std::uint8_t grey[3] = {140, 148, 160};
    const std::uint8_t* c = b.isStatic() ? grey : palette[index % 6];
    out[0] = c[0], out[1] = c[1], out[2] = c[2], out[3] = 255;
}

// The unit sphere as its eight octants, each a patch of its own (its vertices not shared with the
// next), marked 0 and 1 by turns like a beach ball: the two shades meet in sharp lines, so that a
// ball's turning shows however it turns. Each octant spans `slices` steps of longitude and `stacks`
// of latitude.
Renderer::Mesh sphereMesh(int slices, int stacks) {
    Renderer::Mesh m;
    for (int hemisphere = 0; hemisphere < 2; ++hemisphere) {
        for (int quarter = 0; quarter < 4; ++quarter) {
            const auto base = static_cast<std::uint32_t>(m.vertices.size());
            for (int i = 0; i <= stacks; ++i) {
                for (int j = 0; j <= slices; ++j) {
                    const double a = 0.5 * kPi * (hemisphere - 1 + double(i) / stacks);  // latitude
                    const double b = 0.5 * kPi * (quarter + double(j) / slices);         // longitude
                    const Vec3 v(std::cos(a) * std::cos(b), std::sin(a), -std::cos(a) * std::sin(b));
                    m.vertices.push_back(v);
                    m.normals.push_back(v);
                    m.marks.push_back(static_cast<std::uint8_t>((hemisphere + quarter) % 2));
                }
            }
            const auto at = [&](int i, int j) { return base + static_cast<std::uint32_t>(i * (slices + 1) + j); };
            for (int i = 0; i < stacks; ++i) {
                const bool southPole = hemisphere == 0 && i == 0, northPole = hemisphere == 1 && i + 1 == stacks;
                for (int j = 0; j < slices; ++j) {
                    if (!southPole) m.indices.insert(m.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j + 1)});
                    if (!northPole) m.indices.insert(m.indices.end(), {at(i, j), at(i + 1, j + 1), at(i + 1, j)});
                }
            }
        }
    }
    return m;
}

// The cube [-1, 1]^3: four vertices per face with the face's normal, counter-clockwise from outside.
Renderer::Mesh cubeMesh() {
    Renderer::Mesh m;
    for (int axis = 0; axis < 3; ++axis) {
        for (int sign : {-1, 1}) {
            Vec3 n = Vec3::Zero();
            n[axis] = sign;
            Vec3 u = Vec3::Unit((axis + 1) % 3), v = Vec3::Unit((axis + 2) % 3);
            if (sign < 0) std::swap(u, v);
            const auto base = static_cast<std::uint32_t>(m.vertices.size());
            for (const Vec3& c : {Vec3(n - u - v), Vec3(n + u - v), Vec3(n + u + v), Vec3(n - u + v)}) {
                m.vertices.push_back(c);
                m.normals.push_back(n);
            }
            for (std::uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) m.indices.push_back(base + k);
        }
    }
    return m;
}

Renderer::Mesh discMesh(int segments) {
    Renderer::Mesh m;
    m.vertices.push_back(Vec3::Zero());
    for (int j = 0; j < segments; ++j) {
        const double a = 2.0 * kPi * j / segments;
        m.vertices.emplace_back(std::cos(a), 0.0, -std::sin(a));
        m.indices.insert(m.indices.end(), {0u, std::uint32_t(1 + j), std::uint32_t(1 + (j + 1) % segments)});
    }
    m.normals.assign(m.vertices.size(), Vec3::UnitY());
    return m;
}

// Height of the ground: the highest level plane (isGround), when the scene has one.
double groundHeight(const std::vector<Body>& bodies, bool& found) {
    found = false;
    double y = 0.0;
    for (const Body& b : bodies) {
        if (!isGround(b)) continue;
        y = found ? std::max(y, b.position.y()) : b.position.y();
        found = true;
    }
    return y;
}

}  // namespace

std::uint32_t Renderer::Batch::add(const Vec3& p, const Vec3& n, const std::uint8_t rgba[4]) {
    positions.insert(positions.end(), {float(p.x()), float(p.y()), float(p.z())});
    normals.insert(normals.end(), {float(n.x()), float(n.y()), float(n.z())});
    colours.insert(colours.end(), rgba, rgba + 4);
    return static_cast<std::uint32_t>(positions.size() / 3 - 1);
}

void Renderer::Batch::draw(unsigned mode) const {
    if (positions.empty()) return;
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_NORMAL_ARRAY);
    glEnableClientState(GL_COLOR_ARRAY);
    glVertexPointer(3, GL_FLOAT, 0, positions.data());
    glNormalPointer(GL_FLOAT, 0, normals.data());
    glColorPointer(4, GL_UNSIGNED_BYTE, 0, colours.data());
    if (indices.empty()) {
        glDrawArrays(mode, 0, static_cast<GLsizei>(positions.size() / 3));
    } else {
        glDrawElements(mode, static_cast<GLsizei>(indices.size()), GL_UNSIGNED_INT, indices.data());
    }
    glDisableClientState(GL_COLOR_ARRAY);
    glDisableClientState(GL_NORMAL_ARRAY);
    glDisableClientState(GL_VERTEX_ARRAY);
}

void Renderer::Batch::drawTranslucent(unsigned mode) const {
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    draw(mode);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
}

Renderer::Renderer()
    : sphere_{sphereMesh(7, 9), sphereMesh(3, 4), sphereMesh(2, 3)}, cube_(cubeMesh()), disc_(discMesh(10)) {}

void Renderer::append(Batch& batch, const Body& b, const std::uint8_t rgba[4], const Camera& camera, int height) const {
    if (b.shape == Shape::Sphere) {
        // Level of detail from the radius on screen (pixels); the marked octants in a paler shade.
        const double depth = std::max(0.1, (b.position - camera.eye()).dot(camera.forward()));
        const double pixels = b.radius / depth * height / (2.0 * std::tan(Camera::kFieldOfViewY * kPi / 360.0));
        const Mesh& m = sphere_[pixels > 50 ? 0 : pixels > 14 ? 1 : 2];
        std::uint8_t pale[4] = {0, 0, 0, rgba[3]};
        for (int k = 0; k < 3; ++k) pale[k] = static_cast<std::uint8_t>(rgba[k] + (255 - rgba[k]) * 11 / 20);
        const Mat3 r = b.orientation.toRotationMatrix();
        const auto base = static_cast<std::uint32_t>(batch.positions.size() / 3);
        for (std::size_t k = 0; k < m.vertices.size(); ++k) {
            const Vec3 v = r * m.vertices[k];
            batch.add(b.position + b.radius * v, v, m.marks[k] ? pale : rgba);
        }
        for (std::uint32_t i : m.indices) batch.indices.push_back(base + i);
    } else if (b.shape == Shape::Box) {
        const Mat3 r = b.orientation.toRotationMatrix();
        const auto base = static_cast<std::uint32_t>(batch.positions.size() / 3);
        for (std::size_t k = 0; k < cube_.vertices.size(); ++k) {
            batch.add(b.position + r * b.halfExtents.cwiseProduct(cube_.vertices[k]), r * cube_.normals[k], rgba);
        }
        for (std::uint32_t i : cube_.indices) batch.indices.push_back(base + i);
    }
}

void Renderer::appendBall(Batch& batch, const Vec3& centre, double radius, const std::uint8_t rgba[4],
                          int detail) const {
    const Mesh& m = sphere_[std::clamp(detail, 0, 2)];
    const auto base = static_cast<std::uint32_t>(batch.positions.size() / 3);
    for (std::size_t k = 0; k < m.vertices.size(); ++k) batch.add(centre + radius * m.vertices[k], m.normals[k], rgba);
    for (std::uint32_t i : m.indices) batch.indices.push_back(base + i);
}

void Renderer::draw(const Session& session, const Camera& camera, int width, int height, const Options& options) {
    const std::optional<std::size_t> hovered = options.hovered;
    const bool showContacts = options.contacts;
    const auto& bodies = session.engine().bodies();
    glViewport(0, 0, width, height);
    glClearColor(kSky[0], kSky[1], kSky[2], kSky[3]);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    gluPerspective(Camera::kFieldOfViewY, double(width) / std::max(1, height), Camera::kNear, Camera::kFar);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    const Vec3 eye = camera.eye(), at = camera.target(), up = camera.up();
    gluLookAt(eye.x(), eye.y(), eye.z(), at.x(), at.y(), at.z(), up.x(), up.y(), up.z());

    glEnable(GL_DEPTH_TEST);
    glEnable(GL_CULL_FACE);
    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT0);
    glEnable(GL_COLOR_MATERIAL);
    glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
    glShadeModel(GL_SMOOTH);
    const float light[4] = {0.4f, 1.0f, 0.3f, 0.0f}, ambient[4] = {0.35f, 0.35f, 0.38f, 1.0f};
    const float diffuse[4] = {0.75f, 0.75f, 0.72f, 1.0f};
    glLightfv(GL_LIGHT0, GL_POSITION, light);
    glLightModelfv(GL_LIGHT_MODEL_AMBIENT, ambient);
    glLightfv(GL_LIGHT0, GL_DIFFUSE, diffuse);
    // Fog: far things fade into the sky, a depth cue that costs nothing.
    glEnable(GL_FOG);
    glFogi(GL_FOG_MODE, GL_LINEAR);
    glFogfv(GL_FOG_COLOR, kSky);
    glFogf(GL_FOG_START, static_cast<float>(camera.distance() * 1.5));
    glFogf(GL_FOG_END, static_cast<float>(camera.distance() * 5.0 + 60.0));

    // The ground as checkered tiles (fog is computed per vertex, so a plane needs many vertices).
    bool hasFloor = false;
    const double ground = groundHeight(bodies, hasFloor);
    solid_.clear();
    for (const Body& b : bodies) {
        if (!isGround(b)) continue;
        const Vec3 n = (b.orientation * b.normal).normalized();
        const Vec3 u = (std::abs(n.y()) < 0.9 ? n.cross(Vec3::UnitY()) : n.cross(Vec3::UnitX())).normalized();
        const Vec3 v = n.cross(u);
        const int tiles = 15;
        const double tile = 8.0;  // m
        for (int i = -tiles; i < tiles; ++i) {
            for (int j = -tiles; j < tiles; ++j) {
                const std::uint8_t shade = (i + j) % 2 ? 158 : 150;
                const std::uint8_t rgba[4] = {shade, static_cast<std::uint8_t>(shade + 6),
                                              static_cast<std::uint8_t>(shade - 8), 255};
                const Vec3 o = b.position + tile * (i * u + j * v);
                const std::uint32_t first = solid_.add(o, n, rgba);
                solid_.add(o + tile * u, n, rgba);
                solid_.add(o + tile * (u + v), n, rgba);
                solid_.add(o + tile * v, n, rgba);
                for (std::uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) solid_.indices.push_back(first + k);
            }
        }
    }
    glDisable(GL_CULL_FACE);
    solid_.draw(GL_TRIANGLES);
    glEnable(GL_CULL_FACE);

    // The ground that walls enclose (a table's cloth, a box's floor) in the walls' colour, a shade
    // darker, over the tiles.
    if (const auto inside = enclosedGround(bodies)) {
        solid_.clear();
        const std::uint8_t cloth[4] = {52, 118, 84, 255};
        const auto first = static_cast<std::uint32_t>(solid_.positions.size() / 3);
        for (const Vec3& p : inside->corners) solid_.add(p, inside->normal, cloth);
        for (std::uint32_t k = 1; k + 1 < inside->corners.size(); ++k) {
            solid_.indices.insert(solid_.indices.end(), {first, first + k, first + k + 1});
        }
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(-1.0f, -2.0f);
        solid_.draw(GL_TRIANGLES);
        glDisable(GL_POLYGON_OFFSET_FILL);
    }

    // Blob shadows on the floor under every body: discs for spheres, ellipses for boxes, paler when
    // higher and gone above 15 m (where they would only cost time). A scene without a floor draws
    // nothing under its bodies, neither ground nor shadows: nothing stands there.
    glDisable(GL_LIGHTING);
    shadows_.clear();
    for (const Body& b : bodies) {
        const double above = b.position.y() - ground;
        if (!hasFloor || b.shape == Shape::Plane || above < 0.0 || above > kShadowHeight) continue;
        const Vec3 size = b.shape == Shape::Sphere ? Vec3::Constant(b.radius) : b.halfExtents;
        const double grow = 1.0 + 0.02 * above;
        const std::uint8_t rgba[4] = {25, 25, 38,
                                      static_cast<std::uint8_t>(115 * std::clamp(1.0 - above / 40.0, 0.1, 1.0))};
        const Vec3 centre(b.position.x(), ground + 0.006, b.position.z());
        const auto base = static_cast<std::uint32_t>(shadows_.positions.size() / 3);
        for (const Vec3& v : disc_.vertices) shadows_.add(centre + grow * size.cwiseProduct(v), Vec3::UnitY(), rgba);
        for (std::uint32_t i : disc_.indices) shadows_.indices.push_back(base + i);
    }
    // A soft body's shadow as a box's: an ellipse as wide as the body (cloth and ropes cast none).
    const SoftBodies& soft = session.engine().softBodies();
    for (std::size_t m = 0; hasFloor && m < soft.meshes.size(); ++m) {
        if (soft.meshes[m].kind != SoftMesh::Kind::SoftBody) continue;
        const Bounds box = meshBounds(soft, m);
        const double above = box.center().y() - ground;
        if (box.isEmpty() || above < 0.0 || above > kShadowHeight) continue;
        const Vec3 size = 0.5 * box.diagonal();
        const double grow = 1.0 + 0.02 * above;
        const std::uint8_t rgba[4] = {25, 25, 38,
                                      static_cast<std::uint8_t>(115 * std::clamp(1.0 - above / 40.0, 0.1, 1.0))};
        const Vec3 centre(box.center().x(), ground + 0.006, box.center().z());
        const auto base = static_cast<std::uint32_t>(shadows_.positions.size() / 3);
        for (const Vec3& v : disc_.vertices) shadows_.add(centre + grow * size.cwiseProduct(v), Vec3::UnitY(), rgba);
        for (std::uint32_t i : disc_.indices) shadows_.indices.push_back(base + i);
    }
    shadows_.drawTranslucent(GL_TRIANGLES);
    glEnable(GL_LIGHTING);

    // Bodies: one batch; the hovered one a little lighter. A fluid's tank is left out: its
    // container's glass box stands for it (drawFluidContainer()).
    solid_.clear();
    const auto& tank = session.engine().fluids().container();
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        if (tank && isTankWall(bodies[i], *tank)) continue;
        std::uint8_t rgba[4];
        colourOf(bodies[i], i, rgba);
        if (hovered && *hovered == i) {
            for (int k = 0; k < 3; ++k) rgba[k] = static_cast<std::uint8_t>(std::min(255, rgba[k] + 40));
        }
        append(solid_, bodies[i], rgba, camera, height);
    }
    solid_.draw(GL_TRIANGLES);
    drawSoftBodies(session, options);
    drawFluid(session, camera, width, height, options);

    // Springs (green), rods and chain links (dark grey), the container (a wire sphere).
    glDisable(GL_LIGHTING);
    lines_.clear();
    const PhysicsEngine& engine = session.engine();
    const std::uint8_t springColour[4] = {40, 150, 60, 255}, rodColour[4] = {60, 60, 70, 255};
    for (const Spring& sp : engine.springs()) {
        lines_.add(bodies[sp.a].position, Vec3::UnitY(), springColour);
        lines_.add(bodies[sp.b].position, Vec3::UnitY(), springColour);
    }
    for (const DistanceConstraint& c : engine.distanceConstraints()) {
        lines_.add(bodies[c.a].position, Vec3::UnitY(), rodColour);
        lines_.add(bodies[c.b].position, Vec3::UnitY(), rodColour);
    }
    // Ropes: taut ones straight and dark, slack ones sagging and pale.
    const std::uint8_t taut[4] = {75, 45, 20, 255}, slack[4] = {190, 150, 95, 255};
    for (const Rope& r : engine.ropes()) {
        const Vec3 &a = bodies[r.a].position, &b = bodies[r.b].position;
        const bool tight = ropeTaut(r, bodies, engine.contacts());
        auto curve = tight ? std::vector<Vec3>{a, b} : ropeCurve(a, b, r.length, -Vec3::UnitY(), 24);
        for (Vec3& p : curve) {
            if (hasFloor) p.y() = std::max(p.y(), ground + 0.005);  // a slack rope lies on the ground
        }
        for (std::size_t i = 1; i < curve.size(); ++i) {
            lines_.add(curve[i - 1], Vec3::UnitY(), tight ? taut : slack);
            lines_.add(curve[i], Vec3::UnitY(), tight ? taut : slack);
        }
    }
    if (const auto& box = engine.container()) {
        const std::uint8_t wire[4] = {90, 100, 120, 255};
        for (int ring = 0; ring < 3; ++ring) {  // three great circles
            for (int j = 0; j < 48; ++j) {
                for (int k : {j, j + 1}) {
                    const double a = 2.0 * kPi * k / 48;
                    Vec3 p = Vec3::Zero();
                    p[ring] = std::cos(a);
                    p[(ring + 1) % 3] = std::sin(a);
                    lines_.add(box->centre + box->radius * p, Vec3::UnitY(), wire);
                }
            }
        }
    }
    glLineWidth(2.0f);
    lines_.draw(GL_LINES);
    glLineWidth(1.0f);
    glEnable(GL_LIGHTING);

    // The selection as a yellow wire frame; the drag spring as a line to the cursor's point.
    glDisable(GL_LIGHTING);
    const auto selected = session.selected();
    if (selected && *selected < bodies.size()) {
        Body outline = bodies[*selected];
        outline.radius *= 1.03;
        outline.halfExtents *= 1.03;
        const std::uint8_t yellow[4] = {255, 242, 51, 255};
        solid_.clear();
        append(solid_, outline, yellow, camera, height);
        glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
        solid_.draw(GL_TRIANGLES);
        glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
        if (const auto target = session.dragTarget()) {
            lines_.clear();
            lines_.add(bodies[*selected].position, Vec3::UnitY(), yellow);
            lines_.add(*target, Vec3::UnitY(), yellow);
            glLineWidth(2.0f);
            lines_.draw(GL_LINES);
            glLineWidth(1.0f);
        }
    }
    glEnable(GL_LIGHTING);

    // Walls, cushions and slopes: translucent where the camera sees their free side, and outlined
    // only where it looks at them from behind (the front wall of a box would hide what is inside).
    translucent_.clear();
    lines_.clear();
    const Vec3 eyeAt = camera.eye();
    for (const PlanePatch& w : wallPatches(bodies, session.bounds())) {
        const bool facing = w.normal.dot(eyeAt - bodies[w.body].position) > 0.0;
        const std::uint8_t glass[4] = {70, 150, 130, 80}, edge[4] = {35, 95, 80, 255}, back[4] = {95, 140, 128, 255};
        for (std::size_t k = 0; k < w.corners.size(); ++k) {
            lines_.add(w.corners[k], w.normal, facing ? edge : back);
            lines_.add(w.corners[(k + 1) % w.corners.size()], w.normal, facing ? edge : back);
        }
        if (!facing) continue;
        const auto first = static_cast<std::uint32_t>(translucent_.positions.size() / 3);
        for (const Vec3& p : w.corners) translucent_.add(p, w.normal, glass);
        for (std::uint32_t k = 1; k + 1 < w.corners.size(); ++k) {
            translucent_.indices.insert(translucent_.indices.end(), {first, first + k, first + k + 1});
        }
    }
    glDisable(GL_LIGHTING);
    glLineWidth(2.0f);
    lines_.draw(GL_LINES);
    glLineWidth(1.0f);
    glEnable(GL_LIGHTING);
    translucent_.drawTranslucent(GL_TRIANGLES);

    drawFluidContainer(session, camera);

    // The reference ghost, translucent, over everything opaque.
    if (session.ghostOn()) {
        translucent_.clear();
        const std::uint8_t ghost[4] = {140, 190, 255, 90};
        const auto& poses = session.ghostPoses();
        for (std::size_t i = 0; i < std::min(poses.size(), bodies.size()); ++i) {
            Body g = bodies[i];
            const auto& p = poses[i];
            g.position = Vec3(p[0], p[1], p[2]);
            g.orientation = Quat(p[3], p[4], p[5], p[6]);
            append(translucent_, g, ghost, camera, height);
        }
        translucent_.drawTranslucent(GL_TRIANGLES);
        drawSoftGhost(session);
    }

    // Contacts of the last step over everything: a dot at every point, and the normal (from the
    // first body towards the second) as a line that pales towards its tip.
    if (showContacts) {
        glDisable(GL_LIGHTING);
        glDisable(GL_DEPTH_TEST);
        lines_.clear();
        points_.clear();
        const std::uint8_t dot[4] = {235, 30, 190, 255}, tip[4] = {255, 205, 240, 255};
        for (const Contact& c : engine.contacts()) {
            const double length = normalLength(c, bodies);
            for (int k = 0; k < c.pointCount; ++k) {
                points_.add(c.points[k], c.normal, dot);
                lines_.add(c.points[k], c.normal, dot);
                lines_.add(c.points[k] + length * c.normal, c.normal, tip);
            }
        }
        glLineWidth(2.0f);
        lines_.draw(GL_LINES);
        glLineWidth(1.0f);
        glPointSize(6.0f);
        points_.draw(GL_POINTS);
        glPointSize(1.0f);
        glEnable(GL_DEPTH_TEST);
    }
    glDisable(GL_FOG);
    glDisable(GL_LIGHTING);
}

}  // namespace gpl::viewer
