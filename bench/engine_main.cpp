// gpl-bench-engine: this engine against Bullet on the same heap of spheres or of cubes (./lab bench
// engine [--shape box]), side by side from one run: time per step, contacts per step and the quality
// of the settled heap, for heaps of growing size, with the fitted scaling exponent of each engine;
// this engine on one thread and on two side by side (--threads 1 2), and beside a busy process
// (--busy); and the cost of integration alone against a bare loop over packed arrays.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "command_line.h"
#include "gpl/body.h"
#include "gpl/engine.h"
#include "heap.h"
#include "report.h"

namespace {

using gpl::Vec3;
using gpl::bench::HeapRun;
using gpl::study::fixed;
using gpl::study::pad;
using gpl::study::sci;

// The default heaps: spheres up to 27 000 (about two and a half minutes for that size alone here,
// Bullet's steps the most of it), cubes up to 8000 (their steps cost several times a sphere's).
const std::vector<std::size_t> kSphereSizes{100, 300, 1000, 3000, 8000, 27000};
const std::vector<std::size_t> kBoxSizes{100, 300, 1000, 3000, 8000};

// Least-squares slope of log(ms per step) against log(N): the scaling exponent (1: linear).
double scalingExponent(const std::vector<HeapRun>& runs) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 0;
    for (const HeapRun& r : runs) {
        if (r.medianMs <= 0.0) continue;
        const double x = std::log(static_cast<double>(r.bodies)), y = std::log(r.medianMs);
        sx += x, sy += y, sxx += x * x, sxy += x * y, ++n;
    }
    if (n < 2) return std::nan("");
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// ns per body and step: the engine's free fall (gravity and integration stages only), its integration
// stage on its own (integrate(), which calls the integrator() hook), and a bare loop over packed
// arrays of positions and velocities doing the same arithmetic. The three take turns in rounds, and
// the figures are medians over the rounds, the ratios of each round's own pairs, so that a busy
// moment of the machine slows every side of a round rather than one figure.
void integrationAlone(std::size_t n, std::size_t steps, std::ostream& out) {
    gpl::PhysicsEngine e;
    e.setTimeStep(gpl::bench::kTimeStep);
    for (std::size_t i = 0; i < n; ++i) {
        e.add(gpl::sphere("s" + std::to_string(i), 0.5, 1.0).at(Vec3(1.2 * static_cast<double>(i), 10.0, 0.0)));
    }
    e.step();  // the gravity stage fills the accumulators that integrate() alone then keeps using
    std::vector<double> x(3 * n), v(3 * n, 0.0);
    for (std::size_t i = 0; i < n; ++i) x[3 * i] = 1.2 * static_cast<double>(i), x[3 * i + 1] = 10.0;
    const double h = gpl::bench::kTimeStep, g = -9.81;
    const auto nsPerBodyStep = [n](std::chrono::steady_clock::time_point start, std::size_t count) {
        const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count();
        return ns / static_cast<double>(n * count);
    };
    constexpr std::size_t kRounds = 9;
    const std::size_t perRound = std::max<std::size_t>(1, steps / kRounds);
    std::vector<double> whole, stage, bare, wholeRatios, stageRatios;
    for (std::size_t round = 0; round < kRounds; ++round) {
        auto start = std::chrono::steady_clock::now();
        for (std::size_t s = 0; s < perRound; ++s) e.step();
        whole.push_back(nsPerBodyStep(start, perRound));
        start = std::chrono::steady_clock::now();
        for (std::size_t s = 0; s < perRound; ++s) e.integrate();
        stage.push_back(nsPerBodyStep(start, perRound));
        start = std::chrono::steady_clock::now();
        for (std::size_t s = 0; s < perRound; ++s) {
            for (std::size_t i = 0; i < 3 * n; i += 3) {
                v[i + 1] += h * g;
                x[i] += h * v[i];
                x[i + 1] += h * v[i + 1];
                x[i + 2] += h * v[i + 2];
            }
        }
        bare.push_back(nsPerBodyStep(start, perRound));
        wholeRatios.push_back(whole.back() / bare.back());
        stageRatios.push_back(stage.back() / bare.back());
    }
    volatile double sink = x[1] + e.bodies().back().position.y();  // keeps both loops
    (void)sink;
    const auto median = [](std::vector<double> values) {
        std::sort(values.begin(), values.end());
        return values[values.size() / 2];
    };
    out << "\nintegration alone: " << n << " bodies in free fall, " << kRounds << " rounds of " << perRound
        << " steps each way (medians over the rounds)\n"
        << "  this engine, whole step (gravity, integration, finiteness check): " << fixed(median(whole), 1)
        << " ns per body and step, " << fixed(median(wholeRatios), 1) << "x the bare loop\n"
        << "  this engine, integration stage (integrator() hook):              " << fixed(median(stage), 1)
        << " ns per body and step, " << fixed(median(stageRatios), 1) << "x the bare loop\n"
        << "  bare loop over packed arrays:                                     " << fixed(median(bare), 1)
        << " ns per body and step\n";
}

// The time a cache line takes from one thread's core to the other's and back (ns): the two threads
// hand a counter to each other through one line, each waiting for the other's write. Two threads
// that share a stage's bodies pay it for every line the other wrote last; on a virtual machine it
// changes with where the host places the two processors (on one core complex or on two).
double roundTripNs() {
    constexpr int kStop = -1;
    alignas(64) std::atomic<int> turn{0};
    // Each waits with a yield now and then, so that a machine whose other core is busy (or that has
    // one) gives the trips a time slice and the measurement ends.
    const auto waitFor = [&turn](int value) {
        for (int spins = 1;; ++spins) {
            const int now = turn.load(std::memory_order_acquire);
            if (now == value || now == kStop) return;
            if (spins % 4096 == 0) std::this_thread::yield();
        }
    };
    std::thread other([&] {
        for (int k = 0;; ++k) {
            waitFor(2 * k + 1);
            if (turn.load(std::memory_order_acquire) == kStop) return;
            turn.store(2 * k + 2, std::memory_order_release);
        }
    });
    // Trips for a tenth of a second at most, counted in blocks of a thousand.
    const auto start = std::chrono::steady_clock::now();
    int trips = 0;
    double ns = 0.0;
    while (trips < 100000 && ns < 1e8) {
        for (int k = trips; k < trips + 1000; ++k) {
            turn.store(2 * k + 1, std::memory_order_release);
            waitFor(2 * k + 2);
        }
        trips += 1000;
        ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count();
    }
    turn.store(kStop, std::memory_order_release);
    other.join();
    return ns / trips;
}

// How long one processor takes per access for random reads and writes of 64-byte records in 256 KiB
// (ns), a thread pinned to it: what a stage's sweeps do to its bodies. Each processor runs alone, one
// after the other. On a virtual machine two processors can differ here by a factor of two while
// their arithmetic runs alike: two halves of equal work then wait for the slower. -1 where the
// thread cannot be pinned there.
double accessNsOn(int processor) {
    struct alignas(64) Record {
        double value[8];
    };
    constexpr std::size_t kRecords = 256 * 1024 / sizeof(Record);
    constexpr int kRounds = 40;
    std::vector<Record> records(kRecords);
    std::vector<std::uint32_t> visits(4 * kRecords);
    std::mt19937 random(7);
    for (std::uint32_t& v : visits) v = static_cast<std::uint32_t>(random() % kRecords);
    for (std::size_t i = 0; i < kRecords; ++i) records[i].value[0] = static_cast<double>(i);
    double ns = -1.0;
    std::thread pinned([&] {
        cpu_set_t set;
        CPU_ZERO(&set);
        CPU_SET(processor, &set);
        if (pthread_setaffinity_np(pthread_self(), sizeof set, &set) != 0) return;
        std::vector<double> rounds;
        double total = 0.0;
        for (int round = 0; round < kRounds; ++round) {
            const auto start = std::chrono::steady_clock::now();
            for (std::size_t k = 0; k + 1 < visits.size(); k += 2) {
                Record& a = records[visits[k]];
                Record& b = records[visits[k + 1]];
                const double d = 0.01 * (b.value[0] - a.value[0]);  // a pair's exchange, as an impulse's
                a.value[0] += d;
                a.value[1] += d;
                b.value[0] -= d;
                total += d;  // summed, as a sweep sums its impulses
            }
            rounds.push_back(std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count() /
                             static_cast<double>(visits.size()));
        }
        std::sort(rounds.begin(), rounds.end());
        ns = rounds[rounds.size() / 2];
        volatile double sink = total;  // keeps the loop
        (void)sink;
    });
    pinned.join();
    return ns;
}

// What a second thread can give on this machine: two loops run one after the other on one thread,
// then at once on two, for a loop bound by the latency of its arithmetic (a chain of square roots)
// and one bound by the core's arithmetic units (eight independent multiply-add chains). Two
// processors that are the two hardware threads of one core double the first and not the second.
// Then what it costs to share data: a cache line's round trip between the two threads.
void secondThreadGain(std::ostream& out) {
    const auto latency = [] {
        double s = 1.0;
        for (int i = 0; i < 20000000; ++i) s = std::sqrt(s + 1.0);
        return s;
    };
    const auto throughput = [] {
        double a[8] = {1, 1, 1, 1, 1, 1, 1, 1};
        for (int i = 0; i < 40000000; ++i) {
            for (int k = 0; k < 8; ++k) a[k] = a[k] * (1.0 + 1e-9 * k) + 1e-9;
        }
        return a[0] + a[7];
    };
    const auto gain = [](const std::function<double()>& loop) {
        volatile double sink = 0.0;
        auto start = std::chrono::steady_clock::now();
        sink = loop() + loop();
        const double one = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        start = std::chrono::steady_clock::now();
        double other = 0.0;
        std::thread second([&] { other = loop(); });
        sink = loop();
        second.join();
        sink = sink + other;
        const double two = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return one / two;
    };
    out << "\na second thread on this machine (two loops on one thread, then at once on two): "
        << fixed(gain(latency), 2) << "x as fast for a chain of square roots, " << fixed(gain(throughput), 2)
        << "x for eight independent multiply-add chains; a cache line from one thread to the other and back: "
        << fixed(roundTripNs(), 0) << " ns\n";
    const double first = accessNsOn(0), second = accessNsOn(1);
    if (first > 0.0 && second > 0.0) {
        out << "each processor alone, random reads and writes of 64-byte records in 256 KiB: processor 0 "
            << fixed(first, 1) << " ns, processor 1 " << fixed(second, 1) << " ns per access (the slower "
            << fixed(std::max(first, second) / std::min(first, second), 2) << "x the faster)\n";
    }
}

// One busy process beside the run: a child of this program that spins on a core until it is killed,
// as a compiler or a batch job beside the engine would keep a core. The destructor kills it and
// waits for it; should this program die first (a signal, a crash), the kernel kills it
// (PR_SET_PDEATHSIG), so that it is never left behind.
class BusyProcess {
public:
    BusyProcess() {
        const pid_t parent = getpid();
        pid_ = fork();
        if (pid_ < 0) throw std::runtime_error("--busy: could not start the busy process");
        if (pid_ == 0) {
            // A session of its own: the scheduler shares the cores between it and this program as
            // between two programs started apart (Linux's autogroups), not as threads of one.
            setsid();
            prctl(PR_SET_PDEATHSIG, SIGKILL);
            if (getppid() != parent) _exit(0);  // the parent died before prctl()
            for (volatile unsigned long k = 0;; k = k + 1) {
            }
        }
    }
    ~BusyProcess() {
        kill(pid_, SIGKILL);
        waitpid(pid_, nullptr, 0);
    }
    BusyProcess(const BusyProcess&) = delete;
    BusyProcess& operator=(const BusyProcess&) = delete;
    pid_t pid() const { return pid_; }

private:
    pid_t pid_;
};

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"This engine against Bullet on the same heap of spheres or cubes (./lab bench engine)"};
    std::vector<std::size_t> sizes;  // default: kSphereSizes or kBoxSizes
    std::string out = "build/engine";
    bool skipBullet = false;
    bool busy = false;
    std::string shapeName = "sphere";
    std::vector<int> threadCounts;  // default: the engine's, or 1 and 2 with --busy
    int interpenetration = gpl::bench::kInterpenetrationIterations;
    app.add_option("--shape", shapeName, "what the heap is made of: sphere (radius 0.5 m) or box (cubes of half side 0.3 m)")
        ->check(CLI::IsMember({"sphere", "box"}));
    app.add_option("--sizes", sizes, "numbers of bodies (default: 100 300 1000 3000 8000 27000 spheres, to 8000 cubes)")
        ->check(gpl::cli::wholeNumber(1, 1000000));
    app.add_option("--out", out, "folder for engine.csv and the plot's data");
    app.add_flag("--no-bullet", skipBullet, "this engine only");
    app.add_option("--threads", threadCounts,
                   "threads of this engine's broad phase and friction stage, 1 or 2, or both (1 2: a row each, taking "
                   "turns; default: 2 on two cores, both with --busy)")
        ->check(gpl::cli::wholeNumber(1, 2));
    app.add_flag("--busy", busy,
                 "one busy process (a child that spins on a core) beside the whole run, killed at its end: what the "
                 "engine gives on a machine whose other core is taken");
    app.add_option("--interpenetration", interpenetration,
                   "this engine's sweeps of position correction (interpenetration) per step (default: 3; 10: as many as the solver's)")
        ->check(gpl::cli::wholeNumber(1, 100));
    if (const int status = gpl::cli::parse(app, argc, argv); status >= 0) return status;
    if (sizes.empty()) sizes = shapeName == "box" ? kBoxSizes : kSphereSizes;
    if (threadCounts.empty()) threadCounts = busy ? std::vector<int>{1, 2} : std::vector<int>{gpl::PhysicsEngine().threads()};
    std::sort(threadCounts.begin(), threadCounts.end());
    threadCounts.erase(std::unique(threadCounts.begin(), threadCounts.end()), threadCounts.end());
    if (const std::string error = gpl::cli::makeFolder("--out", out); !error.empty()) {
        std::cerr << error << '\n';
        return 2;
    }
    const bool bullet = gpl::bench::hasBullet() && !skipBullet;
    if (!gpl::bench::hasBullet() && !skipBullet) {
        std::cerr << "gpl-bench-engine: built without Bullet (Debian libbullet-dev); ./lab bench engine installs it\n";
        return 2;
    }
    try {
        // Made before any thread of this program, so that the child is a plain copy of one thread.
        std::optional<BusyProcess> spinner;
        if (busy) spinner.emplace();
        gpl::study::Output output(out);
        const bool boxes = shapeName == "box";
        const gpl::bench::HeapShape shape = boxes ? gpl::bench::HeapShape::Boxes : gpl::bench::HeapShape::Spheres;
        const std::string stem = boxes ? "engine-boxes" : "engine";  // of the files written
        const bool bothCounts = threadCounts.size() > 1;
        const auto threadsName = [](int t) { return std::to_string(t) + (t == 1 ? " thread" : " threads"); };
        std::cout << (boxes ? "heap of cubes (half side 0.3 m, 1 kg, turned at random" : "heap of spheres (r = 0.5 m, 1 kg")
                  << ", lattice 1.2 m, fixed seed) dropped on a plane; steps of 1/60 s, "
                  << gpl::bench::kIterations << " solver iterations (this engine: " << interpenetration
                  << " sweeps of position correction); times per step over the whole fall and settling, "
                  << (bullet || bothCounts ? "the engines taking turns of " + std::to_string(gpl::bench::kTurn) + " steps; "
                                           : std::string())
                  << "this engine's broad phase and friction stage on ";
        for (std::size_t i = 0; i < threadCounts.size(); ++i) {
            std::cout << (i == 0 ? "" : " and on ") << threadsName(threadCounts[i]);
        }
        std::cout << '\n';
        if (spinner) {
            std::cout << "beside one busy process (pid " << spinner->pid()
                      << ", spinning on a core from start to end of the run, killed then)\n";
        }
        std::cout << "friction: the pair coefficient " << gpl::bench::kFriction << " in both engines, this engine's"
                  << " sqrt(mu_a mu_b) of its bodies' " << gpl::bench::kFriction << " (worksheet 7's friction stage),"
                  << " Bullet's the product of its bodies' " << fixed(std::sqrt(gpl::bench::kFriction), 3) << " (sqrt "
                  << gpl::bench::kFriction << ", the plane's too); restitution 0 in both\n\n"
                  << std::flush;
        const std::vector<std::size_t> widths{8, 16, 7, 11, 11, 9, 11, 10, 11, 10, 11, 11};
        const char* header[] = {"N",        "engine",    "steps",    "median ms", "p90 ms",   "/Bullet",
                                "/1 thread", "contacts", "deepest m", "height m", "KE end J", "max v m/s"};
        for (std::size_t c = 0; c < widths.size(); ++c) std::cout << pad(header[c], widths[c]);
        std::cout << '\n';
        auto csv = output.open(stem + ".csv");
        csv << "bodies,engine,threads,busy,steps,median_ms,p90_ms,contacts_per_step,deepest_m,height_m,kinetic_j,"
               "fastest_m_s\n";
        // Per thread count, this engine's runs; Bullet's.
        std::vector<std::vector<HeapRun>> ours(threadCounts.size());
        std::vector<HeapRun> theirs;
        std::pair<double, double> friction[2] = {{std::nan(""), std::nan("")}, {std::nan(""), std::nan("")}};
        for (std::size_t n : sizes) {
            std::vector<std::unique_ptr<gpl::bench::HeapSim>> sims;
            std::vector<std::pair<std::string, gpl::bench::HeapSim*>> engines;
            for (int t : threadCounts) {
                sims.push_back(gpl::bench::ourHeap(shape, n, t, interpenetration));
                engines.emplace_back(bothCounts ? "ours " + threadsName(t) : std::string("ours"), sims.back().get());
            }
            if (bullet) {
                sims.push_back(gpl::bench::bulletHeap(shape, n));
                engines.emplace_back("Bullet", sims.back().get());
            }
            const std::vector<HeapRun> runs = gpl::bench::runInTurns(shape, n, gpl::bench::settleTime(n), engines);
            friction[0] = sims.front()->pairFriction();
            if (bullet) friction[1] = sims.back()->pairFriction();
            for (std::size_t e = 0; e < threadCounts.size(); ++e) ours[e].push_back(runs[e]);
            if (bullet) theirs.push_back(runs.back());
            for (std::size_t e = 0; e < runs.size(); ++e) {
                const HeapRun& r = runs[e];
                const bool mine = e < threadCounts.size();
                const std::string overBullet = bullet && mine ? fixed(r.medianMs / runs.back().medianMs, 2) : "";
                const std::string overOne =
                    bothCounts && mine && threadCounts[e] != 1 ? fixed(r.medianMs / runs.front().medianMs, 2) : "";
                const std::string cells[] = {std::to_string(n),   r.engine,           std::to_string(r.steps),
                                             fixed(r.medianMs, 3), fixed(r.p90Ms, 3), overBullet,
                                             overOne,              fixed(r.contactsPerStep, 0), sci(r.deepest),
                                             fixed(r.height, 2),   sci(r.kinetic),    fixed(r.fastest, 2)};
                for (std::size_t c = 0; c < widths.size(); ++c) std::cout << pad(cells[c], widths[c]);
                std::cout << std::endl;
                csv << n << ',' << (mine ? "ours" : "Bullet") << ',' << (mine ? threadCounts[e] : 1) << ','
                    << (busy ? 1 : 0) << ',' << r.steps << ',' << r.medianMs << ',' << r.p90Ms << ','
                    << r.contactsPerStep << ',' << r.deepest << ',' << r.height << ',' << r.kinetic << ','
                    << r.fastest << '\n';
            }
        }
        std::cout << "\nthe pair friction the contacts hold at the end (with the plane, between bodies): this engine "
                  << fixed(friction[0].first, 3) << ", " << fixed(friction[0].second, 3);
        if (bullet) std::cout << "; Bullet " << fixed(friction[1].first, 3) << ", " << fixed(friction[1].second, 3);
        std::cout << '\n';
        // The plot: this engine's fastest thread count against Bullet.
        const std::vector<HeapRun>& plotted = ours.back();
        auto dat = output.open(stem + "-scaling.dat");
        dat << "# bodies ours_median_ms bullet_median_ms (this engine on " << threadsName(threadCounts.back()) << ")\n";
        for (std::size_t i = 0; i < plotted.size(); ++i) {
            dat << plotted[i].bodies << ' ' << plotted[i].medianMs << ' ' << (bullet ? theirs[i].medianMs : std::nan(""))
                << '\n';
        }
        if (sizes.size() < 2) {
            std::cout << "\nscaling exponent of ms per step against N: needs two sizes or more (--sizes)\n";
        } else {
            std::cout << "\nscaling exponent of ms per step against N (least squares on log-log): this engine";
            for (std::size_t e = 0; e < threadCounts.size(); ++e) {
                std::cout << (bothCounts ? (e == 0 ? " " : ", ") + threadsName(threadCounts[e]) + " " : " ")
                          << fixed(scalingExponent(ours[e]), 2);
            }
            if (bullet) std::cout << ", Bullet " << fixed(scalingExponent(theirs), 2);
            std::cout << '\n';
        }
        if (!boxes && !busy) integrationAlone(1000, 2000, std::cout);
        if (threadCounts.back() > 1 && !busy) secondThreadGain(std::cout);
        std::cout << "\nwrote";
        for (const std::string& f : output.written()) std::cout << ' ' << out << '/' << f;
        std::cout << '\n';
    } catch (const std::exception& e) {
        std::cerr << "gpl-bench-engine: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
