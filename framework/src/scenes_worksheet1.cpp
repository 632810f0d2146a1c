// Worksheet 1 scenes: free fall and projectiles under gravity alone.
#include <cmath>
#include <string>

#include "gpl/scenes.h"

namespace gpl {
namespace {

const StageSet kFreeFall{Stage::ConstantAcceleration, Stage::Integration};

void fallingSphere(PhysicsEngine& e) { e.add(sphere("ball", 0.5, 1.0).at({0.0, 10.0, 0.0})); }

// Masses over four orders of magnitude, spheres and boxes: all fall alike.
void massesSideBySide(PhysicsEngine& e) {
    const struct {
        double mass;  // kg
        const char* tag;
    } sizes[] = {{0.1, "0.1kg"}, {1.0, "1kg"}, {10.0, "10kg"}, {1000.0, "1000kg"}};
    double x = -4.5;
    for (const auto& s : sizes) {
        e.add(sphere(std::string("sphere-") + s.tag, 0.4, s.mass).at({x, 10.0, 0.0}));
        e.add(box(std::string("box-") + s.tag, {0.4, 0.4, 0.4}, s.mass).at({x + 1.2, 10.0, 0.0}));
        x += 2.6;
    }
}

// Thrown at 45 degrees with 15 m/s: range v^2/g = 22.9 m, apex v^2/(4g) = 5.7 m above the start.
void projectile(PhysicsEngine& e) {
    const double speed = 15.0;
    const double angle = M_PI / 4.0;
    e.add(sphere("projectile", 0.3, 0.5)
              .at({-10.0, 1.0, 0.0})
              .moving({speed * std::cos(angle), speed * std::sin(angle), 0.0}));
}

// Static bodies (a floor plane, a shelf, a pillar) beside movable ones: only the movable fall.
void staticAndMovable(PhysicsEngine& e) {
    e.add(plane("floor", {0.0, 1.0, 0.0}));
    e.add(box("shelf", {2.0, 0.2, 1.0}, 1.0).at({-3.0, 5.0, 0.0}).makeStatic());
    e.add(box("pillar", {0.5, 3.0, 0.5}, 1.0).at({3.0, 3.0, 0.0}).makeStatic());
    e.add(sphere("ball", 0.5, 2.0).at({0.0, 8.0, 0.0}));
    e.add(box("crate", {0.5, 0.5, 0.5}, 5.0).at({-3.0, 9.0, 0.0}).moving({1.0, 0.0, 0.0}));
    e.add(sphere("pebble", 0.2, 0.1).at({3.0, 9.0, 0.0}).moving({-0.5, 2.0, 0.0}));
}

// A lattice of 1000 spheres and boxes with small sideways velocities: what the viewer draws at
// 60 frames per second, and a free fall that must look the same for every body.
void thousandBodies(PhysicsEngine& e) {
    e.add(plane("floor", {0.0, 1.0, 0.0}));
    int n = 0;
    for (int i = 0; i < 10; ++i) {
        for (int j = 0; j < 10; ++j) {
            for (int k = 0; k < 10; ++k, ++n) {
                const Vec3 at(2.0 * i - 9.0, 5.0 + 2.0 * j, 2.0 * k - 9.0);
                const Vec3 v(0.3 * ((n * 7) % 11 - 5), 0.5 * ((n * 3) % 7), 0.3 * ((n * 5) % 9 - 4));
                const std::string name = (n % 2 ? "box-" : "sphere-") + std::to_string(n);
                if (n % 2) {
                    e.add(box(name, {0.35, 0.35, 0.35}, 1.0 + n % 5).at(at).moving(v));
                } else {
                    e.add(sphere(name, 0.4, 1.0 + n % 5).at(at).moving(v));
                }
            }
        }
    }
}

}  // namespace

void addWorksheet1Scenes(SceneRegistry& r) {
    // Nothing stops a fall before worksheet 3: each view frames the motion until the first body
    // reaches the ground, sqrt(2 (y0 - r) / g) for a body dropped from rest.
    r.add({"falling-sphere", "1", "One sphere dropped from 10 m: free fall under gravity.", 1, kFreeFall,
           kDefaultTimeStep, fallingSphere, Integrator::SemiImplicitEuler, Vec3(0.0, 7.2, 0.0), 18.0, 1.4});
    r.add({"masses", "2", "Spheres and boxes from 0.1 kg to 1000 kg dropped side by side: all fall alike.", 1,
           kFreeFall, kDefaultTimeStep, massesSideBySide, Integrator::SemiImplicitEuler, Vec3(0.0, 7.3, 0.0), 18.5,
           1.4});
    r.add({"projectile", "3", "A ball thrown at 45 degrees with 15 m/s: a parabola.", 1, kFreeFall, kDefaultTimeStep,
           projectile, Integrator::SemiImplicitEuler, Vec3(1.5, 3.0, 0.0), 30.0, 2.25});
    r.add({"static-and-movable", "4", "A floor, a shelf and a pillar that stay put, and three bodies that fall.", 1,
           kFreeFall, kDefaultTimeStep, staticAndMovable, Integrator::SemiImplicitEuler, Vec3(0.0, 6.8, 0.0), 18.0,
           1.25});
    r.add({"thousand-bodies", "0", "1000 spheres and boxes in free fall (no collisions yet): a load for the viewer.", 1,
           kFreeFall, kDefaultTimeStep, thousandBodies, Integrator::SemiImplicitEuler, Vec3(0.0, 15.0, 0.0), 52.0,
           0.95});
}

}  // namespace gpl
