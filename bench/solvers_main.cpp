// gpl-bench-solvers: the contact solvers' test scenes (./lab bench solvers) run with each of this
// engine's solver configurations and with Bullet on the same scene, side by side: whether each
// stands, how far its top body drifts, how fast its bodies still move, the energy it gains or loses,
// its deepest overlap and the time a step takes. A table, solvers.csv, and the data of the plot
// (solvers-*.dat, drawn by bench/solvers.gp).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "command_line.h"
#include "gpl/collision.h"
#include "gpl/engine.h"
#include "gpl/scenes.h"
#include "report.h"
#include "scene_twin.h"

namespace {

using gpl::Body;
using gpl::PhysicsEngine;
using gpl::Vec3;
using gpl::bench::BodyState;
using gpl::study::fixed;
using gpl::study::pad;
using gpl::study::sci;
using gpl::study::split;

// This engine's contact solvers, each set after the scene is loaded.
struct SolverConfig {
    std::string name;
    std::function<void(PhysicsEngine&)> select;
};
std::vector<SolverConfig> solvers() {
    std::vector<SolverConfig> all;
    for (const gpl::ContactSolver solver : gpl::kContactSolvers) {
        all.push_back({gpl::contactSolverName(solver), [solver](PhysicsEngine& e) { e.setContactSolver(solver); }});
    }
    return all;
}
const std::vector<SolverConfig> kSolvers = solvers();

// The scenes run by default: every stacking scene, then worksheet 7's stack and its corner landing
// (worksheet 6's corner drop with friction).
std::vector<std::string> defaultScenes() {
    gpl::SceneRegistry stacking;
    gpl::addStackingScenes(stacking);
    std::vector<std::string> names;
    for (const gpl::Scene& s : stacking.all()) names.push_back(s.name);
    names.insert(names.end(), {"box-stack", "corner-landing"});
    return names;
}

// What theory says a scene does: stand where it starts, fall (the slippery pyramids, below their
// least friction), or move and come to rest.
enum class Expect { Stand, Fall, Settle };
Expect expected(const std::string& scene) {
    if (scene == "sphere-pyramid-slippery" || scene == "sphere-tetrahedron-slippery") return Expect::Fall;
    for (const char* moving : {"friction-ramp", "overlap-recovery", "dominoes", "corner-landing"}) {
        if (scene == moving) return Expect::Settle;
    }
    return Expect::Stand;
}

constexpr double kRestSpeed = 1e-3;  // m/s: at rest below it
constexpr double kStandDrift = 0.01;  // m: a standing body stays this near its start

// What one engine did on one scene.
struct Run {
    std::string scene, solver;
    std::string verdict;
    double topDrift = 0.0;     ///< m, the top body's distance from its start at the end
    double largestDrift = 0.0; ///< m, any movable body's at the end
    double lastSpeed = 0.0;    ///< m/s, the fastest point of any body over the last second
    double peakSpeed = 0.0;    ///< m/s, likewise over the whole run
    double energyChange = 0.0; ///< J, total energy at the end minus at the start
    double deepest = 0.0;      ///< m, the deepest overlap over the last second
    double msPerStep = 0.0;    ///< median wall time of a step
};

// The scene's bodies with a state put in (static bodies keep the loaded pose).
std::vector<Body> withState(const std::vector<Body>& bodies, const std::vector<BodyState>& state) {
    std::vector<Body> out = bodies;
    for (std::size_t i = 0; i < out.size(); ++i) {
        if (out[i].isStatic()) continue;
        out[i].position = state[i].position;
        out[i].orientation = state[i].orientation;
        out[i].velocity = state[i].velocity;
        out[i].angularVelocity = state[i].angularVelocity;
    }
    return out;
}

// The speed of a body's fastest point: a box's fastest corner (|v + w x r| is convex in r, so its
// largest value over the box is at a corner), |v| + |w| r on a sphere.
double fastestPoint(const Body& b) {
    if (b.isStatic()) return 0.0;
    if (b.shape == gpl::Shape::Sphere) return b.velocity.norm() + b.angularVelocity.norm() * b.radius;
    double fastest = 0.0;
    for (int k = 0; k < 8; ++k) {
        const Vec3 corner((k & 1 ? 1 : -1) * b.halfExtents.x(), (k & 2 ? 1 : -1) * b.halfExtents.y(),
                          (k & 4 ? 1 : -1) * b.halfExtents.z());
        fastest = std::max(fastest, (b.velocity + b.angularVelocity.cross(b.orientation * corner)).norm());
    }
    return fastest;
}

double boundingRadius(const Body& b) { return b.shape == gpl::Shape::Sphere ? b.radius : b.halfExtents.norm(); }

// The deepest overlap of any two bodies, by this engine's collision kernels (both engines' states alike).
double deepestOverlap(const std::vector<Body>& bodies) {
    double deepest = 0.0;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        for (std::size_t j = i + 1; j < bodies.size(); ++j) {
            const Body &p = bodies[i], &q = bodies[j];
            if (p.isStatic() && q.isStatic()) continue;
            const bool planes = p.shape == gpl::Shape::Plane || q.shape == gpl::Shape::Plane;
            if (!planes && (p.position - q.position).norm() > boundingRadius(p) + boundingRadius(q)) continue;
            if (const std::optional<gpl::Contact> c = gpl::collide(bodies, i, j)) deepest = std::max(deepest, c->depth);
        }
    }
    return deepest;
}

double totalEnergy(const std::vector<Body>& bodies, const Vec3& gravity) {
    double e = 0.0;
    for (const Body& b : bodies) e += gpl::kineticEnergy(b) + gpl::potentialEnergy(b, gravity);
    return e;
}

// Steps one engine, loaded with the scene whose bodies are `start` (time step h), through `seconds`
// and measures it; `step` advances it, `state` reads it.
Run measure(const std::vector<Body>& start, const Vec3& gravity, double h, double seconds,
            const std::function<void()>& step, const std::function<std::vector<BodyState>()>& state) {
    const auto steps = static_cast<std::size_t>(std::llround(seconds / h));
    const auto lastSecond = static_cast<std::size_t>(std::llround(1.0 / h));
    std::size_t top = 0;  // the movable body highest at the start
    for (std::size_t i = 0; i < start.size(); ++i) {
        if (!start[i].isStatic() && (start[top].isStatic() || start[i].position.y() >= start[top].position.y())) top = i;
    }
    Run run;
    std::vector<double> ms;
    ms.reserve(steps);
    std::vector<Body> now = start;
    for (std::size_t s = 0; s < steps; ++s) {
        const auto begin = std::chrono::steady_clock::now();
        step();
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count());
        now = withState(start, state());
        double fastest = 0.0;
        for (const Body& b : now) fastest = std::max(fastest, fastestPoint(b));
        run.peakSpeed = std::max(run.peakSpeed, fastest);
        if (s + lastSecond >= steps) {
            run.lastSpeed = std::max(run.lastSpeed, fastest);
            run.deepest = std::max(run.deepest, deepestOverlap(now));
        }
    }
    for (std::size_t i = 0; i < start.size(); ++i) {
        run.largestDrift = std::max(run.largestDrift, (now[i].position - start[i].position).norm());
    }
    run.topDrift = (now[top].position - start[top].position).norm();
    run.energyChange = totalEnergy(now, gravity) - totalEnergy(start, gravity);
    if (!ms.empty()) {
        std::sort(ms.begin(), ms.end());
        run.msPerStep = ms[ms.size() / 2];
    }
    return run;
}

std::string verdictOf(const std::string& scene, const Run& r) {
    const bool still = r.lastSpeed < kRestSpeed;
    if (expected(scene) == Expect::Settle) return still ? "rests" : "moves";
    if (!still) return "moves";
    return r.largestDrift < kStandDrift ? "stands" : "fell";
}

// The verdict is what theory says: stands where the scene should stand, anything else where it
// should fall, rests where it should settle.
bool asTheorySays(const std::string& scene, const std::string& verdict) {
    switch (expected(scene)) {
        case Expect::Stand: return verdict == "stands";
        case Expect::Fall: return verdict != "stands";
        case Expect::Settle: return verdict == "rests";
    }
    return false;
}


}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"The contact solvers' test scenes with each solver and with Bullet (./lab bench solvers)"};
    double seconds = 10.0;
    std::string sceneList;
    std::string out = "build/solvers";
    bool skipBullet = false;
    app.add_option("--seconds", seconds, "simulated time of each run (default 10)")->check(gpl::cli::positiveSeconds());
    app.add_option("--scenes", sceneList, "scenes to run, separated by commas (default: the stacking scenes, box-stack, corner-landing)")
        ->check(gpl::cli::expects("scene names separated by commas (./lab run --list lists them)", [](const std::string& text) {
            const std::vector<std::string> names = split(text);
            if (names.empty()) return false;
            for (const std::string& n : names) {
                try {
                    gpl::scenes().find(n);
                } catch (const std::exception&) {
                    return false;
                }
            }
            return true;
        }));
    app.add_option("--out", out, "folder for solvers.csv and the plot's data");
    app.add_flag("--no-bullet", skipBullet, "this engine only");
    if (const int status = gpl::cli::parse(app, argc, argv); status >= 0) return status;
    if (const std::string error = gpl::cli::makeFolder("--out", out); !error.empty()) {
        std::cerr << error << '\n';
        return 2;
    }
    const bool bullet = gpl::bench::hasBulletTwin() && !skipBullet;
    const std::vector<std::string> names = sceneList.empty() ? defaultScenes() : split(sceneList);
    std::vector<std::string> engines;
    for (const SolverConfig& c : kSolvers) engines.push_back(c.name);
    if (bullet) engines.push_back("Bullet");
    try {
        gpl::study::Output output(out);
        const PhysicsEngine defaults;
        std::cout << "each scene for " << seconds << " s at its own time step (0.01 s), " << defaults.contactIterations()
                  << " solver iterations, gravity 9.81 m/s^2, in this engine"
                  << (bullet ? " and in Bullet (split impulses, no sleeping)" : " (built without Bullet)") << ";\n"
                  << "friction matched pair by pair: this engine's pair coefficient is sqrt(mu_a mu_b), Bullet's the product of"
                  << " its bodies', each given sqrt(mu); restitution a product in both\n"
                  << "stands: every point of every body slower than " << kRestSpeed * 1e3
                  << " mm/s over the last second and every body within " << kStandDrift * 100
                  << " cm of its start (fell: at rest elsewhere; moves: not at rest);\n"
                  << "scenes meant to move and settle (ramp, overlap recovery, dominoes, corner landing): rests or moves;"
                  << " the slippery pyramids are meant to fall\n"
                  << "top drift: the body highest at the start, its distance from there at the end; speed: the fastest point"
                  << " over the last second (peak: over the run); dE: total energy end - start; overlap: the deepest over the last"
                  << " second; ms: median wall time per step\n\n";
        const std::vector<std::size_t> widths{28, 21, 8, 11, 11, 11, 12, 11, 9};
        const char* header[] = {"scene", "solver", "verdict", "top drift m", "speed m/s", "peak m/s", "dE J", "overlap m", "ms"};
        for (std::size_t c = 0; c < widths.size(); ++c) std::cout << pad(header[c], widths[c]);
        std::cout << '\n';
        auto csv = output.open("solvers.csv");
        csv << "scene,solver,verdict,top_drift_m,largest_drift_m,speed_last_second_m_s,peak_speed_m_s,energy_change_j,"
               "deepest_overlap_m,ms_per_step\n";
        std::vector<std::vector<Run>> table;  // per scene, per engine
        for (const std::string& name : names) {
            const gpl::Scene& scene = gpl::scenes().find(name);
            std::vector<Run> row;
            for (const SolverConfig& config : kSolvers) {
                PhysicsEngine e;
                gpl::load(e, scene);
                e.setContactIterations(defaults.contactIterations());  // every solver with the same sweeps
                config.select(e);
                const std::vector<Body> start = e.bodies();
                const auto read = [&e] {
                    std::vector<BodyState> s;
                    s.reserve(e.bodies().size());
                    for (const Body& b : e.bodies()) s.push_back({b.position, b.orientation, b.velocity, b.angularVelocity});
                    return s;
                };
                row.push_back(measure(start, e.gravity(), e.timeStep(), seconds, [&e] { e.step(); }, read));
                row.back().solver = config.name;
            }
            if (bullet) {
                PhysicsEngine e;
                gpl::load(e, scene);
                e.setContactIterations(defaults.contactIterations());
                const std::unique_ptr<gpl::bench::SceneTwin> twin = gpl::bench::bulletTwin(e);
                row.push_back(measure(e.bodies(), e.gravity(), e.timeStep(), seconds, [&twin] { twin->step(); },
                                      [&twin] { return twin->state(); }));
                row.back().solver = "Bullet";
            }
            for (Run& r : row) {
                r.scene = name;
                r.verdict = verdictOf(name, r);
                const std::string cells[] = {name, r.solver, r.verdict, sci(r.topDrift), sci(r.lastSpeed), sci(r.peakSpeed),
                                             sci(r.energyChange), sci(r.deepest), fixed(r.msPerStep, 3)};
                for (std::size_t c = 0; c < widths.size(); ++c) std::cout << pad(cells[c], widths[c]);
                std::cout << std::endl;
                csv << name << ',' << r.solver << ',' << r.verdict << ',' << r.topDrift << ',' << r.largestDrift << ','
                    << r.lastSpeed << ',' << r.peakSpeed << ',' << r.energyChange << ',' << r.deepest << ',' << r.msPerStep
                    << '\n';
            }
            table.push_back(row);
        }
        // The plot's data: one file per quantity, a row per scene, a column per engine.
        const std::pair<const char*, double Run::*> quantities[] = {
            {"solvers-drift.dat", &Run::topDrift}, {"solvers-speed.dat", &Run::lastSpeed}, {"solvers-ms.dat", &Run::msPerStep}};
        for (const auto& [file, field] : quantities) {
            auto dat = output.open(file);
            dat << "scene";
            for (const std::string& engine : engines) dat << " \"" << engine << '"';
            dat << '\n';
            for (const std::vector<Run>& row : table) {
                dat << row.front().scene;
                for (const Run& r : row) dat << ' ' << r.*field;
                dat << '\n';
            }
        }
        std::cout << "\nas theory says (stands, falls or rests as the scene should):";
        for (std::size_t k = 0; k < engines.size(); ++k) {
            int agree = 0;
            for (const std::vector<Run>& row : table) agree += asTheorySays(row[k].scene, row[k].verdict);
            std::cout << (k == 0 ? " " : ", ") << engines[k] << ' ' << agree << " of " << table.size();
        }
        std::cout << "\n\nwrote";
        for (const std::string& f : output.written()) std::cout << ' ' << out << '/' << f;
        std::cout << '\n';
    } catch (const std::exception& e) {
        std::cerr << "gpl-bench-solvers: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
