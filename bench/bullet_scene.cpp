// The Bullet 3 twin of a loaded scene (Debian libbullet-dev), set up as bullet_heap.cpp sets up the
// heap: the default collision configuration and dispatcher, the DBVT broad phase, the
// sequential-impulse solver with the engine's contact iterations, no sleeping, one fixed step of
// the engine's time step per call.
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "scene_twin.h"

namespace gpl::bench {

bool hasBulletTwin() { return true; }

namespace {

btVector3 bt(const Vec3& u) { return btVector3(u.x(), u.y(), u.z()); }
Vec3 vec(const btVector3& u) { return Vec3(u.x(), u.y(), u.z()); }

class BulletTwin final : public SceneTwin {
public:
    explicit BulletTwin(const PhysicsEngine& engine)
        : dispatcher_(&configuration_), world_(&dispatcher_, &broadphase_, &solver_, &configuration_),
          timeStep_(engine.timeStep()) {
        world_.setGravity(bt(engine.gravity()));
        world_.getSolverInfo().m_numIterations = engine.contactIterations();
        const bool friction = engine.requiredStages().contains(Stage::Friction);
        for (const Body& b : engine.bodies()) {
            shapes_.push_back(shapeOf(b));
            btVector3 inertia(0.0, 0.0, 0.0);
            if (!b.isStatic()) inertia = bt(b.inertia.diagonal());  // the shapes' inertias are diagonal in their frames
            btRigidBody::btRigidBodyConstructionInfo info(b.isStatic() ? 0.0 : b.mass, nullptr, shapes_.back().get(), inertia);
            info.m_startWorldTransform.setIdentity();
            if (b.shape != Shape::Plane) {
                info.m_startWorldTransform.setOrigin(bt(b.position));
                const Quat& q = b.orientation;
                info.m_startWorldTransform.setRotation(btQuaternion(q.x(), q.y(), q.z(), q.w()));
            }
            // Bullet's pair coefficient is the product of the bodies' (btManifoldResult::
            // calculateCombinedFriction), this engine's their geometric mean: the square roots give it.
            info.m_friction = friction ? std::sqrt(b.staticFriction) : 0.0;
            info.m_restitution = b.restitution;  // a product in both engines
            bodies_.push_back(std::make_unique<btRigidBody>(info));
            btRigidBody& body = *bodies_.back();
            if (b.invMass > 0.0) {  // a movable body starts with its velocities and is never put to sleep
                body.setLinearVelocity(bt(b.velocity));
                body.setAngularVelocity(bt(b.angularVelocity));
                body.setActivationState(DISABLE_DEACTIVATION);
            }
            world_.addRigidBody(&body);
        }
    }
    ~BulletTwin() override {
        for (const auto& body : bodies_) world_.removeRigidBody(body.get());
    }
    BulletTwin(const BulletTwin&) = delete;
    BulletTwin& operator=(const BulletTwin&) = delete;

    void step() override { world_.stepSimulation(timeStep_, 1, timeStep_); }

    std::vector<BodyState> state() const override {
        std::vector<BodyState> now;
        now.reserve(bodies_.size());
        for (const auto& body : bodies_) {
            const btQuaternion q = body->getOrientation();
            now.push_back({vec(body->getCenterOfMassPosition()), Quat(q.w(), q.x(), q.y(), q.z()),
                           vec(body->getLinearVelocity()), vec(body->getAngularVelocity())});
        }
        return now;
    }

private:
    // A plane keeps its offset along its normal; a box's collision margin (0.04 m by default, taken
    // inside its faces) is at most a quarter of its thinnest half extent, so that a card 4 cm
    // thick keeps a core.
    static std::unique_ptr<btCollisionShape> shapeOf(const Body& b) {
        switch (b.shape) {
            case Shape::Sphere:
                return std::make_unique<btSphereShape>(b.radius);
            case Shape::Box: {
                auto shape = std::make_unique<btBoxShape>(bt(b.halfExtents));
                shape->setMargin(std::min<btScalar>(shape->getMargin(), 0.25 * b.halfExtents.minCoeff()));
                return shape;
            }
            case Shape::Plane: {
                const Vec3 n = b.orientation * b.normal;
                return std::make_unique<btStaticPlaneShape>(bt(n), n.dot(b.position));
            }
        }
        return nullptr;
    }

    btDefaultCollisionConfiguration configuration_;
    btCollisionDispatcher dispatcher_;
    btDbvtBroadphase broadphase_;
    btSequentialImpulseConstraintSolver solver_;
    btDiscreteDynamicsWorld world_;
    double timeStep_;
    std::vector<std::unique_ptr<btCollisionShape>> shapes_;
    std::vector<std::unique_ptr<btRigidBody>> bodies_;
};

}  // namespace

std::unique_ptr<SceneTwin> bulletTwin(const PhysicsEngine& engine) { return std::make_unique<BulletTwin>(engine); }

}  // namespace gpl::bench
