// Compiled with -Dgpl=gpl_reference together with the framework and solutions/ (see
// framework/viewer/CMakeLists.txt): every gpl:: name below is the reference engine's.
#include "reference.h"

#include "gpl/scenes.h"

namespace gplref {
namespace {

class World : public ReferenceWorld {
public:
    void load(const std::string& scene, double timeStep, const std::array<double, 3>& g,
              const std::string& integrator) override {
        gpl::load(engine_, gpl::scenes().find(scene));
        engine_.setTimeStep(timeStep);
        engine_.setGravity(gpl::Vec3(g[0], g[1], g[2]));
        engine_.setIntegratorKind(gpl::integratorFromId(integrator));
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

private:
    gpl::PhysicsEngine engine_;
};

}  // namespace

std::unique_ptr<ReferenceWorld> makeReferenceWorld() { return std::make_unique<World>(); }

}  // namespace gplref
