// Compiled with -Dgpl=gpl_reference together with the framework and solutions/ (see
// framework/viewer/CMakeLists.txt): every gpl:: name below is the reference engine's.
#include "reference.h"

#include <algorithm>

#include "gpl/scenes.h"

namespace gplref {
namespace {

class World : public ReferenceWorld {
public:
    void load(const std::string& scene, const Settings& s) override {
        gpl::load(engine_, gpl::scenes().find(scene));
        engine_.setTimeStep(s.timeStep);
        engine_.setGravity(gpl::Vec3(s.gravity[0], s.gravity[1], s.gravity[2]));
        engine_.setIntegratorKind(gpl::integratorFromId(s.integrator));
        engine_.setContactIterations(s.contactIterations);
        engine_.setConstraintIterations(s.constraintIterations);
        // gpl::load() keeps which stages are switched off: set every one.
        for (std::size_t i = 0; i < gpl::kStageCount; ++i) {
            const bool off = std::count(s.disabledStages.begin(), s.disabledStages.end(), static_cast<int>(i)) > 0;
            engine_.setStageEnabled(static_cast<gpl::Stage>(i), !off);
        }
        auto& bodies = engine_.bodies();
        for (std::size_t i = 0; i < std::min(bodies.size(), s.restitution.size()); ++i) {
            bodies[i].restitution = s.restitution[i];
        }
    }
    void step() override { engine_.step(); }
    std::vector<std::array<double, 7>> poses() const override {
        std::vector<std::array<double, 7>> out;
        for (const gpl::Body& b : engine_.bodies()) {
            const auto& q = b.orientation;
            out.push_back({b.position.x(), b.position.y(), b.position.z(), q.w(), q.x(), q.y(), q.z()});
        }
        return out;
    }
    std::vector<std::array<double, 3>> particles() const override {
        std::vector<std::array<double, 3>> out;
        for (const gpl::Vec3& x : engine_.softBodies().x) out.push_back({x.x(), x.y(), x.z()});
        return out;
    }

private:
    gpl::PhysicsEngine engine_;
};

}  // namespace

std::unique_ptr<ReferenceWorld> makeReferenceWorld() { return std::make_unique<World>(); }

}  // namespace gplref
