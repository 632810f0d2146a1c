// Built instead of bullet_scene.cpp when Bullet is not installed: `./lab bench solvers` then runs
// this engine alone; the lab script installs libbullet-dev for it.
#include <stdexcept>

#include "scene_twin.h"

namespace gpl::bench {

bool hasBulletTwin() { return false; }

std::unique_ptr<SceneTwin> bulletTwin(const PhysicsEngine&) {
    throw std::runtime_error("built without Bullet (Debian libbullet-dev): ./lab bench solvers installs it");
}

}  // namespace gpl::bench
