#include "gpl/scenes.h"

#include <algorithm>
#include <cctype>
#include <stdexcept>

namespace gpl {
namespace {

std::string upper(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
    return s;
}

bool validKey(const std::string& key) {
    static const std::vector<std::string> keys = {"1",  "2",  "3",  "4",  "5",  "6",  "7",  "8",  "9",   "0",   "F1",
                                                  "F2", "F3", "F4", "F5", "F6", "F7", "F8", "F9", "F10", "F11", "F12"};
    return std::find(keys.begin(), keys.end(), key) != keys.end();
}

}  // namespace

void SceneRegistry::add(Scene scene) {
    scene.key = upper(scene.key);
    // Keys ran out with worksheet 6: later course scenes have none (the scene list and the command line reach them).
    const bool keyless = scene.key.empty() && scene.worksheet != 0;
    if (!keyless && !validKey(scene.key))
        throw std::invalid_argument("scene '" + scene.name + "': key must be 0-9 or F1-F12");
    const bool studentKey = scene.key == "F11" || scene.key == "F12";
    if (studentKey != (scene.worksheet == 0)) {
        throw std::invalid_argument("scene '" + scene.name + "': F11 and F12 are for the student's own scenes " +
                                    "(worksheet 0), the other keys for the course's");
    }
    for (const Scene& s : scenes_) {
        if (s.name == scene.name) throw std::invalid_argument("two scenes are named '" + scene.name + "'");
        if (!keyless && s.key == scene.key) {
            throw std::invalid_argument("scenes '" + s.name + "' and '" + scene.name + "' share the key " + scene.key);
        }
    }
    scenes_.push_back(std::move(scene));
}

const Scene& SceneRegistry::find(const std::string& nameOrKey) const {
    for (const Scene& s : scenes_) {
        if (s.name == nameOrKey || (!s.key.empty() && s.key == upper(nameOrKey))) return s;
    }
    std::string known;
    for (const Scene& s : scenes_) known += "\n  " + (s.key.empty() ? "-" : s.key) + "\t" + s.name;
    throw std::invalid_argument("unknown scene '" + nameOrKey + "'; known scenes (key, name):" + known);
}

const SceneRegistry& scenes() {
    static const SceneRegistry registry = [] {
        SceneRegistry r;
        addWorksheet1Scenes(r);
        addWorksheet2Scenes(r);
        addWorksheet3Scenes(r);
        addWorksheet4Scenes(r);
        addWorksheet5Scenes(r);
        addWorksheet6Scenes(r);
        addWorksheet7Scenes(r);
        addStackingScenes(r);
        addWorksheet8Scenes(r);
        addWorksheet9Scenes(r);
        addStudentScenes(r);
        return r;
    }();
    return registry;
}

void load(PhysicsEngine& engine, const Scene& scene) {
    engine.clear();
    engine.setGravity(standardGravity());
    engine.setTimeStep(scene.timeStep);
    engine.setRequiredStages(scene.stages);
    engine.setIntegratorKind(scene.integrator);
    const PhysicsEngine defaults;
    engine.setConstraintIterations(scene.constraintIterations > 0 ? scene.constraintIterations
                                                                   : defaults.constraintIterations());
    engine.setContactIterations(scene.contactIterations > 0 ? scene.contactIterations : defaults.contactIterations());
    engine.setInterpenetrationIterations(0);  // as many as the contact iterations
    engine.setContactSolver(scene.contactSolver);
    if (scene.build) scene.build(engine);
}

}  // namespace gpl
