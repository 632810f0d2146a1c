// gpl-bench-fluids: the fluids study of worksheet 9 (./lab bench fluids). How smoothed-particle fluids
// trade speed for accuracy: PBF's density error against its iterations and time step; WCSPH's
// largest stable time step against its speed of sound beside the CFL bound; what a step costs per
// particle against the number of particles, for both methods, with the fitted exponent; each
// method's cost beside a bare loop summing poly6 over the same neighbours (the limit); and both
// methods' dam-break surge front beside Martin and Moyce's measurements. Tables on stdout, CSV
// files and the plots' data (drawn by bench/fluids.gp) in the output folder.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "command_line.h"
#include "fluids_study.h"
#include "gpl/fluid_experiments.h"
#include "report.h"

namespace {

using gpl::study::fixed;
using gpl::study::FluidMethod;
using gpl::study::Output;
using gpl::study::pad;
using gpl::study::row;
using gpl::study::sci;
using gpl::study::split;

const std::vector<std::string> kParts{"iterations", "stiffness", "cost", "limit", "dambreak"};
// Each method's time per iteration-equivalent over the bare loop's, at most.
constexpr double kTarget = 5.0;

// What the parts sweep: the full study, or with --quick a tiny version of each (the tests').
struct Plan {
    gpl::study::Column column;
    std::vector<int> iterations{1, 2, 3, 4, 6, 8, 10, 15, 20};
    std::vector<int> stepsPerSecond{30, 60, 120, 240};
    double settle = 1.0;  // s, PBF's column
    std::vector<double> soundSpeeds{5.0, 10.0, 20.0, 40.0, 80.0};
    double stableSeconds = 0.5;
    std::vector<int> sizes{10000, 20000, 50000, 100000, 200000};
    int costSteps = 5;
    int limitSize = 50000;
    int runs = 5;
    int threads = 1;  // the fluids' in the cost and limit parts
    double damBreakT = 4.2;
};

Plan quickPlan() {
    Plan p;
    p.column = {4, 6, 4, 0.05};
    p.iterations = {1, 4};
    p.stepsPerSecond = {60, 120};
    p.settle = 0.1;
    p.soundSpeeds = {10.0, 20.0};
    p.stableSeconds = 0.05;
    p.sizes = {300, 1000};
    p.costSteps = 2;
    p.limitSize = 500;
    p.runs = 2;
    p.damBreakT = 0.9;
    return p;
}

std::string percent(double relative) { return std::isinf(relative) ? "blew up" : fixed(100.0 * relative, 2); }

// What the cost and limit parts time.
std::string timeKind(const Plan& plan) {
    return plan.threads == 1 ? "the thread's CPU time"
                             : "the fluids on two threads timed by the wall clock (the search alone and the bare "
                               "loop on one thread, its CPU time)";
}

// n with n^3 nearest to `particles`.
int cubeSide(int particles) { return std::max(2, static_cast<int>(std::lround(std::cbrt(particles)))); }

// 1. PBF's density error against iterations and the time step.
void iterationsPart(Output& output, const Plan& plan) {
    const auto& c = plan.column;
    std::cout << "1. PBF's density error: a column of " << c.nx << " x " << c.ny << " x " << c.nz << " particles "
              << c.spacing << " m apart (" << c.nx * c.spacing << " m square, " << c.height()
              << " m tall) released at rest in a closed tank as wide, stepped " << plan.settle
              << " s; the density error measured anew after each step and averaged over the last quarter second "
              << "(the whole run when shorter); cells: mean / largest per cent, the mean over the particles of "
              << "max(rho / rho0 - 1, 0) and the largest rho / rho0 - 1; the rest lattice itself reads 0.98 % "
              << "(poly6 at h = 2 spacings)\n";
    std::vector<std::size_t> widths{12};
    std::vector<std::string> header{"iterations"};
    for (int perSecond : plan.stepsPerSecond) {
        widths.push_back(17);
        header.push_back("h = 1/" + std::to_string(perSecond) + " s");
    }
    row(header, widths);
    auto csv = output.open("fluids-iterations.csv");
    csv << "iterations,h_s,mean_density_error,largest_density_error,finite,ms_per_step\n";
    auto dat = output.open("fluids-iterations.dat");
    dat << "iterations";
    for (int perSecond : plan.stepsPerSecond)
        dat << " \"h = 1/" << perSecond << " s\" \"largest 1/" << perSecond << "\"";
    dat << '\n';
    // The same runs by time step, a row per h (the plot's second panel).
    std::vector<std::vector<double>> byStep(plan.stepsPerSecond.size());
    for (int n : plan.iterations) {
        std::vector<std::string> cells{std::to_string(n)};
        dat << n;
        for (std::size_t k = 0; k < plan.stepsPerSecond.size(); ++k) {
            const double h = 1.0 / plan.stepsPerSecond[k];
            const auto e = gpl::study::pbfColumnError(c, n, h, plan.settle);
            cells.push_back(e.finite ? percent(e.mean) + " / " + percent(e.largest) : "blew up");
            csv << n << ',' << h << ',' << e.mean << ',' << e.largest << ',' << e.finite << ',' << e.msPerStep << '\n';
            dat << ' ' << (e.finite ? e.mean : std::nan("")) << ' ' << (e.finite ? e.largest : std::nan(""));
            byStep[k].push_back(e.finite ? e.mean : std::nan(""));
        }
        dat << '\n';
        row(cells, widths);
    }
    auto steps = output.open("fluids-timestep.dat");
    steps << "h";
    for (int n : plan.iterations) steps << " \"" << n << (n == 1 ? " iteration" : " iterations") << '"';
    steps << '\n';
    for (std::size_t k = 0; k < plan.stepsPerSecond.size(); ++k) {
        steps << 1.0 / plan.stepsPerSecond[k];
        for (double e : byStep[k]) steps << ' ' << e;
        steps << '\n';
    }
}

// 2. WCSPH's largest stable step against the speed of sound.
void stiffnessPart(Output& output, const Plan& plan) {
    const auto& c = plan.column;
    const gpl::FluidParameters water = gpl::study::studyWater(c.spacing);
    std::cout
        << "\n2. WCSPH's largest stable time step: the same column (" << c.nx << " x " << c.ny << " x " << c.nz
        << " particles, smoothing length " << water.smoothingLength << " m) at rest, stepped by one substep of h "
        << "at a time for " << plan.stableSeconds << " s; stable: every particle finite and none faster than ten "
        << "times a fall of the column's height, 10 sqrt(2 g H); the largest stable h bracketed from the CFL bound by "
        << "doubling or halving and bisected on log h to 2 %; Tait's stiffness B = rho0 c^2 / 7; CFL bound: "
        << "h <= " << gpl::study::kCourant << " h_smooth / c (what stepSph()'s substeps take); lambda: the "
        << "largest stable h as a Courant number, h c / h_smooth\n";
    const std::vector<std::size_t> widths{10, 12, 20, 14, 12, 9, 12};
    row({"c m/s", "B Pa", "largest stable h s", "CFL bound s", "stable/CFL", "lambda", "fails by"}, widths);
    auto csv = output.open("fluids-stiffness.csv");
    csv << "sound_speed_m_s,stiffness_pa,largest_stable_h_s,cfl_bound_s,courant_number,fails_by,runs\n";
    auto dat = output.open("fluids-stiffness.dat");
    dat << "c \"largest stable h\" \"CFL bound, lambda = " << gpl::study::kCourant << "\"\n";
    for (double speed : plan.soundSpeeds) {
        const double cfl = gpl::study::cflBound(water.smoothingLength, speed);
        const auto stable = gpl::study::largestStableSphStep(c, speed, cfl, 1e-3 * cfl, 0.02, plan.stableSeconds);
        const double stiffness = water.restDensity * speed * speed / 7.0;
        const double lambda = stable.h * speed / water.smoothingLength;
        row({fixed(speed, 0), sci(stiffness, 2), std::isnan(stable.h) ? "< 1e-3 CFL" : sci(stable.h, 3), sci(cfl, 3),
             fixed(stable.h / cfl, 2), fixed(lambda, 2), stable.failure},
            widths);
        csv << speed << ',' << stiffness << ',' << stable.h << ',' << cfl << ',' << lambda << ',' << stable.failure
            << ',' << stable.runs << '\n';
        dat << speed << ' ' << stable.h << ' ' << cfl << '\n';
    }
}

// 3. What a step costs per particle against N, with the fitted exponents.
void costPart(Output& output, const Plan& plan, const std::vector<int>& sizes) {
    std::cout << "\n3. cost against N: a cube of n x n x n particles 0.025 m apart at rest in a closed tank as "
                 "wide, 1.5 times as tall (N = n^3 nearest the size asked for); "
              << timeKind(plan) << ", median of " << plan.costSteps
              << " steps after 2 untimed; PBF: its four stages, 4 iterations, h = 5 ms; WCSPH: "
              << "one substep at the CFL bound (c = 20 m/s), and a step of 5 ms, which takes that many substeps; "
              << "ns per particle and step; exponent: least squares of log(time per step) on log N\n";
    const std::vector<std::size_t> widths{10, 12, 14, 16, 18, 16};
    row({"N", "neighbours", "PBF ns/p", "WCSPH ns/p sub", "WCSPH ns/p 5 ms", "PBF ms/step"}, widths);
    auto csv = output.open("fluids-cost.csv");
    csv << "particles,neighbours_per_particle,iterations,pbf_predict_ns,pbf_neighbours_ns,pbf_project_ns,"
           "pbf_velocities_ns,pbf_step_ns,sph_substep_ns,sph_substeps,sph_step_ns,search_ns,bare_ns\n";
    auto dat = output.open("fluids-cost.dat");
    dat << "particles \"PBF, 4 iterations\" \"WCSPH, one substep\" \"WCSPH, a step of 5 ms\" "
           "\"neighbour search\" \"bare poly6 loop\"\n";
    std::vector<double> n, pbf, sph;
    for (int size : sizes) {
        const auto c = gpl::study::measureCost(cubeSide(size), 4, 0.005, 2, plan.costSteps, plan.threads);
        const double p = c.particles;
        row({std::to_string(c.particles), fixed(c.neighbours, 1), fixed(c.pbfStepNs() / p, 0),
             fixed(c.sphSubstepNs / p, 0), fixed(c.sphStepNs() / p, 0), fixed(c.pbfStepNs() * 1e-6, 1)},
            widths);
        csv << c.particles << ',' << c.neighbours << ',' << c.iterations << ',' << c.pbfPredictNs << ','
            << c.pbfNeighboursNs << ',' << c.pbfProjectNs << ',' << c.pbfVelocitiesNs << ',' << c.pbfStepNs() << ','
            << c.sphSubstepNs << ',' << c.sphSubsteps << ',' << c.sphStepNs() << ',' << c.searchNs << ',' << c.bareNs
            << '\n';
        dat << c.particles << ' ' << c.pbfStepNs() / p << ' ' << c.sphSubstepNs / p << ' ' << c.sphStepNs() / p << ' '
            << c.searchNs / p << ' ' << c.bareNs / p << '\n';
        n.push_back(p);
        pbf.push_back(c.pbfStepNs());
        sph.push_back(c.sphSubstepNs);
    }
    const double pbfExponent = gpl::study::logLogSlope(n, pbf), sphExponent = gpl::study::logLogSlope(n, sph);
    std::cout << "fitted exponent, time per step ~ N^e: PBF e = " << fixed(pbfExponent, 3)
              << ", WCSPH e = " << fixed(sphExponent, 3) << " (1: linear in N)\n";
    auto fit = output.open("fluids-exponent.csv");
    fit << "method,exponent\nPBF," << pbfExponent << "\nWCSPH," << sphExponent << '\n';
}

// 4. Each method beside the bare neighbour loop, taking turns in one run.
void limitPart(Output& output, const Plan& plan) {
    const int n = cubeSide(plan.limitSize);
    std::cout << "\n4. the limit: a cube of " << n << "^3 = " << n * n * n
              << " particles as in part 3, each stage and the bare loop (every particle's poly6 density summed over "
                 "the same grid's neighbours, poly6 written out, nothing else) taking turns in one run, "
              << plan.runs << " timed steps, " << timeKind(plan) << ", medians; an iteration-equivalent: PBF's whole "
              << "step over its 4 iterations (each iteration three passes over the neighbours: densities, "
              << "multipliers, moves; the push out of the walls; the step's search, prediction and XSPH shared out), "
              << "and one WCSPH substep (its search, densities, forces, push); in an instructor's tree, beside "
              << "them, a bare PBF iteration: the same three passes as the reference hooks compute them, kernels "
              << "written out in place, no hooks, no walls\n";
    const auto c = gpl::study::measureCost(n, 4, 0.005, 2, plan.runs, plan.threads);
    const double p = c.particles;
    const std::vector<std::size_t> widths{44, 12, 14, 10};
    row({"part", "ns/particle", "ms", "x bare"}, widths);
    auto csv = output.open("fluids-limit.csv");
    csv << "part,ns_per_particle,ms,ratio_to_bare\n";
    auto dat = output.open("fluids-limit.dat");
    dat << "part \"ns per particle\"\n";
    const auto line = [&](const std::string& name, double ns) {
        row({name, fixed(ns / p, 1), fixed(ns * 1e-6, 2), fixed(ns / c.bareNs, 2)}, widths);
        csv << '"' << name << "\"," << ns / p << ',' << ns * 1e-6 << ',' << ns / c.bareNs << '\n';
    };
    line("bare poly6 loop over the neighbours", c.bareNs);
    line("neighbour search (ParticleGrid::find)", c.searchNs);
    line("PBF predict", c.pbfPredictNs);
    line("PBF neighbours", c.pbfNeighboursNs);
    line("PBF project, 4 iterations", c.pbfProjectNs);
    line("PBF velocities and XSPH", c.pbfVelocitiesNs);
    line("PBF step", c.pbfStepNs());
    line("PBF iteration-equivalent (step / 4)", c.pbfIterationNs());
    line("PBF project, one iteration", c.pbfProjectNs / c.iterations);
    line("WCSPH substep (iteration-equivalent)", c.sphSubstepNs);
    if (c.barePbfNs > 0.0) line("bare PBF iteration (three passes)", c.barePbfNs);
    for (const auto& [name, ns] : std::vector<std::pair<std::string, double>>{{"bare loop", c.bareNs},
                                                                              {"bare PBF iteration", c.barePbfNs},
                                                                              {"search", c.searchNs},
                                                                              {"PBF iteration", c.pbfIterationNs()},
                                                                              {"WCSPH substep", c.sphSubstepNs}}) {
        if (ns > 0.0) dat << '"' << name << "\" " << ns / p << '\n';
    }
    const double pbfRatio = c.pbfIterationNs() / c.bareNs, sphRatio = c.sphSubstepNs / c.bareNs;
    std::cout << "ratio to the bare loop per iteration-equivalent: PBF " << fixed(pbfRatio, 2) << " ("
              << (pbfRatio <= kTarget ? "met" : "NOT met") << "), WCSPH " << fixed(sphRatio, 2) << " ("
              << (sphRatio <= kTarget ? "met" : "NOT met") << "); target: at most " << kTarget << '\n';
    if (c.barePbfNs > 0.0) {
        std::cout << "a PBF iteration beside the bare PBF iteration (the same work without hooks or framework): "
                  << "project " << fixed(c.pbfProjectNs / c.iterations / c.barePbfNs, 2) << "x, iteration-equivalent "
                  << fixed(c.pbfIterationNs() / c.barePbfNs, 2) << "x\n";
    }
}

// 5. The dam break's surge front of both methods beside Martin and Moyce.
void damBreakPart(Output& output, const Plan& plan) {
    std::cout << "\n5. the dam break: the scenes dam-break (PBF) and dam-break-sph (WCSPH, c = 30 m/s), a column "
                 "a = 0.25 m wide and 2a tall, particles 0.025 m apart, h = 5 ms, to T = "
              << plan.damBreakT
              << "; the surge front Z = z / a (the farthest particle's edge from the back wall) against "
                 "T = t sqrt(2 g / a), interpolated to Martin and Moyce's T (1952, n^2 = 2)\n";
    const auto pbf = gpl::study::damBreakFront("dam-break", plan.damBreakT);
    const auto sph = gpl::study::damBreakFront("dam-break-sph", plan.damBreakT);
    const std::vector<std::size_t> widths{8, 12, 9, 11, 9, 11};
    row({"T", "Z measured", "Z PBF", "PBF / M&M", "Z WCSPH", "WCSPH / M&M"}, widths);
    auto csv = output.open("fluids-dambreak.csv");
    csv << "T,Z_measured,Z_pbf,Z_wcsph\n";
    std::size_t k = 0;
    for (const gpl::FrontPoint& m : gpl::kMartinMoyce) {
        const double zp = pbf.atMeasured[k], zs = sph.atMeasured[k];
        ++k;
        csv << m.T << ',' << m.Z << ',' << zp << ',' << zs << '\n';
        if (std::isnan(zp) && std::isnan(zs)) continue;
        row({fixed(m.T, 3), fixed(m.Z, 3), fixed(zp, 3), fixed(zp / m.Z, 3), fixed(zs, 3), fixed(zs / m.Z, 3)}, widths);
    }
    auto measured = output.open("fluids-dambreak-measured.dat");
    measured << "T \"Martin and Moyce (1952)\"\n";
    for (const gpl::FrontPoint& m : gpl::kMartinMoyce) measured << m.T << ' ' << m.Z << '\n';
    for (const auto& [name, run] : {std::pair{"pbf", &pbf}, std::pair{"wcsph", &sph}}) {
        auto dat = output.open(std::string("fluids-dambreak-") + name + ".dat");
        dat << "T \"" << (std::string(name) == "pbf" ? "PBF" : "WCSPH") << "\"\n";
        for (std::size_t s = 0; s < run->T.size(); ++s) dat << run->T[s] << ' ' << run->Z[s] << '\n';
    }
    if (!pbf.finite || !sph.finite) std::cout << "finite: NO (" << (pbf.finite ? "WCSPH" : "PBF") << ")\n";
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "The fluids study: PBF's density error, WCSPH's stable step, cost against N and against a bare "
        "neighbour loop, and the dam break against Martin and Moyce (./lab bench fluids)"};
    std::string out = "build/fluids";
    std::string partList = "iterations,stiffness,cost,limit,dambreak";
    std::vector<int> sizes;
    bool quick = false;
    Plan plan;
    app.add_option("--out", out, "folder for the CSV files and the plots' data (default build/fluids)");
    app.add_option("--parts", partList,
                   "parts to run, separated by commas: iterations, stiffness, cost, limit, dambreak (default all)")
        ->check(gpl::cli::expects(
            "iterations, stiffness, cost, limit or dambreak, separated by commas", [](const std::string& text) {
                const std::vector<std::string> names = split(text);
                return !names.empty() && std::all_of(names.begin(), names.end(), [](const std::string& n) {
                    return std::find(kParts.begin(), kParts.end(), n) != kParts.end();
                });
            }));
    app.add_option("--sizes", sizes, "particles of the cost part's blocks (default 10000 20000 50000 100000 200000)")
        ->check(gpl::cli::wholeNumber(8, 2000000));
    app.add_option("--runs", plan.runs, "timed steps of the limit part; the median is kept (default 5)")
        ->check(gpl::cli::wholeNumber(1, 99));
    app.add_option("--threads", plan.threads,
                   "the fluids' threads in the cost and limit parts: 1 (the thread's CPU time) or 2 (the wall "
                   "clock; the search alone and the bare loop stay on one thread) (default 1)")
        ->check(gpl::cli::wholeNumber(1, 2));
    app.add_flag("--quick", quick, "a tiny version of every part (seconds; the tests run it)");
    if (const int status = gpl::cli::parse(app, argc, argv); status >= 0) return status;
    if (const std::string error = gpl::cli::makeFolder("--out", out); !error.empty()) {
        std::cerr << "error: " << error << '\n';
        return 2;
    }
    if (quick) {
        const int runs = plan.runs, threads = plan.threads;
        plan = quickPlan();
        if (app.count("--runs") > 0) plan.runs = runs;
        plan.threads = threads;
    }
    if (sizes.empty()) sizes = plan.sizes;
    const std::vector<std::string> parts = split(partList);
    const auto wanted = [&parts](const char* part) {
        return std::find(parts.begin(), parts.end(), part) != parts.end();
    };
    try {
        Output output(out);
        std::cout << "the fluids study, with the " << gpl::study::kHookVariant
                  << " hooks (poly6Kernel(), spikyGradient(), fluidDensity(), densityConstraintLambda(), "
                     "densityCorrection(), xsphViscosity(), simulationTimestep())"
                  << (quick ? ", a tiny version (--quick)" : "") << "\n\n";
        if (wanted("iterations")) iterationsPart(output, plan);
        if (wanted("stiffness")) stiffnessPart(output, plan);
        if (wanted("cost")) costPart(output, plan, sizes);
        if (wanted("limit")) limitPart(output, plan);
        if (wanted("dambreak")) damBreakPart(output, plan);
        std::cout << "\nwrote";
        for (const std::string& f : output.written()) std::cout << ' ' << out << '/' << f;
        std::cout << '\n';
    } catch (const std::exception& e) {
        std::cerr << "gpl-bench-fluids: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
