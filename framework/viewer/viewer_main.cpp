// gpl-viewer: the scene viewer; see ./lab viewer --help and the README.
#include <filesystem>
#include <iostream>

#include "app.h"
#include "command_line.h"
#include "gpl/scenes.h"

int main(int argc, char** argv) {
    gpl::viewer::Options o;
    std::string bindingsText = "\nKeys and mouse:\n";
    for (const auto& [keys, what] : gpl::viewer::bindings()) bindingsText += "  " + keys + ": " + what + "\n";
    CLI::App app{"Game Physics Lab scene viewer.", "gpl-viewer"};
    app.footer(bindingsText);
    std::string positional;
    app.add_option("scene", positional, "scene name or key (default: falling-sphere)")->check(gpl::cli::sceneName());
    app.add_option("--scene,-s", o.scene, "scene name or key")->check(gpl::cli::sceneName());
    app.add_option("--frames", o.frames,
                   "render this many frames (1/60 s of simulated time each) into --out, then exit")
        ->check(gpl::cli::wholeNumber(0, std::numeric_limits<int>::max()));
    app.add_option("--out", o.out, "folder for frames (with --frames: every frame) and screenshots");
    app.add_option("--record", o.record, "record every frame as PNG into this folder from the start");
    app.add_option("--steps", o.presteps, "time steps to take before the first frame")->check(gpl::cli::wholeNumber(0));
    app.add_option("--dt", o.dt, "time step in seconds (default: the scene's)")->check(gpl::cli::positiveSeconds());
    app.add_option("--script", o.script, "input commands separated by ';' (for tests and demos)");
    app.add_option("--width", o.width, "window width (pixels)")->check(gpl::cli::wholeNumber(64, 8192));
    app.add_option("--height", o.height, "window height (pixels)")->check(gpl::cli::wholeNumber(64, 8192));
    app.add_flag("--paused", o.paused, "start paused");
    bool noPanel = false;
    app.add_flag("--no-panel", noPanel, "start without the side panel");
    app.add_flag("--ghost", o.ghost, "start with the reference ghost (builds with the reference engine)");
    app.add_flag("--benchmark", o.benchmark, "print the mean frame time at the end");
    app.add_option("--fluid-particles", o.fluidParticles,
                   "replace the scene's fluid by this many particles at rest, filling its container from the floor "
                   "(to time the drawing: with --paused --benchmark)")
        ->check(gpl::cli::wholeNumber(1, 10000000));
    if (const int status = gpl::cli::parse(app, argc, argv); status >= 0) return status;
    o.panel = !noPanel;
    if (!positional.empty()) o.scene = positional;
    // Frames that are rendered and then thrown away are a mistake, not a run: headless, they are
    // all there is to see.
    if (o.frames > 0 && o.out.empty() && o.record.empty() && o.script.empty() && !o.benchmark) {
        std::cerr << "error: --frames: expects --out DIR to write the frames to (or --benchmark to time them), got "
                     "--frames "
                  << o.frames << " alone\n";
        return 2;
    }

    for (const auto& [option, folder] : {std::pair{"--out", o.out}, std::pair{"--record", o.record}}) {
        if (folder.empty()) continue;
        if (const std::string error = gpl::cli::makeFolder(option, folder); !error.empty()) {
            std::cerr << "error: " << error << '\n';
            return 2;
        }
    }
    if (o.frames > 0 && !o.out.empty()) o.record = o.out;
    int glutArgc = 1;
    return gpl::viewer::runViewer(glutArgc, argv, o);
}
