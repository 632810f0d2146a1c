// The contact solvers' test scenes (worksheet 7): stacks, pyramids, an arch, a card house, mass
// ratios, a friction ramp, overlap recovery, a confined crowd and dominoes. No keys: they are
// reached by name (./lab viewer stack-10) or from the viewer's scene menu. `./lab bench solvers`
// runs them all with each contact solver and with Bullet.
//
// The floor is the plane y = 0; the scenes lie in the x-y plane, which the viewer faces. Bodies
// start exactly touching (every gap and overlap zero) except in overlap-recovery, and at rest
// except the first domino. Restitution is 0 throughout: what the scenes test is resting contact.
#include <cmath>
#include <string>

#include "gpl/scenes.h"

namespace gpl {
namespace {

constexpr double kStackCube = 0.5;  // m, half side of the cubes of the stacks and the pyramid
constexpr double kCube = 0.25;      // m, half side of the other scenes' cubes

Quat turnedAboutZ(double angle) { return Quat(Eigen::AngleAxisd(angle, Vec3::UnitZ())); }

// A floor of friction mu (the pair's coefficient with a body of the same mu is mu).
Body floorOf(double mu) { return plane("floor", Vec3::UnitY()).rough(mu, mu).bouncy(1.0); }

// A plastic box of friction mu.
Body block(const std::string& name, const Vec3& half, double mass, double mu = 0.5) {
    return box(name, half, mass).bouncy(0.0).rough(mu, mu);
}

// A column of cubes, each resting on the one below; offset: every other cube shifted sideways by
// a fifth of its half side, alternately left and right.
void stack(PhysicsEngine& e, int count, double offset) {
    e.add(floorOf(0.5));
    for (int i = 0; i < count; ++i) {
        const double x = (i % 2 == 0 ? offset : -offset);
        e.add(block("box" + std::to_string(i + 1), Vec3::Constant(kStackCube), 1.0).at({x, kStackCube * (2 * i + 1), 0.0}));
    }
}

// Ten and twenty cubes, aligned: every contact is a full face of four points carrying the weight
// above it, 19 times the top cube's at the bottom of 20. A solver that leaves a little error at
// each contact adds it up the column; the stack stands when the sums carry the weights exactly.
void stack10(PhysicsEngine& e) { stack(e, 10, 0.0); }
void stack20(PhysicsEngine& e) { stack(e, 20, 0.0); }
// Offset by 0.2 of the half side, alternately: each face carries its load off centre, so the four
// points of a contact carry unequal shares and a box turns unless those shares are right.
void stack10Offset(PhysicsEngine& e) { stack(e, 10, 0.2 * kStackCube); }
void stack20Offset(PhysicsEngine& e) { stack(e, 20, 0.2 * kStackCube); }

// A pyramid of ten rows, one cube deep: 10 cubes at the bottom, 1 at the top, each resting on two
// below (half a cube over each) and touching its neighbours in the row. The bottom row carries
// the 45 cubes above it; the side contacts carry nothing and must stay so.
void pyramid10(PhysicsEngine& e) {
    e.add(floorOf(0.5));
    constexpr int kRows = 10;
    for (int row = 0; row < kRows; ++row) {
        const int count = kRows - row;
        for (int i = 0; i < count; ++i) {
            const double x = 2.0 * kStackCube * (i - 0.5 * (count - 1));
            e.add(block("box" + std::to_string(row + 1) + "-" + std::to_string(i + 1), Vec3::Constant(kStackCube), 1.0)
                      .at({x, kStackCube * (2 * row + 1), 0.0}));
        }
    }
}

// Three spheres: two on the floor touching, one resting on both. The upper contacts push the lower
// spheres apart along their line of centres, 30 degrees from the vertical. A lower sphere stays put
// only if friction at the upper contact (T) and at the floor (F) hold it: torques about its centre
// give F = T, its horizontal forces P sin 30 = T (1 + cos 30), so T / P = tan 15 deg = 0.268 (the
// floor needs less, T over 1.5 times the weight). The pyramid stands for mu >= 0.268 and falls below.
void spherePyramid(PhysicsEngine& e, double mu) {
    constexpr double r = 0.5;  // m
    e.add(floorOf(mu));
    e.add(sphere("left", r, 1.0).at({-r, r, 0.0}).rough(mu, mu).bouncy(0.0));
    e.add(sphere("right", r, 1.0).at({r, r, 0.0}).rough(mu, mu).bouncy(0.0));
    e.add(sphere("top", r, 1.0).at({0.0, r + std::sqrt(3.0) * r, 0.0}).rough(mu, mu).bouncy(0.0));
}
void spherePyramidRough(PhysicsEngine& e) { spherePyramid(e, 0.5); }
void spherePyramidSlippery(PhysicsEngine& e) { spherePyramid(e, 0.2); }

// Four spheres: three on the floor touching in a triangle, one resting on all three. The upper
// contacts' normals lean alpha = asin(1/sqrt 3) = 35.3 degrees from the vertical, and the balance
// of a lower sphere (as in the 3-sphere pyramid) asks mu >= tan(alpha / 2) = 0.318.
void sphereTetrahedron(PhysicsEngine& e, double mu) {
    constexpr double r = 0.5;                             // m
    const double rho = 2.0 * r / std::sqrt(3.0);          // m, from the axis to a lower centre
    const double rise = 2.0 * r * std::sqrt(2.0 / 3.0);  // m, from the lower centres to the upper
    e.add(floorOf(mu));
    for (int i = 0; i < 3; ++i) {
        const double angle = 2.0 * M_PI * i / 3.0 + M_PI / 2.0;  // one sphere at the back, two in front
        e.add(sphere("lower" + std::to_string(i + 1), r, 1.0)
                  .at({rho * std::cos(angle), r, -rho * std::sin(angle)})
                  .rough(mu, mu)
                  .bouncy(0.0));
    }
    e.add(sphere("top", r, 1.0).at({0.0, r + rise, 0.0}).rough(mu, mu).bouncy(0.0));
}
void sphereTetrahedronRough(PhysicsEngine& e) { sphereTetrahedron(e, 0.5); }
void sphereTetrahedronSlippery(PhysicsEngine& e) { sphereTetrahedron(e, 0.2); }

// The smallest arch: two legs leaning 30 degrees inwards, each standing with its whole lower face on
// a static block cut square to it (a skewback, sunk into the floor), and a keystone between the
// legs' inner upper edges, touching nothing else. The keystone (1 kg) hangs on friction alone: each
// side carries half its weight, F = 0.5 g, and presses with the legs' thrust H. Were a leg's weight
// to bear on its inner lower edge alone, its torques about that edge would give
// 1.73 H = 1.0 F + 0.41 W_leg (W_leg = 4 g), H = 1.24 g: the keystone holds for mu >= F / H = 0.40,
// and the force on a foot leans 15 degrees off the leg's axis (mu >= 0.26). mu = 0.6. On edges
// alone (no skewbacks) the legs and keystone could sway sideways at no cost in energy.
void arch(PhysicsEngine& e) {
    constexpr double mu = 0.6;
    const double tilt = 30.0 * M_PI / 180.0;
    const Vec3 leg(0.1, 1.0, 0.3);  // m, half extents: 2 m long, 0.2 m thick
    const Vec3 key(0.2, 0.2, 0.3);  // m
    const Vec3 skewback(0.3, 0.3, 0.4);  // m
    const double length = 2.0 * leg.y();
    e.add(floorOf(mu));
    for (int side : {-1, 1}) {
        // Along the leg upwards, and across it towards the middle (the inner face's normal).
        const Vec3 up(-side * std::sin(tilt), std::cos(tilt), 0.0);
        const Vec3 in(-side * std::cos(tilt), -std::sin(tilt), 0.0);
        const Vec3 innerTop(side * key.x(), length * std::cos(tilt), 0.0);  // touches the keystone's side
        const Vec3 centre = innerTop - 0.5 * length * up - leg.x() * in;
        const Quat turn = turnedAboutZ(side * tilt);
        const std::string name = side < 0 ? "left" : "right";
        e.add(block(name + "-skewback", skewback, 1.0, mu).makeStatic().at(centre - (leg.y() + skewback.y()) * up).rotated(turn));
        e.add(block(name + "-leg", leg, 4.0, mu).at(centre).rotated(turn));
    }
    e.add(block("keystone", key, 1.0, mu).at({0.0, length * std::cos(tilt), 0.0}));
}

// One A-frame of two cards standing on a surface at height y0, its top at x = xc: the right card
// (1 m) leans 30 degrees to the left, the left card (0.9 m) as much to the right with its inner upper
// edge against the right card's inner face, 0.1 m below that card's top. Both stand on their inner
// lower edges. Returns the height of the frame's top, the right card's outer upper edge.
double cardFrame(PhysicsEngine& e, const std::string& name, double xc, double y0, double mu) {
    const double tilt = 30.0 * M_PI / 180.0;
    constexpr double t = 0.02;  // m, half thickness
    constexpr double w = 0.3;   // m, half width (along z)
    constexpr double l = 0.5;   // m, half length of the right card
    constexpr double d = 0.1;   // m, of the right card above the contact
    const double lLeft = l - 0.5 * d;
    const Vec3 upLeft(std::sin(tilt), std::cos(tilt), 0.0), inLeft(std::cos(tilt), -std::sin(tilt), 0.0);
    const Vec3 upRight(-std::sin(tilt), std::cos(tilt), 0.0), outRight(std::cos(tilt), std::sin(tilt), 0.0);
    // The right card's inner lower edge, on the surface, and its outer upper edge above x = xc.
    const Vec3 rightFoot(xc - 2.0 * l * upRight.x() - 2.0 * t * outRight.x(), y0, 0.0);
    const Vec3 rightTop = rightFoot + 2.0 * l * upRight;  // its inner upper edge
    const Vec3 contact = rightTop - d * upRight;          // the left card's inner upper edge
    const Vec3 leftCentre = contact - lLeft * upLeft - t * inLeft;
    const Vec3 rightCentre = rightFoot + l * upRight + t * outRight;
    e.add(block(name + "-left", {t, lLeft, w}, 0.5, mu).at(leftCentre).rotated(turnedAboutZ(-tilt)));
    e.add(block(name + "-right", {t, l, w}, 0.5, mu).at(rightCentre).rotated(turnedAboutZ(tilt)));
    return (rightTop + 2.0 * t * outRight).y();
}

// A card house of seven cards (4 cm thick): two A-frames, a flat card (1.3 m) on their tops, a
// third A-frame on it. A frame's statics (six forces, six equations) ask for friction up to 0.46 of
// the normal force at the cards' contact and 0.43 at the feet, the lower frames carrying the upper
// storey on their right cards' tops; mu = 0.7. (Steeper cards would ask more at the contact:
// cot(2 tilt) as the load grows.)
void cardHouse(PhysicsEngine& e) {
    constexpr double mu = 0.7;
    constexpr double t = 0.02;  // m, half thickness of a card
    e.add(floorOf(mu));
    const double top = cardFrame(e, "frame1", -0.5, 0.0, mu);
    cardFrame(e, "frame2", 0.5, 0.0, mu);
    e.add(block("flat", {0.65, t, 0.3}, 0.5, mu).at({0.0, top + t, 0.0}));  // on the two frames' tops
    cardFrame(e, "frame3", 0.0, top + 2.0 * t, mu);
}

// Mass ratios of 100: a heavy box (100 kg, 1 m cube) on a light one (1 kg, 0.5 m cube), and a light
// box between two heavy ones. A light body carries a hundred times its own weight: its impulses
// must sum to that while the heavy body's velocity hardly feels each of them.
void massRatio(PhysicsEngine& e) {
    e.add(floorOf(0.5));
    const Vec3 big = Vec3::Constant(0.5), small = Vec3::Constant(kCube);
    e.add(block("light-under", small, 1.0).at({-1.2, small.y(), 0.0}));
    e.add(block("heavy-on-light", big, 100.0).at({-1.2, 2.0 * small.y() + big.y(), 0.0}));
    e.add(block("heavy-under", big, 100.0).at({1.2, big.y(), 0.0}));
    e.add(block("light-between", small, 1.0).at({1.2, 2.0 * big.y() + small.y(), 0.0}));
    e.add(block("heavy-on-top", big, 100.0).at({1.2, 2.0 * (big.y() + small.y()) + big.y(), 0.0}));
}

// Five boxes on a slope of 30 degrees (tan 30 = 0.577) that meets the floor. With the slope's and
// the floor's coefficient 1, a box of mu = m^2 has the pair's coefficient sqrt(1 m^2) = m: m = 0.8
// and 0.65 stay; 0.5, 0.35 and 0.2 slide down at g (sin 30 - m cos 30) and stop on the floor after
// sliding v^2 / (2 m g).
void frictionRamp(PhysicsEngine& e) {
    const double slope = 30.0 * M_PI / 180.0;
    const Vec3 normal(-std::sin(slope), std::cos(slope), 0.0);  // the slope rises along +x from x = 0
    const Vec3 upSlope(std::cos(slope), std::sin(slope), 0.0);
    e.add(plane("slope", normal).rough(1.0, 1.0));
    e.add(plane("floor", Vec3::UnitY()).rough(1.0, 1.0));
    const Vec3 half = Vec3::Constant(0.2);
    const double pair[] = {0.8, 0.65, 0.5, 0.35, 0.2};
    for (int i = 0; i < 5; ++i) {
        const double mu = pair[i] * pair[i];
        e.add(block("mu" + std::to_string(pair[i]).substr(0, 4), half, 1.0, mu)
                  .at(1.5 * upSlope + half.y() * normal + Vec3(0.0, 0.0, 0.6 * (i - 2)))
                  .rotated(turnedAboutZ(slope)));
    }
}

// Three columns of three cubes, each cube started overlapping the one below (and the lowest the
// floor) by 5, 15 and 25 % of its side. The solver must push them apart without flying off: the
// energy it adds to separate them is what it has to get rid of afterwards.
void overlapRecovery(PhysicsEngine& e) {
    e.add(floorOf(0.5));
    const double overlap[] = {0.05, 0.15, 0.25};  // of the side
    for (int c = 0; c < 3; ++c) {
        const double step = 2.0 * kCube * (1.0 - overlap[c]);  // m between centres
        for (int i = 0; i < 3; ++i) {
            e.add(block("box" + std::to_string(c + 1) + "-" + std::to_string(i + 1), Vec3::Constant(kCube), 1.0)
                      .at({1.2 * (c - 1), kCube - 2.0 * kCube * overlap[c] + step * i, 0.0}));
        }
    }
}

// 192 spheres (r = 0.25 m) in a square box of four static walls, eight by eight in three layers,
// each touching its neighbours and the walls, which rise a little above the top layer's centres: a
// jammed crowd. Every sphere presses on its neighbours and the walls; nothing can move, and the
// solver must find that out for every contact at once.
void confined(PhysicsEngine& e) {
    constexpr double r = 0.25;  // m
    constexpr int kSide = 8, kLayers = 3;
    constexpr double inner = kSide * r;  // m, half width inside the walls
    constexpr double wall = 0.1;         // m, half thickness
    const double height = 0.5 * (2.0 * r * kLayers - r + 0.1);  // m, half height of a wall
    e.add(floorOf(0.5));
    for (int side : {-1, 1}) {
        e.add(block(side < 0 ? "wall-left" : "wall-right", {wall, height, inner + 2.0 * wall}, 1.0)
                  .makeStatic()
                  .at({side * (inner + wall), height, 0.0}));
        e.add(block(side < 0 ? "wall-back" : "wall-front", {inner, height, wall}, 1.0)
                  .makeStatic()
                  .at({0.0, height, side * (inner + wall)}));
    }
    for (int layer = 0; layer < kLayers; ++layer) {
        for (int i = 0; i < kSide * kSide; ++i) {
            const double x = 2.0 * r * (i % kSide) - inner + r, z = 2.0 * r * (i / kSide) - inner + r;
            e.add(sphere("ball" + std::to_string(layer * kSide * kSide + i + 1), r, 1.0)
                      .at({x, r + 2.0 * r * layer, z})
                      .bouncy(0.0));
        }
    }
}

// Twelve dominoes (0.8 m tall, 0.1 m thick) 0.5 m apart; the first is flicked over, turning about
// its front lower edge at 2 rad/s. Each falls onto the next and pushes it over; they end leaning on
// one another and the last lies on the floor.
void dominoes(PhysicsEngine& e) {
    e.add(floorOf(0.5));
    const Vec3 half(0.05, 0.4, 0.2);
    constexpr double spin = 2.0;  // rad/s
    for (int i = 0; i < 12; ++i) {
        Body d = block("domino" + std::to_string(i + 1), half, 1.0).at({-2.75 + 0.5 * i, half.y(), 0.0});
        // Turning about the front lower edge: the centre moves at omega x (centre - edge).
        if (i == 0) d.spinning({0.0, 0.0, -spin}).moving({spin * half.y(), spin * half.x(), 0.0});
        e.add(d);
    }
}

// A scene of worksheet 7 with the friction stages; the view looks at `target` from `distance` for
// `seconds`.
Scene scene(const std::string& name, const std::string& description, void (*build)(PhysicsEngine&),
            const Vec3& target, double distance, double seconds = 10.0) {
    return {name,  "", description, 7, kFrictionStages, kDefaultTimeStep, build, Integrator::SemiImplicitEuler,
            target, distance, seconds};
}

// The scene solved with the soft step (soft_step.h) in place of sequential impulses.
Scene softStep(Scene s) {
    s.contactSolver = ContactSolver::SoftStep;
    return s;
}

// The scene solved with sequential impulses in `sweeps` sweeps a step in place of the default ten.
Scene sweeps(int sweeps, Scene s) {
    s.contactIterations = sweeps;
    return s;
}

}  // namespace

void addStackingScenes(SceneRegistry& r) {
    // The aligned columns and the mass ratios run the soft step: sequential impulses with ten sweeps
    // leave them swaying until they fall (the panel switches solvers to show it). The columns off
    // centre run sequential impulses with the sweeps they need to stand still: under the soft step
    // their off-centre loads make them buzz. Every sweep carries the weights a little further up
    // and down the column, so twenty cubes need more sweeps than ten.
    r.add(softStep(scene("stack-10", "Ten cubes stacked exactly, soft step: they stand without drift or jitter.", stack10,
                         {0, 5, 0}, 24)));
    r.add(sweeps(30, scene("stack-10-offset", "Ten cubes stacked off centre by turns, 30 sweeps: they stand still.",
                           stack10Offset, {0, 5, 0}, 24)));
    r.add(softStep(scene("stack-20", "Twenty cubes stacked exactly, soft step: the bottom contact carries 19; it stands.",
                         stack20, {0, 12, 0}, 48)));
    r.add(sweeps(150, scene("stack-20-offset", "Twenty cubes stacked off centre by turns, 150 sweeps: they stand still.",
                            stack20Offset, {0, 12, 0}, 48)));
    r.add(scene("pyramid-10", "A pyramid of 55 cubes in ten rows: it stands, its side contacts idle.", pyramid10,
                {0, 5, 0}, 24));
    r.add(scene("sphere-pyramid", "Three spheres, one on two, mu = 0.5 (above tan 15 deg = 0.268): it stands.",
                spherePyramidRough, {0, 1, 0}, 6));
    r.add(scene("sphere-pyramid-slippery", "The three spheres with mu = 0.2, below tan 15 deg: the lower ones roll apart.",
                spherePyramidSlippery, {0, 1, 0}, 7, 2.5));
    r.add(scene("sphere-tetrahedron", "Four spheres, one on three, mu = 0.5 (above 0.318): it stands.",
                sphereTetrahedronRough, {0, 1, 0}, 6));
    r.add(scene("sphere-tetrahedron-slippery", "The four spheres with mu = 0.2, below 0.318: the lower ones roll apart.",
                sphereTetrahedronSlippery, {0, 1, 0}, 7, 2.5));
    r.add(scene("arch", "Two leaning legs and a keystone held between them by friction alone: it stands.", arch,
                {0, 1, 0}, 7));
    r.add(scene("card-house", "Seven thin cards leaning on each other in two storeys: it stands.", cardHouse,
                {0, 1, 0}, 6));
    r.add(softStep(scene("mass-ratio", "A 100 kg box on a 1 kg box, and a 1 kg box between two of 100 kg, soft step: both stand.",
                         massRatio, {0, 1.2, 0}, 8)));
    r.add(scene("friction-ramp", "Five boxes on a 30 degree slope: those with mu above tan 30 stay, the others slide off.",
                frictionRamp, {0, 0.6, 0}, 7));
    r.add(scene("overlap-recovery", "Cubes started 5, 15 and 25 % into each other: they part gently and come to rest.",
                overlapRecovery, {0, 0.8, 0}, 6));
    r.add(scene("confined", "192 spheres packed in a box of four walls: nothing can move, and nothing does.", confined,
                {0, 0.5, 0}, 9));
    r.add(scene("dominoes", "Twelve dominoes, the first flicked over: each knocks over the next.", dominoes, {0, 0.5, 0},
                8));
}

}  // namespace gpl
