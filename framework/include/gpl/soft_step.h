// The soft step contact solver (worksheet 7's second solver, after Catto's Solver2D and Box2D v3):
// the friction stage's step cut into substeps, each integrating the step's acceleration over its
// share of the step, solving every contact point once with soft constraints (a stiff, heavily
// damped spring that pushes overlapping bodies apart), moving the bodies, and relaxing once
// without the spring. Positions move in every substep, so each solve sees how far the bodies
// overlap now; the spring pushes out what overlaps at a bounded speed, so no body is kicked.
// Framework code in one file (soft_step.cpp) that reads top to bottom; the stage chooses it per
// scene (ContactSolver::SoftStep).
#pragma once

#include <cstddef>
#include <vector>

#include "gpl/body.h"
#include "gpl/contact.h"
#include "gpl/contact_point.h"

namespace gpl {

struct PointImpulse;

class SoftStep {
public:
    /// Substeps per step: enough that a column of twenty cubes stands, its bottom contact
    /// carrying nineteen, and the spring (a quarter of their rate) stays stiff.
    static constexpr int kSubsteps = 8;
    /// Frequency of the contact spring as a share of the substeps' rate (1/hs): as stiff as a
    /// substep still resolves, so a stack of twenty sinks by millimetres, not centimetres.
    static constexpr double kStiffness = 0.25;
    /// Its damping ratio: heavily over-damped, so a pushed-out body does not bounce off the spring.
    static constexpr double kDampingRatio = 10.0;
    /// Fastest the spring pushes overlapping bodies apart (m/s).
    static constexpr double kMaxPushSpeed = 3.0;

    /// One step of the stage. The bodies come from the integration stage (moved by h with the
    /// velocities of this step); the solver takes them back to the start of the step (x - h v, and
    /// v - h a, with a the acceleration accumulator), runs `substeps` substeps, and leaves them
    /// where the substeps took them. depth[i] is point i's overlap where the bodies are now, sums[i]
    /// its impulse of one substep of last step (warm start; the normal's approach speed is
    /// sums[i].approach), and on return that of this step's last substep. first[c] is contact c's
    /// first point; invI[i] is worldInverseInertia() of bodies[i].
    void run(std::vector<Body>& bodies, const std::vector<Mat3>& invI, const std::vector<Contact>& contacts,
             const std::vector<std::size_t>& first, const std::vector<double>& depth, std::vector<PointImpulse>& sums,
             double h, int substeps = kSubsteps);

private:
    /// A contact point, prepared once per step; its sums are those of one substep.
    struct Point : PreparedPoint {
        double separation = 0.0;     ///< gap at the point where the bodies are now (m; < 0 overlapping)
        double approach = 0.0;       ///< normal velocity when the stage began (m/s; < 0 approaching)
        double largestNormal = 0.0;  ///< the largest normal impulse of any substep (N s)
    };
    std::vector<Point> points_;
    std::vector<Vec3> v_, w_;        ///< per body: velocity and angular velocity in the substeps
    std::vector<Vec3> moved_, turned_;  ///< per body: displacement and rotation vector from where it is now

    /// Normal then friction impulses at every point, once. With the spring (soft), overlap is pushed
    /// out; without it (relax), only approach is stopped. Both let a gap close within the substep.
    void solve(const std::vector<Body>& bodies, const std::vector<Mat3>& invI, double hs, bool soft);
    /// The impulse (N s) on b at the point, and its opposite on a, on the substeps' velocities.
    void push(const Point& p, const Vec3& impulse, const std::vector<Body>& bodies, const std::vector<Mat3>& invI);
    /// Velocity of b's material point at p relative to a's (m/s).
    Vec3 relativeVelocity(const Point& p) const;
};

}  // namespace gpl
