#include "gpl/stages.h"

namespace gpl {

const char* stageName(Stage stage) {
    switch (stage) {
        case Stage::ConstantAcceleration:
            return "gravity";
        case Stage::Springs:
            return "springs";
        case Stage::Integration:
            return "integrate";
        case Stage::Rotation:
            return "rotate";
        case Stage::CollisionDetection:
            return "collisions";
        case Stage::Ropes:
            return "ropes";
        case Stage::CollisionImpulses:
            return "impulses";
        case Stage::Friction:
            return "friction";
        case Stage::Interpenetration:
            return "interpenetration";
        case Stage::Constraints:
            return "constraints";
        case Stage::ParticleCollisions:
            return "particle collisions";
        case Stage::SoftPredict:
            return "predict";
        case Stage::SoftContacts:
            return "soft contacts";
        case Stage::SoftProject:
            return "project";
        case Stage::SoftVelocities:
            return "soft velocities";
        case Stage::FluidPredict:
            return "fluid predict";
        case Stage::FluidNeighbours:
            return "neighbours";
        case Stage::FluidProject:
            return "fluid project";
        case Stage::FluidVelocities:
            return "fluid velocities";
        case Stage::FluidSph:
            return "sph";
        case Stage::Count:
            break;
    }
    return "unknown";
}

std::string StageSet::names() const {
    std::string out;
    for (std::size_t i = 0; i < kStageCount; ++i) {
        const auto s = static_cast<Stage>(i);
        if (!contains(s)) continue;
        if (!out.empty()) out += ", ";
        out += stageName(s);
    }
    return out;
}

}  // namespace gpl
