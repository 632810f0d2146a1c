// A twin of a loaded scene in another engine (Bullet, `./lab bench solvers`): the same bodies,
// shapes, masses, inertias, poses, velocities, restitution and friction, the same gravity, time step
// and solver iterations, stepped from outside and read back as poses and velocities.
#pragma once

#include <memory>
#include <vector>

#include "gpl/engine.h"
#include "gpl/math.h"

namespace gpl::bench {

/// One body's state, world frame; static bodies too, in the engine's order of bodies().
struct BodyState {
    Vec3 position;                        ///< m
    Quat orientation = Quat::Identity();
    Vec3 velocity;                        ///< m/s
    Vec3 angularVelocity;                 ///< rad/s
};

class SceneTwin {
public:
    virtual ~SceneTwin() = default;
    virtual void step() = 0;
    /// Every body of the scene, in the order of the engine it was made from.
    virtual std::vector<BodyState> state() const = 0;
};

/// Bullet's default pipeline (DBVT broad phase, sequential impulses with split impulses, no
/// sleeping) on the scene loaded in `engine`, at its time of loading. Friction matched pair by pair:
/// Bullet multiplies the two bodies' coefficients where this engine takes their geometric mean
/// (combineFriction()), so each Bullet body gets the square root of ours, and sqrt(mu_a) sqrt(mu_b) =
/// sqrt(mu_a mu_b); in a scene without the friction stage every coefficient is 0. Restitution is a
/// product in both. Only when built with Bullet (hasBulletTwin()).
std::unique_ptr<SceneTwin> bulletTwin(const PhysicsEngine& engine);
bool hasBulletTwin();

}  // namespace gpl::bench
