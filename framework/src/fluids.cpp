// Worksheet 9's fluids: the particles, PBF's four stages and WCSPH's step (fluids.h). Every sum
// over neighbours goes through the students' kernels (fluid_kernels.h); the rigid bodies' push
// through worksheet 8's contact kernels (soft_constraints.h).
#include "gpl/fluids.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <thread>

#include "gpl/soft_constraints.h"

namespace gpl {
namespace {
namespace fluidstep {

void require(bool ok, const std::string& message) {
    if (!ok) throw std::invalid_argument("fluid: " + message);
}

bool positiveFinite(double value) { return std::isfinite(value) && value > 0.0; }

// A particle of radius r at q pushed out of a plane through `point` (its centre r in front of it).
Vec3 outOfPlane(const Vec3& q, double r, const Vec3& point, const Vec3& normal) {
    const double gap = (q - point).dot(normal) - r;
    return gap < 0.0 ? Vec3(q - gap * normal) : q;
}

}  // namespace fluidstep
}  // namespace

// ---- Building ----------------------------------------------------------------------------------

void Fluids::setParameters(const FluidParameters& f) {
    using fluidstep::positiveFinite;
    using fluidstep::require;
    require(positiveFinite(f.restDensity),
            "rest density must be a positive finite number of kg/m^3, got " + formatNumber(f.restDensity));
    require(positiveFinite(f.spacing), "spacing must be a positive finite number of m, got " + formatNumber(f.spacing));
    require(positiveFinite(f.smoothingLength),
            "smoothing length must be a positive finite number of m, got " + formatNumber(f.smoothingLength));
    require(f.smoothingLength >= f.spacing, "smoothing length " + formatNumber(f.smoothingLength) +
                                                " m is below the spacing " + formatNumber(f.spacing) +
                                                " m: a particle would see no neighbour");
    require(positiveFinite(f.relaxation),
            "relaxation must be a positive finite number, got " + formatNumber(f.relaxation));
    require(std::isfinite(f.tensile.k) && f.tensile.k >= 0.0,
            "tensile k must be a finite number >= 0, got " + formatNumber(f.tensile.k));
    require(f.tensile.dq > 0.0 && f.tensile.dq < 1.0,
            "tensile dq must lie in (0, 1) (a share of the smoothing length), got " + formatNumber(f.tensile.dq));
    require(f.tensile.n >= 1, "tensile n must be >= 1, got " + std::to_string(f.tensile.n));
    require(f.xsph >= 0.0 && f.xsph <= 1.0, "xsph must lie in [0, 1], got " + formatNumber(f.xsph));
    require(f.iterations >= 1, "iterations must be >= 1, got " + std::to_string(f.iterations));
    require(positiveFinite(f.soundSpeed),
            "sound speed must be a positive finite number of m/s, got " + formatNumber(f.soundSpeed));
    require(std::isfinite(f.artificialViscosity) && f.artificialViscosity >= 0.0,
            "artificial viscosity must be a finite number >= 0, got " + formatNumber(f.artificialViscosity));
    parameters_ = f;
}

void Fluids::setContainer(const FluidBox& box) {
    fluidstep::require(isFinite(box.lower) && isFinite(box.upper), "container corners must be finite");
    fluidstep::require((box.upper - box.lower).minCoeff() > 0.0, "container is empty (upper must exceed lower)");
    const std::optional<FluidBox> before = container_;
    container_ = box;
    try {
        for (const Vec3& q : x) requireInside(q, "particle");
    } catch (...) {
        container_ = before;
        throw;
    }
}

void Fluids::requireInside(const Vec3& q, const char* what) const {
    fluidstep::require(isFinite(q), std::string(what) + " position must be finite");
    if (!container_) return;
    const double inset = radius() * (1.0 - 1e-9);  // a lattice's outer layer lies exactly r inside
    const FluidBox inner{container_->lower + Vec3::Constant(inset), container_->upper - Vec3::Constant(inset)};
    if (!inner.contains(q)) {
        throw std::invalid_argument("fluid: " + std::string(what) + " at (" + formatNumber(q.x()) + ", " +
                                    formatNumber(q.y()) + ", " + formatNumber(q.z()) +
                                    ") lies outside the container (half a spacing inside its faces)");
    }
}

std::size_t Fluids::addBlock(const Vec3& lower, const Vec3& upper, const Vec3& velocity) {
    using fluidstep::require;
    require(isFinite(lower) && isFinite(upper), "block corners must be finite");
    require(isFinite(velocity), "block velocity must be finite");
    const double s = parameters_.spacing;
    int counts[3];
    for (int a = 0; a < 3; ++a) {
        counts[a] = static_cast<int>(std::floor((upper[a] - lower[a]) / s + 1e-9));
        require(counts[a] >= 1,
                "block is thinner than one spacing (" + formatNumber(s) + " m) along axis " + std::string(1, "xyz"[a]));
    }
    const std::size_t before = x.size();
    for (int k = 0; k < counts[2]; ++k) {
        for (int j = 0; j < counts[1]; ++j) {
            for (int i = 0; i < counts[0]; ++i) {
                const Vec3 q = lower + s * Vec3(i + 0.5, j + 0.5, k + 0.5);
                try {
                    addParticle(q, velocity);
                } catch (...) {
                    // Nothing of a refused block stays.
                    for (auto* field : {&x, &p, &v}) field->resize(before);
                    for (auto* field : {&density, &lambda, &pressure}) field->resize(before);
                    throw;
                }
            }
        }
    }
    return x.size() - before;
}

void Fluids::addParticle(const Vec3& position, const Vec3& velocity) {
    fluidstep::require(isFinite(velocity), "particle velocity must be finite");
    requireInside(position, "particle");
    x.push_back(position);
    p.push_back(position);
    v.push_back(velocity);
    density.push_back(parameters_.restDensity);
    lambda.push_back(0.0);
    pressure.push_back(0.0);
}

void Fluids::clear() {
    for (auto* field : {&x, &p, &v}) field->clear();
    for (auto* field : {&density, &lambda, &pressure}) field->clear();
    container_.reset();
}

double Fluids::mass() const {
    const double s = parameters_.spacing;
    return parameters_.restDensity * s * s * s;
}

double Fluids::epsilon() const { return parameters_.relaxation / (parameters_.spacing * parameters_.spacing); }

TensileCorrection Fluids::tensile() const {
    TensileCorrection t = parameters_.tensile;
    t.k *= parameters_.spacing * parameters_.spacing;
    t.dq *= parameters_.smoothingLength;
    return t;
}

// ---- Threads -----------------------------------------------------------------------------------

int Fluids::defaultThreads() { return std::thread::hardware_concurrency() >= 2 ? 2 : 1; }

void Fluids::setThreads(int threads) {
    if (threads < 1) throw std::invalid_argument("threads must be at least 1, got " + std::to_string(threads));
    threads_ = threads < 2 ? 1 : 2;
}

template <class Pass>
void Fluids::eachParticle(const Pass& pass) {
    const std::size_t n = x.size();
    if (threads_ < 2 || n < kThreadedParticles) {
        pass(std::size_t{0}, n, neighbours_[0]);
        return;
    }
    // Each half's function holds one reference, which std::function keeps without allocating.
    const auto half = [&](int which) {
        const std::size_t middle = n / 2;
        if (which == 0)
            pass(std::size_t{0}, middle, neighbours_[0]);
        else
            pass(middle, n, neighbours_[1]);
    };
    second_.run(
        true, [&half] { half(0); }, [&half] { half(1); });
}

void Fluids::gather(std::size_t i, const std::vector<Vec3>& positions, std::vector<FluidNeighbour>& into) const {
    const std::uint32_t* row = grid_.list().data() + grid_.start(i);
    into.resize(grid_.count(i));
    for (std::size_t k = 0; k < into.size(); ++k) {
        const std::uint32_t j = row[k];
        into[k] = {positions[j], v[j], density[j], lambda[j]};
    }
}

void Fluids::densities(const std::vector<Vec3>& positions) {
    const double m = mass(), hs = parameters_.smoothingLength, rho0 = parameters_.restDensity;
    const double stiffness = rho0 * parameters_.soundSpeed * parameters_.soundSpeed / 7.0;  // Tait's B (Pa)
    nextDensity_.resize(x.size());
    eachParticle([&](std::size_t begin, std::size_t end, std::vector<FluidNeighbour>& neighbours) {
        for (std::size_t i = begin; i < end; ++i) {
            gather(i, positions, neighbours);
            nextDensity_[i] = fluidDensity(positions[i], neighbours, m, hs);
            pressure[i] = std::max(stiffness * (std::pow(nextDensity_[i] / rho0, 7) - 1.0), 0.0);
        }
    });
    density.swap(nextDensity_);
}

void Fluids::boundBodies(const std::vector<Body>& bodies) {
    const double r = radius();
    reach_.resize(bodies.size());
    for (std::size_t b = 0; b < bodies.size(); ++b) {
        const Body& body = bodies[b];
        Vec3 half = Vec3::Constant(body.radius);
        if (body.shape == Shape::Box) half = body.orientation.toRotationMatrix().cwiseAbs() * body.halfExtents;
        const double margin = 1e-9 * (1.0 + body.position.cwiseAbs().maxCoeff() + half.maxCoeff() + r);
        reach_[b] = {body.position - half - Vec3::Constant(r + margin),
                     body.position + half + Vec3::Constant(r + margin)};
    }
}

void Fluids::pushOut(Vec3& q, const std::vector<Body>& bodies, Vec3* velocity) const {
    const double r = radius();
    for (std::size_t b = 0; b < bodies.size(); ++b) {
        const Body& body = bodies[b];
        if (body.shape != Shape::Plane && !reach_[b].contains(q)) continue;  // too far to push
        Vec3 moved = q;
        switch (body.shape) {
            case Shape::Plane:
                moved = fluidstep::outOfPlane(q, r, body.position, body.orientation * body.normal);
                break;
            case Shape::Sphere:
                moved = projectParticleSphere(q, r, body.position, body.radius);
                break;
            case Shape::Box:
                moved = projectParticleBox(q, r, body.position, body.orientation, body.halfExtents);
                break;
        }
        if (moved == q) continue;
        if (velocity) {
            // No velocity into this body stays (in a corner, into each of its walls).
            const Vec3 normal = (moved - q).normalized();
            const double into = velocity->dot(normal);
            if (into < 0.0) *velocity -= into * normal;
        }
        q = moved;
    }
}

// ---- PBF ---------------------------------------------------------------------------------------

void Fluids::predict(double h, const Vec3& gravity) {
    for (std::size_t i = 0; i < x.size(); ++i) {
        v[i] += h * gravity;
        p[i] = x[i] + h * v[i];
    }
}

void Fluids::findNeighbours() { grid_.find(p, parameters_.smoothingLength, searchThread()); }

void Fluids::project(const std::vector<Body>& bodies) {
    const double m = mass(), h = parameters_.smoothingLength, rho0 = parameters_.restDensity;
    const double eps = epsilon();
    const TensileCorrection sCorr = tensile();
    delta_.resize(x.size());
    nextDensity_.resize(x.size());
    nextLambda_.resize(x.size());
    boundBodies(bodies);
    for (int iteration = 0; iteration < parameters_.iterations; ++iteration) {
        // Densities at the predicted positions, and from each the multiplier of its density
        // constraint (which reads the particle's own density and its neighbours' positions, so one
        // gathering of the neighbours serves both). One-sided: a particle short of neighbours (at a
        // free surface or a wall) counts as at rest, not as stretched, so that it is not pulled
        // into the fluid. The neighbours' densities and multipliers the kernels are shown are the
        // last pass's: this pass writes its own beside them.
        eachParticle([&](std::size_t begin, std::size_t end, std::vector<FluidNeighbour>& neighbours) {
            for (std::size_t i = begin; i < end; ++i) {
                gather(i, p, neighbours);
                nextDensity_[i] = fluidDensity(p[i], neighbours, m, h);
                nextLambda_[i] =
                    densityConstraintLambda(p[i], neighbours, std::max(nextDensity_[i], rho0), rho0, m, h, eps);
            }
        });
        density.swap(nextDensity_);
        lambda.swap(nextLambda_);
        // Moves, all from the same multipliers, then applied, and the rigid bodies push the
        // particles out.
        eachParticle([&](std::size_t begin, std::size_t end, std::vector<FluidNeighbour>& neighbours) {
            for (std::size_t i = begin; i < end; ++i) {
                gather(i, p, neighbours);
                delta_[i] = densityCorrection(p[i], lambda[i], neighbours, rho0, m, h, sCorr);
            }
        });
        eachParticle([&](std::size_t begin, std::size_t end, std::vector<FluidNeighbour>&) {
            for (std::size_t i = begin; i < end; ++i) {
                p[i] += delta_[i];
                pushOut(p[i], bodies, nullptr);
            }
        });
    }
}

void Fluids::updateVelocities(double h) {
    for (std::size_t i = 0; i < x.size(); ++i) v[i] = (p[i] - x[i]) / h;
    // XSPH: every velocity blended with its neighbours' (all from the velocities before the blend).
    blended_.resize(x.size());
    const double m = mass(), hs = parameters_.smoothingLength, c = parameters_.xsph;
    eachParticle([&](std::size_t begin, std::size_t end, std::vector<FluidNeighbour>& neighbours) {
        for (std::size_t i = begin; i < end; ++i) {
            gather(i, p, neighbours);
            blended_[i] = xsphViscosity(p[i], v[i], neighbours, m, hs, c);
        }
    });
    for (std::size_t i = 0; i < x.size(); ++i) {
        v[i] = blended_[i];
        x[i] = p[i];
    }
}

// ---- WCSPH -------------------------------------------------------------------------------------

int Fluids::sphSubsteps(double h) const {
    const double longest = 0.4 * parameters_.smoothingLength / parameters_.soundSpeed;  // s (CFL)
    return std::max(1, static_cast<int>(std::ceil(h / longest - 1e-9)));
}

void Fluids::stepSph(double h, const Vec3& gravity, const std::vector<Body>& bodies, int substeps) {
    const double m = mass(), hs = parameters_.smoothingLength;
    const double c = parameters_.soundSpeed, alpha = parameters_.artificialViscosity;
    if (substeps < 1) substeps = sphSubsteps(h);
    const double dt = h / substeps;
    delta_.resize(x.size());
    boundBodies(bodies);
    for (int substep = 0; substep < substeps; ++substep) {
        // Neighbours, densities and Tait's pressures.
        grid_.find(x, hs, searchThread());
        densities(x);
        // Accelerations: gravity, the symmetric pressure force and Monaghan's viscosity.
        eachParticle([&](std::size_t begin, std::size_t end, std::vector<FluidNeighbour>&) {
            for (std::size_t i = begin; i < end; ++i) {
                Vec3 a = gravity;
                const double pi = pressure[i] / (density[i] * density[i]);
                const std::uint32_t first = grid_.start(i), last = first + grid_.count(i);
                for (std::uint32_t k = first; k < last; ++k) {
                    const std::uint32_t j = grid_.list()[k];
                    const Vec3 r = x[i] - x[j];
                    const double pj = pressure[j] / (density[j] * density[j]);
                    const double approach = (v[i] - v[j]).dot(r);  // < 0: closing
                    double viscous = 0.0;
                    if (approach < 0.0) {
                        const double mu = hs * approach / (r.squaredNorm() + 0.01 * hs * hs);
                        viscous = -alpha * c * mu / (0.5 * (density[i] + density[j]));
                    }
                    a -= m * (pi + pj + viscous) * spikyGradient(r, hs);
                }
                delta_[i] = a;
            }
        });
        // Semi-implicit Euler, then the rigid bodies' push: no velocity into a body stays.
        eachParticle([&](std::size_t begin, std::size_t end, std::vector<FluidNeighbour>&) {
            for (std::size_t i = begin; i < end; ++i) {
                v[i] += dt * delta_[i];
                x[i] += dt * v[i];
                pushOut(x[i], bodies, &v[i]);
                p[i] = x[i];
            }
        });
    }
}

// ---- Diagnostics -------------------------------------------------------------------------------

void Fluids::measureDensities() {
    grid_.find(x, parameters_.smoothingLength, searchThread());
    densities(x);
}

double Fluids::densityError() const {
    if (x.empty()) return 0.0;
    double sum = 0.0;
    for (double rho : density) sum += std::max(rho / parameters_.restDensity - 1.0, 0.0);
    return sum / static_cast<double>(x.size());
}

double Fluids::largestDensityError() const {
    double largest = 0.0;
    for (double rho : density) largest = std::max(largest, rho / parameters_.restDensity - 1.0);
    return largest;
}

double Fluids::kineticEnergy() const {
    double e = 0.0;
    for (const Vec3& velocity : v) e += 0.5 * mass() * velocity.squaredNorm();
    return e;
}

double Fluids::potentialEnergy(const Vec3& gravity) const {
    double e = 0.0;
    for (const Vec3& q : x) e -= mass() * gravity.dot(q);
    return e;
}

Vec3 Fluids::linearMomentum() const {
    Vec3 sum = Vec3::Zero();
    for (const Vec3& velocity : v) sum += mass() * velocity;
    return sum;
}

std::size_t Fluids::firstNonFinite() const {
    for (std::size_t i = 0; i < x.size(); ++i) {
        if (!isFinite(x[i]) || !isFinite(v[i])) return i;
    }
    return x.size();
}

}  // namespace gpl
