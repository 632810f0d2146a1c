// gpl-bench: the speed-versus-accuracy study (./lab bench accuracy). Prints tables, writes CSV
// files and the data files that bench/accuracy.gp turns into plots.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>

#include "command_line.h"
#include "gpl/body.h"
#include "gpl/engine.h"
#include "report.h"
#include "study.h"

namespace {

using gpl::Integrator;
using gpl::kIntegrators;
namespace study = gpl::study;
using study::fixed;
using study::Output;
using study::pad;
using study::sci;

// The integrators the study measures: every one whose hook is written (study::openIntegrators()).
using Methods = std::vector<Integrator>;

struct Sweep {
    study::Problem problem;
    Methods methods;
    std::map<Integrator, std::vector<study::Run>> runs;
    std::map<Integrator, study::Order> orders;
};

Sweep sweep(const study::Problem& p, const Methods& methods) {
    Sweep s{p, methods, {}, {}};
    for (Integrator m : methods) {
        for (std::size_t n : p.steps) s.runs[m].push_back(study::simulate(p, m, n, true));
        s.orders[m] = study::measuredOrder(p, s.runs[m]);
    }
    return s;
}

const study::Run& runWith(const Sweep& s, Integrator m, std::size_t steps) {
    for (const study::Run& r : s.runs.at(m)) {
        if (r.steps == steps) return r;
    }
    return s.runs.at(m).front();
}

void printSweep(const Sweep& s) {
    const auto& p = s.problem;
    const std::size_t n1 = p.steps[p.steps.size() / 4], n2 = p.steps[p.steps.size() / 2],
                      n3 = p.steps[3 * p.steps.size() / 4];
    std::cout << "\n"
              << p.id << ": " << p.title << "; error at T = " << fixed(p.endTime, 4) << " s in " << p.unit
              << " (state error, see README)\n";
    std::cout << pad("integrator", 21) << pad("order (theory)", 16) << pad("err N=" + std::to_string(n1), 13)
              << pad("err N=" + std::to_string(n2), 13) << pad("err N=" + std::to_string(n3), 13)
              << pad("max|dE/E| N=" + std::to_string(n2), 18) << pad("evals/step", 11) << "ns/step\n";
    for (Integrator m : s.methods) {
        const study::Order& o = s.orders.at(m);
        // No run in the asymptotic window: all at rounding (exact) or all still above 1e-2 of the scale.
        const bool exact = runWith(s, m, n1).error < 1e-9 * p.scale;
        const std::string order = o.points ? fixed(o.slope, 2) : exact ? std::string("exact") : std::string("-");
        std::cout << pad(gpl::integratorName(m), 21)
                  << pad(order + " (" + std::to_string(gpl::theoreticalOrder(m)) + ")", 16)
                  << pad(sci(runWith(s, m, n1).error), 13) << pad(sci(runWith(s, m, n2).error), 13)
                  << pad(sci(runWith(s, m, n3).error), 13) << pad(sci(runWith(s, m, n2).energyMax), 18)
                  << pad(fixed(runWith(s, m, n2).evaluationsPerStep, 0), 11)
                  << fixed(1e9 * runWith(s, m, n2).secondsPerStep, 1) << '\n';
    }
}

void writeSweep(Output& out, std::ofstream& csv, std::ofstream& orders, const Sweep& s) {
    const auto& p = s.problem;
    std::ofstream dat = out.open("sweep-" + p.id + ".dat");
    dat << "# one block per integrator measured (methods.gp lists them): h error evaluations seconds energy_max\n";
    for (Integrator m : s.methods) {
        dat << "# " << gpl::integratorId(m) << '\n';
        for (const study::Run& r : s.runs.at(m)) {
            csv << p.id << ',' << gpl::integratorId(m) << ',' << r.steps << ',' << r.h << ',' << r.h * p.omega << ','
                << r.error << ',' << r.energyMax << ',' << r.energyDrift << ',' << r.evaluationsPerStep << ','
                << r.secondsPerStep * 1e9 << '\n';
            if (!r.finite || !(r.error > 0.0)) continue;
            dat << r.h << ' ' << r.error << ' ' << r.evaluationsPerStep * static_cast<double>(r.steps) << ' '
                << r.secondsPerStep * static_cast<double>(r.steps) << ' ' << r.energyMax << '\n';
        }
        dat << "\n\n";
        const study::Order& o = s.orders.at(m);
        const bool exact = s.runs.at(m).front().error < 1e-9 * p.scale;
        orders << p.id << ',' << gpl::integratorId(m) << ',' << gpl::theoreticalOrder(m) << ','
               << (o.points ? std::to_string(o.slope)
                   : exact  ? std::string("exact")
                            : std::string("n/a"))
               << ',' << o.points << '\n';
    }
}

// Reference lines C h^p for the error-vs-h plots, through the finest run of the first method of order p,
// and each problem's unit of errors for the plots' axes.
void writeAnchors(Output& out, const std::vector<Sweep>& sweeps) {
    std::ofstream gp = out.open("anchors.gp");
    for (const Sweep& s : sweeps) {
        std::string id = s.problem.id;
        for (char& ch : id) ch = ch == '-' ? '_' : ch;
        gp << "unit_" << id << " = '" << s.problem.unit << "'\n";
        for (int order : {1, 2, 4}) {
            double c = 0.0;
            for (Integrator m : s.methods) {
                if (gpl::theoreticalOrder(m) != order || !s.orders.at(m).points || c != 0.0) continue;
                for (const study::Run& r : s.runs.at(m)) {
                    if (r.finite && r.error > 0.0 && r.error < 1e-2 * s.problem.scale) {
                        c = r.error / std::pow(r.h, order);
                        break;
                    }
                }
            }
            gp << "c" << order << "_" << id << " = " << std::setprecision(10) << (c > 0 ? c : 0.0) << '\n';
        }
    }
}

// The integrators whose blocks the data files hold, in order, as positions in accuracy.gp's list of
// names (the order of gpl::kIntegrators): measured = "0 1 4" when the Verlet hooks are open.
void writeMethods(Output& out, const Methods& methods) {
    std::ofstream gp = out.open("methods.gp");
    gp << "measured = \"";
    for (std::size_t i = 0; i < methods.size(); ++i) {
        gp << (i ? " " : "") << std::find(kIntegrators.begin(), kIntegrators.end(), methods[i]) - kIntegrators.begin();
    }
    gp << "\"\n";
}

void cheapest(const Sweep& s, double target, std::ofstream& csv) {
    std::cout << "\ncheapest way to an error below " << sci(target, 0) << " " << s.problem.unit << " on "
              << s.problem.id << " (runs of the sweep):\n";
    std::cout << pad("integrator", 21) << pad("steps", 8) << pad("h (s)", 11) << pad("error", 11)
              << pad("force evals", 13) << "wall time (us)\n";
    Integrator byEvals = Integrator::ExplicitEuler, byTime = Integrator::ExplicitEuler;
    double bestEvals = INFINITY, bestTime = INFINITY;
    for (Integrator m : s.methods) {
        const study::Run* pick = nullptr;
        for (const study::Run& r : s.runs.at(m)) {
            if (r.finite && r.error <= target) {
                pick = &r;
                break;
            }
        }
        if (!pick) {
            std::cout << pad(gpl::integratorName(m), 21) << "not reached with " << s.problem.steps.back() << " steps\n";
            csv << s.problem.id << ',' << target << ',' << gpl::integratorId(m) << ",,,,,\n";
            continue;
        }
        const double evals = pick->evaluationsPerStep * static_cast<double>(pick->steps);
        const double seconds = pick->secondsPerStep * static_cast<double>(pick->steps);
        std::cout << pad(gpl::integratorName(m), 21) << pad(std::to_string(pick->steps), 8) << pad(sci(pick->h), 11)
                  << pad(sci(pick->error), 11) << pad(fixed(evals, 0), 13) << fixed(1e6 * seconds, 1) << '\n';
        csv << s.problem.id << ',' << target << ',' << gpl::integratorId(m) << ',' << pick->steps << ',' << pick->h
            << ',' << pick->error << ',' << evals << ',' << seconds << '\n';
        if (evals < bestEvals) bestEvals = evals, byEvals = m;
        if (seconds < bestTime) bestTime = seconds, byTime = m;
    }
    std::cout << "cheapest: " << gpl::integratorName(byEvals) << " by force evaluations, "
              << gpl::integratorName(byTime) << " by wall time\n";
}

void stability(Output& out, const Methods& methods) {
    std::cout << "\nstability: largest stable h*omega on the undamped oscillator (sweep, then bisection)\n";
    std::cout << pad("integrator", 21) << pad("measured", 12) << pad("theory", 12) << "difference\n";
    std::ofstream csv = out.open("stability.csv");
    csv << "integrator,measured_h_omega,theory_h_omega\n";
    const study::Problem p = study::oscillator(1.0);
    for (Integrator m : methods) {
        const double measured = study::stabilityLimit(p, m);
        const double theory = study::theoreticalStabilityLimit(m);
        csv << gpl::integratorId(m) << ',' << measured << ',' << theory << '\n';
        std::cout << pad(gpl::integratorName(m), 21);
        if (theory == 0.0) {
            std::cout << pad(measured == 0.0 ? "none" : fixed(measured, 4), 12) << pad("none", 12)
                      << (measured == 0.0 ? "energy grows at every h*omega tried, down to 0.001" : "DISAGREES") << '\n';
        } else {
            std::cout << pad(fixed(measured, 4), 12) << pad(fixed(theory, 4), 12) << std::showpos
                      << fixed(100.0 * (measured - theory) / theory, 3) << std::noshowpos << " %\n";
        }
    }
}

void longHorizon(Output& out, const Methods& methods) {
    const std::size_t steps = 1000000;
    std::cout << "\nlong horizon: " << steps << " steps, energy E_end/E_0 and largest |E/E_0 - 1|\n";
    std::ofstream csv = out.open("long-horizon.csv");
    csv << "problem,integrator,steps,h,energy_ratio,energy_max,finite\n";
    study::Problem osc = study::oscillator(1.0);
    study::Problem orbit = study::kepler();
    struct Case {
        const study::Problem* p;
        double h;
        const char* label;
    } cases[] = {{&osc, 0.1, "oscillator, h*omega = 0.1 (16 000 periods)"},
                 {&orbit, 2.0 * M_PI / 1000.0, "Kepler e = 0.6, 1000 steps per orbit (1000 orbits)"}};
    for (const Case& c : cases) {
        std::cout << c.label << '\n';
        for (Integrator m : methods) {
            const study::Run r = study::simulateWithStep(*c.p, m, c.h, steps);
            const double ratio = 1.0 + r.energyDrift;
            csv << c.p->id << ',' << gpl::integratorId(m) << ',' << steps << ',' << c.h << ',' << ratio << ','
                << r.energyMax << ',' << r.finite << '\n';
            std::cout << "  " << pad(gpl::integratorName(m), 21)
                      << (r.finite ? "E_end/E_0 = " + fixed(ratio, 9) + "   max |dE/E| = " + sci(r.energyMax)
                                   : std::string("overflowed: the state stopped being finite"))
                      << '\n';
        }
    }
}

void precision(Output& out) {
    std::cout << "\nfloat vs double far from the origin: oscillator centred at the offset, one period, h = 1 ms,"
                 " largest position error (m)\n";
    std::cout << pad("offset (m)", 12) << pad("float", 12) << "double\n";
    std::ofstream csv = out.open("precision.csv");
    csv << "offset_m,error_float_m,error_double_m\n";
    for (double offset : {0.0, 1e3, 1e5, 1e7}) {
        const double f = study::offsetError(offset, true), d = study::offsetError(offset, false);
        csv << offset << ',' << f << ',' << d << '\n';
        std::cout << pad(sci(offset, 0), 12) << pad(sci(f), 12) << sci(d) << '\n';
    }
}

void stepExtremes(Output& out, const Methods& methods) {
    std::cout << "\ntiny and huge steps: oscillator (omega = 2 pi rad/s, 1.3 s), state error (m)\n";
    const study::Problem p = study::oscillator(2.0 * M_PI);
    std::cout << pad("h (s)", 10) << pad("h*omega", 10);
    for (Integrator m : methods) std::cout << pad(gpl::integratorId(m), 21);
    std::cout << '\n';
    std::ofstream csv = out.open("step-extremes.csv");
    csv << "h,h_omega,integrator,error\n";
    for (double h : {1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1.0}) {
        const auto steps = static_cast<std::size_t>(std::max(1.0, std::round(p.endTime / h)));
        const double actual = p.endTime / static_cast<double>(steps);
        std::cout << pad(sci(actual, 1), 10) << pad(sci(actual * p.omega, 1), 10);
        for (Integrator m : methods) {
            const study::Run r = study::simulate(p, m, steps);
            csv << actual << ',' << actual * p.omega << ',' << gpl::integratorId(m) << ',' << r.error << '\n';
            std::cout << pad(sci(r.error), 21);
        }
        std::cout << '\n';
    }
}

void massRatio(Output& out, const Methods& methods) {
    std::cout << "\nmass ratio in a chain of 6 masses and 100 N/m springs: the lightest mass sets the step\n";
    std::ofstream csv = out.open("mass-ratio.csv");
    csv << "masses,omega_max,integrator,limit_h_s,limit_h_omega,theory_h_omega\n";
    const std::vector<double> heavy(6, 1000.0);
    const std::vector<double> ratio = {1.0, 1000.0, 1.0, 1000.0, 1.0, 1000.0};
    for (const auto* masses : {&heavy, &ratio}) {
        const study::Problem p = study::springChain(*masses);
        const std::string label = masses == &heavy ? "all 1000 kg" : "1 and 1000 kg alternating";
        std::cout << "masses " << label << ": omega_max = " << fixed(p.omega, 3) << " rad/s\n";
        for (Integrator m : methods) {
            const double limit = study::stabilityLimit(p, m);
            csv << label << ',' << p.omega << ',' << gpl::integratorId(m) << ',' << limit / p.omega << ',' << limit
                << ',' << study::theoreticalStabilityLimit(m) << '\n';
            std::cout << "  " << pad(gpl::integratorName(m), 21) << "largest stable h = "
                      << (limit > 0 ? sci(limit / p.omega, 3) + " s (h*omega_max = " + fixed(limit, 3) + ")"
                                    : std::string("none"))
                      << '\n';
        }
    }
}

void freeFallEnergy(Output& out, const Methods& methods) {
    std::cout << "\nfree fall, energy change per step and unit mass at h = 0.01 s (theory: explicit Euler "
                 "+g^2h^2/2, semi-implicit -g^2h^2/2, Verlet 0)\n";
    std::ofstream csv = out.open("free-fall-energy.csv");
    csv << "integrator,energy_change_per_step,g2h2_over_2\n";
    const study::Problem p = study::freeFall();
    const double h = 0.01, unit = 0.5 * 9.81 * 9.81 * h * h;
    for (Integrator m : methods) {
        const study::Run r = study::simulateWithStep(p, m, h, 100);
        const double e0 = std::abs(p.energy(p.x0, p.v0));
        const double perStep = r.energyDrift * e0 / 100.0;
        csv << gpl::integratorId(m) << ',' << perStep << ',' << unit << '\n';
        std::cout << "  " << pad(gpl::integratorName(m), 21) << pad(sci(perStep, 6) + " J/kg", 20) << "= "
                  << std::showpos << fixed(perStep / unit, 9) << std::noshowpos << " g^2h^2/2\n";
    }
}

void energyPlots(Output& out, const Methods& methods) {
    struct Case {
        study::Problem p;
        double h;
        std::size_t steps;
    };
    const Case cases[] = {{study::oscillator(1.0), 0.1, 6000}, {study::kepler(), 2.0 * M_PI / 200.0, 2000}};
    for (const Case& c : cases) {
        std::ofstream dat = out.open("energy-" + c.p.id + ".dat");
        dat << "# one block per integrator measured (methods.gp lists them): t |E - E0|/|E0|, h = " << c.h << " s\n";
        for (Integrator m : methods) {
            const std::vector<double> e = study::energyHistory(c.p, m, c.h, c.steps);
            dat << "# " << gpl::integratorId(m) << '\n';
            for (std::size_t i = 0; i < e.size(); i += 5) {
                if (std::isfinite(e[i])) dat << c.h * static_cast<double>(i + 1) << ' ' << std::abs(e[i]) << '\n';
            }
            dat << "\n\n";
        }
    }
}

void inputChecks() {
    std::cout << "\nbad input is rejected before stepping:\n";
    const study::Problem p = study::oscillator(1.0);
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    const auto attempt = [](const std::string& what, const auto& f) {
        try {
            f();
            std::cout << "  " << pad(what, 28) << "ACCEPTED (a defect)\n";
        } catch (const std::invalid_argument& e) {
            std::cout << "  " << pad(what, 28) << "rejected: " << e.what() << '\n';
        }
    };
    for (double h : {nan, inf, 0.0, -0.01}) {
        attempt("step h = " + gpl::formatNumber(h),
                [&] { study::simulateWithStep(p, Integrator::RungeKutta4, h, 10); });
    }
    attempt("start position NaN", [&] {
        study::Problem bad = p;
        bad.x0[0].x() = nan;
        study::simulate(bad, Integrator::PositionVerlet, 10);
    });
    attempt("mass 0 in the spring chain", [] { study::springChain({1.0, 0.0}); });
    attempt("mass -1 kg for a body", [] { gpl::sphere("ball", 0.5, -1.0); });
    attempt("engine time step inf", [&] {
        gpl::PhysicsEngine e;
        e.setTimeStep(inf);
    });
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"The speed-versus-accuracy study: every integrator on problems with exact answers."};
    std::string outDir = "build/accuracy";
    app.add_option("--out", outDir, "folder for the CSV and plot data files");
    if (const int status = gpl::cli::parse(app, argc, argv); status >= 0) return status;
    if (const std::string error = gpl::cli::makeFolder("--out", outDir); !error.empty()) {
        std::cerr << "error: " << error << '\n';
        return 2;
    }

    const auto start = std::chrono::steady_clock::now();
    try {
        Output out(outDir);
        // Methods whose hook is a stub would measure particles that never move: they are left out.
        const Methods open = study::openIntegrators();
        Methods methods;
        for (Integrator m : kIntegrators) {
            if (std::find(open.begin(), open.end(), m) == open.end()) methods.push_back(m);
        }
        std::cout << "accuracy study with the hooks of " << study::kHookVariant << "/";
        if (open.empty()) {
            std::cout << ": every hook it needs is written\n";
        } else {
            std::cout << "; hooks not implemented yet:";
            for (Integrator m : open) std::cout << ' ' << study::hookOf(m);
            std::cout << "\nskipped until their hooks are written:";
            for (std::size_t i = 0; i < open.size(); ++i) std::cout << (i ? ", " : " ") << gpl::integratorName(open[i]);
            std::cout << " (no rows, no curves)\n";
        }
        std::ofstream csv = out.open("sweep.csv");
        csv << "problem,integrator,steps,h,h_omega,error,energy_max,energy_drift,evaluations_per_step,ns_per_step\n";
        std::ofstream orders = out.open("orders.csv");
        orders << "problem,integrator,theory,measured,points\n";
        std::vector<Sweep> sweeps;
        for (const study::Problem& p : {study::freeFall(), study::oscillator(2.0 * M_PI), study::pendulum(0.1),
                                        study::pendulum(2.5), study::kepler()}) {
            sweeps.push_back(sweep(p, methods));
            printSweep(sweeps.back());
            writeSweep(out, csv, orders, sweeps.back());
        }
        writeAnchors(out, sweeps);
        writeMethods(out, methods);
        std::ofstream cheap = out.open("cheapest.csv");
        cheap << "problem,target,integrator,steps,h,error,evaluations,seconds\n";
        cheapest(sweeps[1], 1e-6, cheap);
        cheapest(sweeps[4], 1e-6, cheap);
        freeFallEnergy(out, methods);
        stability(out, methods);
        massRatio(out, methods);
        longHorizon(out, methods);
        precision(out);
        stepExtremes(out, methods);
        energyPlots(out, methods);
        inputChecks();
        std::cout << "\nwrote to " << outDir << ":";
        for (const std::string& f : out.written()) std::cout << ' ' << f;
        std::cout << '\n';
    } catch (const std::exception& e) {
        std::cerr << "error: " << e.what() << '\n';
        return 2;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "study took " << fixed(seconds, 1) << " s\n";
    return 0;
}
