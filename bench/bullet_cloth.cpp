// Bullet's soft-body cloth on the sphere (bullet_cloth.h). Compiled with GPL_WITH_BULLET when
// Debian's libbullet-dev is installed; without it only hasBulletCloth() and the settings' text are
// built and bulletDropOnSphere() throws.
#include "bullet_cloth.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#if GPL_WITH_BULLET
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>
#endif

namespace gpl::bench {

std::string bulletClothSettings() {
    return "Bullet's btSoftBody holds this engine's cloth: the same particles (positions, masses), every link "
           "(stretch, "
           "shear, bend) with its rest length at linear stiffness kLST = 1, which is a PBD projection of stiffness 1 "
           "as "
           "this engine's links of compliance 0 are, and the triangles as faces;\n"
           "matched: time step, gravity, piterations = our projection iterations (no velocity or drift iterations), "
           "no damping (kDP = 0), the sphere's friction coefficient (Bullet's kDF = 1 times the sphere's), contacts at "
           "full "
           "hardness (kCHR = kKHR = 1), collision margin = particle radius, no sleeping, no self-collision;\n"
           "not matched: Bullet finds contacts against a sparse signed-distance field of the sphere (its default, "
           "SDF_RS), this engine against the sphere itself; Bullet's link projection is linearised in the squared "
           "length, ours exact; both hold a node still while its slide is below the coefficient times the step's push "
           "out, but a sliding node loses that fraction of its slide in Bullet, that much of it here";
}

#if GPL_WITH_BULLET

bool hasBulletCloth() { return true; }

namespace {

btVector3 bt(const Vec3& u) { return btVector3(u.x(), u.y(), u.z()); }
Vec3 vec(const btVector3& u) { return Vec3(u.x(), u.y(), u.z()); }

}  // namespace

study::DropRun bulletDropOnSphere(const study::SphereDrop& drop) {
    // This engine's cloth, built only to copy its particles, links and triangles.
    SoftBodies cloth;
    cloth.addCloth(study::sphereDropSpec(drop));
    std::vector<DistanceLink> stretch;
    for (const DistanceLink& l : cloth.links) {
        if (l.kind == LinkKind::Stretch) stretch.push_back(l);
    }

    btSoftBodyRigidBodyCollisionConfiguration configuration;
    btCollisionDispatcher dispatcher(&configuration);
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btSoftRigidDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
    const btVector3 gravity(0.0, -9.81, 0.0);
    world.setGravity(gravity);
    btSoftBodyWorldInfo& info = world.getWorldInfo();
    info.m_gravity = gravity;

    btSphereShape ballShape(drop.sphereRadius);
    btRigidBody::btRigidBodyConstructionInfo ballInfo(0.0, nullptr, &ballShape);
    ballInfo.m_friction = drop.friction;
    auto ownedBall = std::make_unique<btRigidBody>(ballInfo);
    btRigidBody& ball = *ownedBall;
    world.addRigidBody(&ball);

    std::vector<btVector3> x;
    std::vector<btScalar> m;
    for (std::size_t i = 0; i < cloth.x.size(); ++i) {
        x.push_back(bt(cloth.x[i]));
        m.push_back(cloth.w[i] > 0.0 ? cloth.mass[i] : 0.0);  // mass 0 pins a node in Bullet
    }
    auto owned = std::make_unique<btSoftBody>(&info, static_cast<int>(x.size()), x.data(), m.data());
    btSoftBody& body = *owned;
    body.getCollisionShape()->setMargin(drop.radius);
    btSoftBody::Material* material = body.m_materials[0];
    material->m_kLST = 1.0;
    for (const DistanceLink& l : cloth.links) {
        body.appendLink(static_cast<int>(l.i), static_cast<int>(l.j), material);
        body.m_links[body.m_links.size() - 1].m_rl = l.rest;
    }
    for (const SoftMesh& mesh : cloth.meshes) {
        for (const auto& t : mesh.triangles) {
            body.appendFace(static_cast<int>(t[0]), static_cast<int>(t[1]), static_cast<int>(t[2]), material);
        }
    }
    body.m_cfg.piterations = drop.iterations;
    body.m_cfg.viterations = 0;
    body.m_cfg.diterations = 0;
    body.m_cfg.kDP = 0.0;
    body.m_cfg.kDF = 1.0;   // a node's friction coefficient is kDF times the body's
    body.m_cfg.kCHR = 1.0;  // contacts with movable bodies
    body.m_cfg.kKHR = 1.0;  // and with static ones (the sphere): Bullet's default is 0.1
    body.setActivationState(DISABLE_DEACTIVATION);
    world.addSoftBody(&body);

    const auto steps = static_cast<long>(std::llround(drop.seconds / drop.h));
    study::DropRun run;
    run.stepMs.reserve(steps);
    std::vector<Vec3> now(cloth.x.size());
    const auto read = [&] {
        for (int i = 0; i < body.m_nodes.size(); ++i) now[i] = vec(body.m_nodes[i].m_x);
    };
    for (long s = 0; s < steps; ++s) {
        const double cpu = study::processCpuMs();
        const auto begin = std::chrono::steady_clock::now();
        world.stepSimulation(drop.h, 1, drop.h);
        run.stepMs.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count());
        run.cpuMs.push_back(study::processCpuMs() - cpu);
        read();
        run.deepest = std::max(run.deepest, study::penetration(now, drop));
    }
    world.removeSoftBody(&body);
    world.removeRigidBody(&ball);
    run.finite = true;
    for (const Vec3& p : now) run.finite = run.finite && p.allFinite();
    run.medianMs = study::median(run.stepMs);
    run.medianCpuMs = study::median(run.cpuMs);
    study::linkStretch(now, stretch, run.largestStretch, run.meanStretch);
    return run;
}

#else

bool hasBulletCloth() { return false; }

study::DropRun bulletDropOnSphere(const study::SphereDrop&) {
    throw std::runtime_error("built without Bullet (Debian libbullet-dev): ./lab bench cloth installs it");
}

#endif

}  // namespace gpl::bench
