#include "app.h"

#include <GL/freeglut.h>
#include <imgui.h>
#include <imgui_impl_glut.h>
#include <imgui_impl_opengl2.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <deque>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

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
        {"o", "reference ghost on / off (builds with solutions)"},
        {"left drag on a body", "pull it with a spring to the cursor (and select it)"},
        {"left click", "select a body (click on nothing: clear)"},
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

namespace {

using SteadyClock = std::chrono::steady_clock;
constexpr double kFrameSeconds = 1.0 / 60.0;  // per frame in scripted and headless runs

std::string timestamp() {
    char buf[32];
    const std::time_t t = std::time(nullptr);
    std::strftime(buf, sizeof buf, "%Y%m%d-%H%M%S", std::localtime(&t));
    return buf;
}

std::string vec(const Vec3& v, int precision = 3) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%.*f, %.*f, %.*f)", precision, v.x(), precision, v.y(), precision, v.z());
    return buf;
}

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

    void loadScene(const std::string& key);
    void frameScene();  ///< the scene's own view, or every body in view
    void message(const std::string& text);
    void title();
    void drawOverlay();
    void drawPanel();
    void drawHelp();
    void drawTooltip();
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
    bool held_[256] = {};
    bool help_ = false;
    bool panel_ = true;
    std::string message_;
    SteadyClock::time_point messageUntil_;
    SteadyClock::time_point lastFrame_;
    bool deterministic_ = false;
    long frame_ = 0;
    double frameMsSum_ = 0.0, physicsMsSum_ = 0.0;
    std::string recording_;  // folder, empty when not recording
    int recorded_ = 0;
    int screenshots_ = 0;
    std::deque<std::string> script_;
    std::string pendingShot_;  // written after the next frame is drawn, panel and overlays included
    int scriptWait_ = 0;
    int exitCode_ = 0;
    bool quitting_ = false;
};

App* gApp = nullptr;  // GLUT's callbacks are plain functions without a user pointer

void App::init(int argc, char** argv) {
    glutInit(&argc, argv);
    glutSetOption(GLUT_ACTION_ON_WINDOW_CLOSE, GLUT_ACTION_GLUTMAINLOOP_RETURNS);
    glutInitDisplayMode(GLUT_DOUBLE | GLUT_RGBA | GLUT_DEPTH);
    glutInitWindowSize(options_.width, options_.height);
    glutCreateWindow("Game Physics Lab");
    width_ = options_.width;
    height_ = options_.height;

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // never write imgui.ini into the student's folder
    ImGui::StyleColorsDark();
    ImGui_ImplGLUT_Init();
    ImGui_ImplOpenGL2_Init();
    ImGui_ImplGLUT_ReshapeFunc(width_, height_);

    panel_ = options_.panel;
    session_.setPaused(options_.paused);
    session_.setGhost(options_.ghost);
    if (options_.dt > 0.0) session_.setTick(options_.dt);
    for (long long i = 0; i < options_.presteps; ++i) session_.stepOnce();
    frameScene();
    // Dear ImGui sizes auto-sized windows in their first frame and shows them from the second:
    // one frame now, never shown, so that the first frame drawn (or saved) is complete.
    for (int i = 0; i < 2; ++i) {
        ImGui_ImplOpenGL2_NewFrame();
        ImGui_ImplGLUT_NewFrame();
        drawOverlay();
        if (panel_) drawPanel();
        ImGui::Render();
    }
    deterministic_ = options_.frames > 0 || !options_.script.empty();
    std::istringstream script(options_.script);
    for (std::string cmd; std::getline(script, cmd, ';');) {
        const auto b = cmd.find_first_not_of(" \t\n"), e = cmd.find_last_not_of(" \t\n");
        if (b != std::string::npos) script_.push_back(cmd.substr(b, e - b + 1));
    }
    if (!options_.record.empty()) {
        recording_ = options_.record;
        std::filesystem::create_directories(recording_);
    }
    lastFrame_ = SteadyClock::now();
    title();

    glutDisplayFunc([] { gApp->display(); });
    glutIdleFunc([] { glutPostRedisplay(); });
    glutReshapeFunc([](int w, int h) { gApp->reshape(w, h); });
    glutKeyboardFunc([](unsigned char c, int x, int y) { gApp->keyboard(c, x, y); });
    glutKeyboardUpFunc([](unsigned char c, int x, int y) { gApp->keyboardUp(c, x, y); });
    glutSpecialFunc([](int k, int x, int y) { gApp->special(k, x, y); });
    glutSpecialUpFunc([](int k, int x, int y) { ImGui_ImplGLUT_SpecialUpFunc(k, x, y); });
    glutMouseFunc([](int b, int s, int x, int y) { gApp->mouse(b, s, x, y); });
    glutMotionFunc([](int x, int y) { gApp->motion(x, y); });
    glutPassiveMotionFunc([](int x, int y) { gApp->passive(x, y); });
    glutMouseWheelFunc([](int w, int d, int x, int y) { gApp->wheel(w, d, x, y); });
}

void App::shutdown() {
    if (!recording_.empty()) stopRecording();
    ImGui_ImplOpenGL2_Shutdown();
    ImGui_ImplGLUT_Shutdown();
    ImGui::DestroyContext();
    if (options_.benchmark && frame_ > 0) {
        const double ms = frameMsSum_ / frame_;
        std::printf("frames: %ld, bodies: %zu, mean frame time: %.2f ms (%.1f fps), of which physics %.2f ms\n", frame_,
                    session_.engine().bodies().size(), ms, 1000.0 / ms, physicsMsSum_ / frame_);
    }
}

void App::title() {
    const Scene& s = session_.scene();
    glutSetWindowTitle(("Game Physics Lab - " + s.key + " " + s.name).c_str());
}

void App::message(const std::string& text) {
    message_ = text;
    messageUntil_ = SteadyClock::now() + std::chrono::seconds(3);
    std::cout << "viewer: " << text << std::endl;
}

void App::loadScene(const std::string& key) {
    try {
        session_.load(scenes().find(key));
        frameScene();
        hovered_.reset();
        title();
        message("scene " + session_.scene().key + ": " + session_.scene().name);
    } catch (const std::invalid_argument&) {
        message("no scene on key " + key);
    }
}

void App::frameScene() {
    const Scene& s = session_.scene();
    if (s.viewDistance > 0.0) {
        camera_.lookAt(s.viewTarget, s.viewDistance);
    } else {
        camera_.frame(session_.engine().bodies());
    }
}

void App::quit(int code) {
    exitCode_ = code;
    quitting_ = true;
    glutLeaveMainLoop();
}

void App::reshape(int w, int h) {
    width_ = std::max(1, w);
    height_ = std::max(1, h);
    ImGui_ImplGLUT_ReshapeFunc(w, h);
}

void App::display() {
    if (quitting_) return;
    const auto start = SteadyClock::now();
    const double real = deterministic_ ? kFrameSeconds : std::chrono::duration<double>(start - lastFrame_).count();
    lastFrame_ = start;
    runScript();
    if (quitting_) return;

    // Fly mode: held keys move the camera at 8 m/s.
    if (camera_.flying()) {
        const double d = 8.0 * std::min(real, 0.1);
        camera_.move(Vec3((held_['d'] - held_['a']) * d, (held_['e'] - held_['q']) * d, (held_['w'] - held_['s']) * d));
    }
    session_.frame(std::min(real, 0.25));
    const auto physicsDone = SteadyClock::now();

    renderer_.draw(session_, camera_, width_, height_, mouseMode_ == MouseMode::None ? hovered_ : std::nullopt);

    ImGui_ImplOpenGL2_NewFrame();
    ImGui_ImplGLUT_NewFrame();  // calls ImGui::NewFrame() itself (imgui 1.86)
    drawOverlay();
    if (panel_) drawPanel();
    if (help_) drawHelp();
    drawTooltip();
    ImGui::Render();
    ImGui_ImplOpenGL2_RenderDrawData(ImGui::GetDrawData());

    ++frame_;
    if (!pendingShot_.empty()) {
        if (!savePng(pendingShot_)) message("cannot write " + pendingShot_);
        pendingShot_.clear();
    }
    if (!recording_.empty()) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%05d.png", ++recorded_);
        if (!savePng((std::filesystem::path(recording_) / name).string())) {
            message("cannot write frames to " + recording_ + ": recording stopped");
            recording_.clear();
        }
    }
    glutSwapBuffers();
    const auto end = SteadyClock::now();
    frameMsSum_ += std::chrono::duration<double, std::milli>(end - start).count();
    physicsMsSum_ += std::chrono::duration<double, std::milli>(physicsDone - start).count();
    if (options_.frames > 0 && frame_ >= options_.frames) quit(0);
}

bool App::savePng(const std::string& path) {
    std::vector<unsigned char> pixels(static_cast<std::size_t>(width_) * height_ * 3);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, width_, height_, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
    stbi_flip_vertically_on_write(1);
    return stbi_write_png(path.c_str(), width_, height_, 3, pixels.data(), width_ * 3) != 0;
}

void App::toggleRecording() {
    if (!recording_.empty()) {
        stopRecording();
        return;
    }
    const std::string dir = (std::filesystem::path(options_.out.empty() ? "recordings" : options_.out) /
                             (session_.scene().name + "-" + timestamp()))
                                .string();
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) {
        message("cannot create " + dir + ": " + ec.message());
        return;
    }
    recording_ = dir;
    recorded_ = 0;
    message("recording PNG frames to " + dir);
}

void App::stopRecording() {
    const std::string dir = recording_;
    recording_.clear();
    std::string text = "recorded " + std::to_string(recorded_) + " frames in " + dir;
    if (recorded_ > 1 && std::system("command -v ffmpeg >/dev/null 2>&1") == 0) {
        const std::string cmd = "ffmpeg -y -loglevel error -framerate 60 -i '" + dir +
                                "/frame_%05d.png' -pix_fmt yuv420p -vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' '" + dir +
                                "/video.mp4'";
        text += std::system(cmd.c_str()) == 0 ? " and " + dir + "/video.mp4" : " (ffmpeg failed to make a video)";
    }
    message(text);
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
            session_.shoot(camera_.rayThrough(mouseX_, mouseY_, width_, height_), 20.0);
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
                message("no reference ghost in this build (it needs solutions/)");
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
    const Ray ray = camera_.rayThrough(x, y, width_, height_);
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
            session_.dragTo(camera_.rayThrough(x, y, width_, height_));
            break;
        case MouseMode::None:
            break;
    }
}

void App::passive(int x, int y) {
    ImGui_ImplGLUT_MotionFunc(x, y);
    mouseX_ = x;
    mouseY_ = y;
    const auto hit = pick(session_.engine().bodies(), camera_.rayThrough(x, y, width_, height_));
    hovered_ = hit ? std::optional<std::size_t>(hit->index) : std::nullopt;
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
        try {
            const Body& b = session_.engine().body(first.substr(1));
            double px, py;
            if (!camera_.project(b.position, width_, height_, px, py)) return false;
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
            std::cerr << "error: bad script command '" << command << "'\n";
            quit(2);
            return;
        }
    }
}

std::string App::state() const {
    const PhysicsEngine& e = session_.engine();
    nlohmann::json j;
    j["frame"] = frame_;
    j["scene"] = session_.scene().name;
    j["key"] = session_.scene().key;
    j["paused"] = session_.paused();
    j["steps"] = e.stepCount();
    j["time"] = e.time();
    j["speed"] = session_.speed();
    j["substeps"] = session_.substeps();
    j["gravity"] = session_.gravityOn();
    j["integrator"] = integratorId(e.integratorKind());
    j["bodies"] = e.bodies().size();
    j["selected"] = session_.selectedBody() ? nlohmann::json(session_.selectedBody()->name) : nlohmann::json();
    j["hovered"] = hovered_ ? nlohmann::json(e.bodies()[*hovered_].name) : nlohmann::json();
    j["dragging"] = session_.dragging();
    j["history"] = session_.history().size();
    j["ghost"] = session_.ghostOn();
    j["ghost_difference"] = session_.ghostDifference();
    j["fly"] = camera_.flying();
    j["camera_distance"] = camera_.distance();
    j["camera_eye"] = {camera_.eye().x(), camera_.eye().y(), camera_.eye().z()};
    j["help"] = help_;
    j["panel"] = panel_;
    j["recording"] = !recording_.empty();
    j["error"] = session_.error();
    j["missing_hooks"] = e.missingHooks();
    if (e.bodies().size() <= 50) {
        for (const Body& b : e.bodies()) j["positions"][b.name] = {b.position.x(), b.position.y(), b.position.z()};
    }
    return j.dump();
}

// ---- ImGui: overlay, panel, help, tooltip ------------------------------------------------------

void App::drawOverlay() {
    const Scene& s = session_.scene();
    const PhysicsEngine& e = session_.engine();
    ImGui::SetNextWindowPos(ImVec2(10, 10));
    ImGui::SetNextWindowBgAlpha(0.55f);
    ImGui::Begin("overlay", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoInputs | ImGuiWindowFlags_AlwaysAutoResize |
                     ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav);
    ImGui::PushTextWrapPos(ImGui::GetFontSize() * 34.0f);
    ImGui::Text("%s  %s", s.key.c_str(), s.name.c_str());
    ImGui::TextWrapped("%s", s.description.c_str());
    ImGui::PopTextWrapPos();
    ImGui::Text("t = %.2f s   step %zu   h = %s s x %d   speed x%s%s", e.time(), e.stepCount(),
                formatNumber(session_.tick()).c_str(), session_.substeps(), formatNumber(session_.speed()).c_str(),
                session_.paused() ? "   PAUSED" : "");
    ImGui::Text("%s   stages: %s   gravity %s   %.0f fps", integratorName(e.integratorKind()),
                e.requiredStages().names().c_str(), session_.gravityOn() ? "on" : "off", ImGui::GetIO().Framerate);
    if (!e.missingHooks().empty()) {
        std::string hooks;
        for (const auto& h : e.missingHooks()) hooks += (hooks.empty() ? "" : ", ") + h;
        ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.35f, 1.0f), "not implemented: %s", hooks.c_str());
    }
    if (!session_.error().empty()) {
        ImGui::TextColored(ImVec4(1.0f, 0.3f, 0.3f, 1.0f), "%s", session_.error().c_str());
    }
    if (session_.ghostOn()) {
        std::size_t worst = 0;
        const double d = session_.ghostDifference(&worst);
        ImGui::Text("reference ghost: largest difference %.4g m (%s)", d,
                    worst < e.bodies().size() ? e.bodies()[worst].name.c_str() : "-");
    }
    if (!recording_.empty() && options_.frames == 0)
        ImGui::TextColored(ImVec4(1.0f, 0.2f, 0.2f, 1.0f), "REC %d frames", recorded_);
    if (!message_.empty() && SteadyClock::now() < messageUntil_) ImGui::Text("%s", message_.c_str());
    ImGui::TextDisabled("h: help   Tab: panel");
    ImGui::End();
}

void App::drawPanel() {
    const float width = 340.0f;
    ImGui::SetNextWindowPos(ImVec2(static_cast<float>(width_) - width - 10.0f, 10.0f), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(width, static_cast<float>(height_) - 20.0f), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.85f);
    ImGui::Begin("Game Physics Lab", &panel_, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize);
    PhysicsEngine& e = session_.engine();

    if (ImGui::BeginCombo("scene", (session_.scene().key + " " + session_.scene().name).c_str())) {
        for (const Scene& s : scenes().all()) {
            if (ImGui::Selectable((s.key + " " + s.name).c_str(), &s == &session_.scene())) loadScene(s.key);
        }
        ImGui::EndCombo();
    }

    if (ImGui::CollapsingHeader("Time", ImGuiTreeNodeFlags_DefaultOpen)) {
        if (ImGui::Button(session_.paused() ? "resume" : "pause")) session_.togglePause();
        ImGui::SameLine();
        if (ImGui::Button("step")) session_.setPaused(true), session_.stepOnce();
        ImGui::SameLine();
        if (ImGui::Button("back")) session_.setPaused(true), session_.stepBack();
        ImGui::SameLine();
        if (ImGui::Button("reset")) session_.reset();
        float speed = static_cast<float>(session_.speed());
        if (ImGui::SliderFloat("speed", &speed, 1.0f / 64.0f, 8.0f, "x%.3g", ImGuiSliderFlags_Logarithmic)) {
            session_.setSpeed(speed);
        }
        double tick = session_.tick();
        if (ImGui::InputDouble("time step (s)", &tick, 0.0, 0.0, "%.5g", ImGuiInputTextFlags_EnterReturnsTrue)) {
            try {
                session_.setTick(tick);
            } catch (const std::exception& ex) {
                message(ex.what());
            }
        }
        int substeps = session_.substeps();
        if (ImGui::SliderInt("substeps", &substeps, 1, 16)) session_.setSubsteps(substeps);
        ImGui::Text("history: %zu states, %.1f of %.0f MiB", session_.history().size(),
                    session_.history().bytes() / 1048576.0, session_.history().budget() / 1048576.0);
        if (session_.clock().dropped() > 0.0) {
            ImGui::TextColored(ImVec4(1, 0.6f, 0.3f, 1), "behind real time: %.2f s dropped",
                               session_.clock().dropped());
        }
    }

    if (ImGui::CollapsingHeader("Physics", ImGuiTreeNodeFlags_DefaultOpen)) {
        float g[3] = {static_cast<float>(e.gravity().x()), static_cast<float>(e.gravity().y()),
                      static_cast<float>(e.gravity().z())};
        if (ImGui::InputFloat3("gravity (m/s^2)", g, "%.2f", ImGuiInputTextFlags_EnterReturnsTrue)) {
            e.setGravity(Vec3(g[0], g[1], g[2]));
        }
        if (ImGui::BeginCombo("integrator", integratorName(e.integratorKind()))) {
            for (Integrator kind : kIntegrators) {
                if (ImGui::Selectable(integratorName(kind), kind == e.integratorKind())) session_.setIntegrator(kind);
            }
            ImGui::EndCombo();
        }
        ImGui::Text("stages (required by the scene):");
        for (std::size_t i = 0; i < kStageCount; ++i) {
            const auto stage = static_cast<Stage>(i);
            if (!e.requiredStages().contains(stage)) {
                ImGui::TextDisabled("  %s (not required)", stageName(stage));
                continue;
            }
            bool on = e.stageEnabled(stage);
            if (ImGui::Checkbox(stageName(stage), &on)) e.setStageEnabled(stage, on);
        }
        if (!e.missingHooks().empty()) {
            ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.35f, 1.0f), "hooks not implemented yet:");
            for (const auto& h : e.missingHooks()) ImGui::BulletText("%s", h.c_str());
        }
    }

    if (ImGui::CollapsingHeader("Energy", ImGuiTreeNodeFlags_DefaultOpen)) {
        const EnergySeries& s = session_.energies();
        const auto plot = [](const char* label, const std::deque<float>& values) {
            std::vector<float> v(values.begin(), values.end());
            if (v.empty()) return;
            char overlay[48];
            std::snprintf(overlay, sizeof overlay, "%.4g J", v.back());
            ImGui::PlotLines(label, v.data(), static_cast<int>(v.size()), 0, overlay, FLT_MAX, FLT_MAX, ImVec2(0, 50));
        };
        plot("kinetic", s.kinetic);
        plot("potential", s.potential);
        plot("total", s.total);
        const double drift = e.totalEnergy() - s.initialTotal;
        ImGui::Text("drift since reset: %+.4g J (%+.3g %%)", drift,
                    s.initialTotal != 0.0 ? 100.0 * drift / std::abs(s.initialTotal) : 0.0);
    }

    if (ImGui::CollapsingHeader("Reference ghost", ImGuiTreeNodeFlags_DefaultOpen)) {
        if (!session_.ghostAvailable()) {
            ImGui::TextDisabled("not in this build (needs solutions/)");
        } else {
            bool on = session_.ghostWanted();
            if (ImGui::Checkbox("show the reference solution", &on)) {
                session_.setGhost(on);
                if (on) session_.reset();
            }
            if (session_.edited()) ImGui::TextDisabled("scene edited: reset (r) to compare again");
        }
    }

    if (ImGui::CollapsingHeader("Selected body", ImGuiTreeNodeFlags_DefaultOpen)) {
        if (const Body* b = session_.selectedBody()) {
            ImGui::Text("%s (%s%s)", b->name.c_str(), shapeName(b->shape), b->isStatic() ? ", static" : "");
            if (!b->isStatic()) ImGui::Text("mass %.4g kg", b->mass);
            ImGui::Text("position %s m", vec(b->position).c_str());
            ImGui::Text("velocity %s m/s", vec(b->velocity).c_str());
            ImGui::Text("angular velocity %s rad/s", vec(b->angularVelocity).c_str());
            ImGui::Text("kinetic %.4g J, potential %.4g J", kineticEnergy(*b), potentialEnergy(*b, e.gravity()));
            if (ImGui::Button("remove")) session_.removeSelected();
        } else {
            ImGui::TextDisabled("click on a body");
        }
    }

    if (ImGui::CollapsingHeader("Camera and recording")) {
        bool fly = camera_.flying();
        if (ImGui::Checkbox("fly mode (WASD, QE)", &fly)) camera_.setFlying(fly);
        if (ImGui::Button("reset camera")) frameScene();
        if (ImGui::Button(recording_.empty() ? "record PNG frames" : "stop recording")) toggleRecording();
    }
    ImGui::End();
}

void App::drawHelp() {
    ImGui::SetNextWindowPos(ImVec2(width_ * 0.5f, height_ * 0.5f), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::Begin("Keys and mouse", &help_, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse);
    if (ImGui::BeginTable("bindings", 2, ImGuiTableFlags_RowBg)) {
        for (const auto& [keys, what] : bindings()) {
            ImGui::TableNextRow();
            ImGui::TableSetColumnIndex(0);
            ImGui::TextUnformatted(keys.c_str());
            ImGui::TableSetColumnIndex(1);
            ImGui::TextUnformatted(what.c_str());
        }
        ImGui::EndTable();
    }
    ImGui::End();
}

void App::drawTooltip() {
    if (!hovered_ || mouseMode_ != MouseMode::None || ImGui::GetIO().WantCaptureMouse) return;
    const auto& bodies = session_.engine().bodies();
    if (*hovered_ >= bodies.size()) return;
    const Body& b = bodies[*hovered_];
    ImGui::BeginTooltip();
    ImGui::Text("%s (%s%s)", b.name.c_str(), shapeName(b.shape), b.isStatic() ? ", static" : "");
    if (!b.isStatic()) ImGui::Text("mass %.4g kg", b.mass);
    ImGui::Text("x %s m", vec(b.position).c_str());
    ImGui::Text("v %s m/s", vec(b.velocity).c_str());
    ImGui::Text("w %s rad/s", vec(b.angularVelocity).c_str());
    ImGui::Text("energy %.4g J", kineticEnergy(b) + potentialEnergy(b, session_.engine().gravity()));
    ImGui::EndTooltip();
}

}  // namespace

int runViewer(int argc, char** argv, const Options& options) {
    App app(options);
    gApp = &app;
    app.init(argc, argv);
    glutMainLoop();
    app.shutdown();
    gApp = nullptr;
    return app.exitCode();
}

}  // namespace gpl::viewer
