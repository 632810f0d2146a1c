// The baseline contact solver (worksheet 7's third, after box2d-lite): sequential impulses whose
// normal target carries a Baumgarte bias, a share of each point's overlap beyond the slop turned
// into a speed of separation. The bias is a velocity like any other: a body pushed out of overlap
// leaves with the speed that pushed it, so what corrects position also feeds kinetic energy in.
// Framework code in one file (baumgarte.cpp) that reads top to bottom; the stage chooses it per
// scene (ContactSolver::Baumgarte). The stage then moves the bodies where the new velocities take
// them, as for sequential impulses, with no position pass after.
#pragma once

#include <cstddef>
#include <vector>

#include "gpl/body.h"
#include "gpl/contact.h"
#include "gpl/contact_point.h"

namespace gpl {

struct PointImpulse;

class BaumgarteImpulses {
public:
    /// Share of a point's overlap beyond the slop that the bias removes in one step.
    static constexpr double kBias = 0.2;

    /// `sweeps` sweeps over every point of the contacts, warm started from sums (the normal's
    /// approach speed is sums[i].approach), which hold the step's sums on return. depth[i] is point
    /// i's overlap (m; < 0 across a gap), first[c] contact c's first point, invI[i]
    /// worldInverseInertia() of bodies[i]; slop (m) the overlap left alone; h the step (s).
    void run(std::vector<Body>& bodies, const std::vector<Mat3>& invI, const std::vector<Contact>& contacts,
             const std::vector<std::size_t>& first, const std::vector<double>& depth, std::vector<PointImpulse>& sums,
             double slop, double h, int sweeps);

private:
    /// A contact point, prepared once per step.
    struct Point : PreparedPoint {
        double target = 0.0;  ///< normal velocity the point should leave with (m/s)
    };
    std::vector<Point> points_;
};

}  // namespace gpl
