// The viewer's window: start, scenes, messages, quitting, and the state a script dumps (see app_impl.h).
#include <GL/freeglut.h>
#include <imgui.h>
#include <imgui_impl_glut.h>
#include <imgui_impl_opengl2.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "app_impl.h"

namespace gpl::viewer {

std::string timestamp() {
    char buf[32];
    const std::time_t t = std::time(nullptr);
    std::strftime(buf, sizeof buf, "%Y%m%d-%H%M%S", std::localtime(&t));
    return buf;
}

namespace {

App* gApp = nullptr;  // GLUT's callbacks are plain functions without a user pointer

}  // namespace

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
    if (options_.fluidParticles > 0) {
        PhysicsEngine& e = session_.engine();
        const std::size_t placed = fillContainer(e.fluids(), e.bodies(), static_cast<std::size_t>(options_.fluidParticles));
        if (placed < static_cast<std::size_t>(options_.fluidParticles)) {
            message("--fluid-particles: the container holds " + std::to_string(placed) + " of " +
                    std::to_string(options_.fluidParticles));
        }
    }
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
        if (!session_.engine().fluids().empty()) {
            std::printf("fluid particles: %zu, drawing the scene: %.2f ms per frame\n", session_.engine().fluids().size(),
                        drawMsSum_ / frame_);
        }
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
        hoveredParticle_.reset();
        hoveredFluid_.reset();
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
        return;
    }
    // Every body in view, and every soft mesh, each as the ball around its particles.
    std::vector<Body> all = session_.engine().bodies();
    const SoftBodies& soft = session_.engine().softBodies();
    for (std::size_t m = 0; m < soft.meshes.size(); ++m) {
        const Bounds box = meshBounds(soft, m);
        if (!box.isEmpty()) all.push_back(sphere(soft.meshes[m].name, std::max(0.5 * box.diagonal().norm(), 1e-3), 1.0).at(box.center()));
    }
    camera_.frame(all);
}

void App::quit(int code) {
    exitCode_ = code;
    quitting_ = true;
    glutLeaveMainLoop();
}

int App::sceneWidth() const {
    return panel_ ? std::max(width_ / 2, width_ - static_cast<int>(kPanelWidth) - 10) : width_;
}

void App::reshape(int w, int h) {
    width_ = std::max(1, w);
    height_ = std::max(1, h);
    ImGui_ImplGLUT_ReshapeFunc(w, h);
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
    j["kinetic_energy"] = e.kineticEnergy();
    j["contacts_shown"] = contacts_;
    j["contacts"] = e.contacts().size();
    j["contact_iterations"] = e.contactIterations();
    j["constraint_iterations"] = e.constraintIterations();
    for (std::size_t i = 0; i < kStageCount; ++i) {
        const auto s = static_cast<Stage>(i);
        if (e.requiredStages().contains(s)) j["stages"][stageName(s)] = e.stageEnabled(s);
    }
    j["selected_restitution"] =
        session_.selectedBody() ? nlohmann::json(session_.selectedBody()->restitution) : nlohmann::json();
    // The soft bodies: each mesh as the panel shows it, where its particles are, and the particles
    // hovered and selected ("flag#12").
    const SoftBodies& soft = e.softBodies();
    const auto named = [&soft](std::optional<std::uint32_t> i) {
        return i ? nlohmann::json(particleName(soft, *i)) : nlohmann::json();
    };
    j["soft"] = nlohmann::json::array();
    for (std::size_t m = 0; m < soft.meshes.size(); ++m) {
        const SoftMesh& mesh = soft.meshes[m];
        const Bounds box = meshBounds(soft, m);
        nlohmann::json row;
        row["name"] = mesh.name;
        row["kind"] = mesh.kind == SoftMesh::Kind::Cloth ? "cloth" : mesh.kind == SoftMesh::Kind::Rope ? "rope" : "soft body";
        row["method"] = mesh.method == SoftMethod::PBD ? "PBD" : "XPBD";
        row["particles"] = mesh.count;
        row["triangles"] = mesh.triangles.size();
        row["constraints"] = constraintCount(soft, m);
        row["largest_stretch"] = meshStretch(soft, m);
        row["volume_ratio"] = mesh.kind == SoftMesh::Kind::SoftBody ? nlohmann::json(soft.volumeRatio(m)) : nlohmann::json();
        row["min"] = {box.min().x(), box.min().y(), box.min().z()};
        row["max"] = {box.max().x(), box.max().y(), box.max().z()};
        j["soft"].push_back(row);
    }
    j["hovered_particle"] = named(hoveredParticle_);
    j["selected_particle"] = named(session_.selectedParticle());
    if (const auto i = session_.selectedParticle()) {
        j["selected_particle_position"] = {soft.x[*i].x(), soft.x[*i].y(), soft.x[*i].z()};
        j["selected_particle_velocity"] = {soft.v[*i].x(), soft.v[*i].y(), soft.v[*i].z()};
    }
    j["links_shown"] = softWire_;
    // The fluid as the panel shows it, and the particles hovered and selected (their index).
    const Fluids& fluid = e.fluids();
    if (!fluid.empty()) {
        nlohmann::json f;
        f["particles"] = fluid.size();
        f["method"] = fluidMethodName(e);
        f["iterations"] = fluid.parameters().iterations;
        f["density_error"] = fluid.densityError();
        f["largest_density_error"] = fluid.largestDensityError();
        f["colouring"] = fluidColouringName(fluidColouring_);
        f["range"] = fluidRange();
        const Bounds box = fluidBounds(fluid);
        f["min"] = {box.min().x(), box.min().y(), box.min().z()};
        f["max"] = {box.max().x(), box.max().y(), box.max().z()};
        if (const auto& c = fluid.container()) {
            f["container"] = {c->lower.x(), c->lower.y(), c->lower.z(), c->upper.x(), c->upper.y(), c->upper.z()};
            std::size_t outside = 0;
            for (const Vec3& q : fluid.x) outside += c->contains(q) ? 0 : 1;
            f["outside"] = outside;
        }
        f["hovered"] = hoveredFluid_ ? nlohmann::json(*hoveredFluid_) : nlohmann::json();
        const auto i = session_.selectedFluidParticle();
        f["selected"] = i ? nlohmann::json(*i) : nlohmann::json();
        if (i) f["selected_position"] = {fluid.x[*i].x(), fluid.x[*i].y(), fluid.x[*i].z()};
        j["fluid"] = f;
    }
    j["help"] = help_;
    j["panel"] = panel_;
    j["recording"] = !recording_.empty();
    j["error"] = session_.error();
    j["missing_hooks"] = e.missingHooks();
    // Where each moving body (and soft mesh) is drawn, the part of the window the side panel leaves
    // free and the overlay's box in it (pixels, y down), and for how long the scene's view hint
    // means to frame the bodies' motion.
    std::vector<PixelBox> boxes;
    // Each soft mesh with a particle free to move counts as a moving body (after the bodies).
    const bool bodiesInFront = camera_.movingBodies(e.bodies(), sceneWidth(), height_, boxes);
    const bool meshesInFront = movingMeshes(camera_, soft, sceneWidth(), height_, boxes);
    // The fluid counts as one moving body (after the meshes).
    const bool fluidInFront = fluidPixels(camera_, e.fluids(), sceneWidth(), height_, boxes);
    j["view"]["behind_eye"] = !(bodiesInFront && meshesInFront && fluidInFront);
    j["view"]["bodies"] = nlohmann::json::array();
    for (const PixelBox& b : boxes) j["view"]["bodies"].push_back({b.left, b.top, b.right, b.bottom});
    j["view"]["free"] = {0, 0, sceneWidth(), height_};
    j["view"]["overlay"] = {overlay_.left, overlay_.top, overlay_.right, overlay_.bottom};
    j["view"]["line_height"] = ImGui::GetTextLineHeightWithSpacing();
    j["view"]["seconds"] = session_.scene().viewSeconds;
    if (e.bodies().size() <= 50) {
        for (const Body& b : e.bodies()) j["positions"][b.name] = {b.position.x(), b.position.y(), b.position.z()};
    }
    return j.dump();
}

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
