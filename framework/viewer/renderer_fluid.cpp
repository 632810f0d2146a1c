// The renderer's fluids (worksheet 9): every particle one point of one vertex array, drawn in one
// call, front to back (under a software renderer the depth test then spares most of the hidden
// particles' fragments: a block of fluid is mostly hidden). A small GLSL 1.20 program makes each point a sprite as wide on screen as the particle's
// sphere and shades it as a sphere (lit by the scene's light, faded by its fog); where GLSL is not
// available the points are round, flat and of one size. The fluid's container is drawn as a glass
// box: its far faces translucent behind the fluid, its edges as lines.
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
varying vec4 colour;
varying float fog;
void main() {
    vec4 eye = gl_ModelViewMatrix * gl_Vertex;
    gl_Position = gl_ProjectionMatrix * eye;
    gl_PointSize = max(2.0, 2.0 * radius * pixelsPerMetre / max(-eye.z, 1e-3));
    colour = gl_Color;
    fog = clamp((gl_Fog.end - length(eye.xyz)) * gl_Fog.scale, 0.0, 1.0);
}
)";

// The sprite as the front half of a sphere: its normal from where the fragment lies in the point,
// diffuse light from the scene's directional light (already in eye space), a small highlight.
const char* const kFragmentShader = R"(#version 120
varying vec4 colour;
varying float fog;
void main() {
    vec2 q = 2.0 * gl_PointCoord - 1.0;
    float r2 = dot(q, q);
    if (r2 > 1.0) discard;
    vec3 n = vec3(q.x, -q.y, sqrt(1.0 - r2));
    vec3 l = normalize(gl_LightSource[0].position.xyz);
    float diffuse = max(dot(n, l), 0.0);
    float highlight = pow(max(reflect(-l, n).z, 0.0), 24.0);
    vec3 c = colour.rgb * (0.45 + 0.65 * diffuse) + vec3(0.3 * highlight);
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
    fluidDepths_.resize(n);
    float nearest = HUGE_VALF, farthest = -HUGE_VALF;
    for (std::size_t i = 0; i < n; ++i) {
        const auto d = static_cast<float>((fluid.x[i] - eye).dot(forward));
        fluidDepths_[i] = d;
        nearest = std::min(nearest, d), farthest = std::max(farthest, d);
    }
    const float scale = farthest > nearest ? (kBuckets - 1) / (farthest - nearest) : 0.0f;
    fluidBuckets_.assign(kBuckets + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const float at = (fluidDepths_[i] - nearest) * scale;  // not finite for a particle that is not
        const std::size_t b = at >= 0.0f && at < float(kBuckets) ? static_cast<std::size_t>(at) : 0;
        fluidDepths_[i] = static_cast<float>(b);  // kept as the bucket's number
        ++fluidBuckets_[b + 1];
    }
    for (std::size_t b = 1; b <= kBuckets; ++b) fluidBuckets_[b] += fluidBuckets_[b - 1];
    fluidOrder_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        fluidOrder_[fluidBuckets_[static_cast<std::size_t>(fluidDepths_[i])]++] = static_cast<std::uint32_t>(i);
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

void Renderer::drawFluid(const Session& session, const Camera& camera, int height, const Options& options) {
    const Fluids& fluid = session.engine().fluids();
    if (fluid.empty()) return;
    const double pixelsPerMetre = height / (2.0 * std::tan(Camera::kFieldOfViewY * kPi / 360.0));

    // One vertex array: positions as floats, a colour per particle.
    const std::size_t n = fluid.size();
    fluidPositions_.resize(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) fluidPositions_[3 * i + k] = static_cast<float>(fluid.x[i][k]);
    }
    fluidColours(fluid, options.fluidColouring, options.fluidRange, fluidColours_);

    glDisable(GL_LIGHTING);
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_COLOR_ARRAY);
    glVertexPointer(3, GL_FLOAT, 0, fluidPositions_.data());
    glColorPointer(4, GL_UNSIGNED_BYTE, 0, fluidColours_.data());
    depthOrder(fluid, camera);
    const auto count = static_cast<GLsizei>(n);
    if (fluidProgramReady()) {
        glEnable(GL_VERTEX_PROGRAM_POINT_SIZE);
        glEnable(GL_POINT_SPRITE);  // gl_PointCoord in a compatibility context
        glUseProgram(fluidProgram_);
        glUniform1f(glGetUniformLocation(fluidProgram_, "pixelsPerMetre"), static_cast<float>(pixelsPerMetre));
        glUniform1f(glGetUniformLocation(fluidProgram_, "radius"), static_cast<float>(fluid.radius()));
        glDrawElements(GL_POINTS, count, GL_UNSIGNED_INT, fluidOrder_.data());
        glUseProgram(0);
        glDisable(GL_POINT_SPRITE);
        glDisable(GL_VERTEX_PROGRAM_POINT_SIZE);
    } else {
        // Round points as wide as a particle at the camera's target.
        const double pixels = 2.0 * fluid.radius() * pixelsPerMetre / std::max(camera.distance(), 1e-3);
        glEnable(GL_POINT_SMOOTH);
        glPointSize(static_cast<float>(std::clamp(pixels, 2.0, 32.0)));
        glDrawElements(GL_POINTS, count, GL_UNSIGNED_INT, fluidOrder_.data());
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
