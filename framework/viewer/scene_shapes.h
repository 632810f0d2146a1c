// What the renderer draws besides the bodies, as geometry without any GL: planes other than the
// ground cut to finite patches (walls, cushions, slopes), the curve of a rope, the length of a
// contact's normal. The renderer turns these into triangles and lines; the tests check them.
#pragma once

#include <optional>
#include <vector>

#include "gpl/body.h"
#include "gpl/contact.h"

namespace gpl::viewer {

using Bounds = Eigen::AlignedBox3d;

/// True for a plane drawn as the ground (checkered tiles): its normal points up, within 8 degrees.
bool isGround(const Body& body);

/// The space a scene occupies: its spheres and boxes and the points its planes pass through, grown
/// on every side by its largest sphere radius (at least 1 cm).
Bounds sceneBounds(const std::vector<Body>& bodies);

/// A plane cut to a convex polygon.
struct PlanePatch {
    std::size_t body = 0;         ///< index of the plane in the body list
    Vec3 normal = Vec3::UnitY();  ///< unit, world frame, towards the free side
    std::vector<Vec3> corners;    ///< m, counter-clockwise seen from the free side
};

/// Every plane that is not ground, as the part of it that bounds the free space (outside every
/// other plane) within the bounds: the four walls of a box, a table's cushions, the two slopes
/// of a valley meeting at the bottom. Planes with nothing left are not listed.
std::vector<PlanePatch> wallPatches(const std::vector<Body>& bodies, const Bounds& bounds);

/// The part of the ground that the other planes enclose (a table's cloth, a box's floor); nothing
/// when there is no ground or the other planes leave it open on some side.
std::optional<PlanePatch> enclosedGround(const std::vector<Body>& bodies);

/// A rope is taut when it pulled in the last step (one of the contacts is its own: same bodies, the
/// normal from its second body towards its first) or is at its full length, to 0.1 %. A rope that
/// pulled may end the step a little short: the other contacts of its bodies moved them.
bool ropeTaut(const Rope& rope, const std::vector<Body>& bodies, const std::vector<Contact>& contacts);

/// Points of a rope of this length from a to b (m), segments + 1 of them: a parabola that sags
/// towards `down` (any direction across the rope if down is along it) and is as long as the rope;
/// straight when the ends are as far apart as the rope is long (or farther).
std::vector<Vec3> ropeCurve(const Vec3& a, const Vec3& b, double length, const Vec3& down, int segments);

/// Length of the line that shows a contact's normal (m): 80 % of the smaller body that touches
/// (the radius of a sphere, the smallest half extent of a box; planes do not count).
double normalLength(const Contact& contact, const std::vector<Body>& bodies);

}  // namespace gpl::viewer
