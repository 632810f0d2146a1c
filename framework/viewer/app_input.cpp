// Keys, mouse and scripted input: what each binding does (scripts call the same handlers GLUT calls).
#include <GL/freeglut.h>
#include <imgui.h>
#include <imgui_impl_glut.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "app_impl.h"

namespace gpl::viewer {

const std::vector<std::pair<std::string, std::string>>& bindings() {
    static const std::vector<std::pair<std::string, std::string>> b = {
        {"1-9, 0, F1-F10", "switch scene (F11, F12: your own scenes)"},
        {"space", "pause / resume"},
        {"n or .", "one step (pauses)"},
        {"b or ,", "step back through the recorded history (pauses)"},
        {"+ / -", "faster / slower (slow motion)"},
        {"r", "reset the scene"},
        {"g", "gravity on / off"},
        {"m", "next integrator (explicit Euler, semi-implicit Euler, Verlet, RK4)"},
        {"x", "shoot a sphere from the camera"},
        {"i", "insert a box at the camera's target"},
        {"Delete, Backspace", "remove the selected body"},
        {"o", "reference ghost on / off (builds with the reference engine)"},
        {"k", "contacts of the last step on / off: points and normals"},
        {"left drag on a body", "pull it with a spring to the cursor (and select it)"},
        {"left drag on cloth, a rope", "hold the particle and move it with the cursor (and select it)"},
        {"left drag in a fluid", "lead the particle with the cursor: the fluid makes way (and select it)"},
        {"left click", "select a body or particle (click on nothing: clear)"},
        {"left drag elsewhere", "orbit the camera"},
        {"right or middle drag", "pan"},
        {"mouse wheel", "zoom"},
        {"f", "fly mode on / off: W A S D move, Q E down / up, left drag looks"},
        {"c", "reset the camera"},
        {"Tab", "side panel on / off"},
        {"p", "save a PNG screenshot"},
        {"v", "start / stop recording PNG frames (and a video when ffmpeg is installed)"},
        {"h", "this help"},
        {"Esc", "close the help, or quit"},
    };
    return b;
}

void App::keyboard(unsigned char c, int x, int y) {
    ImGui_ImplGLUT_KeyboardFunc(c, x, y);
    if (ImGui::GetIO().WantCaptureKeyboard) return;
    onKey(c);
}

void App::onKey(unsigned char c) {
    held_[std::tolower(c)] = true;
    if (c >= '0' && c <= '9') return loadScene(std::string(1, static_cast<char>(c)));
    if (camera_.flying() && std::string("wasdqe").find(static_cast<char>(std::tolower(c))) != std::string::npos) return;
    switch (c) {
        case ' ':
            session_.togglePause();
            message(session_.paused() ? "paused" : "running");
            break;
        case 'n':
        case '.':
            session_.setPaused(true);
            session_.stepOnce();
            break;
        case 'b':
        case ',':
            session_.setPaused(true);
            if (!session_.stepBack()) message("the history is empty");
            break;
        case '+':
        case '=':
            session_.faster();
            message("speed x" + formatNumber(session_.speed()));
            break;
        case '-':
            session_.slower();
            message("speed x" + formatNumber(session_.speed()));
            break;
        case 'r':
            session_.reset();
            message("scene reset");
            break;
        case 'g':
            session_.toggleGravity();
            message(session_.gravityOn() ? "gravity on" : "gravity off");
            break;
        case 'x':
            session_.shoot(camera_.rayThrough(mouseX_, mouseY_, sceneWidth(), height_), 20.0);
            break;
        case 'i':
            session_.addBox(camera_.target() + Vec3(0.0, 3.0, 0.0));
            break;
        case 127:
        case 8:
            if (!session_.removeSelected()) message("select a body first (click on it)");
            break;
        case 'o':
            if (!session_.ghostAvailable()) {
                message("no reference ghost in this build: this copy of the lab comes without the reference solution");
            } else if (session_.ghostWanted()) {
                session_.setGhost(false);
                message("reference ghost off");
            } else {
                // The comparison starts from the scene's first state.
                session_.setGhost(true);
                session_.reset();
                message("reference ghost on: the scene starts again beside the reference solution");
            }
            break;
        case 'k':
            contacts_ = !contacts_;
            message(contacts_ ? "contacts shown" : "contacts hidden");
            break;
        case 'f':
            camera_.setFlying(!camera_.flying());
            message(camera_.flying() ? "fly mode: WASD, QE" : "orbit mode");
            break;
        case 'c':
            frameScene();
            break;
        case '\t':
            panel_ = !panel_;
            break;
        case 'h':
            help_ = !help_;
            break;
        case 'p': {
            const std::string dir = options_.out.empty() ? "recordings" : options_.out;
            std::filesystem::create_directories(dir);
            const std::string path =
                dir + "/" + session_.scene().name + "-" + timestamp() + "-" + std::to_string(++screenshots_) + ".png";
            message(savePng(path) ? "saved " + path : "cannot write " + path);
            break;
        }
        case 'v':
            toggleRecording();
            break;
        case 27:
            if (help_) {
                help_ = false;
            } else {
                quit(0);
            }
            break;
        default:
            break;
    }
}

void App::keyboardUp(unsigned char c, int x, int y) {
    ImGui_ImplGLUT_KeyboardUpFunc(c, x, y);
    held_[std::tolower(c)] = false;
}

void App::special(int key, int x, int y) {
    ImGui_ImplGLUT_SpecialFunc(key, x, y);
    if (ImGui::GetIO().WantCaptureKeyboard) return;
    onSpecial(key);
}

void App::onSpecial(int key) {
    if (key >= GLUT_KEY_F1 && key <= GLUT_KEY_F12) loadScene("F" + std::to_string(key - GLUT_KEY_F1 + 1));
}

void App::mouse(int button, int state, int x, int y) {
    ImGui_ImplGLUT_MouseFunc(button, state, x, y);
    const bool down = state == GLUT_DOWN;
    if (button == 3 || button == 4) {  // a wheel reported as buttons
        if (down) wheel(0, button == 3 ? 1 : -1, x, y);
        return;
    }
    if (down) {
        buttonsDown_ |= 1 << button;
    } else {
        buttonsDown_ &= ~(1 << button);
    }
    mouseX_ = x;
    mouseY_ = y;
    if (!down) {
        if (mouseMode_ == MouseMode::Drag) session_.endDrag();
        mouseMode_ = MouseMode::None;
        return;
    }
    if (ImGui::GetIO().WantCaptureMouse) return;
    const Ray ray = camera_.rayThrough(x, y, sceneWidth(), height_);
    if (button == GLUT_LEFT_BUTTON) {
        if (camera_.flying()) {
            mouseMode_ = MouseMode::Look;
        } else if (session_.beginDrag(ray, camera_.forward())) {
            mouseMode_ = MouseMode::Drag;
        } else {
            session_.pickAndSelect(ray);  // a static body, or nothing
            mouseMode_ = MouseMode::Orbit;
        }
    } else {
        mouseMode_ = MouseMode::Pan;
    }
}

void App::motion(int x, int y) {
    ImGui_ImplGLUT_MotionFunc(x, y);
    const int dx = x - mouseX_, dy = y - mouseY_;
    mouseX_ = x;
    mouseY_ = y;
    switch (mouseMode_) {
        case MouseMode::Orbit:
            camera_.orbit(dx, dy);
            break;
        case MouseMode::Look:
            camera_.look(dx, dy);
            break;
        case MouseMode::Pan:
            camera_.pan(dx, dy, height_);
            break;
        case MouseMode::Drag:
            session_.dragTo(camera_.rayThrough(x, y, sceneWidth(), height_));
            break;
        case MouseMode::None:
            break;
    }
}

void App::passive(int x, int y) {
    ImGui_ImplGLUT_MotionFunc(x, y);
    mouseX_ = x;
    mouseY_ = y;
    const Session::Picked hit = session_.pickAt(camera_.rayThrough(x, y, sceneWidth(), height_));
    const bool inScene = x < sceneWidth();
    hovered_ = inScene ? hit.body : std::nullopt;
    hoveredParticle_ = inScene ? hit.particle : std::nullopt;
    hoveredFluid_ = inScene ? hit.fluidParticle : std::nullopt;
}

void App::wheel(int wheelNumber, int direction, int x, int y) {
    ImGui_ImplGLUT_MouseWheelFunc(wheelNumber, direction, x, y);
    if (ImGui::GetIO().WantCaptureMouse) return;
    camera_.zoom(direction);
}

// ---- Scripted input: the same handlers, called from a list of commands --------------------------

bool App::scriptPoint(std::istringstream& in, int& x, int& y) {
    std::string first;
    if (!(in >> first)) return false;
    if (first[0] == '@') {
        // @name: a body; @mesh#k: the k-th particle of a cloth, rope or soft body.
        const auto particle = particleByName(session_.engine().softBodies(), first.substr(1));
        try {
            const Vec3 at = particle ? session_.engine().softBodies().x[*particle]
                                     : session_.engine().body(first.substr(1)).position;
            double px, py;
            if (!camera_.project(at, sceneWidth(), height_, px, py)) return false;
            x = static_cast<int>(std::lround(px));
            y = static_cast<int>(std::lround(py));
            return true;
        } catch (const std::out_of_range&) {
            return false;
        }
    }
    x = std::atoi(first.c_str());
    return static_cast<bool>(in >> y);
}

void App::runScript() {
    if (scriptWait_ > 0) {
        --scriptWait_;
        return;
    }
    while (!script_.empty()) {
        const std::string command = script_.front();
        script_.pop_front();
        std::istringstream in(command);
        std::string verb;
        in >> verb;
        int x = 0, y = 0;
        bool ok = true;
        if (verb == "wait") {
            in >> scriptWait_;
            return;  // the rest on later frames
        } else if (verb == "key" || verb == "keyup") {
            std::string k;
            in >> k;
            static const std::pair<const char*, unsigned char> names[] = {
                {"space", ' '},   {"esc", 27},   {"tab", '\t'}, {"del", 127},
                {"backspace", 8}, {"plus", '+'}, {"minus", '-'}};
            int fkey = 0;
            unsigned char c = k.size() == 1 ? static_cast<unsigned char>(k[0]) : 0;
            for (const auto& [name, code] : names) {
                if (k == name) c = code;
            }
            if (k.size() > 1 && k[0] == 'F') fkey = GLUT_KEY_F1 + std::atoi(k.c_str() + 1) - 1;
            // Keys go past Dear ImGui, which would ask GLUT for modifier keys outside an input callback.
            if (fkey) {
                onSpecial(fkey);
            } else if (c && verb == "key") {
                onKey(c);
            } else if (c) {
                held_[std::tolower(c)] = false;
            } else {
                ok = false;
            }
        } else if (verb == "down" || verb == "up") {
            std::string button;
            in >> button;
            const int b = button == "left"    ? GLUT_LEFT_BUTTON
                          : button == "right" ? GLUT_RIGHT_BUTTON
                                              : GLUT_MIDDLE_BUTTON;
            ok = scriptPoint(in, x, y);
            if (ok) mouse(b, verb == "down" ? GLUT_DOWN : GLUT_UP, x, y);
        } else if (verb == "move") {
            ok = scriptPoint(in, x, y);
            if (ok && buttonsDown_) motion(x, y);
            if (ok && !buttonsDown_) passive(x, y);
        } else if (verb == "wheel") {
            std::string dir;
            in >> dir;
            ok = scriptPoint(in, x, y);
            if (ok) wheel(0, dir == "up" ? 1 : -1, x, y);
        } else if (verb == "set") {
            // What the panel's widgets set: "set restitution 0.3" (of the selected body),
            // "set contact-iterations 4", "set constraint-iterations 20", "set speed 6",
            // "set stage impulses off", "set links on" (the soft bodies' wire view),
            // "set fluid-iterations 8", "set fluid-colour speed" (or density), "set fluid-range 0.05".
            std::string what, value;
            in >> what >> value;
            ok = !value.empty();
            if (ok && what == "restitution" && session_.selected()) {
                session_.setRestitution(*session_.selected(), std::atof(value.c_str()));
            } else if (ok && what == "contact-iterations") {
                session_.setContactIterations(std::atoi(value.c_str()));
            } else if (ok && what == "constraint-iterations") {
                session_.setConstraintIterations(std::atoi(value.c_str()));
            } else if (ok && what == "fluid-iterations") {
                session_.setFluidIterations(std::atoi(value.c_str()));
            } else if (ok && what == "fluid-colour" && (value == "speed" || value == "density")) {
                fluidColouring_ = value == "speed" ? FluidColouring::Speed : FluidColouring::DensityError;
            } else if (ok && what == "fluid-range") {
                // The panel's range of the colour map now shown (> 0).
                char* end = nullptr;
                const double range = std::strtod(value.c_str(), &end);
                ok = *end == '\0' && range > 0.0 && std::isfinite(range);
                if (ok) (fluidColouring_ == FluidColouring::Speed ? speedRange_ : densityRange_) = range;
            } else if (ok && what == "links" && (value == "on" || value == "off")) {
                softWire_ = value == "on";
            } else if (ok && what == "speed") {
                // The panel's slider: simulated seconds per real second.
                char* end = nullptr;
                const double speed = std::strtod(value.c_str(), &end);
                ok = *end == '\0' && speed >= Session::kMinSpeed && speed <= Session::kMaxSpeed;
                if (ok) session_.setSpeed(speed);
            } else if (ok && what == "stage") {
                // The stage's name may have spaces: the last word is on or off.
                std::string name = value, onOff;
                for (std::string word; in >> word;) name += " " + word;
                const auto space = name.rfind(' ');
                if (space != std::string::npos) onOff = name.substr(space + 1), name.resize(space);
                ok = false;
                for (std::size_t i = 0; i < kStageCount; ++i) {
                    if (name == stageName(static_cast<Stage>(i)) && (onOff == "on" || onOff == "off")) {
                        session_.setStageEnabled(static_cast<Stage>(i), onOff == "on");
                        ok = true;
                    }
                }
            } else {
                ok = false;
            }
        } else if (verb == "dump") {
            std::cout << "state " << state() << std::endl;
        } else if (verb == "shot") {
            std::string path;
            in >> path;
            ok = !path.empty();
            pendingShot_ = path;
            return;  // the shot is taken when this frame is drawn; the rest on later frames
        } else if (verb == "quit") {
            quit(0);
            return;
        } else {
            ok = false;
        }
        if (!ok) {
            std::cerr << "error: --script: expects commands such as 'key k', 'wait 10', 'down left X Y', "
                         "'set stage impulses off', 'dump', 'shot FILE.png' or 'quit', got '"
                      << command << "'\n";
            quit(2);
            return;
        }
    }
}

}  // namespace gpl::viewer
