// The friction stage's position correction (worksheet 7): split impulses. Overlap that the contacts
// leave after the velocity sweeps is removed by impulses on velocities of their own (pseudo
// velocities, zero at the start of every step) that move the bodies' positions and orientations and
// are then forgotten: the bodies' real velocities, and so their kinetic energy, never see them.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "gpl/body.h"
#include "gpl/contact.h"
#include "gpl/halves.h"
#include "gpl/second_thread.h"

namespace gpl {

/// How far body b must move along n to leave body a, measured on the line through p along n (m):
/// where a's stretch of that line ends minus where b's begins. Positive while they overlap there,
/// negative across a gap; NaN when the line misses either body. (n points from a towards b, as a
/// contact's normal does.) With a margin (m), measured on the bodies grown as collide() grows them
/// for it, less the margin: the same for points on faces, and a point that lies on the grown faces
/// just outside the bodies themselves still has its depth.
double depthAlong(const Body& a, const Body& b, const Vec3& p, const Vec3& n, double margin = 0.0);
/// p moved along n to midway between where body a ends and body b begins on the line through p
/// (each body's own surface, found on the bodies grown by the margin as depthAlong() grows them);
/// p itself when the line misses either.
Vec3 betweenSurfaces(const Body& a, const Body& b, const Vec3& p, const Vec3& n, double margin);

class SplitImpulses {
public:
    /// Share of a point's overlap beyond the slop removed in one step: less than all of it, so
    /// that a body pushed out of two overlaps at once does not overshoot.
    static constexpr double kShare = 0.2;

    /// Starts a step with `count` points, each to be set with set() before run().
    void resize(std::size_t count) { points_.resize(count); }
    /// Point k: a contact point of bodies a and b at p with normal n (from a towards b), whose
    /// overlap at the end of the step is expected to be `depth` (m); invIa, invIb are the bodies'
    /// world inverse inertias.
    void set(std::size_t k, std::size_t a, std::size_t b, const Vec3& p, const Vec3& n, double depth,
             const std::vector<Body>& bodies, const Mat3& invIa, const Mat3& invIb);
    /// Removes kShare of every point's overlap beyond `slop` (m) with `sweeps` Gauss-Seidel sweeps
    /// of summed, non-negative normal impulses on the pseudo velocities, then moves and turns every
    /// body by h times its pseudo velocities. Does nothing when no point overlaps by more than the slop.
    /// With `halves` cut in two (a large stage's, as the velocity sweeps cut it), each sweep takes the
    /// left half's points, then the right half's, then the middle's, the two halves at once on
    /// `second`: the same result on one thread and two.
    void run(std::vector<Body>& bodies, const std::vector<Mat3>& invI, double slop, double h, int sweeps,
             const Halves* halves = nullptr, SecondThread* second = nullptr);

private:
    struct Point {
        std::size_t a, b;
        Vec3 ra, rb;          ///< lever arms from the centres of mass (m)
        Vec3 n;               ///< normal, from a towards b
        double ma, mb;        ///< the bodies' inverse masses (1/kg)
        double wn;            ///< inverse effective mass along n (1/kg)
        double depth;         ///< overlap expected at the end of the step (m)
        double target = 0.0;  ///< pseudo velocity of separation the point asks for (m/s)
        double sum = 0.0;     ///< summed pseudo impulse (N s), >= 0
    };
    std::vector<Point> points_;
    /// A body's pseudo velocities, on a cache line of their own (the two halves write their bodies').
    struct alignas(64) Pseudo {
        Vec3 v = Vec3::Zero();  ///< m/s
        Vec3 w = Vec3::Zero();  ///< rad/s, world frame
    };
    std::vector<Pseudo> pseudo_;  ///< per body
    /// The points swept, copied part by part (left half, right half, middle; all in the middle
    /// without a cut), each in their order: each thread writes its own part's.
    std::array<std::vector<Point>, 3> parts_;

    /// One sweep over `points`.
    void sweep(std::vector<Point>& points, const std::vector<Mat3>& invI);
};

}  // namespace gpl
