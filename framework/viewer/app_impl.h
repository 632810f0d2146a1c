// The viewer application's one class, shared by the files that implement it, one concern each:
//   app.cpp        the window's life: start, scenes, messages, quitting, the state a script dumps
//   app_draw.cpp   one frame: step, draw the scene and Dear ImGui, save PNG frames and recordings
//   app_input.cpp  keys, mouse and scripted input (the same handlers GLUT calls)
//   app_panel.cpp  Dear ImGui: the overlay, the side panel, the help and the tooltip
// Only these files include it; the rest of the program sees app.h.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <optional>
#include <sstream>
#include <string>

#include "app.h"

namespace gpl::viewer {

using SteadyClock = std::chrono::steady_clock;

/// Local time as YYYYmmdd-HHMMSS, for the names of screenshots and recordings.
std::string timestamp();

class App {
public:
    explicit App(const Options& o) : options_(o), session_(scenes().find(o.scene)) {}

    void init(int argc, char** argv);
    int exitCode() const { return exitCode_; }
    void shutdown();

    // GLUT handlers.
    void display();
    void reshape(int w, int h);
    void keyboard(unsigned char c, int x, int y);
    void keyboardUp(unsigned char c, int x, int y);
    void special(int key, int x, int y);
    // What a key does, once Dear ImGui has declined it (also called by scripts).
    void onKey(unsigned char c);
    void onSpecial(int key);
    void mouse(int button, int state, int x, int y);
    void motion(int x, int y);
    void passive(int x, int y);
    void wheel(int wheelNumber, int direction, int x, int y);

private:
    enum class MouseMode { None, Orbit, Pan, Drag, Look };
    static constexpr float kPanelWidth = 340.0f;  ///< pixels, 10 more to the window's right edge

    /// Width of the scene's viewport (pixels): the window left of the side panel when it is shown
    /// (at least half the window), so that the scene is framed where nothing covers it.
    int sceneWidth() const;

    void loadScene(const std::string& key);
    void frameScene();  ///< the scene's own view, or every body in view
    void message(const std::string& text);
    void title();
    void drawOverlay();
    void drawPanel();
    void drawHelp();
    void drawTooltip();
    void drawSoftPanel();
    void drawFluidPanel();
    /// The colour map's range for the fluid's colouring now shown.
    double fluidRange() const { return fluidColouring_ == FluidColouring::Speed ? speedRange_ : densityRange_; }
    void runScript();
    bool scriptPoint(std::istringstream& in, int& x, int& y);
    bool savePng(const std::string& path);
    void toggleRecording();
    void stopRecording();
    void quit(int code);
    std::string state() const;

    Options options_;
    Session session_;
    Camera camera_;
    Renderer renderer_;
    int width_ = 0, height_ = 0;
    int mouseX_ = 0, mouseY_ = 0;
    int buttonsDown_ = 0;
    MouseMode mouseMode_ = MouseMode::None;
    std::optional<std::size_t> hovered_;
    std::optional<std::uint32_t> hoveredParticle_;  ///< of the soft bodies
    std::optional<std::uint32_t> hoveredFluid_;     ///< of the fluid
    FluidColouring fluidColouring_ = FluidColouring::DensityError;
    double densityRange_ = kDefaultDensityRange;  ///< +- this share of the rest density at the map's ends
    double speedRange_ = kDefaultSpeedRange;      ///< m/s at the sequential map's end
    bool held_[256] = {};
    bool help_ = false;
    bool panel_ = true;
    bool contacts_ = false;  ///< draw the contacts of the last step
    bool softWire_ = false;  ///< draw the soft bodies' links over their surfaces
    std::string message_;
    SteadyClock::time_point messageUntil_;
    SteadyClock::time_point lastFrame_;
    bool deterministic_ = false;
    long frame_ = 0;
    double frameMsSum_ = 0.0, physicsMsSum_ = 0.0;
    double drawMsSum_ = 0.0;  ///< the scene's drawing, finished (glFinish), with --benchmark
    std::string recording_;  // folder, empty when not recording
    int recorded_ = 0;
    int screenshots_ = 0;
    std::deque<std::string> script_;
    PixelBox overlay_;         // where the overlay was drawn last (pixels, y down)
    std::string pendingShot_;  // written after the next frame is drawn, panel and overlays included
    int scriptWait_ = 0;
    int exitCode_ = 0;
    bool quitting_ = false;
};

}  // namespace gpl::viewer
