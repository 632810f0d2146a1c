// The friction stage (friction.cpp, contact_sweeps.cpp): PhysicsEngine::solveContacts() runs it over
// a step's contacts with worksheet 7's kernels (friction.h). A small stage sweeps its points in a
// plain loop; ContactSweeps sweeps a large one in halves, on two threads where they gain; ContactMemory
// keeps last step's points and sums for warm starting.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "gpl/baumgarte.h"
#include "gpl/body.h"
#include "gpl/contact.h"
#include "gpl/friction.h"
#include "gpl/halves.h"
#include "gpl/second_thread.h"
#include "gpl/soft_step.h"
#include "gpl/split_impulses.h"

namespace gpl {

/// A point holds an impulse: a normal sum or a friction sum. One that holds none is neither warm
/// started nor given friction: its cone has no width, and friction leaves its zero sum as it is.
inline bool holdsImpulse(const PointImpulse& sum) { return sum.normal != 0.0 || !sum.tangent.isZero(0.0); }

/// Framework (contact_sweeps.cpp): every point of `contacts` prepared once with
/// prepareContactPoint(), then `sweeps` sweeps of applyNormalImpulse() then applyFrictionImpulse()
/// over every point; sums[first[c] + k] is point k of contact c, invI[i] worldInverseInertia() of
/// bodies[i]. Below kSplitFrom points, in the order of `contacts`;
/// from there on, each sweep solves the two Halves of the contacts, each in order, and then the
/// contacts across the cut. With `second`, the two halves are solved at once; the result is the same
/// to the bit. With skipIdle (what the friction stage does), a point whose last solve changed neither
/// its sums nor its bodies' velocities, and whose bodies no solve has changed since, is not solved
/// again: the kernels are pure, so that solve would change nothing. The state is the same, to the
/// bit, as without.
///
/// A first pass before the sweeps prepares every point from the approach its sums hold. With `start`
/// (the friction stage), that pass starts every point first: start() sets the sums of contact c's
/// points (their approach, and last step's sums to start from) from its bodies; each point is then
/// prepared, and each whose sums are not zero warm started with applyWarmStart().
/// Every approach is measured before any warm start, as an impulse at one point changes the
/// others': the middle's first, then each half measures its own and warm starts them (its impulses
/// reach no body of the other half), then the middle is warm started. With two halves, the halves
/// do this at once too.
class ContactSweeps {
public:
    /// Points from which a stage is cut in halves: below, the halves would be too small to gain
    /// from a second thread, and small scenes keep the plain order of their contacts.
    static constexpr std::size_t kSplitFrom = 512;
    /// Sets the sums of contact c's points, sums[0 .. pointCount), from its bodies a and b as a part
    /// sees them, and closing[k], the speed that closes point k's gap at the step's start within the
    /// step (m/s; <= 0 where it touches; mayCloseGap()). Called on either thread.
    using Start =
        std::function<void(std::size_t c, const Body& a, const Body& b, PointImpulse* sums, double* closing)>;

    void run(const std::vector<Contact>& contacts, const std::vector<std::size_t>& first,
             const std::vector<Mat3>& invI, std::vector<Body>& bodies, std::vector<PointImpulse>& sums, int sweeps,
             bool skipIdle = true, SecondThread* second = nullptr, const Start* start = nullptr);
    /// The halves of the last run (cut in two for a large stage), for the stage's position correction.
    const Halves& halves() const { return halves_; }

private:
    /// One contact as a part solves it, everything it needs found beforehand.
    struct Job {
        const Contact* contact;
        Body* a;
        Body* b;
        const Mat3* invIa;
        const Mat3* invIb;
        std::uint32_t* versionA;  ///< the bodies' versions (changes counted)
        std::uint32_t* versionB;
        std::size_t point;  ///< its first point in the part's arrays (the stage's: `global`)
        std::size_t global;
    };
    /// A contact's last solve.
    struct Record {
        std::uint32_t seenA = 0, seenB = 0;  ///< its bodies' versions then
        bool idle = false;                   ///< it changed nothing
    };
    /// What one part solves, with its own arrays (a second thread writes nothing the first reads).
    struct alignas(64) Part {  // on cache lines of its own: the two threads write their parts
        std::vector<Job> jobs;
        std::vector<PointImpulse> sums;    ///< per point, copied in and out of the stage's
        std::vector<ContactPoint> points;  ///< per point, prepared by the first pass
        std::vector<Record> records;       ///< per point (a contact's at its first point)
        /// Its bodies that another part writes too (of pairs across the cut), asked for before each
        /// solve: the other thread has most likely written them last.
        std::vector<const Body*> shared;
    };
    std::vector<char> inMiddle_;  ///< split()'s, per body: of a pair across the cut
    std::array<Part, 3> parts_;  ///< left half, right half, middle
    Halves halves_;

    /// The halves and the parts' jobs for this stage.
    void split(const std::vector<Contact>& contacts, const std::vector<std::size_t>& first,
               const std::vector<Mat3>& invI, std::vector<Body>& bodies, const std::vector<PointImpulse>& sums);
    static void solve(Part& part, bool skipIdle);
    /// The first pass with `start` (see the class).
    void warmStart(const std::vector<Contact>& contacts, const Start& start, std::vector<Body>& bodies,
                   SecondThread* second);
    /// The part's points started (with `start`) and prepared.
    static void measure(Part& part, const std::vector<Contact>& contacts, const Start* start);
    static void applyWarmStarts(Part& part);
    /// The two halves' work, at once with `second` (else left first); then what they did to their
    /// copies of the static bodies reaches the bodies.
    void bothHalves(const std::function<void()>& left, const std::function<void()>& right, std::vector<Body>& bodies,
                    SecondThread* second);
};
/// ContactSweeps().run(...) on one thread (for tests).
void sweepContacts(const std::vector<Contact>& contacts, const std::vector<std::size_t>& first,
                   const std::vector<Mat3>& invI, std::vector<Body>& bodies, std::vector<PointImpulse>& sums,
                   int sweeps, bool skipIdle = true);

/// Last step's contact points and their sums, for warm starting (kept by the engine). One entry per
/// pair, and its points and their sums in arrays of their own: a sphere's contact has one point of
/// kMaxContactPoints, and the stage reads the pairs (keeping resting contacts, finding last step's
/// pair) far more often than their points.
///
/// A point of this step finds last step's by where the bodies carry it, not by the order or the
/// number of points the collision kernels return (see match()): the clippers of worksheet 5 give
/// their points no names, and may return a face's corners in another order, one fewer or one
/// more, with the two boxes' roles swapped, or the pair in the other order (normal reversed).
struct ContactMemory {
    struct Entry {
        std::size_t a = 0, b = 0;  ///< the pair's body indices
        Vec3 normal = Vec3::UnitY();
        std::uint32_t first = 0;       ///< its points' index in points and sums
        std::uint32_t pointCount = 0;  ///< 1..kMaxContactPoints
        double restitution = 0.0, friction = 0.0, staticFriction = 0.0;  ///< the pair's coefficients
        mutable bool found = false;  ///< a contact of this step is of this pair
    };
    /// What a point keeps of its sums: the normal and friction impulse (its approach is this step's).
    struct Sums {
        double normal = 0.0;
        Vec3 tangent = Vec3::Zero();
    };
    /// Per point of a contact of this step: the point of last step's entry it continues (an index
    /// into points and sums), or kNone.
    using Pairing = std::array<std::uint32_t, kMaxContactPoints>;
    static constexpr std::uint32_t kNone = UINT32_MAX;

    std::vector<Entry> entries;  ///< sorted by (a, b)
    std::vector<Vec3> points;    ///< the entries' points (m, world frame), entry by entry
    std::vector<Sums> sums;      ///< and their sums
    /// Per point, the material points of a and of b that were there (m, each body's own frame): where
    /// the point is when the bodies have moved on, and how far they have slid apart there.
    std::vector<Vec3> onA, onB;
    /// The entries of pairs whose first body is a: [firstOf[a], firstOf[a + 1]).
    std::vector<std::size_t> firstOf;

    /// Last step's entry of the pair of bodies a and b, in either order (`flipped` says it was
    /// (b, a): its normal, its friction sums and its roles of a and b are reversed), or nullptr.
    const Entry* find(std::size_t a, std::size_t b, bool& flipped) const;
    /// Where last step's point k (an index into points) is now: the midpoint of the material points
    /// of its two bodies that met there, placed with the bodies as they are (a and b in the order
    /// of the point's entry).
    Vec3 pointNow(std::uint32_t k, const Body& a, const Body& b) const;
    /// Which of last step's points of `old` (found for `contact` with find()) each point of the
    /// contact continues; a and b are the contact's bodies (its order). One to one: each point of
    /// last step goes to at most one point of this step, the nearest pairs first, none farther than
    /// kWarmStartDistance from where the bodies carry it (pointNow()).
    Pairing pairUp(const Entry& old, bool flipped, const Contact& contact, const Body& a, const Body& b) const;
    /// The sums that the contact's points start from (sums[0 .. pointCount)), their approach left
    /// as it is: match()'s answer for a contact of a pair last step had (old from find(), else
    /// nullptr: every sum zero).
    ///
    /// A point paired with one of last step's (pairUp()) takes its sums, the friction sum turned
    /// into this step's tangent plane (and reversed with the pair's order). A point that last step
    /// did not have starts from zero, and its neighbours keep theirs. A point of last step that no
    /// point continues hands its sums to the points that continue others, in proportion to their
    /// normal sums: the contact's total normal impulse (what it carries of the weight above it)
    /// and its total friction impulse are kept when the kernels return fewer points, or others,
    /// and a face that loses a corner does not drop that corner's load for a step. The moments
    /// of the loads change; the sweeps set them right.
    /// `paired`, when given, is pairUp()'s answer for this contact, found before.
    void match(const Entry* old, bool flipped, const Contact& contact, const Body& a, const Body& b, PointImpulse* sums,
               const Pairing* paired = nullptr) const;

    void clear() {
        entries.clear();
        points.clear();
        sums.clear();
        onA.clear();
        onB.clear();
        firstOf.clear();
    }
};

/// The friction stage (friction.cpp): what it keeps from one step to the next (last step's sums,
/// for warm starting) and the buffers of a step. PhysicsEngine::solveContacts() says what a step does.
class FrictionStage {
public:
    /// One step of the stage over the step's contacts: first the points that last step's contacts
    /// keep (keepPoints()), then `sweeps` sweeps of the impulse kernels, `positionSweeps` of the
    /// position correction; with `second`, a large stage's halves run at once.
    void step(std::vector<Body>& bodies, std::vector<Contact>& contacts, double h, int sweeps, int positionSweeps,
              SecondThread* second, ContactSolver solver = ContactSolver::SequentialImpulses);
    /// Forgets last step's sums (they name bodies by index: after bodies are removed or restored).
    void forget() { memory_.clear(); }
    /// What the stage keeps for the next step: this step's points and their sums.
    const ContactMemory& memory() const { return memory_; }

private:
    ContactMemory memory_;                   ///< last step's sums, for warm starting
    std::vector<Mat3> invI_;                 ///< per body: worldInverseInertia() this step
    std::vector<std::pair<Vec3, Vec3>> before_;  ///< per body: v and omega when the stage began
    std::vector<std::size_t> first_;         ///< per contact: its first point's index in sums_
    std::vector<PointImpulse> sums_;         ///< per contact point of this step
    std::vector<ContactPoint> points_;       ///< per contact point: prepared (a small stage's sweeps)
    std::vector<double> depths_;             ///< per contact point: its overlap (m)
    std::vector<const ContactMemory::Entry*> remembered_;  ///< per contact: last step's entry of its pair, or nullptr
    std::vector<char> flipped_;              ///< per contact: that entry has the pair in the other order
    /// Per contact: keepPoints()'s pairUp() of it, where it kept no point (paired_), for match().
    std::vector<ContactMemory::Pairing> pairings_;
    std::vector<char> paired_;
    ContactSweeps sweeps_;                   ///< the sweeps of a large stage, in halves
    SplitImpulses split_;                    ///< the position correction
    SoftStep soft_;                          ///< the soft step solver
    BaumgarteImpulses baumgarte_;            ///< the baseline solver
    std::vector<std::size_t> order_, placeAt_;  ///< keep()'s buffers: the contacts sorted by pair

    /// Adds to the step's contacts the points of last step that the kernels no longer report and
    /// that still touch: within kKeepGap of touching, slid less than kKeepSlide, continued by no
    /// point of this step (ContactMemory::pairUp()), up to kMaxContactPoints a contact; and a
    /// contact of such points for a pair the kernels report no more. Finds each contact's entry of
    /// last step (remembered_, flipped_) on the way. With `twoThreads`, the contacts in two halves.
    void keepPoints(const std::vector<Body>& bodies, std::vector<Contact>& contacts, SecondThread* twoThreads);
    /// The first pass (start, prepare, warm start) and the sweeps of a small stage: the plain loop
    /// (see step()).
    void sweep(std::vector<Body>& bodies, const std::vector<Contact>& contacts, int sweeps, double h);
    /// Last step's sums of contact c's points and their approach now; with `closing`, the speed that
    /// closes each point's gap at the step's start within the step of h (s) (mayCloseGap()).
    void start(const std::vector<Contact>& contacts, std::size_t c, const Body& a, const Body& b, PointImpulse* sums,
               double h = 0.0, double* closing = nullptr) const;
    /// Keeps this step's sums, sorted by pair, for the next step (their points in two halves with
    /// `twoThreads`).
    void keep(const std::vector<Contact>& contacts, const std::vector<Body>& bodies,
              SecondThread* twoThreads = nullptr);
};

}  // namespace gpl
