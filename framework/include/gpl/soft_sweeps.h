// A large mesh's links in two halves and the rest, for two threads (SoftBodies::projectInHalves(),
// which SoftBodies::project() hands a step to where a mesh is cut and it has two threads).
//
// A mesh of at least kHalvesFrom links is cut in two at its middle particle: a cloth's particles
// are stored row by row and a soft body's layer by layer, so the cut runs across the mesh. In the
// sweep order (sweepOrder()), a link waits for the cut when it crosses it, or when it shares a
// particle with an earlier link that waits; every other link lies in one half (both its particles
// before the cut, or both after it) and depends on no link of the other half. The mesh stores its
// links in that order: the first half's links that do not wait, then the second half's, then the
// rest, each in sweep order. That moves no link past an earlier one that shares a particle with it,
// so a sweep in the stored order (the plain loop of SoftBodies::project()) gives the result of the
// sweep order to the bit; so do the two halves swept at once on two threads (sweepHalves()) and then
// the rest: the threads change nothing but the time. A cloth's links are built from both edges
// towards the middle row (ClothSpec), so that the two halves wait for the cut alike and most links do
// not wait at all. Within each half, the links that wait for the rest of the sweep before
// (holdBackWaitingLinks()) come last, so that on two threads the others overlap that rest
// (sweepOverlapped()).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "gpl/math.h"
#include "gpl/second_thread.h"
#include "gpl/soft_bodies.h"

namespace gpl {

/// From this many links on, a mesh is cut in two halves (a 30 x 30 cloth has about 5000).
constexpr std::uint32_t kHalvesFrom = 4096;

/// The particle a mesh is cut at: its first half is [mesh.first, cut), its second [cut, first + count).
inline std::uint32_t halvesCut(const SoftMesh& mesh) { return mesh.first + mesh.count / 2; }

/// The order in which a mesh's links are stored: order[k] is the index among `links` (as built)
/// of the link stored at k. Fewer than kHalvesFrom links: sweepOrder(links, particles), and
/// first = second = 0. Otherwise the links of the first half (both particles before `cut`) that do
/// not wait for the cut, then the second half's (both at or after it), then the rest, each in
/// sweepOrder(); first and second count the halves' links.
struct HalvesOrder {
    std::vector<std::uint32_t> order;
    std::uint32_t first = 0, second = 0;
};
HalvesOrder halvesOrder(const std::vector<DistanceLink>& links, std::uint32_t cut, std::size_t particles);

/// SoftBodies::projectInHalves() also groups the step's contacts: for each cut mesh in turn, those of its first
/// half's particles that may go with the half's links, then its second half's; then the rest: first
/// those not in a cut mesh's second half, then those in one, each group in the order found. A
/// particle's contacts may go with its half's links when nothing else of the sweep moves the particle
/// after them: no link or volume of the rest (a cut mesh's volumes are all of the rest), and no
/// self-collision pair this step. A contact moves its own particle only, so contacts of different
/// particles give the same result in any order, and a particle's contacts keep theirs: pushed out
/// right after their half's links, on that half's thread, they give the result of the plain loop
/// (every link, the self-collision pairs, then every contact) to the bit.
///
/// One sweep of a cut mesh's halves (mesh.firstHalfLinks > 0), as the plain loop of
/// SoftBodies::project() sweeps their links for the mesh's method (XPBD: solveDistanceConstraint()
/// with the compliance, the multiplier summed; PBD: with alpha = 0, the move scaled by the per-sweep
/// share of the stiffness over `iterations`), each followed on its thread by then(half), half 0 or
/// 1 (the caller pushes out that half's contacts there): the two at once, the second on `second` (or
/// here after the first, while the machine gives that thread no core). The rest of the links are the
/// caller's.
void sweepHalves(const SoftMesh& mesh, std::vector<DistanceLink>& links, std::vector<Vec3>& p,
                 const std::vector<double>& w, double h, int iterations, SecondThread& second,
                 const std::function<void(int)>& then);

/// One cut mesh's sweeps on two threads, with the result of the plain loop of SoftBodies::project()
/// to the bit, where nothing but the mesh's rest, the other meshes and the rest's contacts (rest())
/// moves a particle that the rest's links and volumes move (no self-collision pairs): each half's
/// links that do not wait for the rest (SoftMesh::firstHalfWaiting) depend on nothing of the sweep
/// before but their own half, so they are swept while the rest of the sweep before is. The first
/// half's thread (this one) sweeps, in each sweep, its half's waiting links and then(0), the next
/// sweep's links that do not wait, and, once the second half's thread has swept its half and
/// then(1), rest(); the second sweeps its links that do not wait and, once that rest is done,
/// then(2) (the caller pushes out the rest's contacts in the second half there, which rest() leaves),
/// its waiting links and then(1). Where the second finds both halves of the sweep before done and
/// their rest not yet taken (the first is behind, on a core another program shares), it sweeps that
/// rest itself. The second half's part of each sweep goes to `second`, or is swept
/// here in turn when that thread has not taken it by the time the rest needs it (a thread without a
/// core joins late, or not at all). The thread that sweeps a half first sets its multipliers to 0, so
/// that its links stay in that core's cache. One hand-over a step.
void sweepOverlapped(const SoftMesh& mesh, std::vector<DistanceLink>& links, std::vector<Vec3>& p,
                     const std::vector<double>& w, double h, int iterations, SecondThread& second,
                     const std::function<void(int)>& then, const std::function<void()>& rest);

/// Stores each half's links that wait for the rest of the sweep after those that do not, each in
/// their order, and sets mesh.firstHalfWaiting and secondHalfWaiting: in its half's order, a link
/// waits when it moves a particle that moved[] marks (markMovedByTheRest()) or one that an earlier
/// waiting link moves. No link moves past an earlier one that shares a particle with it.
void holdBackWaitingLinks(SoftMesh& mesh, std::vector<DistanceLink>& links, const std::vector<char>& moved);

/// Sets moved[i] (1) for each particle i that a link or volume of a cut mesh's rest moves (links and
/// volumes of neither half): its contacts wait for the rest. Nothing for a mesh that is not cut.
void markMovedByTheRest(const SoftMesh& mesh, const std::vector<DistanceLink>& links,
                        const std::vector<TetVolume>& volumes, std::vector<char>& moved);

}  // namespace gpl
