#include "soft_shapes.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gpl::viewer {
namespace {

// Möller-Trumbore: how far along the ray it crosses the triangle (either side), if it does.
std::optional<double> crossTriangle(const Ray& ray, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 e1 = b - a, e2 = c - a;
    const Vec3 q = ray.direction.cross(e2);
    const double det = e1.dot(q);
    if (std::abs(det) <= 1e-12 * e1.norm() * e2.norm()) return std::nullopt;  // edge-on, or no area
    const Vec3 s = ray.origin - a;
    const double u = s.dot(q) / det;
    if (u < 0.0 || u > 1.0) return std::nullopt;
    const Vec3 r = s.cross(e1);
    const double v = ray.direction.dot(r) / det;
    if (v < 0.0 || u + v > 1.0) return std::nullopt;
    const double t = e2.dot(r) / det;
    return t >= 0.0 ? std::optional<double>(t) : std::nullopt;
}

// Distance along the ray to where it enters the sphere, if it does (0 from inside).
std::optional<double> enterSphere(const Ray& ray, const Vec3& centre, double radius) {
    const Vec3 m = ray.origin - centre;
    const double b = m.dot(ray.direction), c = m.squaredNorm() - radius * radius;
    const double disc = b * b - c;
    if (disc < 0.0) return std::nullopt;
    const double t = -b - std::sqrt(disc);
    if (t >= 0.0) return t;
    return c <= 0.0 ? std::optional<double>(0.0) : std::nullopt;
}

// A unit vector across d (unit).
Vec3 across(const Vec3& d) {
    const Vec3 other = std::abs(d.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    return d.cross(other).normalized();
}

LinkKind stretchKind(SoftMesh::Kind kind) {
    switch (kind) {
        case SoftMesh::Kind::Cloth:
            return LinkKind::Stretch;
        case SoftMesh::Kind::Rope:
            return LinkKind::Rope;
        case SoftMesh::Kind::SoftBody:
            break;
    }
    return LinkKind::Edge;
}

}  // namespace

void surfaceNormals(const std::vector<Vec3>& x, const SoftMesh& mesh, std::vector<Vec3>& normals) {
    normals.assign(mesh.count, Vec3::Zero());
    for (const auto& t : mesh.triangles) {
        const Vec3 n = (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]);  // twice the area long
        for (std::uint32_t i : t) normals[i - mesh.first] += n;
    }
    for (Vec3& n : normals) {
        const double length = n.norm();
        n = length > 0.0 ? Vec3(n / length) : Vec3::Zero();
    }
}

TriangleMesh ropeTube(const std::vector<Vec3>& points, double radius, int sides) {
    TriangleMesh m;
    constexpr double kPi = 3.14159265358979323846;
    Vec3 side = Vec3::Zero();  // carried from segment to segment
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
        const Vec3 axis = points[i + 1] - points[i];
        const double length = axis.norm();
        const Vec3 d = length > 0.0 ? Vec3(axis / length) : Vec3::UnitY();
        // Parallel transport: the last segment's side vector, made perpendicular to this one.
        const Vec3 carried = side - side.dot(d) * d;
        side = carried.norm() > 1e-6 ? Vec3(carried.normalized()) : across(d);
        const Vec3 other = d.cross(side);
        const auto base = static_cast<std::uint32_t>(m.vertices.size());
        for (const Vec3& centre : {points[i], points[i + 1]}) {
            for (int k = 0; k < sides; ++k) {
                const double a = 2.0 * kPi * k / sides;
                const Vec3 n = std::cos(a) * side + std::sin(a) * other;
                m.vertices.push_back(centre + radius * n);
                m.normals.push_back(n);
            }
        }
        const auto s = static_cast<std::uint32_t>(sides);
        for (std::uint32_t k = 0; k < s; ++k) {
            const std::uint32_t k1 = (k + 1) % s;
            // Counter-clockwise seen from outside: side, then other, is the turn about d.
            m.indices.insert(m.indices.end(), {base + k, base + k1, base + s + k1, base + k, base + s + k1, base + s + k});
        }
    }
    return m;
}

double ropeDrawRadius(const SoftBodies& soft, std::size_t mesh) {
    const SoftMesh& m = soft.meshes[mesh];
    double length = 0.0;
    for (std::uint32_t i = m.first; i + 1 < m.first + m.count; ++i) length += (soft.x[i + 1] - soft.x[i]).norm();
    const double segment = m.count > 1 ? length / (m.count - 1) : 0.0;
    return std::max(m.radius, 0.2 * segment);
}

std::optional<ParticleHit> pickParticle(const SoftBodies& soft, const Ray& ray) {
    std::optional<ParticleHit> best;
    for (std::size_t mi = 0; mi < soft.meshes.size(); ++mi) {
        const SoftMesh& m = soft.meshes[mi];
        if (m.triangles.empty()) {
            const double r = ropeDrawRadius(soft, mi);
            for (std::uint32_t i = m.first; i < m.first + m.count; ++i) {
                const auto t = enterSphere(ray, soft.x[i], r);
                if (t && (!best || *t < best->distance)) best = ParticleHit{i, *t};
            }
            continue;
        }
        // A particle's own sphere (a cloth's edges and corners, where a ray may graze the surface).
        for (std::uint32_t i = m.first; i < m.first + m.count; ++i) {
            const auto t = enterSphere(ray, soft.x[i], m.radius);
            if (t && (!best || *t < best->distance)) best = ParticleHit{i, *t};
        }
        for (const auto& tri : m.triangles) {
            const auto t = crossTriangle(ray, soft.x[tri[0]], soft.x[tri[1]], soft.x[tri[2]]);
            if (!t || (best && *t >= best->distance)) continue;
            const Vec3 at = ray.origin + *t * ray.direction;
            std::uint32_t nearest = tri[0];
            for (std::uint32_t i : tri) {
                if ((soft.x[i] - at).squaredNorm() < (soft.x[nearest] - at).squaredNorm()) nearest = i;
            }
            best = ParticleHit{nearest, *t};
        }
    }
    return best;
}

std::optional<std::uint32_t> particleByName(const SoftBodies& soft, const std::string& name) {
    const auto hash = name.rfind('#');
    if (hash == std::string::npos || hash + 1 == name.size()) return std::nullopt;
    const std::string digits = name.substr(hash + 1);
    if (digits.size() > 9 || !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        return std::nullopt;  // not a number, or more particles than a mesh holds
    }
    const unsigned long k = std::stoul(digits);
    for (const SoftMesh& m : soft.meshes) {
        if (m.name == name.substr(0, hash) && k < m.count) return static_cast<std::uint32_t>(m.first + k);
    }
    return std::nullopt;
}

std::string particleName(const SoftBodies& soft, std::uint32_t particle) {
    const SoftMesh& m = soft.meshes[soft.meshOf[particle]];
    return m.name + "#" + std::to_string(particle - m.first);
}

std::size_t constraintCount(const SoftBodies& soft, std::size_t mesh) {
    return std::size_t{soft.meshes[mesh].linkCount} + soft.meshes[mesh].volumeCount;
}

double meshStretch(const SoftBodies& soft, std::size_t mesh) {
    return soft.largestStretch(mesh, stretchKind(soft.meshes[mesh].kind));
}

Bounds meshBounds(const SoftBodies& soft, std::size_t mesh) {
    const SoftMesh& m = soft.meshes[mesh];
    Bounds box;
    for (std::uint32_t i = m.first; i < m.first + m.count; ++i) box.extend(soft.x[i]);
    if (!box.isEmpty()) {
        box.min() -= Vec3::Constant(m.radius);
        box.max() += Vec3::Constant(m.radius);
    }
    return box;
}

bool movingMeshes(const Camera& camera, const SoftBodies& soft, int width, int height, std::vector<PixelBox>& boxes) {
    constexpr double kPi = 3.14159265358979323846;
    const double pixelsPerRadian = 0.5 * std::max(1, height) / std::tan(Camera::kFieldOfViewY * kPi / 360.0);
    bool allInFront = true;
    for (std::size_t mi = 0; mi < soft.meshes.size(); ++mi) {
        if (!meshMoves(soft, mi)) continue;
        const SoftMesh& m = soft.meshes[mi];
        const double radius = m.kind == SoftMesh::Kind::Rope ? ropeDrawRadius(soft, mi) : m.radius;
        PixelBox box{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                     -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
        bool inFront = true;
        for (std::uint32_t i = m.first; i < m.first + m.count; ++i) {
            double x, y;
            if (!camera.project(soft.x[i], width, height, x, y)) {
                inFront = false;
                break;
            }
            // A particle's sphere spans about its radius over its depth, as a body's in movingBodies().
            const double r = radius * pixelsPerRadian / (soft.x[i] - camera.eye()).dot(camera.forward());
            box = {std::min(box.left, x - r), std::min(box.top, y - r), std::max(box.right, x + r),
                   std::max(box.bottom, y + r)};
        }
        if (inFront) {
            boxes.push_back(box);
        } else {
            allInFront = false;
        }
    }
    return allInFront;
}

bool meshMoves(const SoftBodies& soft, std::size_t mesh) {
    const SoftMesh& m = soft.meshes[mesh];
    for (std::uint32_t i = m.first; i < m.first + m.count; ++i) {
        if (soft.w[i] > 0.0) return true;
    }
    return false;
}

}  // namespace gpl::viewer
