// gpl-bench-contacts: the speed-versus-accuracy study of contacts (./lab bench contacts). Prints
// tables, writes CSV files and the data files that bench/contacts.gp turns into plots.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "command_line.h"
#include "contacts.h"
#include "report.h"

namespace {

namespace study = gpl::study;
using study::fixed;
using study::Output;
using study::pad;
using study::Response;
using study::sci;

constexpr Response kResponses[] = {Response::Positions, Response::Impulses};
constexpr int kIterations[] = {1, 2, 4, 8, 10, 16, 32, 64};  // 10: the engine's default
constexpr int kPhases = 64;                                  // start phases per speed in the tunnelling experiments

bool has(const std::vector<Response>& responses, Response r) {
    return std::find(responses.begin(), responses.end(), r) != responses.end();
}

// The hooks of `needed` that are still stubs, as " a() b()"; empty when all are written.
std::string missing(const std::vector<std::string>& needed, const std::vector<std::string>& open) {
    std::string list;
    for (const std::string& h : needed) {
        if (std::find(open.begin(), open.end(), h) != open.end()) list += " " + h;
    }
    return list;
}

// Runs one experiment over the responses it wants whose hooks are written; names the hooks that
// keep the others from running, and says why the experiment failed when it does.
void experiment(const std::string& title, const std::vector<Response>& wanted, const std::vector<std::string>& open,
                const std::function<void(const std::vector<Response>&)>& body) {
    std::cout << "\n" << title << '\n';
    std::vector<Response> can;
    for (Response r : wanted) {
        if (missing(study::hooksNeeded(r), open).empty()) can.push_back(r);
    }
    if (can.empty()) {
        std::cout << "  skipped: needs" << missing(study::hooksNeeded(wanted.front()), open)
                  << " (not implemented yet)\n";
        return;
    }
    for (Response r : wanted) {
        const std::string m = missing(study::hooksNeeded(r), open);
        if (!m.empty())
            std::cout << "  " << study::responseName(r) << ": skipped, needs" << m << " (not implemented yet)\n";
    }
    try {
        body(can);
    } catch (const std::exception& e) {
        std::cout << "  failed: " << e.what() << '\n';
    }
}

void pile(Output& out, const std::vector<Response>& responses) {
    std::ofstream csv = out.open("pile-iterations.csv");
    csv << "response,iterations,contacts_per_step,found_depth_m,mean_depth_m,largest_depth_m,largest_any_pair_m,"
           "mean_approach_m_s,largest_approach_m_s,ns_per_step\n";
    std::ofstream dat = out.open("pile-iterations.dat");
    dat << "# one block per response (positions, impulses): iterations found_mm mean_mm largest_mm any_pair_mm "
           "mean_approach largest_approach us_per_step\n";
    for (Response r : kResponses) {
        dat << "# " << study::responseName(r) << '\n';
        if (!has(responses, r)) {
            dat << "\n\n";
            continue;
        }
        const bool impulses = r == Response::Impulses;
        std::cout << "  " << study::responseName(r) << ": overlap in mm" << (impulses ? ", approach speed in m/s" : "")
                  << "; after the step unless 'found'\n";
        std::cout << "  " << pad("iterations", 12) << pad("contacts", 10) << pad("found", 8) << pad("mean", 10)
                  << pad("largest", 10) << pad("any pair", 10);
        if (impulses) std::cout << pad("approach mean", 15) << pad("largest", 10);
        std::cout << "us/step\n";
        for (int k : kIterations) {
            const study::PileRun p = study::pileWithIterations(r, k);
            std::cout << "  " << pad(std::to_string(k), 12) << pad(fixed(p.contactsPerStep, 1), 10)
                      << pad(fixed(1e3 * p.foundDepth, 2), 8) << pad(sci(1e3 * p.meanDepth, 1), 10)
                      << pad(sci(1e3 * p.largestDepth, 1), 10) << pad(fixed(1e3 * p.largestAnyPair, 1), 10);
            if (impulses) std::cout << pad(sci(p.meanApproach, 1), 15) << pad(sci(p.largestApproach, 1), 10);
            std::cout << fixed(1e-3 * p.nsPerStep, 1) << '\n';
            csv << study::responseName(r) << ',' << k << ',' << p.contactsPerStep << ',' << p.foundDepth << ','
                << p.meanDepth << ',' << p.largestDepth << ',' << p.largestAnyPair << ',' << p.meanApproach << ','
                << p.largestApproach << ',' << p.nsPerStep << '\n';
            dat << k << ' ' << 1e3 * p.foundDepth << ' ' << 1e3 * p.meanDepth << ' ' << 1e3 * p.largestDepth << ' '
                << 1e3 * p.largestAnyPair << ' ' << p.meanApproach << ' ' << p.largestApproach << ' '
                << 1e-3 * p.nsPerStep << '\n';
        }
        dat << "\n\n";
    }
}

void tunnellingLimit(Output& out, const std::vector<Response>& responses) {
    struct Pair {
        double ra, rb;
    };
    const Pair pairs[] = {{0.01, 0.01}, {0.01, 0.1}, {0.1, 0.1}, {0.1, 1.0}};
    const double steps[] = {0.0005, 0.001, 0.002, 0.005, 0.01, 0.02, 0.05};
    std::ofstream csv = out.open("tunnelling-limit.csv");
    csv << "response,ra_m,rb_m,h_s,v_max_m_s,theory_m_s,reach_over_h_m_s\n";
    std::ofstream dat = out.open("tunnelling-limit.dat");
    dat << "# one block per pair of radii: h v_max theory (r_a + r_b)/h (the first response measured: "
        << study::responseName(responses.front()) << ")\n";
    std::cout << "  " << pad("r_a (m)", 9) << pad("r_b (m)", 9) << pad("h (s)", 9);
    for (Response r : responses) std::cout << pad(std::string("v_max, ") + study::responseName(r), 21);
    std::cout << pad("theory (m/s)", 14) << pad("rel. diff.", 12) << "(r_a+r_b)/h\n";
    for (const Pair& p : pairs) {
        dat << "# r_a = " << p.ra << " m, r_b = " << p.rb << " m\n";
        for (double h : steps) {
            const double theory = study::theoreticalSafeSpeed(p.ra, p.rb, h, kPhases);
            const double simple = (p.ra + p.rb) / h;
            std::vector<double> measured;
            for (Response r : responses) {
                measured.push_back(study::largestSafeSpeed(r, p.ra, p.rb, h, kPhases));
                csv << study::responseName(r) << ',' << p.ra << ',' << p.rb << ',' << h << ',' << measured.back() << ','
                    << theory << ',' << simple << '\n';
            }
            dat << h << ' ' << measured.front() << ' ' << theory << ' ' << simple << '\n';
            if (h != 0.001 && h != 0.01 && h != 0.05) continue;  // the CSV has every step
            std::cout << "  " << pad(fixed(p.ra, 2), 9) << pad(fixed(p.rb, 2), 9) << pad(fixed(h, 3), 9);
            double worst = 0.0;
            for (double m : measured) {
                std::cout << pad(fixed(m, 3), 21);
                if (std::abs(m - theory) >= std::abs(worst)) worst = m - theory;
            }
            std::cout << pad(fixed(theory, 3), 14) << pad(sci(worst / theory, 1), 12) << fixed(simple, 3) << '\n';
        }
        dat << "\n\n";
    }
}

void tunnelFractions(Output& out, const std::vector<Response>& responses) {
    const double ra = 0.05, rb = 0.05, h = 0.01, reach = ra + rb;
    std::ofstream csv = out.open("tunnel-fraction.csv");
    csv << "response,v_h_over_reach,speed_m_s,measured,theory\n";
    std::ofstream dat = out.open("tunnel-fraction.dat");
    dat << "# one block per response (positions, impulses): v h / (r_a + r_b), fraction of " << kPhases
        << " start phases that tunnel, theory\n";
    std::vector<int> percents;  // 100 v h / R: fine steps up to 2.5, where the curves bend, coarse ones to 8
    for (int p = 25; p <= 250; p += 5) percents.push_back(p);
    for (int p = 260; p <= 800; p += 20) percents.push_back(p);
    std::map<Response, std::map<int, std::pair<double, double>>> shown;  // by percent: measured, theory
    for (Response r : kResponses) {
        dat << "# " << study::responseName(r) << '\n';
        for (int percent : percents) {
            if (!has(responses, r)) break;
            const double x = percent / 100.0, v = x * reach / h;
            const double measured = study::tunnelFraction(r, ra, rb, v, h, kPhases);
            const double theory = study::theoreticalTunnelFraction(r, ra, rb, v, h, kPhases);
            csv << study::responseName(r) << ',' << x << ',' << v << ',' << measured << ',' << theory << '\n';
            dat << x << ' ' << measured << ' ' << theory << '\n';
            shown[r][percent] = {measured, theory};
        }
        dat << "\n\n";
    }
    std::cout << "  " << pad("v h/R", 8) << pad("v (m/s)", 10);
    for (Response r : responses) std::cout << pad(std::string(study::responseName(r)) + " (theory)", 22);
    std::cout << '\n';
    for (int percent : {50, 100, 105, 150, 200, 400, 800}) {
        std::cout << "  " << pad(fixed(percent / 100.0, 2), 8) << pad(fixed(percent * reach / h / 100.0, 1), 10);
        for (Response r : responses) {
            const auto [measured, theory] = shown[r][percent];
            std::cout << pad(fixed(measured, 4) + " (" + fixed(theory, 4) + ")", 22);
        }
        std::cout << '\n';
    }
}

// One table of the columns: a row per number of spheres, a cell per number of sweeps.
void columnTable(const std::string& title, const std::vector<std::vector<study::Column>>& table,
                 const std::function<std::string(const study::Column&)>& cell, bool oneSweepTheory) {
    std::cout << "  " << title << "; 'through': spheres passed through each other\n";
    std::cout << "  " << pad("spheres", 9);
    for (int k : kIterations) std::cout << pad(std::to_string(k) + " it.", 10);
    if (oneSweepTheory) std::cout << "theory 1 it.";
    std::cout << '\n';
    for (const auto& row : table) {
        std::cout << "  " << pad(std::to_string(row.front().spheres), 9);
        for (const study::Column& c : row) std::cout << pad(c.passedThrough ? "through" : cell(c), 10);
        if (oneSweepTheory) std::cout << fixed(1e3 * study::theoreticalOneSweepSink(row.front().spheres), 2);
        std::cout << '\n';
    }
}

void columns(Output& out, const std::vector<Response>& responses) {
    std::ofstream csv = out.open("resting-column.csv");
    csv << "response,spheres,iterations,jitter_m,sink_m,largest_overlap_m,largest_speed_m_s,passed_through\n";
    std::ofstream dat = out.open("resting-column.dat");
    dat << "# blocks: response (positions, impulses) x spheres (2, 3, 5, 10): iterations sink_mm largest_speed "
           "jitter_mm passed_through\n";
    for (Response r : kResponses) {
        std::vector<std::vector<study::Column>> table;
        for (int n = 1; n <= 10 && has(responses, r); ++n) {
            table.emplace_back();
            for (int k : kIterations) {
                const study::Column c = study::restingColumn(r, n, k);
                table.back().push_back(c);
                csv << study::responseName(r) << ',' << n << ',' << k << ',' << c.jitter << ',' << c.sink << ','
                    << c.largestOverlap << ',' << c.largestSpeed << ',' << c.passedThrough << '\n';
            }
        }
        for (int n : {2, 3, 5, 10}) {
            dat << "# " << study::responseName(r) << ", " << n << " spheres\n";
            if (!table.empty()) {
                for (const study::Column& c : table[n - 1]) {
                    dat << c.iterations << ' ' << 1e3 * c.sink << ' ' << c.largestSpeed << ' ' << 1e3 * c.jitter << ' '
                        << c.passedThrough << '\n';
                }
            }
            dat << "\n\n";
        }
        if (table.empty()) continue;
        const bool positions = r == Response::Positions;
        columnTable(
            std::string(study::responseName(r)) + ": sink of the top sphere (mm)", table,
            [](const study::Column& c) { return fixed(1e3 * c.sink, 2); }, positions);
        if (!positions) {
            columnTable(
                "impulses: largest speed of a sphere at the end of a step (m/s)", table,
                [](const study::Column& c) { return sci(c.largestSpeed, 1); }, false);
        }
        const study::Column* worst = &table.front().front();
        for (const auto& row : table) {
            for (const study::Column& c : row) {
                if (!c.passedThrough && c.jitter > worst->jitter) worst = &c;
            }
        }
        std::cout << "  " << study::responseName(r) << ": largest jitter (peak to peak of the top sphere) "
                  << sci(1e3 * worst->jitter) << " mm, " << worst->spheres << " spheres, " << worst->iterations
                  << " it.\n";
    }
}

std::string ratioName(double bottom, double top) { return fixed(bottom, 0) + ":" + fixed(top, 0); }

void massRatios(Output& out, const std::vector<Response>& responses) {
    const double ratios[] = {1.0, 10.0, 100.0, 1000.0};
    // Bottom and top masses (kg): heavy on light, then light on heavy.
    std::vector<std::pair<double, double>> stacks;
    for (double ratio : ratios) stacks.push_back({1.0, ratio});
    for (double ratio : ratios) {
        if (ratio > 1.0) stacks.push_back({ratio, 1.0});
    }

    std::ofstream csv = out.open("mass-ratio-stage.csv");
    csv << "response,bottom_kg,top_kg,iterations,residual,theory\n";
    std::ofstream dat = out.open("mass-ratio-stage.dat");
    dat << "# blocks: response (positions, impulses) x heavy on light 1:1, 1:10, 1:100, 1:1000: iterations "
           "residual/initial theory/initial\n";
    const int sweeps[] = {1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024};
    for (Response r : responses) {
        const bool positions = r == Response::Positions;
        const double unit = positions ? 2e-3 : 1.0;  // what the stage starts from: 2 mm, 1 m/s
        std::cout << "  one " << (positions ? "interpenetration" : "impulse")
                  << " stage alone on two spheres on a plane: what is left of the lower sphere's "
                  << (positions ? "overlap with the plane (start: 2 mm)" : "approach to the plane (start: 1 m/s)")
                  << ", as a fraction; theory rho^k\n";
        std::cout << "  " << pad("bottom:top", 12) << pad("rho", 10);
        for (int k : {1, 10, 100, 1000}) std::cout << pad(std::to_string(k) + " it. (theory)", 23);
        std::cout << "sweeps for 99 %\n";
        for (const auto& [bottom, top] : stacks) {
            const double rho = top / (bottom + top);
            std::cout << "  " << pad(ratioName(bottom, top), 12) << pad(fixed(rho, 6), 10);
            for (int k : {1, 10, 100, 1000}) {
                const double measured = study::twoSphereResidual(r, bottom, top, k) / unit;
                const double theory = study::theoreticalTwoSphereResidual(r, bottom, top, k) / unit;
                std::cout << pad(sci(measured, 2) + " (" + sci(theory, 2) + ")", 23);
            }
            std::cout << fixed(std::ceil(std::log(0.01) / std::log(rho)), 0) << '\n';
            const bool plotted = bottom == 1.0;
            if (plotted) dat << "# " << study::responseName(r) << ", " << ratioName(bottom, top) << '\n';
            for (int k : sweeps) {
                const double measured = study::twoSphereResidual(r, bottom, top, k);
                const double theory = study::theoreticalTwoSphereResidual(r, bottom, top, k);
                csv << study::responseName(r) << ',' << bottom << ',' << top << ',' << k << ',' << measured << ','
                    << theory << '\n';
                if (plotted) dat << k << ' ' << measured / unit << ' ' << theory / unit << '\n';
            }
            if (plotted) dat << "\n\n";
        }
    }

    std::cout << "  two spheres (0.25 m) resting on a plane for 10 s, 10 iterations (the engine's default); over the "
                 "last 5 s; theory q g h^2/(1 - q) (positions), q g h^2/(1 - q)^2 and q g h/(1 - q) (impulses), "
                 "q = rho^10\n";
    std::cout << "  " << pad("response", 11) << pad("bottom:top", 12) << pad("sink (mm) (theory)", 24)
              << pad("speed (m/s) (theory)", 24) << pad("jitter (mm)", 13) << "passed through\n";
    std::ofstream stack = out.open("mass-ratio-stack.csv");
    stack << "response,bottom_kg,top_kg,iterations,jitter_m,sink_m,theory_sink_m,largest_overlap_m,largest_speed_m_s,"
             "theory_speed_m_s,passed_through\n";
    for (Response r : responses) {
        for (const auto& [bottom, top] : stacks) {
            const study::Column c = study::restingColumn(r, {bottom, top}, 10);
            const double sink = study::theoreticalStackSink(r, bottom, top, 10);
            const double speed = study::theoreticalStackSpeed(r, bottom, top, 10);
            stack << study::responseName(r) << ',' << bottom << ',' << top << ",10," << c.jitter << ',' << c.sink << ','
                  << sink << ',' << c.largestOverlap << ',' << c.largestSpeed << ',' << speed << ',' << c.passedThrough
                  << '\n';
            // The closed forms hold while the light sphere's centre stays above the plane (0.25 m).
            const bool holds = sink < 0.25;
            std::cout << "  " << pad(study::responseName(r), 11) << pad(ratioName(bottom, top), 12)
                      << pad(sci(1e3 * c.sink) + " (" + (holds ? sci(1e3 * sink) : std::string("too deep")) + ")", 24)
                      << pad(sci(c.largestSpeed) + " (" + (holds ? sci(speed) : std::string("-")) + ")", 24)
                      << pad(fixed(1e3 * c.jitter, 3), 13) << (c.passedThrough ? "YES" : "no") << '\n';
        }
    }
}

void fastAndSmall(Output& out) {
    const double radii[] = {0.001, 0.01, 0.1, 1.0};
    const double speeds[] = {1.0, 10.0, 100.0, 1000.0};
    std::ofstream csv = out.open("fast-small.csv");
    csv << "radius_m,speed_m_s,v_h_over_reach,sphere_fraction,theory_fraction,plane_fraction,largest_energy_ratio,"
           "finite\n";
    std::ofstream dat = out.open("fast-small.dat");
    dat << "# v h / (r_a + r_b), fraction of start phases through the sphere, theory\n";
    std::cout << "  h = 0.01 s, equal radii; cell: fraction of " << kPhases
              << " start phases through the sphere (theory) | through the plane\n";
    std::cout << "  " << pad("radius", 9);
    for (double v : speeds) std::cout << pad(fixed(v, 0) + " m/s", 24);
    std::cout << '\n';
    double worstEnergy = 0.0;
    bool allFinite = true;
    for (double r : radii) {
        std::cout << "  " << pad(fixed(1e3 * r, 0) + " mm", 9);
        for (double v : speeds) {
            const study::Extreme x = study::fastSmall(r, v, kPhases);
            csv << r << ',' << v << ',' << x.stepOverR << ',' << x.sphereFraction << ',' << x.theoryFraction << ','
                << x.planeFraction << ',' << x.largestEnergyRatio << ',' << x.finite << '\n';
            dat << x.stepOverR << ' ' << x.sphereFraction << ' ' << x.theoryFraction << '\n';
            std::cout << pad(
                fixed(x.sphereFraction, 2) + " (" + fixed(x.theoryFraction, 2) + ") | " + fixed(x.planeFraction, 2),
                24);
            worstEnergy = std::max(worstEnergy, x.largestEnergyRatio);
            allFinite = allFinite && x.finite;
        }
        std::cout << '\n';
    }
    std::cout << "  every state finite: " << (allFinite ? "yes" : "NO") << "; largest kinetic energy after a shot / "
              << "before: " << fixed(worstEnergy, 12) << '\n';

    std::cout << "  a column of three spheres resting for 10 s (impulses, 10 iterations), in units of the radius\n";
    std::cout << "  " << pad("radius", 9) << pad("g h^2 / r", 11) << pad("jitter / r", 12) << pad("sink / r", 12)
              << pad("overlap / r", 13) << "passed through\n";
    std::ofstream small = out.open("small-column.csv");
    small << "radius_m,jitter_m,sink_m,largest_overlap_m,largest_speed_m_s,passed_through\n";
    for (double r : radii) {
        const study::Column c = study::restingColumn(Response::Impulses, {1.0, 1.0, 1.0}, 10, r);
        small << r << ',' << c.jitter << ',' << c.sink << ',' << c.largestOverlap << ',' << c.largestSpeed << ','
              << c.passedThrough << '\n';
        std::cout << "  " << pad(fixed(1e3 * r, 0) + " mm", 9) << pad(sci(9.81e-4 / r, 1), 11)
                  << pad(sci(c.jitter / r), 12) << pad(sci(c.sink / r), 12) << pad(sci(c.largestOverlap / r), 13)
                  << (c.passedThrough ? "YES" : "no") << '\n';
    }
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"The speed-versus-accuracy study of contacts: iterations, tunnelling, resting stacks, mass ratios."};
    std::string outDir = "build/contacts";
    app.add_option("--out", outDir, "folder for the CSV and plot data files");
    if (const int status = gpl::cli::parse(app, argc, argv); status >= 0) return status;
    if (const std::string error = gpl::cli::makeFolder("--out", outDir); !error.empty()) {
        std::cerr << "error: " << error << '\n';
        return 2;
    }

    const auto start = std::chrono::steady_clock::now();
    try {
        Output out(outDir);
        const std::vector<std::string> open = study::openContactHooks();
        std::cout << "contacts study with the hooks of " << study::kHookVariant << "/";
        if (open.empty()) {
            std::cout << ": every hook it needs is written\n";
        } else {
            std::cout << "; hooks not implemented yet:";
            for (const std::string& h : open) std::cout << ' ' << h;
            std::cout << "\n(what needs them is skipped; 'positions' is worksheet 3, 'impulses' worksheet 4)\n";
        }
        const std::vector<Response> both(std::begin(kResponses), std::end(kResponses));
        const std::vector<Response> impulses = {Response::Impulses};

        experiment(
            "1. resolution iterations on a pile: balls-in-a-box (45 balls, 5 planes, h = 0.01 s), measured "
            "after every step from 3 s to 4 s",
            both, open, [&](const auto& rs) { pile(out, rs); });
        experiment("2. largest speed that does not tunnel: a ball shot head-on at a static sphere, " +
                       std::to_string(kPhases) + " start phases; theory (r_a + r_b) / (h (1 - 1/" +
                       std::to_string(2 * kPhases) + "))",
                   both, open, [&](const auto& rs) { tunnellingLimit(out, rs); });
        experiment(
            "   fraction of start phases that tunnel against v h / R, R = r_a + r_b = 10 cm, h = 0.01 s; theory "
            "1 - R/(v h) with impulses, min(1, 2 (1 - R/(v h))) with positions (the step after the push)",
            both, open, [&](const auto& rs) { tunnelFractions(out, rs); });
        experiment(
            "3. resting contact: a column of spheres (0.25 m, 1 kg, restitution 0) placed at rest on a plane, 10 s, "
            "measured over the last 5 s",
            both, open, [&](const auto& rs) { columns(out, rs); });
        experiment("4. mass ratios 1:1 to 1:1000, heavy on light and light on heavy (masses bottom:top)", both, open,
                   [&](const auto& rs) { massRatios(out, rs); });
        experiment("5. very fast and very small bodies: radius 1 mm to 1 m, speed 1 to 1000 m/s", impulses, open,
                   [&](const auto&) { fastAndSmall(out); });

        if (out.written().empty()) {
            std::cout << "\nnothing was measured, nothing written\n";
        } else {
            std::cout << "\nwrote to " << outDir << ":";
            for (const std::string& f : out.written()) std::cout << ' ' << f;
            std::cout << '\n';
        }
    } catch (const std::exception& e) {
        std::cerr << "error: " << e.what() << '\n';
        return 2;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "study took " << fixed(seconds, 1) << " s\n";
    return 0;
}
