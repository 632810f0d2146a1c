// The heap of `./lab bench engine` (spheres or cubes) in Bullet 3 (Debian libbullet-dev), set up as people use it:
// the default collision configuration and dispatcher, the DBVT broad phase, the sequential-impulse
// solver with the same iteration count, no sleeping, one fixed step of 1/60 s per call. Bullet's
// pair friction is the product of the two bodies' coefficients (btManifoldResult::
// calculateCombinedFriction) where this engine's is their geometric mean: each Bullet body gets
// sqrt(kFriction), the ground too, so that every pair, with the ground or between bodies, has
// kFriction in both; the table's header prints the coefficient each engine's contacts hold.
#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <memory>

#include "heap.h"

namespace gpl::bench {

bool hasBullet() { return true; }

namespace {

const btScalar kBodyFriction = std::sqrt(kFriction);

class BulletHeap final : public HeapSim {
public:
    BulletHeap(HeapShape shape, std::size_t n)
        : dispatcher_(&configuration_),
          world_(&dispatcher_, &broadphase_, &solver_, &configuration_),
          ground_(btRigidBody::btRigidBodyConstructionInfo(0.0, nullptr, &groundShape_)) {
        world_.setGravity(btVector3(0.0, -9.81, 0.0));
        world_.getSolverInfo().m_numIterations = kIterations;
        ground_.setFriction(kBodyFriction);
        ground_.setRestitution(0.0);
        world_.addRigidBody(&ground_);
        btCollisionShape* bodyShape =
            shape == HeapShape::Spheres ? static_cast<btCollisionShape*>(&sphereShape_) : &cubeShape_;
        btVector3 inertia(0.0, 0.0, 0.0);
        bodyShape->calculateLocalInertia(kMass, inertia);
        bodies_.reserve(n);
        const std::vector<Vec3> at = heapPositions(n);
        const std::vector<Quat> turn = heapOrientations(n);
        for (std::size_t i = 0; i < n; ++i) {
            btTransform pose;
            pose.setIdentity();
            pose.setOrigin(btVector3(at[i].x(), at[i].y(), at[i].z()));
            if (shape == HeapShape::Boxes) pose.setRotation(btQuaternion(turn[i].x(), turn[i].y(), turn[i].z(), turn[i].w()));
            btRigidBody::btRigidBodyConstructionInfo info(kMass, nullptr, bodyShape, inertia);
            info.m_startWorldTransform = pose;
            info.m_friction = kBodyFriction;
            info.m_restitution = 0.0;
            bodies_.push_back(std::make_unique<btRigidBody>(info));
            bodies_.back()->setActivationState(DISABLE_DEACTIVATION);
            world_.addRigidBody(bodies_.back().get());
        }
    }
    ~BulletHeap() override {
        for (const auto& body : bodies_) world_.removeRigidBody(body.get());
        world_.removeRigidBody(&ground_);
    }
    BulletHeap(const BulletHeap&) = delete;
    BulletHeap& operator=(const BulletHeap&) = delete;

    void step() override { world_.stepSimulation(kTimeStep, 1, kTimeStep); }
    double contactPoints() const override {
        double points = 0.0;
        for (int m = 0; m < dispatcher_.getNumManifolds(); ++m) points += dispatcher_.getManifoldByIndexInternal(m)->getNumContacts();
        return points;
    }
    std::pair<double, double> pairFriction() const override {
        double ground = std::nan(""), between = std::nan("");
        for (int m = 0; m < dispatcher_.getNumManifolds(); ++m) {
            const btPersistentManifold* manifold = dispatcher_.getManifoldByIndexInternal(m);
            if (manifold->getNumContacts() == 0) continue;
            const bool withGround = manifold->getBody0() == &ground_ || manifold->getBody1() == &ground_;
            (withGround ? ground : between) = manifold->getContactPoint(0).m_combinedFriction;
        }
        return {ground, between};
    }
    std::vector<HeapBody> state() const override {
        const auto vec = [](const btVector3& u) { return Vec3(u.x(), u.y(), u.z()); };
        std::vector<HeapBody> end;
        for (const auto& body : bodies_) {
            const btQuaternion q = body->getOrientation();
            end.push_back({vec(body->getCenterOfMassPosition()), Quat(q.w(), q.x(), q.y(), q.z()),
                           vec(body->getLinearVelocity()), vec(body->getAngularVelocity())});
        }
        return end;
    }

private:
    btDefaultCollisionConfiguration configuration_;
    btCollisionDispatcher dispatcher_;
    btDbvtBroadphase broadphase_;
    btSequentialImpulseConstraintSolver solver_;
    btDiscreteDynamicsWorld world_;
    btStaticPlaneShape groundShape_{btVector3(0.0, 1.0, 0.0), 0.0};
    btRigidBody ground_;
    btSphereShape sphereShape_{kRadius};
    btBoxShape cubeShape_{btVector3(kHalfSide, kHalfSide, kHalfSide)};
    std::vector<std::unique_ptr<btRigidBody>> bodies_;
};

}  // namespace

std::unique_ptr<HeapSim> bulletHeap(HeapShape shape, std::size_t n) { return std::make_unique<BulletHeap>(shape, n); }

}  // namespace gpl::bench
