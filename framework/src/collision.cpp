// Collision detection in the engine: the broad phase proposes pairs, the kernels of
// gpl/collision.h decide (a long list of pairs in two halves on an engine's two threads), and taut
// ropes join the contacts.
#include "gpl/collision.h"

#include <utility>
#include <vector>

#include "gpl/broadphase.h"
#include "gpl/engine.h"
#include "gpl/split_impulses.h"

namespace gpl {

namespace {

// The kernel for the shapes of a and b, which come in the order sphere, box, plane; none for two
// static bodies and for two planes. Each return hands the kernel's answer on uncopied.
std::optional<Contact> kernelContact(const Body& a, const Body& b) {
    if (a.isStatic() && b.isStatic()) return std::nullopt;
    switch (a.shape) {
        case Shape::Sphere:
            if (b.shape == Shape::Sphere) return sphereSphere(a, b);
            if (b.shape == Shape::Plane) return spherePlane(a, b);
            return sphereBox(a, b);
        case Shape::Box:
            if (b.shape == Shape::Box) return boxBox(a, b);
            if (b.shape == Shape::Plane) return boxPlane(a, b);
            return std::nullopt;
        case Shape::Plane:
            return std::nullopt;
    }
    return std::nullopt;
}

// Kernels take their shapes in this order.
int shapeOrder(Shape s) { return s == Shape::Sphere ? 0 : s == Shape::Box ? 1 : 2; }

// The body grown by `by` (m) all round; a plane as it is.
Body grown(const Body& body, double by) {
    Body g = body;
    if (g.shape == Shape::Sphere) g.radius += by;
    if (g.shape == Shape::Box) g.halfExtents += Vec3::Constant(by);
    return g;
}

// From this many pairs on, the kernels run on two threads (an engine with two): a half's work
// then outweighs a hand-over to the second thread many times.
constexpr std::size_t kSplitPairsFrom = 512;

}  // namespace

std::optional<Contact> collide(const std::vector<Body>& bodies, std::size_t i, std::size_t j, double margin) {
    if (shapeOrder(bodies[i].shape) > shapeOrder(bodies[j].shape)) std::swap(i, j);  // sphere, box, plane
    const Body& p = bodies[i];
    const Body& q = bodies[j];
    // A sphere touches at one point, the same whether grown or not: it is grown only when apart.
    // A box is grown always: of two boxes tilted by a hair against each other, the grown ones
    // still meet face to face, with all four corners, where the boxes themselves meet at two.
    const bool boxes = p.shape == Shape::Box || q.shape == Shape::Box;
    std::optional<Contact> c;
    if (margin <= 0.0 || !boxes) c = kernelContact(p, q);
    if (!c && margin > 0.0) {
        const double share = q.shape == Shape::Plane ? margin : 0.5 * margin;  // p is never the plane
        c = kernelContact(grown(p, share), grown(q, margin - share));
        if (c) {  // the kernels' points lie on the grown surfaces: put them between the bodies' own
            c->depth -= margin;
            for (int k = 0; k < c->pointCount; ++k) c->points[k] = betweenSurfaces(p, q, c->points[k], c->normal, margin);
        }
    }
    if (c) {
        c->a = i;
        c->b = j;
        c->restitution = combineRestitution(p.restitution, q.restitution);
        c->friction = combineFriction(p.friction, q.friction);
        c->staticFriction = combineFriction(p.staticFriction, q.staticFriction);
    }
    return c;
}

double normalVelocity(const Contact& contact, const Body& a, const Body& b) {
    return (b.velocity - a.velocity).dot(contact.normal);
}

void PhysicsEngine::detectCollisions() {
    // The pairs near enough to touch soon: interpenetration looks among them for the overlaps
    // that its own moves create.
    const std::vector<BodyPair>& pairs = broadPhase_->findPairs(bodies_, kContactMargin, &second_, kPairsAhead * timeStep_);
    nearPairs_.assign(pairs.begin(), pairs.end());
    // The friction stage also answers bodies that are within kKeepGap of touching: a stack that
    // starts with every face exactly on the one below has all its contacts from the first step.
    const double margin = stageActive(Stage::Friction) ? kKeepGap : 0.0;
    pairInContacts_.assign(nearPairs_.size(), 0);
    const auto detect = [this, margin](std::size_t from, std::size_t to, std::vector<Contact>& into) {
        for (std::size_t k = from; k < to; ++k) {
            if (std::optional<Contact> c = collide(bodies_, nearPairs_[k].a, nearPairs_[k].b, margin)) {
                into.push_back(*c);
                pairInContacts_[k] = 1;
            }
        }
    };
    const std::size_t n = nearPairs_.size();
    if (threads() < 2 || n < kSplitPairsFrom || !second_.helps()) {
        detect(0, n, contacts_);
    } else {
        // The pairs in two halves, the second on the second thread, its contacts after the first's:
        // the same contacts in the same order as one loop. The halves hold as many pairs of two
        // movable bodies each: a pair with a static body (the broad phase lists a plane's last) costs
        // its kernel a fraction of theirs.
        const auto movable = [this](const BodyPair& p) { return !bodies_[p.a].isStatic() && !bodies_[p.b].isStatic(); };
        std::size_t both = 0;
        for (const BodyPair& p : nearPairs_) both += movable(p) ? 1 : 0;
        std::size_t half = 0;
        for (std::size_t seen = 0; half < n && 2 * seen < both; ++half) seen += movable(nearPairs_[half]) ? 1 : 0;
        std::vector<Contact> secondHalf;
        second_.run(true, [&] { detect(0, half, contacts_); }, [&] { detect(half, n, secondHalf); });
        contacts_.insert(contacts_.end(), secondHalf.begin(), secondHalf.end());
    }
    recordOpenKernels();
}

std::optional<Contact> PhysicsEngine::ropeContactOf(const Rope& rope) const {
    std::optional<Contact> c = ropeContact(bodies_[rope.a], bodies_[rope.b], rope.length);
    if (c) {
        c->a = rope.a;
        c->b = rope.b;
        c->restitution = 0.0;  // a rope stops the stretch; it does not bounce back
    }
    return c;
}

void PhysicsEngine::addRopeContacts() {
    ropeInContacts_.assign(ropes_.size(), 0);
    for (std::size_t k = 0; k < ropes_.size(); ++k) {
        if (std::optional<Contact> c = ropeContactOf(ropes_[k])) {
            contacts_.push_back(*c);
            ropeInContacts_[k] = 1;
        }
    }
    recordOpenKernels();
}

}  // namespace gpl
