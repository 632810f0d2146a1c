// The renderer's fluids (worksheet 9): the particles as points in one interleaved vertex array,
// drawn in one call, front to back. A small GLSL 1.20 program makes each point a sprite as wide on
// screen as the particle's sphere and shades it as a sphere (lit by the scene's light, faded by its
// fog). A software renderer pays for every sprite it rasterises, hidden or not, so the sprites wholly
// behind nearer ones are left out before drawing (visibleSprites(): a block of fluid shows little
// more than its outer layers), and the rest go nearest first, so that the depth test spares the
// hidden parts of those. Where GLSL is not available the points are round, flat, of one size and
// all drawn. The fluid's container is drawn as a glass box: its far faces translucent behind the
// fluid, its edges as lines.
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "fluid_shapes.h"
#include "renderer.h"

namespace gpl::viewer {
namespace {

constexpr double kPi = 3.14159265358979323846;

const char* const kVertexShader = R"(#version 120
uniform float pixelsPerMetre;  // at unit depth: the viewport's height / (2 tan(fovy / 2))
uniform float radius;          // m, the particle's
uniform float smallest;        // pixels, the narrowest sprite (kSmallestSprite)
varying vec3 colour;
varying float fog;
void main() {
    vec4 eye = gl_ModelViewMatrix * gl_Vertex;
    gl_Position = gl_ProjectionMatrix * eye;
    gl_PointSize = max(smallest, 2.0 * radius * pixelsPerMetre / max(-eye.z, 1e-3));  // spriteWidth()
    colour = gl_Color.rgb;
    fog = clamp((gl_Fog.end - length(eye.xyz)) * gl_Fog.scale, 0.0, 1.0);
}
)";

// The sprite as the front half of a sphere: its normal from where the fragment lies in the point,
// diffuse light from the scene's directional light (a unit vector in eye space), a small highlight
// (Phong's, to the 24th power by squarings: the reflected light's z is 2 (n.l) n.z - l.z).
const char* const kFragmentShader = R"(#version 120
uniform vec3 light;
varying vec3 colour;
varying float fog;
void main() {
    vec2 q = 2.0 * gl_PointCoord - 1.0;
    float r2 = dot(q, q);
    if (r2 > 1.0) discard;
    float z = sqrt(1.0 - r2);
    float d = dot(vec3(q.x, -q.y, z), light);
    float s = max(2.0 * d * z - light.z, 0.0);
    s *= s;
    s *= s;
    s *= s;
    vec3 c = colour * (0.45 + 0.65 * max(d, 0.0)) + vec3(0.3 * s * s * s);
    gl_FragColor = vec4(mix(gl_Fog.color.rgb, c, fog), 1.0);
}
)";

GLuint compile(GLenum kind, const char* source) {
    const GLuint shader = glCreateShader(kind);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        char log[1024] = "";
        glGetShaderInfoLog(shader, sizeof log, nullptr, log);
        std::fprintf(stderr, "viewer: the fluid's point shader does not compile (flat points instead): %s\n", log);
        glDeleteShader(shader);
        return 0;
    }
    return shader;
}

// GL 2.0 or later: the version string begins with the major number.
bool hasGlsl() {
    const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    return version && std::atoi(version) >= 2;
}

}  // namespace

void Renderer::depthOrder(const Fluids& fluid, const Camera& camera) {
    // A counting sort on the depth along the view, in kBuckets slices from the nearest particle to
    // the farthest: near enough to front to back for the depth test, in time linear in the count.
    constexpr std::size_t kBuckets = 1024;
    const std::size_t n = fluid.size();
    const Vec3 eye = camera.eye(), forward = camera.forward();
    fluidKeys_.resize(n);
    float nearest = HUGE_VALF, farthest = -HUGE_VALF;
    for (std::size_t i = 0; i < n; ++i) {
        const auto d = static_cast<float>((fluid.x[i] - eye).dot(forward));
        fluidKeys_[i] = d;
        nearest = std::min(nearest, d), farthest = std::max(farthest, d);
    }
    const float scale = farthest > nearest ? (kBuckets - 1) / (farthest - nearest) : 0.0f;
    fluidBuckets_.assign(kBuckets + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const float at = (fluidKeys_[i] - nearest) * scale;  // not finite for a particle that is not
        const std::size_t b = at >= 0.0f && at < float(kBuckets) ? static_cast<std::size_t>(at) : 0;
        fluidKeys_[i] = static_cast<float>(b);  // kept as the bucket's number
        ++fluidBuckets_[b + 1];
    }
    for (std::size_t b = 1; b <= kBuckets; ++b) fluidBuckets_[b] += fluidBuckets_[b - 1];
    fluidOrder_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        fluidOrder_[fluidBuckets_[static_cast<std::size_t>(fluidKeys_[i])]++] = static_cast<std::uint32_t>(i);
    }
}

bool Renderer::fluidProgramReady() {
    if (fluidProgramTried_) return fluidProgram_ != 0;
    fluidProgramTried_ = true;
    if (!hasGlsl()) return false;
    const GLuint vertex = compile(GL_VERTEX_SHADER, kVertexShader);
    const GLuint fragment = compile(GL_FRAGMENT_SHADER, kFragmentShader);
    if (!vertex || !fragment) return false;
    const GLuint program = glCreateProgram();
    glAttachShader(program, vertex);
    glAttachShader(program, fragment);
    glLinkProgram(program);
    glDeleteShader(vertex);
    glDeleteShader(fragment);
    GLint ok = GL_FALSE;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        std::fprintf(stderr, "viewer: the fluid's point shader does not link (flat points instead)\n");
        glDeleteProgram(program);
        return false;
    }
    fluidProgram_ = program;
    return true;
}

void Renderer::drawFluid(const Session& session, const Camera& camera, int width, int height, const Options& options) {
    const Fluids& fluid = session.engine().fluids();
    if (fluid.empty()) return;
    const double pixelsPerMetre = height / (2.0 * std::tan(Camera::kFieldOfViewY * kPi / 360.0));
    const std::size_t n = fluid.size();
    depthOrder(fluid, camera);
    const bool sprites = fluidProgramReady();
    // Sprites: only those that can show (a block of fluid hides most of its particles). Flat points
    // are all of one size, not the size visibleSprites() takes: all of them.
    if (sprites) visibleSprites(camera, fluid, width, height, fluidOrder_, fluidDepths_, fluidShown_);
    const std::vector<std::uint32_t>& shown = sprites ? fluidShown_ : fluidOrder_;

    // One interleaved vertex array of the particles drawn, nearest first: a position as three
    // floats and a colour as four bytes.
    fluidVertices_.resize(shown.size());
    for (std::size_t k = 0; k < shown.size(); ++k) {
        FluidVertex& v = fluidVertices_[k];
        const Vec3& q = fluid.x[shown[k]];
        v.position[0] = static_cast<float>(q.x()), v.position[1] = static_cast<float>(q.y());
        v.position[2] = static_cast<float>(q.z());
        fluidColour(fluid, shown[k], options.fluidColouring, options.fluidRange, v.colour);
    }
    const auto count = static_cast<GLsizei>(shown.size());

    glDisable(GL_LIGHTING);
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_COLOR_ARRAY);
    glVertexPointer(3, GL_FLOAT, sizeof(FluidVertex), fluidVertices_.data()->position);
    glColorPointer(4, GL_UNSIGNED_BYTE, sizeof(FluidVertex), fluidVertices_.data()->colour);
    if (sprites) {
        glEnable(GL_VERTEX_PROGRAM_POINT_SIZE);
        glEnable(GL_POINT_SPRITE);  // gl_PointCoord in a compatibility context
        glUseProgram(fluidProgram_);
        glUniform1f(glGetUniformLocation(fluidProgram_, "pixelsPerMetre"), static_cast<float>(pixelsPerMetre));
        glUniform1f(glGetUniformLocation(fluidProgram_, "radius"), static_cast<float>(fluid.radius()));
        glUniform1f(glGetUniformLocation(fluidProgram_, "smallest"), static_cast<float>(kSmallestSprite));
        // The scene's light in eye space (GL keeps its direction as transformed when it was set).
        float light[4] = {0.0f, 0.0f, 1.0f, 0.0f};
        glGetLightfv(GL_LIGHT0, GL_POSITION, light);
        const float length = std::sqrt(light[0] * light[0] + light[1] * light[1] + light[2] * light[2]);
        if (length > 0.0f) {
            glUniform3f(glGetUniformLocation(fluidProgram_, "light"), light[0] / length, light[1] / length,
                        light[2] / length);
        }
        glDrawArrays(GL_POINTS, 0, count);
        glUseProgram(0);
        glDisable(GL_POINT_SPRITE);
        glDisable(GL_VERTEX_PROGRAM_POINT_SIZE);
    } else {
        // Round points as wide as a particle at the camera's target.
        const double pixels = 2.0 * fluid.radius() * pixelsPerMetre / std::max(camera.distance(), 1e-3);
        glEnable(GL_POINT_SMOOTH);
        glPointSize(static_cast<float>(std::clamp(pixels, 2.0, 32.0)));
        glDrawArrays(GL_POINTS, 0, count);
        glDisable(GL_POINT_SMOOTH);
        glPointSize(1.0f);
    }
    glDisableClientState(GL_COLOR_ARRAY);
    glDisableClientState(GL_VERTEX_ARRAY);

    // The hovered particle white, the selected one yellow with the drag's line (over the fluid).
    points_.clear();
    const std::uint8_t white[4] = {255, 255, 255, 255}, yellow[4] = {255, 242, 51, 255};
    if (options.hoveredFluidParticle && *options.hoveredFluidParticle < n) {
        points_.add(fluid.x[*options.hoveredFluidParticle], Vec3::UnitY(), white);
    }
    if (const auto selected = session.selectedFluidParticle(); selected && *selected < n) {
        points_.add(fluid.x[*selected], Vec3::UnitY(), yellow);
        if (const auto target = session.dragTarget()) {
            lines_.clear();
            lines_.add(fluid.x[*selected], Vec3::UnitY(), yellow);
            lines_.add(*target, Vec3::UnitY(), yellow);
            glLineWidth(2.0f);
            lines_.draw(GL_LINES);
            glLineWidth(1.0f);
        }
    }
    glDisable(GL_DEPTH_TEST);
    glPointSize(10.0f);
    points_.draw(GL_POINTS);
    glPointSize(1.0f);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_LIGHTING);
}

void Renderer::drawFluidContainer(const Session& session, const Camera& camera) {
    const auto& box = session.engine().fluids().container();
    if (!box) return;
    const Vec3 lower = box->lower, upper = box->upper, eye = camera.eye();
    const auto corner = [&](int bits) {
        return Vec3(bits & 1 ? upper.x() : lower.x(), bits & 2 ? upper.y() : lower.y(), bits & 4 ? upper.z() : lower.z());
    };
    // Edges: corners that differ in one bit.
    lines_.clear();
    const std::uint8_t edge[4] = {60, 90, 120, 255};
    for (int a = 0; a < 8; ++a) {
        for (int bit : {1, 2, 4}) {
            if (a & bit) continue;
            lines_.add(corner(a), Vec3::UnitY(), edge);
            lines_.add(corner(a | bit), Vec3::UnitY(), edge);
        }
    }
    glDisable(GL_LIGHTING);
    glLineWidth(1.5f);
    lines_.draw(GL_LINES);
    glLineWidth(1.0f);
    // Far faces (the eye on their inner side) as glass behind the fluid; near faces left open.
    translucent_.clear();
    const std::uint8_t glass[4] = {120, 160, 190, 70};
    for (int axis = 0; axis < 3; ++axis) {
        for (int side : {0, 1}) {
            const double at = side ? upper[axis] : lower[axis];
            const bool far = side ? eye[axis] < at : eye[axis] > at;
            if (!far) continue;
            const int u = 1 << ((axis + 1) % 3), v = 1 << ((axis + 2) % 3), fixed = side << axis;
            Vec3 normal = Vec3::Zero();
            normal[axis] = side ? -1.0 : 1.0;  // towards the inside, where the eye is
            const std::uint32_t first = translucent_.add(corner(fixed), normal, glass);
            translucent_.add(corner(fixed | u), normal, glass);
            translucent_.add(corner(fixed | u | v), normal, glass);
            translucent_.add(corner(fixed | v), normal, glass);
            for (std::uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) translucent_.indices.push_back(first + k);
        }
    }
    glDisable(GL_CULL_FACE);
    translucent_.drawTranslucent(GL_TRIANGLES);
    glEnable(GL_CULL_FACE);
    glEnable(GL_LIGHTING);
}

}  // namespace gpl::viewer
