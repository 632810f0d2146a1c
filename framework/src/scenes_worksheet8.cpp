// Worksheet 8 scenes: cloth, ropes and soft bodies of particles held by position-based constraints
// (PBD and XPBD). No keys: they are reached by name (./lab viewer flag) or from the viewer's scene
// menu. The rigid bodies are static: the particles' stages alone run.
//
// The floor is the plane y = 0. Each scene steps h = 5 ms with the sweeps it declares, each cloth's
// particles have a radius of 1 cm (half the cloth's thickness) and the ground and the obstacles
// hold the cloth with friction.
#include <cmath>

#include "gpl/scenes.h"

namespace gpl {
namespace {
namespace worksheet8 {

constexpr double kSoftStep = 0.005;  // s
constexpr int kSoftSweeps = 15;      // projection sweeps per step

Body ground() { return plane("floor", Vec3::UnitY()).rough(0.6, 0.5); }

// A flag of 30 x 20 particles (1.45 m x 0.95 m, 0.3 kg), pinned at the two corners of its edge on a
// pole 3 m high, in a wind of 6 m/s across the pole with gusts (SoftBodies::windAt()). It starts
// flat, reaching downwind, sags and flutters; soft bending lets it fold.
void flag(PhysicsEngine& e) {
    e.add(ground());
    e.add(box("pole", {0.02, 1.5, 0.02}, 1.0).at({-0.035, 1.5, 0.0}).makeStatic());
    ClothSpec c;
    c.name = "flag";
    c.nx = 30;
    c.ny = 20;
    c.spacing = 0.05;
    c.origin = {0.0, 2.95, 0.0};
    c.u = Vec3::UnitX();
    c.v = -Vec3::UnitY();
    c.mass = 0.3;
    c.stretchCompliance = 0.0;
    c.shearCompliance = 1e-3;
    c.bendCompliance = 1.0;
    c.pinned = {{0, 0}, {0, c.ny - 1}};
    e.softBodies().addCloth(c);
    e.softBodies().setWind({6.0, 0.0, 0.0}, 1.0);
}

// A cloth of 40 x 40 particles (1.56 m square, 0.5 kg) dropped flat from 1.3 m onto a static ball of
// radius 0.4 m on the floor. It drapes over the ball and folds onto the floor around it, its folds
// kept apart by self-collision.
void clothOnSphere(PhysicsEngine& e) {
    e.add(ground());
    e.add(sphere("ball", 0.4, 1.0).at({0.0, 0.4, 0.0}).rough(0.5, 0.4).makeStatic());
    ClothSpec c;
    c.name = "cloth";
    c.nx = 40;
    c.ny = 40;
    c.spacing = 0.04;
    c.origin = {-0.78, 1.3, -0.78};
    c.u = Vec3::UnitX();
    c.v = Vec3::UnitZ();
    c.mass = 0.5;
    c.shearCompliance = 1e-3;
    c.bendCompliance = 0.5;
    c.selfCollision = true;
    e.softBodies().addCloth(c);
}

// A cloth of 20 x 38 particles (0.76 m x 1.48 m, 0.4 kg) dropped from 1 m onto a static table 0.8 m
// high, 0.7 m of it beyond the table's front edge (towards the viewer): that part hangs down;
// friction (mu_s = 0.9 with the table) holds the rest on the table against its pull.
void clothOnTable(PhysicsEngine& e) {
    e.add(ground());
    e.add(box("table", {0.5, 0.4, 0.4}, 1.0).at({0.0, 0.4, 0.0}).rough(0.9, 0.7).makeStatic());
    ClothSpec c;
    c.name = "cloth";
    c.nx = 20;
    c.ny = 38;
    c.spacing = 0.04;
    c.origin = {-0.38, 1.0, -0.38};
    c.u = Vec3::UnitX();
    c.v = Vec3::UnitZ();
    c.mass = 0.4;
    c.shearCompliance = 1e-3;
    c.bendCompliance = 0.5;
    c.selfCollision = true;
    e.softBodies().addCloth(c);
}

// A soft cube of side 0.5 m (4 x 4 x 4 cells of six tetrahedra, 12.5 kg) dropped from 1 m onto the
// floor: its edges give (compliance 2e-3 m/N), it squashes by about a fifth of its height, springs
// back, jiggles and comes to rest; its volumes are held (compliance 0).
void softCube(PhysicsEngine& e) {
    e.add(ground());
    TetMeshSpec s = makeSoftCube("cube", {0.0, 1.25, 0.0}, 0.5, 4);
    s.edgeCompliance = 2e-3;
    s.volumeCompliance = 0.0;
    s.radius = 0.01;
    e.softBodies().addSoftBody(s);
}

// A soft ball of radius 0.4 m (a lattice of 6 cells across, 100 kg/m^3) dropped from 1 m onto the
// floor: its edges give as the cube's, it squashes into a cushion, bounces and recovers, its volume
// held.
void softBall(PhysicsEngine& e) {
    e.add(ground());
    TetMeshSpec s = makeSoftBall("ball", {0.0, 1.4, 0.0}, 0.4, 6);
    s.edgeCompliance = 2e-3;
    s.volumeCompliance = 0.0;
    s.radius = 0.01;
    e.softBodies().addSoftBody(s);
}

// Two ropes of 50 segments, 2.5 m and 0.5 kg each, pinned at one end 3 m up and released
// horizontal: "rope-pbd" with PBD's stiffness 0.8 (its stretch depends on the sweeps and the step:
// with 15 it hangs a fifth longer),
// "rope-xpbd" with XPBD's compliance 1e-4 m/N (hanging, its top segment stretches by 1e-4 times the
// 4.9 N it carries, whatever the sweeps).
void ropePbdXpbd(PhysicsEngine& e) {
    e.add(ground());
    RopeSpec r;
    r.segments = 50;
    r.mass = 0.5;
    r.radius = 0.02;
    r.name = "rope-pbd";
    r.method = SoftMethod::PBD;
    r.stiffness = 0.8;
    r.start = {-1.25, 3.0, -0.4};
    r.end = {1.25, 3.0, -0.4};
    e.softBodies().addRope(r);
    r.name = "rope-xpbd";
    r.method = SoftMethod::XPBD;
    r.stiffness = 1.0;
    r.compliance = 1e-4;
    r.start = {-1.25, 3.0, 0.4};
    r.end = {1.25, 3.0, 0.4};
    e.softBodies().addRope(r);
}

// Two cloths of 20 x 20 particles (0.95 m square, 0.5 kg) hanging from their top edges, pinned
// along it: "stretchy" with stretch and shear compliance 0.1 m/N (its top row's vertical links
// carry about a twentieth of its weight each, 0.25 N, which would stretch them by half their
// length; the diagonals take part of it), which sags longer, and "stiff" with none.
void clothStretchyStiff(PhysicsEngine& e) {
    e.add(ground());
    for (const bool stretchy : {true, false}) {
        ClothSpec c;
        c.name = stretchy ? "stretchy" : "stiff";
        c.nx = 20;
        c.ny = 20;
        c.spacing = 0.05;
        c.origin = {stretchy ? -1.1 : 0.15, 2.5, 0.0};
        c.u = Vec3::UnitX();
        c.v = -Vec3::UnitY();
        c.mass = 0.5;
        c.stretchCompliance = stretchy ? 0.1 : 0.0;
        c.shearCompliance = stretchy ? 0.1 : 1e-3;
        c.bendCompliance = 1.0;
        for (int i = 0; i < c.nx; ++i) c.pinned.push_back({i, 0});
        e.softBodies().addCloth(c);
    }
}

// A soft-body scene of worksheet 8: the particles' stages, h = 5 ms and its sweeps; the view looks at
// `target` from `distance` for `seconds`.
Scene softScene(const std::string& name, const std::string& description, void (*build)(PhysicsEngine&),
                const Vec3& target, double distance, double seconds = 10.0) {
    Scene s;
    s.name = name;
    s.description = description;
    s.worksheet = 8;
    s.stages = kSoftStages;
    s.timeStep = kSoftStep;
    s.build = build;
    s.viewTarget = target;
    s.viewDistance = distance;
    s.viewSeconds = seconds;
    s.constraintIterations = kSoftSweeps;
    return s;
}

}  // namespace worksheet8
}  // namespace

void addWorksheet8Scenes(SceneRegistry& r) {
    using namespace worksheet8;
    r.add(softScene("flag", "A flag pinned at two corners on a pole, in a gusty wind: it flutters.", flag,
                    {0.7, 2.3, 0.0}, 4.5));
    r.add(softScene("cloth-on-sphere", "A cloth dropped on a ball: it drapes over it, its folds kept apart.",
                    clothOnSphere, {0.0, 0.6, 0.0}, 4.0));
    r.add(softScene("cloth-on-table", "A cloth dropped over a table's edge: friction holds it, the rest hangs down.",
                    clothOnTable, {0.0, 0.6, 0.3}, 3.3));
    r.add(softScene("soft-cube", "A soft cube dropped on the floor: it squashes and springs back, its volume kept.",
                    softCube, {0.0, 0.9, 0.0}, 3.0));
    r.add(softScene("soft-ball", "A soft ball dropped on the floor: it squashes and recovers, its volume kept.", softBall,
                    {0.0, 1.0, 0.0}, 3.8));
    r.add(softScene("rope-pbd-xpbd", "Two ropes released horizontal: PBD (stiffness 0.8) stretches, XPBD holds its length.",
                    ropePbdXpbd, {-1.2, 2.2, 0.0}, 5.5));
    r.add(softScene("cloth-stretchy-stiff", "Two hanging cloths: one with stretch compliance sags long, the other keeps its size.",
                    clothStretchyStiff, {0.0, 1.9, 0.0}, 4.0));
}

}  // namespace gpl
