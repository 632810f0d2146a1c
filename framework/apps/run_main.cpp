// gpl-run: steps a scene without a display and prints a summary; see ./lab run --help.
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>

#include "command_line.h"
#include "gpl/runner.h"
#include "gpl/scenes.h"

namespace {

int fail(const std::string& message) {
    std::cerr << "error: " << message << '\n';
    return 2;
}

// A failed assertion in a hook aborts the program within a step: the handler names the step and
// keeps the CSV of the steps before it (run() flushes each as it ends). Async-signal-safe only.
char csvPartial[4096] = "";
char csvFinal[4096] = "";

void say(const char* text) {
    if (write(STDOUT_FILENO, text, std::strlen(text)) < 0) return;
}

void onAbort(int signal) {
    const std::size_t step = gpl::stepInProgress();
    if (step > 0) {
        char digits[24];
        int n = 0;
        for (std::size_t s = step; s > 0 || n == 0; s /= 10) digits[n++] = static_cast<char>('0' + s % 10);
        char number[24];
        for (int i = 0; i < n; ++i) number[i] = digits[n - 1 - i];
        number[n] = '\0';
        say("stopped early: a failed assertion ended step ");
        say(number);
        if (csvFinal[0] && std::rename(csvPartial, csvFinal) == 0) {
            say("; the steps before it are in ");
            say(csvFinal);
        }
        say("\n");
    }
    ::signal(signal, SIG_DFL);
    raise(signal);
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Steps a scene headless and prints a summary (energy drift, hooks still open)."};
    std::string sceneName = "falling-sphere";
    long long steps = 500;
    double dt = NAN;
    std::string csvPath;
    std::string integrator;
    bool list = false;
    app.add_option("--scene,-s", sceneName, "scene name or key (1-9, 0, F1-F12)")->check(gpl::cli::sceneName());
    app.add_option("--steps,-n", steps, "number of time steps")->check(gpl::cli::wholeNumber(0));
    app.add_option("--dt", dt, "time step in seconds (default: the scene's)")->check(gpl::cli::positiveSeconds());
    app.add_option("--csv", csvPath, "write one row per body and step to this file");
    std::vector<std::string> integrators;
    for (const gpl::Integrator i : gpl::kIntegrators) integrators.push_back(gpl::integratorId(i));
    app.add_option("--integrator", integrator, "the integrator (default: the scene's)")
        ->check(gpl::cli::oneOf(integrators));
    app.add_flag("--list", list, "list the scenes and exit");
    if (const int status = gpl::cli::parse(app, argc, argv); status >= 0) return status;

    if (list) {
        for (const auto& s : gpl::scenes().all()) {
            std::cout << s.key << '\t' << s.name << "\t" << s.description << '\n';
        }
        return 0;
    }

    gpl::PhysicsEngine engine;
    const gpl::Scene* scene = nullptr;
    try {
        scene = &gpl::scenes().find(sceneName);
        gpl::load(engine, *scene);
        if (app.count("--dt")) engine.setTimeStep(dt);
        if (!integrator.empty()) engine.setIntegratorKind(gpl::integratorFromId(integrator));
    } catch (const std::exception& e) {
        return fail(e.what());
    }

    std::ofstream csv;
    const std::string partial = csvPath + ".partial";
    if (!csvPath.empty()) {
        csv.open(partial);
        if (!csv) return fail("--csv: cannot write the CSV file '" + csvPath + "'");
        gpl::writeCsvHeader(csv);
    }

    if (!csvPath.empty() && csvPath.size() < sizeof csvFinal && partial.size() < sizeof csvPartial) {
        std::strcpy(csvFinal, csvPath.c_str());
        std::strcpy(csvPartial, partial.c_str());
    }
    std::signal(SIGABRT, onAbort);
    std::cout << "scene " << scene->key << " '" << scene->name << "': " << scene->description << std::endl;
    const gpl::RunSummary summary = gpl::run(engine, static_cast<std::size_t>(steps), csvPath.empty() ? nullptr : &csv);
    std::cout << gpl::describe(summary, engine);

    if (!csvPath.empty()) {
        csv.close();
        if (!csv || std::rename(partial.c_str(), csvPath.c_str()) != 0) {
            std::remove(partial.c_str());
            return fail("could not finish writing '" + csvPath + "'");
        }
        std::cout << "wrote " << csvPath << '\n';
    }
    return summary.error.empty() ? 0 : 1;
}
