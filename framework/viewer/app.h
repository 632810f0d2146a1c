// The viewer application: a freeglut window with the scene, Dear ImGui's panel and overlays, and
// every key and mouse binding. Scripted input (--script) calls the same handlers GLUT calls.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "camera.h"
#include "renderer.h"
#include "session.h"

namespace gpl::viewer {

struct Options {
    std::string scene = "falling-sphere";
    int width = 1280, height = 720;
    int frames = 0;          ///< > 0: stop after this many frames (time steps 1/60 s per frame)
    std::string out;         ///< write every frame as PNG here (with frames > 0: the headless mode)
    std::string record;      ///< start recording into this folder
    long long presteps = 0;  ///< ticks to take before the first frame
    double dt = 0.0;         ///< > 0: the tick (s) instead of the scene's time step
    std::string script;      ///< commands separated by ';' (see README)
    bool paused = false;
    bool panel = true;
    bool ghost = false;
    bool benchmark = false;  ///< print frame timings at the end
    long long fluidParticles = 0;  ///< > 0: the scene's fluid replaced by this many at rest (fillContainer())
};

/// Runs the viewer; returns the process exit status.
int runViewer(int argc, char** argv, const Options& options);

/// The help text: every key and mouse binding (shown by 'h' and by --help).
const std::vector<std::pair<std::string, std::string>>& bindings();

}  // namespace gpl::viewer
