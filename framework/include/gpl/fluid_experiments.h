// What the fluids' tests and the fluids study (bench/fluids_study.h) both build and measure: a closed
// tank of static boxes around a fluid's container, the dam break's surge front, and Martin and
// Moyce's measurements of it.
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
