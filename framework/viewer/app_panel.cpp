// Dear ImGui on top of the scene: the overlay, the side panel, the help and the tooltip.
#include <imgui.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>

#include "app_impl.h"
#include "gpl/rotation.h"

namespace gpl::viewer {
namespace {

constexpr const char* kLongestLabel = "gravity (m/s^2)";  // of the side panel's fields

std::string vec(const Vec3& v, int precision = 3) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%.*f, %.*f, %.*f)", precision, v.x(), precision, v.y(), precision, v.z());
    return buf;
}

}  // namespace

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
    // Gravity acts only through its stage (on particles, through their prediction): a scene
    // without it (spinning boxes in space) says so.
    const bool applied = e.stageActive(Stage::ConstantAcceleration) || e.stageActive(Stage::SoftPredict) ||
                         e.stageActive(Stage::FluidPredict) || e.stageActive(Stage::FluidSph);
    const char* gravity = !applied ? "not applied" : session_.gravityOn() ? "on" : "off";
    ImGui::Text("%s   stages: %s   gravity %s   %.0f fps", integratorName(e.integratorKind()),
                e.requiredStages().names().c_str(), gravity, ImGui::GetIO().Framerate);
    // Without the rotation stage a box keeps its orientation through every contact: a box balanced
    // on an edge or a corner is then the physics of the scene, not a fault of the student's kernel.
    const auto& bodies = e.bodies();
    if (e.stageActive(Stage::CollisionDetection) && !e.stageActive(Stage::Rotation) &&
        std::any_of(bodies.begin(), bodies.end(),
                    [](const Body& b) { return b.shape == Shape::Box && !b.isStatic(); })) {
        ImGui::TextUnformatted(
            "no rotate stage: a tilted box stays balanced on the edge or corner it lands on (rotation is worksheet 6)");
    }
    if (!e.missingHooks().empty()) {
        std::string hooks;
        for (const auto& h : e.missingHooks()) hooks += (hooks.empty() ? "" : ", ") + h;
        ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.35f, 1.0f), "not implemented: %s", hooks.c_str());
    }
    if (!session_.error().empty()) {
        ImGui::TextColored(ImVec4(1.0f, 0.3f, 0.3f, 1.0f), "%s", session_.error().c_str());
    }
    if (session_.ghostOn()) {
        std::string worst;
        const double d = session_.ghostDifference(&worst);
        ImGui::Text("reference ghost: largest difference %.4g m (%s)", d, worst.empty() ? "-" : worst.c_str());
    }
    if (!recording_.empty() && options_.frames == 0)
        ImGui::TextColored(ImVec4(1.0f, 0.2f, 0.2f, 1.0f), "REC %d frames", recorded_);
    if (!message_.empty() && SteadyClock::now() < messageUntil_) ImGui::Text("%s", message_.c_str());
    ImGui::TextDisabled("h: help   Tab: panel");
    const ImVec2 at = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
    overlay_ = {at.x, at.y, at.x + size.x, at.y + size.y};
    ImGui::End();
}

void App::drawPanel() {
    ImGui::SetNextWindowPos(ImVec2(static_cast<float>(width_) - kPanelWidth - 10.0f, 10.0f), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(kPanelWidth, static_cast<float>(height_) - 20.0f), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.85f);
    ImGui::Begin("Game Physics Lab", &panel_, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize);
    // Every field leaves room for the longest label beside it, whether the scrollbar shows or not.
    ImGui::PushItemWidth(-(ImGui::CalcTextSize(kLongestLabel).x + ImGui::GetStyle().ItemInnerSpacing.x));
    PhysicsEngine& e = session_.engine();

    if (ImGui::BeginCombo("scene", (session_.scene().key + " " + session_.scene().name).c_str())) {
        for (const Scene& s : scenes().all()) {
            if (ImGui::Selectable((s.key + " " + s.name).c_str(), &s == &session_.scene())) loadScene(s.name);
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
        if (ImGui::SliderFloat("speed", &speed, float(Session::kMinSpeed), float(Session::kMaxSpeed), "x%.3g", ImGuiSliderFlags_Logarithmic)) {
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
        if (ImGui::InputFloat3(kLongestLabel, g, "%.2f", ImGuiInputTextFlags_EnterReturnsTrue)) {
            try {
                session_.setGravity(Vec3(g[0], g[1], g[2]));
            } catch (const std::exception& ex) {
                message(ex.what());
            }
        }
        if (ImGui::BeginCombo("integrator", integratorName(e.integratorKind()))) {
            for (Integrator kind : kIntegrators) {
                if (ImGui::Selectable(integratorName(kind), kind == e.integratorKind())) session_.setIntegrator(kind);
            }
            ImGui::EndCombo();
        }
        if (e.requiredStages().contains(Stage::Friction) &&
            ImGui::BeginCombo("contact solver", contactSolverName(e.contactSolver()))) {
            for (ContactSolver solver : kContactSolvers) {
                if (ImGui::Selectable(contactSolverName(solver), solver == e.contactSolver())) {
                    session_.setContactSolver(solver);
                }
            }
            ImGui::EndCombo();
        }
        // The stages the scene requires, in the order a step runs them, each one can be switched off;
        // the others in one line.
        ImGui::Text("stages of a step (required by the scene):");
        std::string others;
        for (std::size_t i = 0; i < kStageCount; ++i) {
            const auto stage = static_cast<Stage>(i);
            if (!e.requiredStages().contains(stage)) {
                others += (others.empty() ? "" : ", ") + std::string(stageName(stage));
                continue;
            }
            // While the friction stage runs, it answers the contacts and these two stand idle (they
            // answer them again once it is switched off): shown greyed, still switchable.
            const bool idle = (stage == Stage::Interpenetration || stage == Stage::CollisionImpulses) &&
                              e.stageActive(Stage::Friction);
            bool on = e.stageEnabled(stage);
            if (idle) ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
            if (ImGui::Checkbox(stageName(stage), &on)) session_.setStageEnabled(stage, on);
            if (idle) {
                ImGui::PopStyleColor();
                if (ImGui::IsItemHovered()) ImGui::SetTooltip("idle while the friction stage answers the contacts");
            }
        }
        if (!others.empty()) ImGui::TextWrapped("not required: %s", others.c_str());
        if (!e.missingHooks().empty()) {
            ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.35f, 1.0f), "hooks not implemented yet:");
            for (const auto& h : e.missingHooks()) ImGui::BulletText("%s", h.c_str());
        }
    }

    if ((e.requiredStages().contains(Stage::CollisionDetection) || e.requiredStages().contains(Stage::Ropes)) &&
        ImGui::CollapsingHeader("Contacts", ImGuiTreeNodeFlags_DefaultOpen)) {
        ImGui::Checkbox("show contacts (k)", &contacts_);
        if (ImGui::IsItemHovered()) {
            ImGui::SetTooltip(
                "every point of every contact found in the last step, and its normal from the\n"
                "first body towards the second (none after a step back: they are found in a step)");
        }
        double deepest = 0.0;
        for (const Contact& c : e.contacts()) deepest = std::max(deepest, c.depth);
        ImGui::Text("contacts of the last step: %zu", e.contacts().size());
        if (!e.contacts().empty()) ImGui::Text("deepest overlap: %.3g mm", 1000.0 * deepest);
        int iterations = e.contactIterations();
        if (ImGui::SliderInt("iterations", &iterations, 1, Session::kMaxContactIterations, "%d",
                             ImGuiSliderFlags_Logarithmic)) {
            session_.setContactIterations(iterations);
        }
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("sweeps over the contacts per step, for impulses and overlaps");
    }

    drawSoftPanel();
    drawFluidPanel();

    if (ImGui::CollapsingHeader("Selected body", ImGuiTreeNodeFlags_DefaultOpen)) {
        if (const Body* b = session_.selectedBody()) {
            ImGui::Text("%s (%s%s)", b->name.c_str(), shapeName(b->shape), b->isStatic() ? ", static" : "");
            if (!b->isStatic()) ImGui::Text("mass %.4g kg", b->mass);
            ImGui::Text("position %s m", vec(b->position).c_str());
            ImGui::Text("velocity %s m/s", vec(b->velocity).c_str());
            ImGui::Text("angular velocity %s rad/s", vec(b->angularVelocity).c_str());
            ImGui::Text("kinetic %.4g J, potential %.4g J", kineticEnergy(*b), potentialEnergy(*b, e.gravity()));
            if (e.stageActive(Stage::Rotation)) {
                ImGui::TextWrapped("angular momentum %s kg m^2/s", vec(angularMomentum(*b)).c_str());
                if (ImGui::IsItemHovered()) ImGui::SetTooltip("about the origin: x cross m v + R I R^T omega");
            }
            float restitution = static_cast<float>(b->restitution);
            if (ImGui::SliderFloat("restitution", &restitution, 0.0f, 1.0f, "%.2f")) {
                session_.setRestitution(*session_.selected(), restitution);
            }
            if (ImGui::IsItemHovered()) {
                ImGui::SetTooltip("0 plastic .. 1 elastic; a pair bounces with the product of its two");
            }
            if (ImGui::Button("remove")) session_.removeSelected();
        } else {
            ImGui::TextDisabled("click on a body");
        }
    }

    if (ImGui::CollapsingHeader("Energy", ImGuiTreeNodeFlags_DefaultOpen)) {
        const EnergySeries& s = session_.energies();
        // Each curve fills its box from its lowest to its highest value: the box's height in joules
        // beside the last value tells a drift of microjoules from a fall of many joules.
        const auto plot = [](const char* label, const std::deque<float>& values) {
            std::vector<float> v(values.begin(), values.end());
            if (v.empty()) return;
            const auto [lowest, highest] = std::minmax_element(v.begin(), v.end());
            char overlay[64];
            std::snprintf(overlay, sizeof overlay, "%.4g J, span %.2g J", v.back(), *highest - *lowest);
            ImGui::PlotLines(label, v.data(), static_cast<int>(v.size()), 0, overlay, FLT_MAX, FLT_MAX, ImVec2(0, 50));
        };
        plot("kinetic", s.kinetic);
        plot("potential", s.potential);
        plot("total", s.total);
        const double drift = e.totalEnergy() - s.initialTotal;
        ImGui::Text("drift since reset: %+.4g J (%+.3g %%)", drift,
                    s.initialTotal != 0.0 ? 100.0 * drift / std::abs(s.initialTotal) : 0.0);
        if (e.stageActive(Stage::Rotation)) {
            ImGui::TextWrapped("angular momentum %s kg m^2/s", vec(e.angularMomentum()).c_str());
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("of every body, about the origin");
        }
    }

    if (ImGui::CollapsingHeader("Reference ghost", ImGuiTreeNodeFlags_DefaultOpen)) {
        if (!session_.ghostAvailable()) {
            ImGui::PushTextWrapPos(0.0f);
            ImGui::TextDisabled("not in this copy of the lab: it comes without the reference solution");
            ImGui::PopTextWrapPos();
        } else {
            bool on = session_.ghostWanted();
            if (ImGui::Checkbox("show the reference solution", &on)) {
                session_.setGhost(on);
                if (on) session_.reset();
            }
            if (session_.edited()) ImGui::TextDisabled("scene edited: reset (r) to compare again");
        }
    }

    if (ImGui::CollapsingHeader("Camera and recording")) {
        bool fly = camera_.flying();
        if (ImGui::Checkbox("fly mode (WASD, QE)", &fly)) camera_.setFlying(fly);
        if (ImGui::Button("reset camera")) frameScene();
        if (ImGui::Button(recording_.empty() ? "record PNG frames" : "stop recording")) toggleRecording();
    }
    ImGui::PopItemWidth();
    ImGui::End();
}

void App::drawSoftPanel() {
    const PhysicsEngine& e = session_.engine();
    const SoftBodies& soft = e.softBodies();
    if (soft.meshes.empty() || !ImGui::CollapsingHeader("Soft bodies", ImGuiTreeNodeFlags_DefaultOpen)) return;
    static const char* const kinds[] = {"cloth", "rope", "soft body"};
    for (std::size_t m = 0; m < soft.meshes.size(); ++m) {
        const SoftMesh& mesh = soft.meshes[m];
        ImGui::Text("%s (%s, %s)", mesh.name.c_str(), kinds[static_cast<int>(mesh.kind)],
                    mesh.method == SoftMethod::PBD ? "PBD" : "XPBD");
        ImGui::Indent();
        ImGui::Text("%u particles, %zu constraints", mesh.count, constraintCount(soft, m));
        if (mesh.kind == SoftMesh::Kind::SoftBody) {
            ImGui::Text("largest stretch %.3g %%, volume %.4g %%", 100.0 * meshStretch(soft, m),
                        100.0 * soft.volumeRatio(m));
        } else {
            ImGui::Text("largest stretch %.3g %%", 100.0 * meshStretch(soft, m));
        }
        if (ImGui::IsItemHovered()) {
            ImGui::SetTooltip("(length - rest) / rest over its %s%s",
                              mesh.kind == SoftMesh::Kind::Cloth  ? "grid's edges"
                              : mesh.kind == SoftMesh::Kind::Rope ? "segments"
                                                                  : "edges",
                              mesh.kind == SoftMesh::Kind::SoftBody
                                  ? ";\nvolume: its tetrahedra's over their rest volume"
                                  : "");
        }
        ImGui::Unindent();
    }
    int iterations = e.constraintIterations();
    if (ImGui::SliderInt("iterations##soft", &iterations, 1, Session::kMaxConstraintIterations, "%d",
                         ImGuiSliderFlags_Logarithmic)) {
        session_.setConstraintIterations(iterations);
    }
    if (ImGui::IsItemHovered()) {
        ImGui::SetTooltip(
            "projection sweeps per step over every constraint: a PBD mesh grows stiffer with more,\n"
            "an XPBD mesh keeps its compliance and only converges closer");
    }
    ImGui::Checkbox("show links", &softWire_);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("the distance constraints: edges dark, shear blue, bending green");
    if (const auto i = session_.selectedParticle()) {
        ImGui::Text("particle %s%s", particleName(soft, *i).c_str(), soft.w[*i] == 0.0 ? " (pinned)" : "");
        ImGui::Text("mass %.4g kg", soft.mass[*i]);
        ImGui::Text("position %s m", vec(soft.x[*i]).c_str());
        ImGui::Text("velocity %s m/s", vec(soft.v[*i]).c_str());
    } else {
        ImGui::TextDisabled("drag a particle with the mouse");
    }
}

void App::drawFluidPanel() {
    const PhysicsEngine& e = session_.engine();
    const Fluids& fluid = e.fluids();
    if (fluid.empty() || !ImGui::CollapsingHeader("Fluid", ImGuiTreeNodeFlags_DefaultOpen)) return;
    const FluidParameters& f = fluid.parameters();
    const bool sph = std::string(fluidMethodName(e)) == "WCSPH";
    ImGui::Text("%zu particles (%s)", fluid.size(), sph ? "WCSPH" : "PBF");
    if (ImGui::IsItemHovered()) {
        ImGui::SetTooltip(sph ? "weakly compressible SPH: Tait's pressure, stiff by its speed of sound (the comparison)"
                              : "position-based fluids: the density constraints projected, XSPH viscosity");
    }
    ImGui::Text("spacing %.3g cm, smoothing length %.3g cm", 100.0 * f.spacing, 100.0 * f.smoothingLength);
    ImGui::Text("density error: mean %.3g %%, largest %.3g %%", 100.0 * fluid.densityError(),
                100.0 * fluid.largestDensityError());
    if (ImGui::IsItemHovered()) {
        ImGui::SetTooltip(
            "rho / rho0 - 1 of the last density computation: the mean of its compression (above 0) and\n"
            "the largest (a particle at a free surface or a wall reads below rho0 without being stretched)");
    }
    if (sph) {
        ImGui::Text("%d substeps per step, speed of sound %.3g m/s", fluid.sphSubsteps(e.timeStep()), f.soundSpeed);
    } else {
        int iterations = f.iterations;
        if (ImGui::SliderInt("iterations##fluid", &iterations, 1, Session::kMaxFluidIterations, "%d",
                             ImGuiSliderFlags_Logarithmic)) {
            session_.setFluidIterations(iterations);
        }
        if (ImGui::IsItemHovered()) {
            ImGui::SetTooltip("sweeps of the density constraints per step: more hold the density closer to rho0");
        }
    }
    int colouring = fluidColouring_ == FluidColouring::Speed ? 1 : 0;
    ImGui::RadioButton("density error", &colouring, 0);
    ImGui::SameLine();
    ImGui::RadioButton("speed", &colouring, 1);
    fluidColouring_ = colouring == 1 ? FluidColouring::Speed : FluidColouring::DensityError;
    // The colour map as a bar, its range in the slider under it.
    const bool speed = fluidColouring_ == FluidColouring::Speed;
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImVec2 at = ImGui::GetCursorScreenPos();
    const float width = ImGui::CalcItemWidth(), height = ImGui::GetTextLineHeight();
    constexpr int kSteps = 32;
    for (int k = 0; k < kSteps; ++k) {
        std::uint8_t a[4], b[4];
        const double t0 = double(k) / kSteps, t1 = double(k + 1) / kSteps;
        speed ? sequentialColour(t0, a) : divergingColour(2.0 * t0 - 1.0, a);
        speed ? sequentialColour(t1, b) : divergingColour(2.0 * t1 - 1.0, b);
        const ImU32 left = IM_COL32(a[0], a[1], a[2], 255), right = IM_COL32(b[0], b[1], b[2], 255);
        draw->AddRectFilledMultiColor(ImVec2(at.x + width * float(t0), at.y), ImVec2(at.x + width * float(t1), at.y + height),
                                      left, right, right, left);
    }
    ImGui::Dummy(ImVec2(width, height));
    ImGui::SameLine();
    ImGui::TextUnformatted(speed ? "speed" : "rho / rho0 - 1");
    const double range = fluidRange();
    if (speed) {
        ImGui::Text("0 m/s .. %.3g m/s", range);
    } else {
        ImGui::Text("-%.3g %% .. 0 .. +%.3g %%", 100.0 * range, 100.0 * range);
    }
    float shown = static_cast<float>(speed ? range : 100.0 * range);
    if (ImGui::SliderFloat(speed ? "range (m/s)" : "range (%)", &shown, speed ? 0.1f : 0.1f, speed ? 10.0f : 50.0f, "%.3g",
                           ImGuiSliderFlags_Logarithmic) &&
        shown > 0.0f) {
        (speed ? speedRange_ : densityRange_) = speed ? shown : shown / 100.0;
    }
    if (const auto i = session_.selectedFluidParticle(); i && *i < fluid.size()) {
        ImGui::Text("particle %u", *i);
        ImGui::Text("position %s m", vec(fluid.x[*i]).c_str());
        ImGui::Text("velocity %s m/s", vec(fluid.v[*i]).c_str());
        ImGui::Text("rho / rho0 - 1: %.3g %%", 100.0 * densityErrorOf(fluid, *i));
    } else {
        ImGui::TextDisabled("drag a particle with the mouse");
    }
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
    if (mouseMode_ != MouseMode::None || ImGui::GetIO().WantCaptureMouse) return;
    const SoftBodies& soft = session_.engine().softBodies();
    if (hoveredParticle_ && *hoveredParticle_ < soft.x.size()) {
        const std::uint32_t i = *hoveredParticle_;
        ImGui::BeginTooltip();
        ImGui::Text("%s%s", particleName(soft, i).c_str(), soft.w[i] == 0.0 ? " (pinned)" : "");
        ImGui::Text("mass %.4g kg", soft.mass[i]);
        ImGui::Text("x %s m", vec(soft.x[i]).c_str());
        ImGui::Text("v %s m/s", vec(soft.v[i]).c_str());
        ImGui::EndTooltip();
        return;
    }
    const Fluids& fluid = session_.engine().fluids();
    if (hoveredFluid_ && *hoveredFluid_ < fluid.size()) {
        const std::uint32_t i = *hoveredFluid_;
        ImGui::BeginTooltip();
        ImGui::Text("fluid particle %u", i);
        ImGui::Text("x %s m", vec(fluid.x[i]).c_str());
        ImGui::Text("v %s m/s", vec(fluid.v[i]).c_str());
        ImGui::Text("rho / rho0 - 1: %.3g %%", 100.0 * densityErrorOf(fluid, i));
        ImGui::EndTooltip();
        return;
    }
    if (!hovered_) return;
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

}  // namespace gpl::viewer
