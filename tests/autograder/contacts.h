// What the worksheet-3, 4 and 5 autograders share: random configurations from a fixed seed, the
// geometry the tests compare with (closed forms, written here once), messages that show vectors,
// and the fixture that names hooks still open.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "gpl/body.h"
#include "gpl/contact.h"
#include "gpl/engine.h"
#include "gpl/hooks.h"

namespace gpl::checks {

inline std::string str(const Vec3& v) {
    std::ostringstream out;
    out.precision(12);
    out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
    return out.str();
}

inline std::string str(const Body& b) {
    std::ostringstream out;
    out.precision(12);
    out << b.name << " at " << str(b.position);
    if (b.shape == Shape::Sphere) out << ", radius " << b.radius;
    if (b.shape == Shape::Plane) out << ", world normal " << str(b.orientation * b.normal);
    if (b.shape == Shape::Box) {
        const Quat& q = b.orientation;
        out << ", half extents " << str(b.halfExtents) << ", orientation (w, x, y, z) (" << q.w() << ", " << q.x()
            << ", " << q.y() << ", " << q.z() << ")";
    }
    if (b.isStatic()) {
        out << ", static";
    } else {
        out << ", " << b.mass << " kg, velocity " << str(b.velocity);
    }
    return out.str();
}

inline std::string str(const std::optional<Contact>& c) {
    if (!c) return "no contact";
    std::ostringstream out;
    out.precision(12);
    out << "contact with normal " << str(c->normal) << ", depth " << c->depth << ", " << c->pointCount << " point(s)";
    if (c->pointCount >= 1) out << ", the first at " << str(c->points[0]);
    return out.str();
}

/// The run's part of every seed: 0, so that a submission graded twice gets the same inputs and the
/// same score; GPL_CHECKER_SEED=N draws other inputs (graded.cpp), to try the tests on many.
std::uint32_t runSeed();

/// Uniform numbers from std::mt19937, whose output the standard fixes: with the same seeds, the same
/// configurations on every machine (std::uniform_real_distribution is left to the library).
class Random {
public:
    explicit Random(std::uint32_t seed) : engine_(seed ^ runSeed()) {}
    double uniform(double lo, double hi) { return lo + (hi - lo) * (static_cast<double>(engine_()) / 4294967296.0); }
    Vec3 inBox(double half) { return {uniform(-half, half), uniform(-half, half), uniform(-half, half)}; }
    /// A unit vector, uniform over the sphere.
    Vec3 direction() {
        const double z = uniform(-1.0, 1.0), phi = uniform(0.0, 2.0 * M_PI), s = std::sqrt(1.0 - z * z);
        return {s * std::cos(phi), s * std::sin(phi), z};
    }
    /// A unit vector perpendicular to n (unit).
    Vec3 perpendicular(const Vec3& n) {
        const Vec3 t = direction().cross(n);
        return t.norm() > 1e-3 ? Vec3(t.normalized()) : Vec3(n.unitOrthogonal());
    }
    Quat rotation() { return Quat(Eigen::AngleAxisd(uniform(0.0, 2.0 * M_PI), direction())); }

private:
    std::mt19937 engine_;
};

/// The plane's normal in the world frame.
inline Vec3 worldNormal(const Body& plane) { return (plane.orientation * plane.normal).normalized(); }

/// Signed distance (m) of a point in front of a plane: > 0 on the free side, < 0 inside the solid.
inline double heightAbove(const Body& plane, const Vec3& x) { return worldNormal(plane).dot(x - plane.position); }

/// The eight corners of a box (m, world frame).
inline std::vector<Vec3> corners(const Body& box) {
    std::vector<Vec3> out;
    for (int k = 0; k < 8; ++k) {
        const Vec3 signs(k & 1 ? 1.0 : -1.0, k & 2 ? 1.0 : -1.0, k & 4 ? 1.0 : -1.0);
        out.push_back(box.position + box.orientation * signs.cwiseProduct(box.halfExtents));
    }
    return out;
}

/// The body turned by R about the origin and then moved by t: a rigid motion of the whole scene.
inline Body carried(Body b, const Quat& R, const Vec3& t) {
    b.position = R * b.position + t;
    b.orientation = (R * b.orientation).normalized();
    return b;
}

/// How far two spheres overlap (m): > 0 overlapping, 0 touching, < 0 apart.
inline double overlap(const Body& a, const Body& b) { return a.radius + b.radius - (b.position - a.position).norm(); }

/// A hand-made contact between two bodies, as the collision kernels define it (for testing the
/// response kernels on their own).
inline Contact contactAlong(const Vec3& normal, double depth, const Vec3& point, double restitution = 0.0) {
    Contact c = Contact::at(point, normal, depth);
    c.restitution = restitution;
    return c;
}

/// Failures of a test say which hooks are still stubs: kernels report themselves in this process,
/// engine hooks in the engine.
class ContactsTest : public ::testing::Test {
protected:
    PhysicsEngine engine;

    void TearDown() override {
        if (!HasFailure()) return;
        std::vector<std::string> open = kernelsNotImplemented();
        for (const std::string& h : engine.missingHooks()) {
            if (std::find(open.begin(), open.end(), h) == open.end()) open.push_back(h);
        }
        if (open.empty()) return;
        std::string hooks;
        for (const auto& h : open) hooks += " " + h;
        ADD_FAILURE() << "hooks still not implemented:" << hooks;
    }
};

}  // namespace gpl::checks
