// The heap of `./lab bench engine` in Bullet 3 (Debian libbullet-dev), set up as people use it:
// the default collision configuration and dispatcher, the DBVT broad phase, the sequential-impulse
// solver with the same iteration count, no sleeping, one fixed step of 1/60 s per call.
#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <memory>

#include "heap.h"

namespace gpl::bench {

bool hasBullet() { return true; }

HeapRun runBullet(std::size_t n, double seconds) {
    btDefaultCollisionConfiguration configuration;
    btCollisionDispatcher dispatcher(&configuration);
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
    world.setGravity(btVector3(0.0, -9.81, 0.0));
    world.getSolverInfo().m_numIterations = kIterations;

    btStaticPlaneShape groundShape(btVector3(0.0, 1.0, 0.0), 0.0);
    btRigidBody ground(btRigidBody::btRigidBodyConstructionInfo(0.0, nullptr, &groundShape));
    ground.setFriction(kFriction);
    ground.setRestitution(0.0);
    world.addRigidBody(&ground);

    btSphereShape sphereShape(kRadius);
    btVector3 inertia(0.0, 0.0, 0.0);
    sphereShape.calculateLocalInertia(kMass, inertia);
    std::vector<std::unique_ptr<btRigidBody>> spheres;
    spheres.reserve(n);
    for (const Vec3& p : heapPositions(n)) {
        btTransform at;
        at.setIdentity();
        at.setOrigin(btVector3(p.x(), p.y(), p.z()));
        btRigidBody::btRigidBodyConstructionInfo info(kMass, nullptr, &sphereShape, inertia);
        info.m_startWorldTransform = at;
        info.m_friction = kFriction;
        info.m_restitution = 0.0;
        spheres.push_back(std::make_unique<btRigidBody>(info));
        spheres.back()->setActivationState(DISABLE_DEACTIVATION);
        world.addRigidBody(spheres.back().get());
    }

    HeapRun run;
    run.engine = "Bullet";
    run.bodies = n;
    timeSteps(
        seconds, [&world] { world.stepSimulation(kTimeStep, 1, kTimeStep); },
        [&dispatcher] {
            double contacts = 0.0;
            for (int m = 0; m < dispatcher.getNumManifolds(); ++m)
                contacts += dispatcher.getManifoldByIndexInternal(m)->getNumContacts();
            return contacts;
        },
        run);
    std::vector<Vec3> x, v;
    for (const auto& body : spheres) {
        const btVector3& p = body->getCenterOfMassPosition();
        const btVector3& u = body->getLinearVelocity();
        x.emplace_back(p.x(), p.y(), p.z());
        v.emplace_back(u.x(), u.y(), u.z());
    }
    measureQuality(x, v, run);
    for (const auto& body : spheres) world.removeRigidBody(body.get());
    world.removeRigidBody(&ground);
    return run;
}

}  // namespace gpl::bench
