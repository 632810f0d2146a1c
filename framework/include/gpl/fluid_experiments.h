// What the fluids' tests, the worksheet-9 autograder and the fluids study (bench/fluids_study.h)
// build and measure: a closed tank of static boxes around a fluid's container, a line of pressure
// against height, the dam break's surge front, and Martin and Moyce's measurements of it.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include "gpl/body.h"
#include "gpl/fluids.h"

namespace gpl {

/// The six static boxes (floor, lid, four walls) of a closed tank whose inside is `inside`, each
/// 2 `wall` thick (m) and overlapping the others at the edges by 2 `wall`, so that no particle
/// slips out at a corner.
inline std::vector<Body> tankWalls(const FluidBox& inside, double wall = 0.05) {
    const Vec3 size = inside.upper - inside.lower, centre = 0.5 * (inside.lower + inside.upper);
    const char* names[3][2] = {{"wall-left", "wall-right"}, {"floor", "lid"}, {"wall-back", "wall-front"}};
    std::vector<Body> walls;
    for (int axis = 0; axis < 3; ++axis) {
        for (const int side : {-1, 1}) {
            Vec3 half = 0.5 * size + Vec3::Constant(2.0 * wall);
            half[axis] = wall;
            Vec3 at = centre;
            at[axis] += side * (0.5 * size[axis] + wall);
            walls.push_back(box(names[axis][side > 0], half, 1.0).at(at).makeStatic());
        }
    }
    return walls;
}

/// A least-squares line of pressure against height over the samples added: in a fluid at rest
/// hydrostatics says dp/dy = -rho g, and p = 0 at the surface.
struct PressureLine {
    double n = 0.0, sy = 0.0, sp = 0.0, syy = 0.0, syp = 0.0;
    void add(double y, double p) {
        n += 1.0;
        sy += y;
        sp += p;
        syy += y * y;
        syp += y * p;
    }
    /// dp/dy (Pa/m).
    double slope() const { return (n * syp - sy * sp) / (n * syy - sy * sy); }
    /// The height (m) where the line reaches p = 0; 0 when the pressure does not fall with height.
    double zeroHeight() const { return slope() < 0.0 ? (sp - slope() * sy) / n / -slope() : 0.0; }
};

/// Martin and Moyce, "An experimental study of the collapse of liquid columns on a rigid horizontal
/// plane", Phil. Trans. R. Soc. Lond. A 244 (1952) 312-324, figure 3: the surge front's distance
/// from the back wall Z = z / a against T = t sqrt(2 g / a) for their column of n^2 = 2 (height 2a),
/// a = 2.25 in, as digitised in PySPH (pypr/pysph, pysph/examples/db_exp_data.py). The points up to
/// Z = 4.2, before the front nears the far wall of the dam-break scenes' tank, 5a away.
struct FrontPoint {
    double T, Z;
};
inline constexpr FrontPoint kMartinMoyce[] = {
    {0.832, 1.217}, {1.219, 1.474}, {1.997, 2.292}, {2.547, 2.995}, {3.345, 4.134}};

/// The dam break's surge front (m): the farthest particle's edge from the back wall (x = 0).
inline double surgeFront(const Fluids& f) {
    double front = 0.0;
    for (const Vec3& q : f.x) front = std::max(front, q.x());
    return front + f.radius();
}

}  // namespace gpl
