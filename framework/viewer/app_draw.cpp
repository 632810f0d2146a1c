// One frame of the viewer: step, draw the scene and Dear ImGui, save PNG frames and recordings.
#include <GL/freeglut.h>
#include <imgui.h>
#include <imgui_impl_glut.h>
#include <imgui_impl_opengl2.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "app_impl.h"

namespace gpl::viewer {
namespace {

constexpr double kFrameSeconds = 1.0 / 60.0;  // per frame in scripted and headless runs

}  // namespace

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
        const auto held = [this](unsigned char key) { return held_[key] ? 1.0 : 0.0; };
        camera_.move(Vec3((held('d') - held('a')) * d, (held('e') - held('q')) * d, (held('w') - held('s')) * d));
    }
    session_.frame(std::min(real, 0.25));
    const auto physicsDone = SteadyClock::now();

    Renderer::Options view;
    if (mouseMode_ == MouseMode::None) view.hovered = hovered_, view.hoveredParticle = hoveredParticle_;
    view.contacts = contacts_;
    view.softWire = softWire_;
    if (mouseMode_ == MouseMode::None) view.hoveredFluidParticle = hoveredFluid_;
    view.fluidColouring = fluidColouring_;
    view.fluidRange = fluidRange();
    renderer_.draw(session_, camera_, sceneWidth(), height_, view);
    if (options_.benchmark) {
        // The scene's drawing alone: a software renderer draws when asked to finish.
        glFinish();
        drawMsSum_ += std::chrono::duration<double, std::milli>(SteadyClock::now() - physicsDone).count();
    }

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
    // The rendered scenes are large flat colours: rows stored as they are (filter 0) write a frame
    // in about half the time of stb's default (all five filters tried per row), and the file is
    // no larger.
    stbi_write_force_png_filter = 0;
    stbi_write_png_compression_level = 2;
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

}  // namespace gpl::viewer
