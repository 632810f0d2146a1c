// Fluids (worksheet 9): smoothed particles as pure kernels. A fluid is particles of one mass m and
// one rest density rho0; each particle sees its neighbours, the other particles nearer than the
// smoothing length h, and every field at a particle is a sum over them weighted by a kernel W that
// falls from W(0, h) to 0 at distance h.
//
// Student hooks (bodies in assignments/, reference bodies in solutions/):
//   poly6Kernel()              W(r, h): the kernel the densities are summed with
//   spikyGradient()            grad W(r, h): the gradient the pressure pushes along
//   fluidDensity()             rho_i at a particle from its neighbours
//   densityConstraintLambda()  PBF: the multiplier of the constraint rho_i / rho0 - 1 = 0
//   densityCorrection()        PBF: a particle's move from its and its neighbours' multipliers
//   xsphViscosity()            XSPH: a particle's velocity blended with its neighbours'
// Framework (fluids.cpp): the particles, the neighbour search, the position-based step that calls
// these kernels, and the weakly compressible SPH step the study compares it with.
//
// Position-based fluids (Macklin and Mueller) in one line: each particle i holds the constraint
// C_i = rho_i / rho0 - 1 = 0; an iteration computes every lambda_i = -C_i / (sum_k |grad_k C_i|^2 + eps)
// and then moves every particle by dp_i = (m / rho0) sum_j (lambda_i + lambda_j + s_corr) grad W(x_i - x_j).
#pragma once

#include <vector>

#include "gpl/math.h"

namespace gpl {

/// What the kernels are told of one neighbour j of a particle i: a particle other than i, nearer to
/// it than h. The framework fills the fields the step has computed so far (in an iteration of PBF:
/// the predicted positions, then the densities, then the multipliers).
struct FluidNeighbour {
    Vec3 x = Vec3::Zero();  ///< position (m)
    Vec3 v = Vec3::Zero();  ///< velocity (m/s)
    double density = 0.0;   ///< rho_j (kg/m^3)
    double lambda = 0.0;    ///< PBF's multiplier lambda_j (m^2: C is dimensionless, grad C in 1/m)
};

/// The tensile correction of PBF: s_corr = -k (W(|x_i - x_j|, h) / W(dq, h))^n, which pushes
/// apart the particles of a sparse surface that the density constraint alone pulls into clumps.
struct TensileCorrection {
    double k = 0.0;   ///< strength (m^2, as the multipliers it is added to; >= 0; 0: none)
    double dq = 0.0;  ///< the distance at which |s_corr| = k (m, 0 < dq < h)
    int n = 4;        ///< exponent (>= 1)
};

/// Student hook (worksheet 9, assignment 1). The poly6 kernel: W(r, h) = 315 / (64 pi h^9) (h^2 - r^2)^3
/// for 0 <= r <= h and 0 beyond (1/m^3). r: a distance (m, >= 0); h: the smoothing length (m, > 0).
double poly6Kernel(double r, double h);

/// Student hook (worksheet 9, assignment 1). The gradient of the spiky kernel with respect to x_i,
/// for r = x_i - x_j: grad W(r, h) = -45 / (pi h^6) (h - |r|)^2 r / |r| for 0 < |r| <= h, and the zero
/// vector at r = 0 and beyond h (1/m^4).
Vec3 spikyGradient(const Vec3& r, double h);

/// Student hook (worksheet 9, assignment 2). rho_i = m sum W(|x_i - x_j|, h) over the neighbours and
/// over i itself (kg/m^3). x: the particle's position; mass m (kg, > 0); h as above.
double fluidDensity(const Vec3& x, const std::vector<FluidNeighbour>& neighbours, double mass, double h);

/// Student hook (worksheet 9, assignment 3). PBF's multiplier of particle i:
///   lambda_i = -C_i / (sum_k |grad_k C_i|^2 + eps),  C_i = density / rho0 - 1,
///   grad_j C_i = -(m / rho0) grad W(x_i - x_j) for a neighbour j,
///   grad_i C_i = (m / rho0) sum_j grad W(x_i - x_j),
/// with W the spiky kernel. density: rho_i (kg/m^3); restDensity rho0 (kg/m^3, > 0); epsilon: the
/// relaxation (1/m^2, > 0), which keeps the quotient finite where a particle has few neighbours.
double densityConstraintLambda(const Vec3& x, const std::vector<FluidNeighbour>& neighbours, double density,
                               double restDensity, double mass, double h, double epsilon);

/// Student hook (worksheet 9, assignment 4). PBF's move of particle i (m):
///   dp_i = (m / rho0) sum_j (lambda_i + lambda_j + s_corr) grad W(x_i - x_j)
/// with W the spiky kernel and s_corr = -k (W_poly6(|x_i - x_j|, h) / W_poly6(dq, h))^n (0 when k = 0).
Vec3 densityCorrection(const Vec3& x, double lambda, const std::vector<FluidNeighbour>& neighbours,
                       double restDensity, double mass, double h, const TensileCorrection& tensile);

/// Student hook (worksheet 9, assignment 5). XSPH viscosity: particle i's velocity blended with its
/// neighbours',
///   v_i' = v_i + c sum_j (m / rho_j) (v_j - v_i) W_poly6(|x_i - x_j|, h)
/// where c (dimensionless, 0 <= c <= 1) is how much. Returns v_i'.
Vec3 xsphViscosity(const Vec3& x, const Vec3& v, const std::vector<FluidNeighbour>& neighbours, double mass, double h,
                   double c);

}  // namespace gpl
