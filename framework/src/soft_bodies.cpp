// Worksheet 8's step of the soft bodies: predict, find contacts, project, update velocities
// (soft_bodies.h), and their diagnostics. The meshes are built in soft_meshes.cpp; the constraint
// and contact kernels are the students' hooks (soft_constraints.h).
#include "gpl/soft_bodies.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>

#include "gpl/soft_constraints.h"

namespace gpl {
namespace {

// How far q lies outside a rigid body's surface (m): negative inside. Planes, spheres and boxes.
double surfaceGap(const Body& body, const Vec3& q) {
    switch (body.shape) {
        case Shape::Plane:
            return (q - body.position).dot(body.orientation * body.normal);
        case Shape::Sphere:
            return (q - body.position).norm() - body.radius;
        case Shape::Box: {
            const Vec3 local = body.orientation.conjugate() * (q - body.position);
            const Vec3 nearest = local.cwiseMax(-body.halfExtents).cwiseMin(body.halfExtents);
            if (nearest != local) return (local - nearest).norm();
            return -(body.halfExtents - local.cwiseAbs()).minCoeff();
        }
    }
    return std::numeric_limits<double>::infinity();
}

// How near a particle's sphere lies to a body's surface to touch it, relative to the particle's
// radius: the rounding of a push out, far below any move of a step.
constexpr double kTouching = 1e-6;

// A particle of radius r at q pushed out of a plane (its centre at distance r in front of it).
Vec3 projectParticlePlane(const Vec3& q, double r, const Vec3& point, const Vec3& normal) {
    const double gap = (q - point).dot(normal) - r;
    return gap < 0.0 ? Vec3(q - gap * normal) : q;
}

// How far any point of the body moves in a step of h (m), at most.
double bodyTravel(const Body& body, double h) {
    double reach = 0.0;  // m, from the centre to the farthest point that matters
    if (body.shape == Shape::Sphere) reach = body.radius;
    if (body.shape == Shape::Box) reach = body.halfExtents.norm();
    return h * (body.velocity.norm() + body.angularVelocity.norm() * reach);
}

// The spatial hash's cell of a coordinate, and a cell's bucket (Teschner et al.'s primes).
int hashCell(double coordinate, double spacing) { return static_cast<int>(std::floor(coordinate / spacing)); }
std::uint32_t hashBucket(int cx, int cy, int cz, std::uint32_t buckets) {
    const long long h = (static_cast<long long>(cx) * 92837111) ^ (static_cast<long long>(cy) * 689287499) ^
                        (static_cast<long long>(cz) * 283923481);
    return static_cast<std::uint32_t>(std::llabs(h) % buckets);
}

}  // namespace

int SoftBodies::defaultThreads() { return std::thread::hardware_concurrency() >= 2 ? 2 : 1; }

void SoftBodies::setThreads(int threads) {
    if (threads < 1) throw std::invalid_argument("threads must be at least 1, got " + std::to_string(threads));
    threads_ = threads < 2 ? 1 : 2;
}

Vec3 SoftBodies::windAt(double t, const Vec3& q) const {
    const double speed = wind_.norm();
    if (speed == 0.0) return wind_;
    const Vec3 along = wind_ / speed;
    Vec3 across = along.cross(Vec3::UnitY());
    across = across.norm() > 1e-9 ? Vec3(across.normalized()) : Vec3::UnitX();
    const double s = q.dot(along);  // m downwind: the gusts travel that way
    const double strength = 1.0 + 0.25 * std::sin(2.1 * t - 1.3 * s);
    const double sideways = 0.2 * std::sin(1.7 * t - 2.0 * s + 0.7);
    return strength * wind_ + sideways * speed * across;
}

void SoftBodies::predict(double h, const Vec3& gravity, double time) {
    // Wind on every cloth triangle, a third of it at each corner.
    const bool windy = windDrag_ > 0.0 && wind_ != Vec3::Zero();
    if (windy) {
        std::fill(force_.begin(), force_.end(), Vec3::Zero());
        for (const SoftMesh& mesh : meshes) {
            if (mesh.kind != SoftMesh::Kind::Cloth) continue;
            for (const auto& t : mesh.triangles) {
                const Vec3 normal = (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]);
                const double twiceArea = normal.norm();
                if (twiceArea == 0.0) continue;
                const Vec3 n = normal / twiceArea;
                const Vec3 centroid = (x[t[0]] + x[t[1]] + x[t[2]]) / 3.0;
                const Vec3 velocity = (v[t[0]] + v[t[1]] + v[t[2]]) / 3.0;
                const Vec3 f = windDrag_ * (windAt(time, centroid) - velocity).dot(n) * n * (0.5 * twiceArea);
                for (std::uint32_t corner : t) force_[corner] += f / 3.0;
            }
        }
    }
    // Every free particle: v += h a, p = x + h v. A pinned one stays where it is.
    for (std::size_t i = 0; i < x.size(); ++i) {
        if (w[i] == 0.0) {
            v[i] = Vec3::Zero();
            p[i] = x[i];
            continue;
        }
        Vec3 a = gravity;
        if (windy) a += w[i] * force_[i];
        v[i] += h * a;
        p[i] = x[i] + h * v[i];
    }
}

void SoftBodies::findContacts(const std::vector<Body>& bodies, double h) {
    // Particles near the rigid bodies: within two radii plus both travels.
    contacts.clear();
    for (std::uint32_t b = 0; b < bodies.size(); ++b) {
        const Body& body = bodies[b];
        const double travel = bodyTravel(body, h);
        for (const SoftMesh& mesh : meshes) {
            for (std::uint32_t i = mesh.first; i < mesh.first + mesh.count; ++i) {
                if (w[i] == 0.0) continue;
                const double reach = 2.0 * mesh.radius + (p[i] - x[i]).norm() + travel;
                if (surfaceGap(body, p[i]) >= reach) continue;
                ParticleContact c;
                c.particle = i;
                c.body = b;
                contacts.push_back(c);
            }
        }
    }
    // Self-collision: particles of one cloth near each other. Two particles approach each other by
    // at most twice the farthest any particle travels apart from the cloth's mean move (a cloth
    // falling as a whole brings none of its particles nearer).
    selfPairs.clear();
    for (const SoftMesh& mesh : meshes) {
        if (!mesh.selfCollision) continue;
        Vec3 mean = Vec3::Zero();
        for (std::uint32_t i = mesh.first; i < mesh.first + mesh.count; ++i) mean += p[i] - x[i];
        mean /= mesh.count;
        double travel = 0.0;
        for (std::uint32_t i = mesh.first; i < mesh.first + mesh.count; ++i)
            travel = std::max(travel, (p[i] - x[i] - mean).norm());
        collectSelfPairs(mesh, travel);
    }
}

void SoftBodies::collectSelfPairs(const SoftMesh& mesh, double travel) {
    // A dense spatial hash (Teschner et al., as in Mueller's Ten Minute Physics): each particle counted
    // into its cell's bucket, the counts summed into each bucket's first entry, then each particle
    // placed; cells of the query distance's size, so that a particle's neighbours lie in the 27
    // cells around it.
    const double minimum = 2.0 * mesh.radius;           // m, how near two particles may come
    const double query = minimum + 2.0 * travel;        // m, how near they may come in this step
    const double query2 = query * query;
    const auto buckets = 2 * mesh.count;
    cellStart_.assign(buckets + 1, 0);
    cellEntries_.resize(mesh.count);
    for (std::uint32_t i = mesh.first; i < mesh.first + mesh.count; ++i)
        ++cellStart_[hashBucket(hashCell(p[i].x(), query), hashCell(p[i].y(), query), hashCell(p[i].z(), query), buckets)];
    for (std::uint32_t b = 1; b <= buckets; ++b) cellStart_[b] += cellStart_[b - 1];
    for (std::uint32_t i = mesh.first; i < mesh.first + mesh.count; ++i) {
        const std::uint32_t b =
            hashBucket(hashCell(p[i].x(), query), hashCell(p[i].y(), query), hashCell(p[i].z(), query), buckets);
        cellEntries_[--cellStart_[b]] = i;
    }
    for (std::uint32_t i = mesh.first; i < mesh.first + mesh.count; ++i) {
        nearby_.clear();
        const int x0c = hashCell(p[i].x() - query, query), x1c = hashCell(p[i].x() + query, query);
        const int y0c = hashCell(p[i].y() - query, query), y1c = hashCell(p[i].y() + query, query);
        const int z0c = hashCell(p[i].z() - query, query), z1c = hashCell(p[i].z() + query, query);
        for (int cx = x0c; cx <= x1c; ++cx) {
            for (int cy = y0c; cy <= y1c; ++cy) {
                for (int cz = z0c; cz <= z1c; ++cz) {
                    const std::uint32_t b = hashBucket(cx, cy, cz, buckets);
                    for (std::uint32_t e = cellStart_[b]; e < cellStart_[b + 1]; ++e) {
                        const std::uint32_t j = cellEntries_[e];
                        if (j <= i || (w[i] == 0.0 && w[j] == 0.0)) continue;
                        if ((p[i] - p[j]).squaredNorm() >= query2) continue;
                        // Neighbours in the cloth's rest shape lie that near already: not a collision.
                        if ((x0[i] - x0[j]).squaredNorm() < minimum * minimum) continue;
                        // Two cells may share a bucket: each neighbour once.
                        if (std::find(nearby_.begin(), nearby_.end(), j) != nearby_.end()) continue;
                        nearby_.push_back(j);
                        selfPairs.push_back({i, j});
                    }
                }
            }
        }
    }
}

void SoftBodies::project(double h, int iterations, const std::vector<Body>& bodies) {
    // A mesh cut in halves, on two threads: the same sweeps with its halves swept at once, with the
    // result of the loop below to the bit (soft_sweeps.cpp).
    const bool cutMesh =
        std::any_of(meshes.begin(), meshes.end(), [](const SoftMesh& mesh) { return mesh.firstHalfLinks > 0; });
    if (threads_ > 1 && cutMesh) {
        projectInHalves(h, iterations, bodies);
        return;
    }
    for (DistanceLink& link : links) link.lambda = 0.0;
    for (TetVolume& volume : volumes) volume.lambda = 0.0;
    for (ParticleContact& c : contacts) {
        c.pushed = false;
        c.depth = 0.0;
        c.friction = Vec3::Zero();
    }
    for (int iteration = 0; iteration < iterations; ++iteration) {
        for (const SoftMesh& mesh : meshes) sweepMesh(mesh, mesh.firstLink, h, iterations);
        pushSelfPairs();
        // Contacts last, so that no particle ends a sweep inside a body.
        pushOutOfBodies(h, bodies, 0, contacts.size());
    }
    catchMissedContacts(bodies);
}

void SoftBodies::sweepMesh(const SoftMesh& mesh, std::uint32_t firstLink, double h, int iterations) {
    const std::uint32_t lastLink = mesh.firstLink + mesh.linkCount;
    const std::uint32_t lastVolume = mesh.firstVolume + mesh.volumeCount;
    if (mesh.method == SoftMethod::XPBD) {
        // XPBD: each constraint with its compliance, its multiplier summed over the sweeps.
        for (std::uint32_t k = firstLink; k < lastLink; ++k) {
            DistanceLink& link = links[k];
            const DistanceCorrection c = solveDistanceConstraint(p[link.i], p[link.j], w[link.i], w[link.j],
                                                                 link.rest, link.compliance, h, link.lambda);
            p[link.i] += c.dx1;
            p[link.j] += c.dx2;
            link.lambda += c.dlambda;
        }
        for (std::uint32_t k = mesh.firstVolume; k < lastVolume; ++k) {
            TetVolume& tet = volumes[k];
            const auto& t = tet.v;
            const VolumeCorrection c = solveVolumeConstraint({p[t[0]], p[t[1]], p[t[2]], p[t[3]]},
                                                             {w[t[0]], w[t[1]], w[t[2]], w[t[3]]}, tet.rest,
                                                             tet.compliance, h, tet.lambda);
            for (int corner = 0; corner < 4; ++corner) p[t[corner]] += c.dx[corner];
            tet.lambda += c.dlambda;
        }
        return;
    }
    // PBD: each projection with alpha = 0, scaled by the per-sweep stiffness 1 - (1 - k)^(1/n), so
    // that n sweeps of a constraint of stiffness k leave (1 - k) of it.
    double stiffness = -1.0, perSweep = 0.0;  // the last stiffness seen, and its per-sweep share
    const auto sweepShare = [&](double k) {
        if (k != stiffness) {
            stiffness = k;
            perSweep = 1.0 - std::pow(1.0 - k, 1.0 / iterations);
        }
        return perSweep;
    };
    for (std::uint32_t k = firstLink; k < lastLink; ++k) {
        const DistanceLink& link = links[k];
        const double share = sweepShare(link.stiffness);
        const DistanceCorrection c =
            solveDistanceConstraint(p[link.i], p[link.j], w[link.i], w[link.j], link.rest, 0.0, h, 0.0);
        p[link.i] += share * c.dx1;
        p[link.j] += share * c.dx2;
    }
    for (std::uint32_t k = mesh.firstVolume; k < lastVolume; ++k) {
        const TetVolume& tet = volumes[k];
        const auto& t = tet.v;
        const double share = sweepShare(tet.stiffness);
        const VolumeCorrection c = solveVolumeConstraint({p[t[0]], p[t[1]], p[t[2]], p[t[3]]},
                                                         {w[t[0]], w[t[1]], w[t[2]], w[t[3]]}, tet.rest, 0.0, h, 0.0);
        for (int corner = 0; corner < 4; ++corner) p[t[corner]] += share * c.dx[corner];
    }
}

void SoftBodies::pushSelfPairs() {
    for (const auto& pair : selfPairs) {
        const std::uint32_t i = pair[0], j = pair[1];
        const double minimum = 2.0 * meshes[meshOf[i]].radius;
        const Vec3 d = p[i] - p[j];
        const double distance = d.norm();
        const double wSum = w[i] + w[j];
        if (distance >= minimum || distance == 0.0 || wSum == 0.0) continue;
        const Vec3 push = (minimum - distance) / (distance * wSum) * d;
        p[i] += w[i] * push;
        p[j] -= w[j] * push;
    }
}

// A particle of radius r pushed out of a rigid plane, sphere or box by the kernels; its own place
// when it lies r or farther from the body.
Vec3 SoftBodies::pushedOut(const Body& body, const Vec3& q, double r) const {
    switch (body.shape) {
        case Shape::Plane:
            return projectParticlePlane(q, r, body.position, body.orientation * body.normal);
        case Shape::Sphere:
            return projectParticleSphere(q, r, body.position, body.radius);
        case Shape::Box:
            return projectParticleBox(q, r, body.position, body.orientation, body.halfExtents);
    }
    return q;
}

void SoftBodies::pushOutOfBodies(double h, const std::vector<Body>& bodies, std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
        ParticleContact& contact = contacts[k];
        const std::uint32_t i = contact.particle;
        const Body& body = bodies[contact.body];
        const double r = meshes[meshOf[i]].radius;
        // Friction acts while the particle touches the body: pushed now, or pushed earlier in this
        // step and still on the surface (a later sweep may pull it along the surface, not into it).
        // Its move lies in the plane of the last push. Just pushed, the particle lies on that plane,
        // which touches the body (a sphere, a box or a plane: convex) and has all of it on one side,
        // so the move keeps it out; otherwise it is pushed out again after the move.
        if (push(contact, pushedOut(body, p[i], r), r)) {
            applyFriction(contact, h, body);
        } else if (contact.pushed && surfaceGap(body, p[i]) <= r * (1.0 + kTouching)) {
            if (applyFriction(contact, h, body)) push(contact, pushedOut(body, p[i], r), r);
        }
    }
}

bool SoftBodies::push(ParticleContact& contact, const Vec3& moved, double r) {
    Vec3& q = p[contact.particle];
    const Vec3 push = moved - q;
    const double depth = push.norm();
    q = moved;
    // A push of the rounding's size (a particle on the surface) points anywhere: not the surface's normal.
    if (depth <= kTouching * r) return false;
    contact.normal = push / depth;
    contact.depth += depth;
    contact.pushed = true;
    return true;
}

bool SoftBodies::applyFriction(ParticleContact& contact, double h, const Body& body) {
    // Positional friction (Mueller et al., unified particle physics) whose sum over the step's sweeps
    // keeps within the Coulomb cone of the step's summed push, as worksheet 7's sequential impulses
    // keep the summed friction impulse within mu times the summed normal one: the particle's slide
    // along the surface in this step so far, relative to the body's at that point, is stopped when
    // the step's friction would then stay below mu_s times the step's push; otherwise the step's
    // friction is mu_d times the push, against the slide. Each move lies along the surface.
    const std::uint32_t i = contact.particle;
    const Vec3& n = contact.normal;
    contact.bodyVelocity = body.velocity + body.angularVelocity.cross(p[i] - body.position);
    const Vec3 relative = (p[i] - x[i]) - h * contact.bodyVelocity;
    const Vec3 slide = relative - relative.dot(n) * n;
    const Vec3 held = contact.friction - contact.friction.dot(n) * n;  // this step's friction so far
    Vec3 total = held - slide;                                         // stopping the slide
    const double stopping = total.norm();
    if (stopping > body.staticFriction * contact.depth) total *= std::min(body.friction * contact.depth / stopping, 1.0);
    const Vec3 move = total - held;
    contact.friction = total;
    if (move == Vec3::Zero()) return false;
    p[i] += move;
    return true;
}

void SoftBodies::catchMissedContacts(const std::vector<Body>& bodies) {
    // A particle the sweeps' constraints pulled into a body that findContacts() did not expect near
    // it: pushed out once more and kept as a contact, so that its velocity into the body goes too.
    for (std::uint32_t b = 0; b < bodies.size(); ++b) {
        const Body& body = bodies[b];
        for (std::uint32_t i = 0; i < x.size(); ++i) {
            const double r = meshes[meshOf[i]].radius;
            if (w[i] == 0.0 || surfaceGap(body, p[i]) >= r * (1.0 - kTouching)) continue;
            const auto known = std::find_if(contacts.begin(), contacts.end(), [&](const ParticleContact& c) {
                return c.particle == i && c.body == b;
            });
            if (known != contacts.end()) continue;
            ParticleContact c;
            c.particle = i;
            c.body = b;
            c.bodyVelocity = body.velocity + body.angularVelocity.cross(p[i] - body.position);
            push(c, pushedOut(body, p[i], r), r);
            contacts.push_back(c);
        }
    }
}

void SoftBodies::updateVelocities(double h) {
    for (std::size_t i = 0; i < x.size(); ++i) {
        v[i] = (p[i] - x[i]) / h;
        x[i] = p[i];
    }
    // What a body pushed out keeps no velocity into it.
    for (const ParticleContact& contact : contacts) {
        if (!contact.pushed) continue;
        Vec3& velocity = v[contact.particle];
        const double approach = (velocity - contact.bodyVelocity).dot(contact.normal);
        if (approach < 0.0) velocity -= approach * contact.normal;
    }
}

// ---- Diagnostics ---------------------------------------------------------------------------------

double SoftBodies::kineticEnergy() const {
    double e = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i)
        if (w[i] > 0.0) e += 0.5 * mass[i] * v[i].squaredNorm();
    return e;
}

double SoftBodies::potentialEnergy(const Vec3& gravity) const {
    double e = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i)
        if (w[i] > 0.0) e -= mass[i] * gravity.dot(x[i]);
    return e;
}

double SoftBodies::elasticEnergy() const {
    double e = 0.0;
    for (const SoftMesh& mesh : meshes) {
        if (mesh.method != SoftMethod::XPBD) continue;
        for (std::uint32_t k = mesh.firstLink; k < mesh.firstLink + mesh.linkCount; ++k) {
            const DistanceLink& link = links[k];
            if (link.compliance == 0.0) continue;  // a rigid link holds no energy
            const double C = (x[link.i] - x[link.j]).norm() - link.rest;
            e += C * C / (2.0 * link.compliance);
        }
        for (std::uint32_t k = mesh.firstVolume; k < mesh.firstVolume + mesh.volumeCount; ++k) {
            const TetVolume& tet = volumes[k];
            if (tet.compliance == 0.0) continue;
            const double C = tetrahedronVolume({x[tet.v[0]], x[tet.v[1]], x[tet.v[2]], x[tet.v[3]]}) - tet.rest;
            e += C * C / (2.0 * tet.compliance);
        }
    }
    return e;
}

double SoftBodies::largestStretch(std::size_t mesh, LinkKind kind) const {
    const SoftMesh& m = meshes.at(mesh);
    double largest = 0.0;
    for (std::uint32_t k = m.firstLink; k < m.firstLink + m.linkCount; ++k) {
        const DistanceLink& link = links[k];
        if (link.kind != kind || link.rest == 0.0) continue;
        largest = std::max(largest, ((x[link.i] - x[link.j]).norm() - link.rest) / link.rest);
    }
    return largest;
}

double SoftBodies::volumeRatio(std::size_t mesh) const {
    const SoftMesh& m = meshes.at(mesh);
    double volume = 0.0, rest = 0.0;
    for (std::uint32_t k = m.firstVolume; k < m.firstVolume + m.volumeCount; ++k) {
        const TetVolume& tet = volumes[k];
        volume += tetrahedronVolume({x[tet.v[0]], x[tet.v[1]], x[tet.v[2]], x[tet.v[3]]});
        rest += tet.rest;
    }
    return rest > 0.0 ? volume / rest : 1.0;
}

double SoftBodies::deepestPenetration(const std::vector<Body>& bodies) const {
    double deepest = 0.0;
    for (const Body& body : bodies) {
        for (std::size_t i = 0; i < x.size(); ++i) {
            const double r = meshes[meshOf[i]].radius;
            deepest = std::max(deepest, r - surfaceGap(body, x[i]));
        }
    }
    return deepest;
}

bool SoftBodies::allFinite() const { return firstNonFinite() == static_cast<std::size_t>(-1); }

std::size_t SoftBodies::firstNonFinite() const {
    // Free particles first: a pinned one turns NaN only through a neighbour's (0 times NaN).
    for (std::size_t i = 0; i < x.size(); ++i)
        if (w[i] != 0.0 && (!isFinite(x[i]) || !isFinite(v[i]))) return i;
    for (std::size_t i = 0; i < x.size(); ++i)
        if (!isFinite(x[i]) || !isFinite(v[i])) return i;
    return static_cast<std::size_t>(-1);
}

}  // namespace gpl
