// Friction and resting contact (worksheet 7): pure kernels for one contact point, prepared once per
// step, and the impulses there that a sequence of sweeps sums up; the per-point sums the framework
// keeps between sweeps and from one step to the next.
//
// Student hooks (bodies in assignments/, reference bodies in solutions/):
//   prepareContactPoint()   the point prepared once per step: lever arms, tangents, inverse effective
//                           masses along the normal and the tangents, the normal velocity to reach
//   applyWarmStart()        last step's sums applied again before the first sweep
//   applyNormalImpulse()    the normal impulse, summed over the sweeps and the sum kept >= 0
//   applyFrictionImpulse()  the friction impulse, summed likewise, kept in the Coulomb cone
// The last three act on the bodies through applyImpulseAtPoint() (worksheet 6).
// Framework: the friction stage that sweeps these kernels over a step's contacts, and what it keeps
// from one step to the next, are in friction_stage.h; a scene may choose another ContactSolver in
// place of its sweeps (baumgarte.h, soft_step.h).
#pragma once

#include <array>

#include "gpl/body.h"
#include "gpl/contact.h"

namespace gpl {

/// Approach speed (m/s) below which a contact does not bounce: a body resting on another gains
/// g h ~ 0.1 m/s towards it in every step of 0.01 s, and a bounce of e times that would make it
/// jitter. Five such steps' worth; a ball dropped from 1.3 cm or more still bounces.
constexpr double kRestingSpeed = 0.5;

/// Greatest distance (m) between a contact point of this step and where the bodies carry one of
/// last step's (same pair of bodies) for last step's impulses to warm start it.
constexpr double kWarmStartDistance = 0.05;

/// Gap (m) up to which a contact point of last step stays in its pair's contact when the collision
/// kernels no longer report it: a box tilted by a hair lifts a corner off the box below, and the
/// clipped face then loses that corner; kept, the corner goes on carrying its share of the weight
/// with the sums it had, and the stack does not rock from one set of points to another. A body
/// held by a kept point rests at most this far above what holds it.
constexpr double kKeepGap = 0.0005;

/// Greatest slide (m) of the two bodies' material points that met at a kept point: beyond it the
/// bodies have slid apart there, and the kernels' points of this step say where they touch.
constexpr double kKeepSlide = 0.005;

/// Overlap (m) that the friction stage leaves between resting bodies: its position correction
/// removes only what lies deeper. Correcting every last micrometre in every step would push the
/// spheres of a pyramid apart along their slanted normals, where friction, which acts on
/// velocities, does not hold them.
constexpr double kContactSlop = 0.0005;

/// The friction stage's contact solvers, each in a file of its own (a scene chooses one).
enum class ContactSolver {
    /// The baseline: sequential impulses with a Baumgarte bias, positions that follow the
    /// velocities and no position pass (baumgarte.cpp).
    Baumgarte,
    /// Sequential impulses: the sweeps of the worksheet's kernels over the step, then positions that
    /// follow the velocities and split impulses for what still overlaps (friction.cpp).
    SequentialImpulses,
    /// Soft step: substeps with soft contacts and a relaxing solve each (soft_step.cpp).
    SoftStep,
};
/// Every contact solver, in the order the viewer and the benchmark list them.
inline constexpr std::array<ContactSolver, 3> kContactSolvers{ContactSolver::Baumgarte, ContactSolver::SequentialImpulses,
                                                              ContactSolver::SoftStep};
/// The solver's name as the viewer and the benchmark show it.
const char* contactSolverName(ContactSolver solver);

/// What the sweeps have summed up at one contact point.
struct PointImpulse {
    double normal = 0.0;          ///< accumulated normal impulse (N s) along the contact normal; >= 0
    Vec3 tangent = Vec3::Zero();  ///< accumulated friction impulse (N s, world frame), perpendicular to the normal
    /// Normal velocity of the two material points at this point when the stage began, before warm
    /// starting (m/s; < 0 approaching): what restitution answers.
    double approach = 0.0;
};

/// One direction d of a prepared contact point (its normal or a tangent): what the sweeps need to
/// measure the point's velocity along d and to push along d, without a cross product or an inverse
/// inertia of their own. With u the relative velocity of the two material points at p,
///   u . d = d . (v_b - v_a) + (r_b x d) . omega_b - (r_a x d) . omega_a,
/// and an impulse lambda d on b (-lambda d on a) changes omega_b by lambda I_b^-1 (r_b x d) and omega_a
/// by -lambda I_a^-1 (r_a x d).
struct ContactAxis {
    Vec3 d = Vec3::Zero();          ///< the unit direction (world frame)
    Vec3 raXd = Vec3::Zero();       ///< r_a x d (m)
    Vec3 rbXd = Vec3::Zero();       ///< r_b x d (m)
    Vec3 invIaRaXd = Vec3::Zero();  ///< I_a^-1 (r_a x d) (1/(kg m)), a's world inverse inertia
    Vec3 invIbRbXd = Vec3::Zero();  ///< I_b^-1 (r_b x d) (1/(kg m)), b's world inverse inertia
    double K = 0.0;                 ///< inverse effective mass along d, K(d) (1/kg)
};

/// A contact point as the sweeps read it, prepared once per step by prepareContactPoint(): what stays
/// the same while the sweeps change the velocities.
struct ContactPoint {
    Vec3 p = Vec3::Zero();        ///< the point (m, world frame)
    Vec3 ra = Vec3::Zero();       ///< lever arm of body a, p - x_a (m)
    Vec3 rb = Vec3::Zero();       ///< lever arm of body b, p - x_b (m)
    ContactAxis n;                ///< along the unit normal n.d, from a towards b; n.K is K_n
    ContactAxis t1;               ///< along the unit tangent t1.d (tangentBasis(n.d)); t1.K is K_t1
    ContactAxis t2;               ///< along the unit tangent t2.d = n.d x t1.d; t2.K is K_t2
    /// Normal velocity the point is to leave with (m/s): >= 0 from prepareContactPoint(); negative
    /// where the framework lets a resting point close a gap (mayCloseGap()).
    double target = 0.0;
    double staticFriction = 0.0;  ///< the pair's mu_s
    double friction = 0.0;        ///< the pair's mu_d (<= mu_s)
};

/// A resting point (target 0) on a static body, still apart when the step began by a gap that
/// `closing` (m/s, the gap over h) closes within the step: it may approach at up to that speed and
/// no faster, so its target becomes -closing, and the step ends with the gap closed, not held open.
/// Without it a body held by points within kKeepGap of the floor rests above it, by up to
/// kKeepGap + g h^2. The framework's, applied after prepareContactPoint(); a point that touches
/// (closing <= 0), bounces, or lies between two movable bodies (closing 0) keeps its target.
inline void mayCloseGap(ContactPoint& point, double closing) {
    if (point.target == 0.0 && closing > 0.0) point.target = -closing;
}

/// Student hook (worksheet 7), solutions/prepare_contact_point.cpp: contact.points[k] prepared for
/// the sweeps; invIa, invIb are worldInverseInertia() of a and b, approach the normal velocity at
/// the point when the stage began (m/s, < 0 approaching).
ContactPoint prepareContactPoint(const Contact& contact, int k, const Body& a, const Body& b, const Mat3& invIa,
                                 const Mat3& invIb, double approach);
/// Student hook (worksheet 7), solutions/warm_start.cpp: the sums of last step at the point, applied
/// to the bodies again.
void applyWarmStart(const ContactPoint& point, Body& a, Body& b, const PointImpulse& sum);
/// Student hook (worksheet 7), solutions/normal_impulse.cpp: one sweep's normal impulse at the point.
void applyNormalImpulse(const ContactPoint& point, Body& a, Body& b, PointImpulse& sum);
/// Student hook (worksheet 7), solutions/friction_impulse.cpp: one sweep's friction impulse at the point.
void applyFrictionImpulse(const ContactPoint& point, Body& a, Body& b, PointImpulse& sum);

}  // namespace gpl
