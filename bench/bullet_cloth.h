// Bullet's side of the cloth study (./lab bench cloth): the same cloth dropped on the same sphere
// as dropOnSphere() (cloth_study.h), run by Bullet 3's soft bodies (Debian libbullet-dev,
// BulletSoftBody) and measured alike. Built with Bullet only when it is installed; the lab and its
// tests need nothing of it.
#pragma once

#include <string>

#include "cloth_study.h"

namespace gpl::bench {

/// Whether the program was built with Bullet.
bool hasBulletCloth();

/// The drop in Bullet: a btSoftBody with this engine's cloth's particles (positions, masses) and
/// every one of its links (stretch, shear and bend, each with its rest length), each at linear
/// stiffness kLST = 1 (a PBD projection of stiffness 1, as this engine's links of compliance 0),
/// and its triangles as faces; m_cfg.piterations = the drop's iterations, no velocity or drift
/// iterations, no damping (kDP = 0), the sphere's friction coefficient (kDF = 1 times the sphere
/// body's friction: Bullet multiplies them), contacts at full hardness (kCHR and, for static
/// bodies, kKHR = 1), the collision margin = the particles' radius, gravity 9.81 m/s^2, never put to sleep; a static
/// btSphereShape of the same radius, and one fixed step of h per stepSimulation(). Bullet's default soft-rigid
/// collision (fCollision:: SDF_RS: the nodes against a sparse signed-distance field of the sphere). Throws
/// std::runtime_error when built without Bullet.
study::DropRun bulletDropOnSphere(const study::SphereDrop& drop);

/// What bulletDropOnSphere() matches and how, in a few lines for the program's output.
std::string bulletClothSettings();

}  // namespace gpl::bench
