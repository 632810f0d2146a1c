// gpl-bench-cloth: the cloth study of worksheet 8 (./lab bench cloth). How position-based cloth
// trades speed for accuracy: a hanging cloth's settled stretch against the projection iterations
// and against the time step for PBD and XPBD; what a step and one constraint projection cost; the
// largest time step that keeps the flag stable; and the same cloth dropped on a sphere beside
// Bullet's soft bodies, both engines in the same run. Tables on stdout, CSV files and the plots'
// data (drawn by bench/cloth.gp) in the output folder.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "bullet_cloth.h"
#include "cloth_study.h"
#include "command_line.h"
#include "report.h"

namespace {

using gpl::study::ClothMethod;
using gpl::study::fixed;
using gpl::study::Output;
using gpl::study::pad;
using gpl::study::row;
using gpl::study::sci;
using gpl::study::split;

// The hanging cloth of the stretch sweeps: small enough that 64 iterations of XPBD converge.
constexpr int kHangingN = 12;
constexpr double kHangingSide = 1.0;  // m
constexpr double kHangingMass = 1.0;  // kg
const std::vector<int> kIterations{1, 2, 4, 8, 16, 32, 64};
const std::vector<int> kStepsPerSecond{30, 60, 120, 240, 480};
constexpr int kSweepStepsPerSecond = 60;  // the iteration sweep's time step, 1/60 s
constexpr int kSweepIterations = 16;      // the time-step sweep's iterations
// The cost's cloths, and the flag's iteration counts.
const std::vector<int> kCostSizes{16, 32, 64, 128};
constexpr int kCostIterations = 10;
const std::vector<int> kFlagIterations{4, 16};
// This engine's time per step over Bullet's on the drop, at most.
constexpr double kTarget = 0.5;

const std::vector<std::string> kParts{"stretch", "cost", "flag", "bullet"};

std::string stretchCell(bool finite, double largest, double mean) {
    return finite ? sci(largest) + " / " + sci(mean) : "blew up";
}

// 1. The hanging cloth's settled stretch against iterations (h = 1/60 s) and against the time step
// (16 iterations), each method a column.
void stretchPart(Output& output, const std::vector<ClothMethod>& methods) {
    const ClothMethod& soft = methods.back();
    const auto theory = gpl::study::chainStretch(kHangingN, kHangingSide, kHangingMass, soft.compliance);
    std::cout << "1. stretch: a hanging cloth of " << kHangingN << " x " << kHangingN << " particles, " << kHangingSide
              << " m square, " << kHangingMass << " kg, pinned along its top edge; gravity ramped in over 1 s, held "
              << "1 s, each stretch link's relative stretch averaged over the next 1 s; cells: the largest / the mean "
              << "over the stretch links\n"
              << "   PBD: every link the stiffness k, applied per iteration as 1 - (1 - k)^(1/n); XPBD: the stretch "
              << "links the compliance a, shear and bend links " << gpl::study::kShearBendSofter << " a\n"
              << "   theory: XPBD converged is each column a chain of springs, whatever h and n: "
              << stretchCell(true, theory.largest, theory.mean) << " for " << soft.name
              << " (the top link: tension x a / rest), 0 for a = 0; PBD's stretch is the solver's, falling as h^2 and "
              << "(k = 1) with n\n";
    std::vector<std::size_t> widths{12};
    std::vector<std::string> header{"iterations"};
    for (const ClothMethod& m : methods) {
        widths.push_back(22);
        header.push_back(m.name);
    }
    auto csv = output.open("cloth-stretch.csv");
    csv << "sweep,method,iterations,h_s,largest_stretch,mean_stretch,ms_per_step\n";
    const auto sweep = [&](const char* file, const char* first, const std::vector<std::pair<int, double>>& points,
                           const std::vector<std::string>& labels) {
        auto dat = output.open(file);
        dat << first;
        for (const ClothMethod& m : methods) dat << " \"" << m.name << "\" \"" << m.name << " mean\"";
        dat << " \"theory, " << soft.name << "\"\n";
        row(header, widths);
        for (std::size_t k = 0; k < points.size(); ++k) {
            const auto [iterations, h] = points[k];
            std::vector<std::string> cells{labels[k]};
            dat << (std::string(first) == "iterations" ? static_cast<double>(iterations) : h);
            for (const ClothMethod& m : methods) {
                const auto s = gpl::study::settleHanging(
                    gpl::study::hangingClothSpec(kHangingN, kHangingSide, kHangingMass, m), h, iterations);
                cells.push_back(stretchCell(s.finite, s.largest, s.mean));
                csv << first << ',' << m.name << ',' << iterations << ',' << h << ',' << s.largest << ',' << s.mean
                    << ',' << s.msPerStep << '\n';
                dat << ' ' << s.largest << ' ' << s.mean;
            }
            dat << ' ' << theory.largest << '\n';
            row(cells, widths);
        }
    };
    std::cout << "\n   against the projection iterations n, h = 1/" << kSweepStepsPerSecond << " s\n";
    std::vector<std::pair<int, double>> points;
    std::vector<std::string> labels;
    for (int n : kIterations) {
        points.emplace_back(n, 1.0 / kSweepStepsPerSecond);
        labels.push_back(std::to_string(n));
    }
    sweep("cloth-iterations.dat", "iterations", points, labels);
    std::cout << "\n   against the time step h, " << kSweepIterations << " iterations\n";
    header[0] = "h s";
    points.clear();
    labels.clear();
    for (int perSecond : kStepsPerSecond) {
        points.emplace_back(kSweepIterations, 1.0 / perSecond);
        labels.push_back("1/" + std::to_string(perSecond));
    }
    sweep("cloth-timestep.dat", "h", points, labels);
}

// 2. What a step and one projection cost, on hanging cloths of growing size.
void costPart(Output& output) {
    std::cout << "\n2. cost: hanging cloths (1 m square, XPBD, compliance 0), " << kCostIterations
              << " iterations, h = 1/60 s, 120 steps, nothing to collide with; each part's median CPU time per step; "
              << "ns per projection: the projection part over iterations x links\n";
    const std::vector<std::size_t> widths{11, 11, 8, 12, 13, 12, 15, 10, 14};
    row({"n x n", "particles", "links", "predict us", "contacts us", "project us", "velocities us", "step us",
         "ns/projection"},
        widths);
    auto csv = output.open("cloth-cost.csv");
    csv << "n,particles,links,iterations,predict_ns,contacts_ns,project_ns,velocities_ns,step_ns,ns_per_projection\n";
    auto dat = output.open("cloth-cost.dat");
    dat << "particles \"ns per projection\" \"us per step\"\n";
    const ClothMethod rigid{"XPBD a=0", gpl::SoftMethod::XPBD, 1.0, 0.0};
    for (int n : kCostSizes) {
        const auto c = gpl::study::measureStepCost(gpl::study::hangingClothSpec(n, kHangingSide, kHangingMass, rigid),
                                                   1.0 / 60.0, kCostIterations, 120);
        row({std::to_string(n) + " x " + std::to_string(n), std::to_string(c.particles), std::to_string(c.links),
             fixed(c.predictNs * 1e-3, 1), fixed(c.contactsNs * 1e-3, 1), fixed(c.projectNs * 1e-3, 1),
             fixed(c.velocitiesNs * 1e-3, 1), fixed(c.stepNs() * 1e-3, 1), fixed(c.nsPerProjection(), 1)},
            widths);
        csv << n << ',' << c.particles << ',' << c.links << ',' << c.iterations << ',' << c.predictNs << ','
            << c.contactsNs << ',' << c.projectNs << ',' << c.velocitiesNs << ',' << c.stepNs() << ','
            << c.nsPerProjection() << '\n';
        dat << c.particles << ' ' << c.nsPerProjection() << ' ' << c.stepNs() * 1e-3 << '\n';
    }
}

// 3. The flag's largest stable time step for each method.
void flagPart(Output& output) {
    const gpl::study::Flag flag;
    const gpl::study::Stability stability;
    // XPBD: the scene's flag (stretch compliance 0), and one whose stretch links give about 1 % under
    // the weight at the pinned corners.
    const std::vector<ClothMethod> methods{{"PBD k=1", gpl::SoftMethod::PBD, 1.0, 0.0},
                                           {"PBD k=0.5", gpl::SoftMethod::PBD, 0.5, 0.0},
                                           {"XPBD a=0", gpl::SoftMethod::XPBD, 1.0, 0.0},
                                           {"XPBD a=1e-03", gpl::SoftMethod::XPBD, 1.0, 1e-3}};
    std::cout << "\n3. stability: the scene flag without its pole and floor, " << flag.nx << " x " << flag.ny
              << " particles " << flag.spacing << " m apart, " << flag.mass << " kg, pinned at the pole's two corners, "
              << "XPBD's shear and bend compliances the scene's (" << flag.shearCompliance << ", "
              << flag.bendCompliance << " m/N), PBD's stiffness on every link, in a gusting wind of (" << flag.wind.x()
              << ", " << flag.wind.y() << ", " << flag.wind.z() << ") m/s, drag " << flag.drag
              << " kg/(m^2 s); the largest stable h, bracketed from 1/60 s by doubling or halving and bisected on log "
              << "h to 2 %; stable: for " << stability.seconds << " s, at every step, every particle finite, none "
              << "faster than 10 (|wind| + sqrt(2 g diagonal)) m/s (the kinetic energy bounded) and every stretch link "
              << "within " << stability.stretchBound * 100 << " % of its rest length (the cloth holds together); "
              << "fails by: what failed first just above it\n";
    const std::vector<std::size_t> widths{14, 12, 20, 12};
    row({"method", "iterations", "largest stable h s", "fails by"}, widths);
    auto csv = output.open("cloth-stable.csv");
    csv << "method,iterations,largest_stable_h_s,fails_by\n";
    for (const ClothMethod& m : methods) {
        for (int n : kFlagIterations) {
            const auto stable = gpl::study::largestStableStep(flag, m, n, stability);
            const double h = stable.h;
            const std::string cell = std::isnan(h)   ? "< 1e-3"
                                     : std::isinf(h) ? "> 0.25"
                                                     : sci(h, 3) + " (1/" + fixed(1.0 / h, 0) + ")";
            row({m.name, std::to_string(n), cell, stable.failure}, widths);
            csv << m.name << ',' << n << ',' << h << ',' << stable.failure << '\n';
        }
    }
}

// Runs of the bare XPBD sweeps per size (each a few milliseconds).
constexpr int kBareRepeats = 15;

// 4. The same cloth dropped on a sphere in both engines, taking turns: in each round this engine
// on each thread count, then Bullet.
void bulletPart(Output& output, const std::vector<int>& sizes, const std::vector<int>& threadCounts, int runs,
                bool bullet, const std::string& without) {
    gpl::study::SphereDrop drop;
    std::cout << "\n4. beside Bullet: a cloth " << drop.side << " m square, " << drop.mass << " kg, flat, centred "
              << drop.drop << " m above a static sphere of radius " << drop.sphereRadius << " m and friction "
              << drop.friction
              << ", dropped on it, nothing pinned, every link rigid (XPBD, compliance 0), particle radius "
              << drop.radius << " m, h = 1/" << fixed(1.0 / drop.h, 0) << " s, " << drop.iterations << " iterations, "
              << drop.seconds << " s; "
              << (bullet ? std::to_string(runs) +
                               " rounds, each running this engine on each thread count and then Bullet, the median "
                               "of the runs' median step times"
                         : "this engine only (" + without + ")")
              << "; CPU ratio: the same with each step's CPU time, every thread's, which leaves out the time other "
              << "programs had the cores; stretch: the grid's links at the end, the largest / the mean; depth: the "
              << "deepest a particle's sphere lay inside the rigid sphere over the run; both measured alike from the "
              << "particles' positions\n";
    if (bullet) std::cout << gpl::bench::bulletClothSettings() << '\n';
    std::cout << "threads: this engine's (SoftBodies::setThreads(); two sweep a large cloth's halves at once, with the "
              << "same result as one); Bullet's soft bodies run on one\n";
    const std::vector<std::size_t> widths{11, 8, 9, 11, 7, 10, 9, 22, 22, 13, 13};
    row({"n x n", "threads", "ours ms", "Bullet ms", "ratio", "CPU ratio", "target", "stretch ours", "stretch Bullet",
         "depth ours m", "depth Bullet m"},
        widths);
    auto csv = output.open("cloth-bullet.csv");
    csv << "n,engine,threads,runs,median_ms_per_step,median_cpu_ms_per_step,largest_stretch,mean_stretch,"
           "deepest_penetration_m,finite\n";
    auto dat = output.open("cloth-bullet.dat");
    dat << "cloth \"Bullet\"";
    for (int t : threadCounts) dat << " \"this engine, " << t << (t == 1 ? " thread" : " threads") << '"';
#ifdef GPL_BARE_XPBD
    dat << " \"bare XPBD sweeps, 1 thread\"";
#endif
    dat << '\n';
    std::vector<std::string> bareLines;  // per size: the bare sweeps' time against Bullet's step
    const std::string dash = "-";
    for (int n : sizes) {
        drop.n = n;
        std::vector<std::vector<double>> ours(threadCounts.size()), oursCpu(threadCounts.size());
        std::vector<double> theirs, theirsCpu;
        std::vector<gpl::study::DropRun> mine(threadCounts.size());
        gpl::study::DropRun other;
        for (int r = 0; r < runs; ++r) {
            for (std::size_t t = 0; t < threadCounts.size(); ++t) {
                drop.threads = threadCounts[t];
                mine[t] = gpl::study::dropOnSphere(drop);
                ours[t].push_back(mine[t].medianMs);
                oursCpu[t].push_back(mine[t].medianCpuMs);
            }
            if (bullet) {
                other = gpl::bench::bulletDropOnSphere(drop);
                theirs.push_back(other.medianMs);
                theirsCpu.push_back(other.medianCpuMs);
            }
        }
        const double theirMs = bullet ? gpl::study::median(theirs) : std::nan("");
        const double theirCpuMs = bullet ? gpl::study::median(theirsCpu) : std::nan("");
        if (bullet) {
            csv << n << ",Bullet,1," << runs << ',' << theirMs << ',' << theirCpuMs << ',' << other.largestStretch
                << ',' << other.meanStretch << ',' << other.deepest << ',' << other.finite << '\n';
        }
        dat << n << 'x' << n << ' ' << theirMs;
        for (std::size_t t = 0; t < threadCounts.size(); ++t) {
            const gpl::study::DropRun& m = mine[t];
            const double oursMs = gpl::study::median(ours[t]), oursCpuMs = gpl::study::median(oursCpu[t]);
            const double ratio = oursMs / theirMs;
            row({std::to_string(n) + " x " + std::to_string(n), std::to_string(threadCounts[t]), fixed(oursMs, 2),
                 bullet ? fixed(theirMs, 2) : dash, bullet ? fixed(ratio, 2) : dash,
                 bullet ? fixed(oursCpuMs / theirCpuMs, 2) : dash,
                 bullet ? (ratio <= kTarget ? "met" : "NOT met") : dash,
                 stretchCell(m.finite, m.largestStretch, m.meanStretch),
                 bullet ? stretchCell(other.finite, other.largestStretch, other.meanStretch) : dash, sci(m.deepest),
                 bullet ? sci(other.deepest) : dash},
                widths);
            csv << n << ",ours," << threadCounts[t] << ',' << runs << ',' << oursMs << ',' << oursCpuMs << ','
                << m.largestStretch << ',' << m.meanStretch << ',' << m.deepest << ',' << m.finite << '\n';
            dat << ' ' << oursMs;
        }
        if (const double bareMs = gpl::study::bareSweepsMs(drop, kBareRepeats); bareMs > 0.0) {
            dat << ' ' << bareMs;
            csv << n << ",bare XPBD sweeps,1," << kBareRepeats << ',' << bareMs << ",,,,,\n";
            std::ostringstream line;
            line << "  " << n << " x " << n << ": " << fixed(bareMs, 2) << " ms";
            if (bullet) {
                line << ", " << fixed(bareMs / theirMs, 2) << " of Bullet's step; on two threads at best "
                     << fixed(0.5 * bareMs / theirMs, 2);
            }
            bareLines.push_back(line.str());
        }
        dat << '\n';
    }
    if (!bareLines.empty()) {
        std::cout << "bare XPBD sweeps (an instructor's tree: bench/instructor/bare_xpbd.cpp): the step's "
                  << drop.iterations << " sweeps of the cloth's links as the reference solveDistanceConstraint() "
                  << "computes them, written out in place, on one thread from the cloth half way through the drop; "
                  << "no hooks, contacts or threads: the method's own work, which two threads can at best halve "
                  << "(median of " << kBareRepeats << " runs)\n";
        for (const std::string& line : bareLines) std::cout << line << '\n';
    }
    std::cout << "target: this engine's time per step at most " << kTarget << " of Bullet's" << std::endl;
}

}  // namespace

int main(int argc, char** argv) {
#ifdef __GLIBC__
    // Each run's large arrays (a cloth's particles and links, in either engine) come fresh from the
    // system, as in the first round. With glibc's own threshold, which rises at the first large free,
    // later rounds take theirs from a heap the engine before them left behind, and both engines'
    // steps run slower there than in the first round: the rounds would then time the heap, not the
    // engines.
    mallopt(M_MMAP_THRESHOLD, 128 * 1024);
#endif
    CLI::App app{
        "The cloth study: PBD and XPBD stretch, cost and stability, and the cloth beside Bullet (./lab bench cloth)"};
    std::string out = "build/cloth";
    bool skipBullet = false;
    int runs = 3;
    std::vector<int> sizes{64, 128};
    std::vector<int> threadCounts{1, 2};
    std::string partList = "stretch,cost,flag,bullet";
    app.add_option("--out", out, "folder for the CSV files and the plots' data (default build/cloth)");
    app.add_option("--parts", partList, "parts to run, separated by commas: stretch, cost, flag, bullet (default all)")
        ->check(gpl::cli::expects("stretch, cost, flag or bullet, separated by commas", [](const std::string& text) {
            const std::vector<std::string> names = split(text);
            return !names.empty() && std::all_of(names.begin(), names.end(), [](const std::string& n) {
                return std::find(kParts.begin(), kParts.end(), n) != kParts.end();
            });
        }));
    app.add_option("--sizes", sizes, "particles along a side of the dropped cloth (default 64 128)")
        ->check(gpl::cli::wholeNumber(2, 1024));
    app.add_option("--threads", threadCounts,
                   "this engine's thread counts on the dropped cloth, each run in every round (default 1 2)")
        ->check(gpl::cli::wholeNumber(1, 2));
    app.add_option("--runs", runs, "runs of each engine on each drop, taking turns; the median is kept (default 3)")
        ->check(gpl::cli::wholeNumber(1, 99));
    app.add_flag("--no-bullet", skipBullet, "this engine only");
    if (const int status = gpl::cli::parse(app, argc, argv); status >= 0) return status;
    if (const std::string error = gpl::cli::makeFolder("--out", out); !error.empty()) {
        std::cerr << "error: " << error << '\n';
        return 2;
    }
    const std::vector<std::string> parts = split(partList);
    const auto wanted = [&parts](const char* part) {
        return std::find(parts.begin(), parts.end(), part) != parts.end();
    };
    const bool bullet = gpl::bench::hasBulletCloth() && !skipBullet;
    const std::vector<ClothMethod> methods = gpl::study::clothMethods();
    try {
        Output output(out);
        std::cout << "the cloth study, with the " << gpl::study::kHookVariant
                  << " hooks (solveDistanceConstraint(), projectParticleSphere())\n\n";
        if (wanted("stretch")) stretchPart(output, methods);
        if (wanted("cost")) costPart(output);
        if (wanted("flag")) flagPart(output);
        if (wanted("bullet")) {
            bulletPart(output, sizes, threadCounts, runs, bullet, skipBullet ? "--no-bullet" : "built without Bullet");
        }
        std::cout << "\nwrote";
        for (const std::string& f : output.written()) std::cout << ' ' << out << '/' << f;
        std::cout << '\n';
    } catch (const std::exception& e) {
        std::cerr << "gpl-bench-cloth: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
