#include "camera.h"

#include <algorithm>
#include <cmath>

namespace gpl::viewer {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadiansPerPixel = 0.005;
constexpr double kMaxPitch = 1.5;  // rad, just short of straight down or up

}  // namespace

void Camera::reset() {
    target_ = Vec3(0.0, 4.0, 0.0);
    yaw_ = 0.0;
    pitch_ = 0.25;
    distance_ = 24.0;
    flying_ = false;
}

void Camera::frame(const std::vector<Body>& bodies) {
    reset();
    Eigen::AlignedBox3d box;
    for (const Body& b : bodies) {
        if (b.shape == Shape::Plane) continue;
        const Vec3 r = b.shape == Shape::Sphere ? Vec3::Constant(b.radius) : Vec3::Constant(b.halfExtents.norm());
        box.extend(b.position - r);
        box.extend(b.position + r);
    }
    if (box.isEmpty()) return;
    target_ = box.center();
    // The bounding sphere fills about two thirds of the view's height.
    const double radius = std::max(1.0, 0.5 * box.diagonal().norm());
    distance_ = std::clamp(1.5 * radius / std::tan(kFieldOfViewY * kPi / 360.0), 16.0, 400.0);
}

void Camera::lookAt(const Vec3& target, double distance) {
    reset();
    target_ = target;
    distance_ = distance;
}

Vec3 Camera::forward() const {
    return Vec3(std::sin(yaw_) * std::cos(pitch_), -std::sin(pitch_), -std::cos(yaw_) * std::cos(pitch_));
}

Vec3 Camera::right() const { return forward().cross(Vec3::UnitY()).normalized(); }

Vec3 Camera::up() const { return right().cross(forward()); }

void Camera::orbit(double dx, double dy) {
    yaw_ += dx * kRadiansPerPixel;
    pitch_ = std::clamp(pitch_ + dy * kRadiansPerPixel, -kMaxPitch, kMaxPitch);
}

void Camera::pan(double dx, double dy, int viewportHeight) {
    // One pixel moves the target by the size of a pixel at the target's distance.
    const double metresPerPixel = 2.0 * distance_ * std::tan(kFieldOfViewY * kPi / 360.0) / std::max(1, viewportHeight);
    target_ += metresPerPixel * (-dx * right() + dy * up());
}

void Camera::zoom(double steps) { distance_ = std::clamp(distance_ * std::pow(0.9, steps), 0.5, 500.0); }

void Camera::move(const Vec3& d) { target_ += d.x() * right() + d.y() * up() + d.z() * forward(); }

void Camera::look(double dx, double dy) {
    const Vec3 e = eye();
    orbit(dx, dy);
    target_ = e + distance_ * forward();
}

Ray Camera::rayThrough(double x, double y, int width, int height) const {
    const double w = std::max(1, width), h = std::max(1, height);
    const double t = std::tan(kFieldOfViewY * kPi / 360.0);
    const double nx = 2.0 * x / w - 1.0, ny = 1.0 - 2.0 * y / h;
    const Vec3 dir = forward() + right() * (nx * t * w / h) + up() * (ny * t);
    return {eye(), dir.normalized()};
}

bool Camera::project(const Vec3& p, int width, int height, double& x, double& y) const {
    const Vec3 d = p - eye();
    const double depth = d.dot(forward());
    if (depth <= kNear) return false;
    const double w = std::max(1, width), h = std::max(1, height);
    const double t = std::tan(kFieldOfViewY * kPi / 360.0);
    const double nx = d.dot(right()) / (depth * t * w / h);
    const double ny = d.dot(up()) / (depth * t);
    x = (nx + 1.0) * 0.5 * w;
    y = (1.0 - ny) * 0.5 * h;
    return true;
}

bool Camera::movingBodies(const std::vector<Body>& bodies, int width, int height, std::vector<PixelBox>& boxes) const {
    const double pixelsPerRadian = 0.5 * std::max(1, height) / std::tan(kFieldOfViewY * kPi / 360.0);
    bool allInFront = true;
    for (const Body& b : bodies) {
        if (b.isStatic() || b.shape == Shape::Plane) continue;
        double x, y;
        if (!project(b.position, width, height, x, y)) {
            allInFront = false;
            continue;
        }
        // A sphere's outline spans about its radius over its depth (exact at the view's centre).
        const double r = (b.shape == Shape::Sphere ? b.radius : b.halfExtents.norm()) * pixelsPerRadian /
                         (b.position - eye()).dot(forward());
        boxes.push_back({x - r, y - r, x + r, y + r});
    }
    return allInFront;
}

}  // namespace gpl::viewer
