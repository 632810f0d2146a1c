// What the worksheet-9 autograders share: fluids of one rest density drawn from a fixed seed, the
// cubic lattice a fluid at rest fills, neighbours found by brute force, the kernels' definitions as
// the worksheet states them, and messages that show every input.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "contacts.h"
#include "gpl/fluid_kernels.h"

namespace gpl::checks {

constexpr double kFluidPi = 3.14159265358979323846;

/// The fluid the tests use: water at rest density rho0, particles on a spacing s, so that each
/// carries the mass of its cube of fluid, m = rho0 s^3, and seen over a smoothing length h.
struct Fluid {
    double rho0 = 1000.0;  ///< kg/m^3
    double s = 0.05;       ///< m
    double h = 0.1;        ///< m
    double mass() const { return rho0 * s * s * s; }
};

inline std::string fluidText(const Fluid& f) {
    return "\n  rho0 " + formatNumber(f.rho0) + " kg/m^3, spacing " + formatNumber(f.s) + " m, h " + formatNumber(f.h) +
           " m, m " + formatNumber(f.mass()) + " kg";
}

/// The spiky kernel itself, W = 15 / (pi h^6) (h - r)^3 for r <= h (1/m^3): the function whose gradient
/// spikyGradient() returns, as the worksheet defines it.
inline double spikyValue(double r, double h) {
    return r <= h ? 15.0 / (kFluidPi * std::pow(h, 6)) * std::pow(h - r, 3) : 0.0;
}

/// How many sites (i, j, k) of the cubic lattice have i^2 + j^2 + k^2 = n, for every n up to N^2:
/// a lattice sum of a radial function over the ball of N spacings needs one value per shell.
inline std::vector<long> latticeShells(int N) {
    std::vector<long> shells(static_cast<std::size_t>(N) * N + 1, 0);
    for (int i = -N; i <= N; ++i) {
        for (int j = -N; j <= N; ++j) {
            for (int k = -N; k <= N; ++k) {
                const int n = i * i + j * j + k * k;
                if (n <= N * N) ++shells[static_cast<std::size_t>(n)];
            }
        }
    }
    return shells;
}

/// A neighbour at x, at rest, with no density or lambda yet.
inline FluidNeighbour neighbourAt(const Vec3& x) {
    FluidNeighbour j;
    j.x = x;
    return j;
}

/// The sites of the cubic lattice of spacing s through `centre`, turned by R about it, nearer to it
/// than h and other than the centre: the neighbours of a particle inside a fluid at rest.
inline std::vector<FluidNeighbour> latticeNeighbours(const Vec3& centre, double s, double h,
                                                     const Quat& R = Quat::Identity()) {
    std::vector<FluidNeighbour> out;
    const int N = static_cast<int>(std::ceil(h / s));
    for (int i = -N; i <= N; ++i) {
        for (int j = -N; j <= N; ++j) {
            for (int k = -N; k <= N; ++k) {
                const Vec3 offset = s * Vec3(i, j, k);
                if ((i == 0 && j == 0 && k == 0) || !(offset.norm() < h)) continue;
                out.push_back(neighbourAt(centre + R * offset));
            }
        }
    }
    return out;
}

/// `count` neighbours of a particle at x, spread over the ball of radius h around it, 0.05 h to
/// 0.98 h away (none at the centre, where the spiky gradient has no direction), with velocities up
/// to 1 m/s, densities within 10 % of rho0 and lambdas of either sign.
inline std::vector<FluidNeighbour> randomNeighbours(Random& rnd, const Vec3& x, const Fluid& f, int count) {
    std::vector<FluidNeighbour> out;
    for (int n = 0; n < count; ++n) {
        FluidNeighbour j;
        j.x = x + f.h * std::cbrt(rnd.uniform(0.05 * 0.05 * 0.05, 0.98 * 0.98 * 0.98)) * rnd.direction();
        j.v = rnd.inBox(1.0);
        j.density = f.rho0 * rnd.uniform(0.9, 1.1);
        j.lambda = rnd.uniform(-1e-3, 1e-3) * f.h * f.h / (f.s * f.s);
        out.push_back(j);
    }
    return out;
}

/// A cloud of particles: positions, velocities, densities and lambdas, and each particle's
/// neighbours (every other particle nearer than h), found by trying every pair.
struct Cloud {
    std::vector<FluidNeighbour> particles;
    std::vector<std::vector<FluidNeighbour>> neighbours;
    std::size_t pairs = 0;  ///< neighbour pairs, each counted once
};

/// Lists the neighbours of every particle of `particles` by brute force.
inline Cloud withNeighbours(std::vector<FluidNeighbour> particles, double h) {
    Cloud c;
    c.particles = std::move(particles);
    c.neighbours.resize(c.particles.size());
    for (std::size_t i = 0; i < c.particles.size(); ++i) {
        for (std::size_t j = 0; j < c.particles.size(); ++j) {
            if (i == j || !((c.particles[i].x - c.particles[j].x).norm() < h)) continue;
            c.neighbours[i].push_back(c.particles[j]);
            c.pairs += i < j;
        }
    }
    return c;
}

/// n particles scattered in a cube of side (n)^(1/3) s around `centre`, as a fluid near rest density
/// (a particle has a few dozen neighbours when h = 2 s), with velocities, densities and lambdas as
/// randomNeighbours() draws them.
inline Cloud randomCloud(Random& rnd, const Vec3& centre, const Fluid& f, int n) {
    const double half = 0.5 * std::cbrt(static_cast<double>(n)) * f.s;
    std::vector<FluidNeighbour> particles;
    for (int i = 0; i < n; ++i) {
        FluidNeighbour p;
        p.x = centre + rnd.inBox(half);
        p.v = rnd.inBox(1.0);
        p.density = f.rho0 * rnd.uniform(0.9, 1.1);
        p.lambda = rnd.uniform(-1e-3, 1e-3) * f.h * f.h / (f.s * f.s);
        particles.push_back(p);
    }
    return withNeighbours(std::move(particles), f.h);
}

/// A rotation drawn uniformly enough for a test: an axis and an angle.
inline Quat randomRotation(Random& rnd) {
    return Quat(Eigen::AngleAxisd(rnd.uniform(0.1, 3.0), rnd.direction())).normalized();
}

/// The neighbours turned by R about the origin and moved by t, velocities turned along.
inline std::vector<FluidNeighbour> carried(std::vector<FluidNeighbour> list, const Quat& R, const Vec3& t) {
    for (FluidNeighbour& j : list) {
        j.x = R * j.x + t;
        j.v = R * j.v;
    }
    return list;
}

/// The neighbours in another order (reversed, then every odd one moved to the back).
inline std::vector<FluidNeighbour> relabelled(std::vector<FluidNeighbour> list) {
    std::reverse(list.begin(), list.end());
    std::vector<FluidNeighbour> out;
    for (std::size_t k = 0; k < list.size(); k += 2) out.push_back(list[k]);
    for (std::size_t k = 1; k < list.size(); k += 2) out.push_back(list[k]);
    return out;
}

inline std::string neighboursText(const Vec3& x, const std::vector<FluidNeighbour>& list) {
    std::string s = "\n  particle at " + str(x) + ", " + std::to_string(list.size()) + " neighbours";
    for (std::size_t k = 0; k < list.size() && k < 3; ++k) {
        s += "\n    x_j " + str(list[k].x) + ", v_j " + str(list[k].v) + ", rho_j " + formatNumber(list[k].density) +
             ", lambda_j " + formatNumber(list[k].lambda);
    }
    if (list.size() > 3) s += "\n    ...";
    return s;
}

inline bool finite(const Vec3& v) { return v.allFinite(); }

}  // namespace gpl::checks
