// The viewer's camera: orbit / pan / zoom around a target, or fly (WASD and mouse look). GL-free,
// so the tests can check it and picking uses exactly the rays the renderer sees.
#pragma once

#include <vector>

#include "gpl/body.h"

namespace gpl::viewer {

struct Ray {
    Vec3 origin;     ///< m
    Vec3 direction;  ///< unit
};

/// A rectangle of the viewport in pixels (y down).
struct PixelBox {
    double left = 0.0, top = 0.0, right = 0.0, bottom = 0.0;
};

class Camera {
public:
    static constexpr double kFieldOfViewY = 45.0;  ///< degrees, vertical
    static constexpr double kNear = 0.1;           ///< m
    static constexpr double kFar = 2000.0;         ///< m

    Camera() { reset(); }
    /// The default view: looking at (0, 4, 0) from 24 m away, slightly from above.
    void reset();
    /// The default direction, moved and zoomed so that every sphere and box is in view.
    void frame(const std::vector<Body>& bodies);
    /// The default direction, looking at target from distance (m).
    void lookAt(const Vec3& target, double distance);

    void orbit(double dxPixels, double dyPixels);                    ///< left drag
    void pan(double dxPixels, double dyPixels, int viewportHeight);  ///< right drag
    void zoom(double wheelSteps);                                    ///< > 0 moves closer
    void setFlying(bool on) { flying_ = on; }
    bool flying() const { return flying_; }
    /// Fly: moves eye and target by (right, up, forward) metres.
    void move(const Vec3& rightUpForward);
    /// Fly: turns the view about the eye (mouse look).
    void look(double dxPixels, double dyPixels);

    Vec3 eye() const { return target_ - distance_ * forward(); }
    const Vec3& target() const { return target_; }
    double distance() const { return distance_; }
    Vec3 forward() const;
    Vec3 right() const;
    Vec3 up() const;

    /// The ray from the eye through pixel (x, y) of a width x height viewport (y down, as GLUT).
    Ray rayThrough(double x, double y, int width, int height) const;
    /// Where a world point lands in the viewport (pixels, y down); false when behind the eye.
    bool project(const Vec3& point, int width, int height, double& x, double& y) const;
    /// The pixels each moving (not static) sphere or box covers, taken as its bounding sphere, in
    /// the bodies' order; false (and fewer boxes) when one lies behind the eye.
    bool movingBodies(const std::vector<Body>& bodies, int width, int height, std::vector<PixelBox>& boxes) const;

private:
    Vec3 target_;
    double yaw_ = 0.0;       ///< rad, 0 looks along -z
    double pitch_ = 0.0;     ///< rad, > 0 looks down
    double distance_ = 1.0;  ///< m, eye to target
    bool flying_ = false;
};

}  // namespace gpl::viewer
