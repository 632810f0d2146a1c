// The heap of `./lab bench engine` (spheres or cubes) in Bullet 3 (Debian libbullet-dev), set up as people use it:
// the default collision configuration and dispatcher, the DBVT broad phase, the sequential-impulse
// solver with the same iteration count, no sleeping, one fixed step of 1/60 s per call.
#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <memory>

#include "heap.h"

namespace gpl::bench {

bool hasBullet() { return true; }

HeapRun runBullet(HeapShape shape, std::size_t n, double seconds) {
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
    btBoxShape cubeShape(btVector3(kHalfSide, kHalfSide, kHalfSide));
    btCollisionShape* bodyShape = shape == HeapShape::Spheres ? static_cast<btCollisionShape*>(&sphereShape) : &cubeShape;
    btVector3 inertia(0.0, 0.0, 0.0);
    bodyShape->calculateLocalInertia(kMass, inertia);
    std::vector<std::unique_ptr<btRigidBody>> bodies;
    bodies.reserve(n);
    const std::vector<Vec3> at = heapPositions(n);
    const std::vector<Quat> turn = heapOrientations(n);
    for (std::size_t i = 0; i < n; ++i) {
        btTransform pose;
        pose.setIdentity();
        pose.setOrigin(btVector3(at[i].x(), at[i].y(), at[i].z()));
        if (shape == HeapShape::Boxes) pose.setRotation(btQuaternion(turn[i].x(), turn[i].y(), turn[i].z(), turn[i].w()));
        btRigidBody::btRigidBodyConstructionInfo info(kMass, nullptr, bodyShape, inertia);
        info.m_startWorldTransform = pose;
        info.m_friction = kFriction;
        info.m_restitution = 0.0;
        bodies.push_back(std::make_unique<btRigidBody>(info));
        bodies.back()->setActivationState(DISABLE_DEACTIVATION);
        world.addRigidBody(bodies.back().get());
    }

    HeapRun run;
    run.engine = "Bullet";
    run.shape = shape;
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
    const auto vec = [](const btVector3& u) { return Vec3(u.x(), u.y(), u.z()); };
    std::vector<HeapBody> end;
    for (const auto& body : bodies) {
        const btQuaternion q = body->getOrientation();
        end.push_back({vec(body->getCenterOfMassPosition()), Quat(q.w(), q.x(), q.y(), q.z()),
                       vec(body->getLinearVelocity()), vec(body->getAngularVelocity())});
    }
    measureQuality(end, run);
    for (const auto& body : bodies) world.removeRigidBody(body.get());
    world.removeRigidBody(&ground);
    return run;
}

}  // namespace gpl::bench
