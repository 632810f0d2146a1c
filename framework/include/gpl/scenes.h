// Scenes: one small function per scene, registered with a name, a key and a description.
// Keys 1-9, 0 and F1-F10 belong to the course's scenes of worksheets 1-6; F11 and F12 to the
// student's own (assignments/student_scenes.cpp). Later course scenes have no key (empty): the
// viewer's scene menu and the command line (./lab viewer SCENE) reach them by name.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "gpl/engine.h"

namespace gpl {

struct Scene {
    std::string name;                           ///< e.g. "falling-sphere"; used on the command line
    std::string key;                            ///< "1".."9", "0", "F1".."F12"; empty: none (worksheet 7 on)
    std::string description;                    ///< one sentence: what to look at
    int worksheet = 0;                          ///< the worksheet the scene belongs to (0: the student's own)
    StageSet stages;                            ///< the stages the scene requires
    double timeStep = kDefaultTimeStep;         ///< s
    std::function<void(PhysicsEngine&)> build;  ///< adds the bodies (and springs, constraints, container)
    Integrator integrator = Integrator::SemiImplicitEuler;  ///< the scene's integrator; changeable at run time
    // Where the viewer looks first; a distance of 0 frames the bodies as they start. A course
    // scene's hint keeps its moving bodies in the part of the window the side panel leaves free
    // for its first viewSeconds (free falls without a floor: until they have passed the ground).
    Vec3 viewTarget = Vec3::Zero();  ///< m
    double viewDistance = 0.0;       ///< m
    double viewSeconds = 10.0;       ///< s
    /// The friction stage's contact solver (scenes that require it); changeable at run time.
    ContactSolver contactSolver = ContactSolver::SequentialImpulses;
    /// The friction stage's sweeps per step; 0: the engine's default. A scene that needs more to
    /// stand declares them and pays for them alone; changeable at run time.
    int contactIterations = 0;
    /// Sweeps per step of the constraint stages (worksheet 2's projections, worksheet 8's
    /// projection of the soft bodies); 0: the engine's default. Changeable at run time.
    int constraintIterations = 0;
};

class SceneRegistry {
public:
    /// Adds a scene; throws std::invalid_argument on a duplicate name or key or an unknown key.
    void add(Scene scene);
    const std::vector<Scene>& all() const { return scenes_; }
    /// The scene with this name or key (case-insensitive key); throws std::invalid_argument
    /// listing the known scenes when there is none.
    const Scene& find(const std::string& nameOrKey) const;

private:
    std::vector<Scene> scenes_;
};

/// The stages of a scene with friction and resting contact (worksheet 7 and the stacking scenes):
/// worksheet 6's landing, with the friction stage answering the contacts in place of the impulses.
inline const StageSet kFrictionStages{Stage::ConstantAcceleration, Stage::Integration,      Stage::Rotation,
                                      Stage::CollisionDetection,   Stage::Interpenetration, Stage::CollisionImpulses,
                                      Stage::Friction};

/// The stages of a scene of soft bodies (worksheet 8): the particles' step, the rigid bodies at rest.
inline const StageSet kSoftStages{Stage::SoftPredict, Stage::SoftContacts, Stage::SoftProject, Stage::SoftVelocities};

/// The stages of a scene of position-based fluid (worksheet 9): the particles' step, the rigid bodies at rest.
inline const StageSet kFluidStages{Stage::FluidPredict, Stage::FluidNeighbours, Stage::FluidProject,
                                   Stage::FluidVelocities};

/// The stages of a scene of weakly compressible SPH (worksheet 9's comparison): one stage, in substeps.
inline const StageSet kSphStages{Stage::FluidSph};

/// Every scene: the course's and the student's (F11/F12).
const SceneRegistry& scenes();

/// Empties the engine and loads the scene: settings to defaults (gravity, iterations of the
/// constraint and contact sweeps), the scene's stages, time step and integrator, then its bodies.
void load(PhysicsEngine& engine, const Scene& scene);

// Registration functions, one per group of scenes (called by scenes()).
void addWorksheet1Scenes(SceneRegistry& registry);
void addWorksheet2Scenes(SceneRegistry& registry);
void addWorksheet3Scenes(SceneRegistry& registry);
void addWorksheet4Scenes(SceneRegistry& registry);
void addWorksheet5Scenes(SceneRegistry& registry);
void addWorksheet6Scenes(SceneRegistry& registry);
void addWorksheet7Scenes(SceneRegistry& registry);
void addStackingScenes(SceneRegistry& registry);  // the contact solvers' test scenes (worksheet 7)
void addWorksheet8Scenes(SceneRegistry& registry);  // cloth, ropes and soft bodies
void addWorksheet9Scenes(SceneRegistry& registry);  // fluids
void addStudentScenes(SceneRegistry& registry);  // defined in assignments/student_scenes.cpp

}  // namespace gpl
