#include "panel.hpp"

#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "key_help.hpp"

namespace viewer {

namespace {

const char* method_names[] = {"fitted rotations", "paper (Au et al.)"};

// A grey line of text that wraps at the panel's edge.
void note(const char* text) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
    ImGui::TextWrapped("%s", text);
    ImGui::PopStyleColor();
}

}  // namespace

void Panel::remember(const char* name) {
    // A control scrolled out of sight cannot be clicked: a script finds
    // only what a user could.
    if (!ImGui::IsItemVisible()) return;
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    controls_[name] = {a.x, a.y, b.x, b.y};
}

bool Panel::find_control(const std::string& name, ControlRect& out) const {
    const auto it = controls_.find(name);
    if (it == controls_.end()) return false;
    out = it->second;
    return true;
}

void Panel::set_path(const std::string& path) {
    std::snprintf(path_, sizeof path_, "%s", path.c_str());
}

void Panel::draw(double frame_ms) {
    controls_.clear();
    if (path_[0] == '\0') set_path(editor_.mesh_output());
    const ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(0, 0));
    ImGui::SetNextWindowSize(ImVec2(width, io.DisplaySize.y));
    ImGui::Begin("Dualform", nullptr,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
    const dfm_mesh_info& mesh = editor_.mesh_info();
    ImGui::TextWrapped("%s", editor_.mesh_spec().c_str());
    ImGui::Text("%zu vertices, %zu triangles", mesh.vertex_count, mesh.triangle_count);
    draw_region();
    draw_handles();
    draw_solver(frame_ms);
    draw_edit();
    draw_file();
    if (!editor_.last_error().empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.45f, 0.4f, 1.0f));
        ImGui::TextWrapped("%s", editor_.last_error().c_str());
        ImGui::PopStyleColor();
    }
    ImGui::End();
    if (help_open_) draw_help();
}

void Panel::draw_region() {
    if (!ImGui::CollapsingHeader("Region", ImGuiTreeNodeFlags_DefaultOpen)) return;
    switch (editor_.stage()) {
        case Editor::Stage::pick_first: note("Click the limb's tip."); return;
        case Editor::Stage::pick_last: note("Click where the region should end."); return;
        case Editor::Stage::suspect:
        case Editor::Stage::handles: break;
    }
    const dfm_water_fill_diagnosis& d = editor_.diagnosis();
    ImGui::Text("ROI %zu vertices, %zu boundary loop%s", editor_.roi_size(), d.loops,
                d.loops == 1 ? "" : "s");
    if (!d.suspect) {
        ImGui::Text("diagnosis: plausible");
        return;
    }
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.35f, 0.3f, 1.0f));
    ImGui::Text("SUSPECT region");
    ImGui::PopStyleColor();
    // dfm_water_fill_diagnosis: a region that leaked is bounded by more than
    // one loop, or not by the loop through the second click.
    if (!d.bounded_by_last_loop) note("The loop through the second click does not bound it.");
    if (d.loops > 1) note("More than one cut loop bounds it: it may have leaked.");
    if (editor_.stage() == Editor::Stage::suspect) {
        if (ImGui::Button("Keep it (Enter)")) editor_.key("enter");
        remember("keep");
        ImGui::SameLine();
        if (ImGui::Button("Cancel (Esc)")) editor_.key("escape");
        remember("cancel");
    }
}

void Panel::draw_handles() {
    if (!ImGui::CollapsingHeader("Handles", ImGuiTreeNodeFlags_DefaultOpen)) return;
    const auto& groups = editor_.groups();
    if (editor_.stage() != Editor::Stage::handles) {
        note("Select a region first.");
        return;
    }
    if (groups.empty()) note("Click on the region to add a handle group.");
    for (std::size_t g = 0; g < groups.size(); ++g) {
        ImGui::BulletText("group %zu: %zu vertices", g + 1, groups[g].size());
    }
    ImGui::Text("ball %.3f x diag", editor_.handle_radius());
    ImGui::SameLine();
    if (ImGui::SmallButton("-")) editor_.key("[");
    ImGui::SameLine();
    if (ImGui::SmallButton("+")) editor_.key("]");
    ImGui::SameLine();
    if (ImGui::SmallButton("Reset (R)")) editor_.reset_transforms();
    remember("reset");
}

void Panel::draw_solver(double frame_ms) {
    if (!ImGui::CollapsingHeader("Solver", ImGuiTreeNodeFlags_DefaultOpen)) return;
    dfm_solver_settings s = editor_.solver();
    bool changed = false;
    const ImGuiInputTextFlags field = ImGuiInputTextFlags_EnterReturnsTrue |
                                      ImGuiInputTextFlags_AutoSelectAll |
                                      ImGuiInputTextFlags_CharsScientific;
    ImGui::PushItemWidth(110);
    changed |= ImGui::InputDouble("tolerance", &s.tolerance, 0.0, 0.0, "%.3g", field);
    remember("tolerance");
    int cap = static_cast<int>(s.max_iterations);
    if (ImGui::InputInt("max iterations", &cap, 0, 0, ImGuiInputTextFlags_EnterReturnsTrue)) {
        s.max_iterations = cap > 0 ? static_cast<std::uint32_t>(cap) : 0u;
        changed = true;
    }
    remember("iterations");
    if (!s.hard_handles) {
        changed |= ImGui::InputDouble("weight", &s.handle_weight, 0.0, 0.0, "%.3g", field);
        remember("weight");
        ImGui::SameLine();
    }
    changed |= ImGui::Checkbox("hard", &s.hard_handles);
    remember("hard");
    int method = s.method == DFM_METHOD_PAPER ? 1 : 0;
    ImGui::SetNextItemWidth(140);
    if (ImGui::Combo("method", &method, method_names, 2)) {
        s.method = method == 1 ? DFM_METHOD_PAPER : DFM_METHOD_FITTED_ROTATIONS;
        changed = true;
    }
    remember("method");
    ImGui::PopItemWidth();
    if (changed) editor_.set_solver(s);

    const dfm_frame_info& f = editor_.last_frame();
    ImGui::Text("viewer frame %.1f ms", frame_ms);
    if (!editor_.has_session()) {
        note("The solve starts with the first drag.");
        return;
    }
    if (f.preparing) {
        ImGui::Text("setting up the system...");
        return;
    }
    ImGui::Text("solve %llu: %u iteration%s, %.2f ms",
                static_cast<unsigned long long>(f.generation), f.iterations,
                f.iterations == 1 ? "" : "s", f.solve_ms);
    const ImVec4 amber(1.0f, 0.8f, 0.3f, 1.0f), green(0.45f, 0.9f, 0.45f, 1.0f);
    if (f.partial) {
        ImGui::TextColored(amber, "preview: newer targets waiting");
    } else if (f.converged) {
        ImGui::TextColored(green, "converged, last update %.1e", f.last_update);
    } else {
        ImGui::TextColored(amber, "stopped at the iteration cap");
    }
    dfm_solve_report report = {};
    if (editor_.solve_report(report)) {
        ImGui::Text("%zu unknowns, set-up %.1f ms", report.unknowns, report.setup_ms);
    }
}

void Panel::draw_edit() {
    char header[64];
    // ### keeps the header's identity while its text changes.
    std::snprintf(header, sizeof header, "Edit: %zu baked###edit", editor_.bakes());
    if (!ImGui::CollapsingHeader(header, ImGuiTreeNodeFlags_DefaultOpen)) return;
    if (ImGui::Button("Bake (B)")) editor_.bake();
    remember("bake");
    ImGui::SameLine();
    if (ImGui::Button("Undo (^Z)")) editor_.undo_or_redo(true);
    remember("undo");
    ImGui::SameLine();
    if (ImGui::Button("Redo (^Y)")) editor_.undo_or_redo(false);
    remember("redo");
}

void Panel::draw_file() {
    if (!ImGui::CollapsingHeader("File", ImGuiTreeNodeFlags_DefaultOpen)) return;
    ImGui::PushItemWidth(-1);
    ImGui::InputText("##path", path_, sizeof path_, ImGuiInputTextFlags_AutoSelectAll);
    remember("path");
    ImGui::PopItemWidth();
    if (ImGui::Button("Open")) {
        file_message_ = editor_.reopen(path_) ? std::string("opened ") + path_ : "";
    }
    remember("open");
    ImGui::SameLine();
    if (ImGui::Button("Save (S)")) {
        file_message_ =
            editor_.save_mesh(path_, morph_target_) ? std::string("saved ") + path_ : "";
    }
    remember("save");
    ImGui::SameLine();
    if (ImGui::Button(help_open_ ? "Hide help" : "Help (H)")) toggle_help();
    remember("help");
    ImGui::PushItemWidth(-1);
    ImGui::InputTextWithHint("##morph", "morph target name (glTF, FBX)", morph_target_,
                             sizeof morph_target_);
    remember("morph");
    ImGui::PopItemWidth();
    note("Format by extension: .off .obj .ply .gltf .glb .fbx");
    if (!file_message_.empty()) ImGui::TextWrapped("%s", file_message_.c_str());
}

void Panel::draw_help() {
    // Centred over the whole window and in front of the panel.
    const ImGuiIO& io = ImGui::GetIO();
    const float help_width = std::min(560.0f, io.DisplaySize.x - 16.0f);
    ImGui::SetNextWindowPos(ImVec2(0.5f * io.DisplaySize.x, 0.5f * io.DisplaySize.y),
                            ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowSize(ImVec2(help_width, 0.0f));
    ImGui::SetNextWindowFocus();
    ImGui::Begin("Help: H or F1 closes it", &help_open_,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoResize |
                     ImGuiWindowFlags_AlwaysAutoResize);
    const auto table = [](const char* id, std::span<const KeyHelp> rows) {
        if (!ImGui::BeginTable(id, 2, ImGuiTableFlags_RowBg)) return;
        ImGui::TableSetupColumn("input", ImGuiTableColumnFlags_WidthFixed, 150.0f);
        ImGui::TableSetupColumn("does", ImGuiTableColumnFlags_WidthStretch);
        for (const KeyHelp& row : rows) {
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(row.input);
            ImGui::TableNextColumn();
            ImGui::TextWrapped("%s", row.does);
        }
        ImGui::EndTable();
    };
    ImGui::Text("Mouse (outside the panel)");
    table("mouse", mouse_help());
    ImGui::Separator();
    ImGui::Text("Keys (while no panel field has the keyboard)");
    table("keys", key_help());
    ImGui::End();
}

}  // namespace viewer
