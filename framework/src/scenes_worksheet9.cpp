// Worksheet 9 scenes: fluids of particles (position-based fluids; one scene with weakly compressible
// SPH beside it). No keys: they are reached by name (./lab viewer dam-break) or from the viewer's
// scene menu. The rigid bodies are static: the fluid's stages alone run.
//
// Every fluid is water (1000 kg/m^3) of particles 2.5 cm apart, seeing 5 cm (two spacings), in a
// closed tank of static boxes whose inside is the fluid's container. The dam breaks step h = 5 ms
// (the surge front's timing is what they show); the others h = 10 ms, in which no particle moves
// more than about a spacing.
#include <cmath>

#include "gpl/fluid_experiments.h"
#include "gpl/scenes.h"

namespace gpl {
namespace {
namespace worksheet9 {

constexpr double kDamBreakStep = 0.005;  // s
constexpr double kFluidStep = 0.01;      // s
constexpr double kSpacing = 0.025;       // m
constexpr double kWall = 0.05;           // m, the tank walls' half thickness

FluidParameters water() {
    FluidParameters f;
    f.restDensity = 1000.0;
    f.spacing = kSpacing;
    f.smoothingLength = kSmoothingRatio * kSpacing;
    return f;
}

// A closed tank whose inside is `inside` (its floor at inside.lower.y): a floor, four walls and a
// lid of static boxes kWall * 2 thick (tankWalls()), and the box as the fluid's container.
void addTank(PhysicsEngine& e, const FluidBox& inside) {
    for (const Body& wall : tankWalls(inside, kWall)) e.add(wall);
    e.fluids().setContainer(inside);
}

// Martin and Moyce's dam break (1952), their column of n^2 = 2: water of width a = 0.25 m and height
// 2a against the left wall of a closed tank 5a long, 0.25 m deep (across the flow), released at
// t = 0. The surge front runs along the floor and hits the far wall at T = t sqrt(2 g / a) of
// about 4 (t ~ 0.45 s), climbs it and falls back.
void damBreakColumn(PhysicsEngine& e) {
    constexpr double a = 0.25;  // m
    addTank(e, {{0.0, 0.0, 0.0}, {5.0 * a, 3.0 * a, a}});
    e.fluids().setParameters(water());
    e.fluids().addBlock({0.0, 0.0, 0.0}, {a, 2.0 * a, a});
}

void damBreak(PhysicsEngine& e) { damBreakColumn(e); }

// The same column stepped by weakly compressible SPH: speed of sound ten times the fastest flow,
// sqrt(2 g 2a) ~ 3 m/s.
void damBreakSph(PhysicsEngine& e) {
    damBreakColumn(e);
    FluidParameters f = water();
    f.soundSpeed = 30.0;
    e.fluids().setParameters(f);
}

// A ball of water 0.2 m across dropped from 0.3 m above a pool 0.15 m deep in a tank 0.6 m square:
// it splashes, a crown rises and waves run to the walls and back.
void dropIntoPool(PhysicsEngine& e) {
    addTank(e, {{-0.3, 0.0, -0.3}, {0.3, 0.6, 0.3}});
    e.fluids().setParameters(water());
    e.fluids().addBlock({-0.3, 0.0, -0.3}, {0.3, 0.15, 0.3});
    const Vec3 centre(0.0, 0.45, 0.0);
    constexpr double r = 0.1;  // m
    for (double x = -r; x <= r; x += kSpacing) {
        for (double y = -r; y <= r; y += kSpacing) {
            for (double z = -r; z <= r; z += kSpacing) {
                if (x * x + y * y + z * z <= r * r) e.fluids().addParticle(centre + Vec3(x, y, z));
            }
        }
    }
}

// A column of water 0.2 m square and 0.45 m tall released above a static ball of radius 0.12 m in a
// tank 0.6 m square: it pours onto the ball, parts around it, runs off its sides and spreads over
// the floor a few particles deep.
void pourOntoSphere(PhysicsEngine& e) {
    addTank(e, {{-0.3, 0.0, -0.3}, {0.3, 1.0, 0.3}});
    e.add(sphere("ball", 0.12, 1.0).at({0.0, 0.2, 0.0}).makeStatic());
    e.fluids().setParameters(water());
    e.fluids().addBlock({-0.1, 0.4, -0.1}, {0.1, 0.85, 0.1});
}

// A tank 1 m long holding water 0.2 m deep, pushed at t = 0: the water moves at 1 m/s towards the
// right wall, piles up against it, runs back, and sloshes from wall to wall.
void tankSlosh(PhysicsEngine& e) {
    addTank(e, {{-0.5, 0.0, -0.15}, {0.5, 0.5, 0.15}});
    e.fluids().setParameters(water());
    e.fluids().addBlock({-0.5, 0.0, -0.15}, {0.5, 0.2, 0.15}, {1.0, 0.0, 0.0});
}

// A fluid scene of worksheet 9: the stages of PBF (or of WCSPH), step h; the view looks at `target`
// from `distance` for `seconds`: the first seconds hold the motion (the surge, the splash, the first
// run across the tank), and a fluid's step is costly to run for long in the viewer's checks.
Scene fluidScene(const std::string& name, const std::string& description, void (*build)(PhysicsEngine&),
                 const Vec3& target, double distance, double h = kFluidStep, const StageSet& stages = kFluidStages,
                 double seconds = 3.0) {
    Scene s;
    s.name = name;
    s.description = description;
    s.worksheet = 9;
    s.stages = stages;
    s.timeStep = h;
    s.build = build;
    s.viewTarget = target;
    s.viewDistance = distance;
    s.viewSeconds = seconds;
    return s;
}

}  // namespace worksheet9
}  // namespace

void addWorksheet9Scenes(SceneRegistry& r) {
    using namespace worksheet9;
    r.add(fluidScene("dam-break", "Martin and Moyce's water column collapses: the surge front runs along the floor.",
                     damBreak, {0.625, 0.3, 0.125}, 2.3, kDamBreakStep));
    r.add(fluidScene("dam-break-sph", "The same dam break stepped by weakly compressible SPH, the comparison.",
                     damBreakSph, {0.625, 0.3, 0.125}, 2.3, kDamBreakStep, kSphStages));
    r.add(fluidScene("drop-into-pool", "A ball of water falls into a pool: it splashes and waves run to the walls.",
                     dropIntoPool, {0.0, 0.25, 0.0}, 1.8));
    r.add(fluidScene("pour-onto-sphere", "A column of water pours onto a ball, parts around it and spreads.",
                     pourOntoSphere, {0.0, 0.4, 0.0}, 2.1));
    r.add(fluidScene("tank-slosh", "Water in a tank given a push: it piles up against a wall and sloshes back.",
                     tankSlosh, {0.0, 0.2, 0.0}, 2.0));
}

}  // namespace gpl
