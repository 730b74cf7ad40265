#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "dualform/dualform.h"
#include "dualform/dualform_vulkan.h"
#include "orbit_camera.hpp"

namespace viewer {

// The interactive edit, apart from where its input comes from: GLFW's
// callbacks and a --script file call the same methods. It talks to
// Dualform through dualform.h and draws through dualform_vulkan.h only.
class Editor {
public:
    enum class Stage { pick_first, pick_last, suspect, handles };
    enum class Button { left, middle, right };

    Editor(dfm_context* context, dfm_vk_renderer* renderer);
    ~Editor();
    Editor(const Editor&) = delete;
    Editor& operator=(const Editor&) = delete;

    // Loads the mesh and frames it; false with the SDK's message on stderr.
    bool open(const std::string& mesh_spec, int width, int height);
    // Replaces the mesh (selection and edit dropped), keeping the view's
    // size; the old mesh stays when the new one cannot be loaded.
    bool reopen(const std::string& mesh_spec);

    void resize(int width, int height);
    void press(Button button, double x, double y, bool shift);
    void release(Button button, double x, double y);
    void move(double x, double y);
    void scroll(double steps);
    // "b", "ctrl+z", "enter", "escape", "backspace", "w", ... (see README).
    void key(const std::string& name);

    // Once per frame: hands changed transforms to the solver, picks up its
    // newest result and gives the renderer what changed.
    bool update();

    bool write_screenshot(const std::string& path);
    bool save_scenario(const std::string& path) const;
    // The view as the camera JSON of docs/scenarios.md (for `dualform render`).
    bool save_camera(const std::string& path) const;
    // Bakes an unbaked edit, then writes the mesh; the format follows the
    // extension (dfm_mesh_save_with_options).
    // Saves the rest pose (baking an unbaked edit first). `morph_target`,
    // when not empty, keeps a glTF asset's positions and adds the edit as a
    // morph target of that name.
    bool save_mesh(const std::string& path, const std::string& morph_target = {});
    void set_mesh_output(const std::string& path) { mesh_output_ = path; }
    const std::string& mesh_output() const { return mesh_output_; }
    const std::string& mesh_spec() const { return mesh_spec_; }

    void bake();
    void undo_or_redo(bool undo);
    void reset_transforms();

    // The solver settings the next solves use. Tolerance and the iteration
    // cap reach a running session through dfm_session_set_solver; the
    // settings fixed at a session's creation (handle weight, hard handles,
    // method) start a new session on the same edit.
    const dfm_solver_settings& solver() const { return solver_; }
    bool set_solver(const dfm_solver_settings& settings);

    // What the panel shows.
    const dfm_mesh_info& mesh_info() const { return info_; }
    std::size_t roi_size() const { return roi_vertices_.size(); }
    const dfm_water_fill_diagnosis& diagnosis() const { return diagnosis_; }
    const std::vector<std::vector<std::uint32_t>>& groups() const { return groups_; }
    const dfm_frame_info& last_frame() const { return last_info_; }
    bool has_session() const { return session_ != nullptr; }
    // The newest frame's solve report; false without a session.
    bool solve_report(dfm_solve_report& out) const;
    double handle_radius() const { return handle_radius_; }
    std::size_t bakes() const { return bakes_; }
    // The last failure's text ("" when none yet), also printed on stderr.
    const std::string& last_error() const { return last_error_; }

    // True when no targets are waiting for their finished result.
    bool settled() const;
    bool quit_requested() const { return quit_; }
    std::string status_line() const;
    dfm_vk_frame frame() const;
    Stage stage() const { return stage_; }

private:
    using Matrix = std::array<double, 16>;

    bool open_loaded(dfm_mesh* mesh, const std::string& mesh_spec, int width, int height);
    void click(double x, double y);
    void pick_endpoint(double x, double y);
    void add_handle(double x, double y);
    void begin_drag(double x, double y, bool rotate);
    void drag_to(double x, double y);
    bool ensure_session();
    void end_session();
    void cancel_selection();
    bool has_unbaked_edit() const;
    void reload_rest_pose();
    void read_copies();
    void refresh_marks();
    void refresh_lines();
    Vec3 group_centroid(std::size_t group) const;
    bool report(dfm_result result, const char* call) const;

    dfm_context* context_;
    dfm_vk_renderer* renderer_;
    std::string mesh_spec_;
    std::string mesh_output_ = "viewer_mesh.off";
    dfm_mesh* mesh_ = nullptr;
    dfm_mesh_info info_{};
    std::vector<std::uint32_t> indices_;
    // A glTF mesh's seam-split copies: each vertex's lowest copy (the index
    // the SDK returns for all of them), and each lowest copy's copies,
    // copies_[copy_begin_[v] .. copy_begin_[v + 1]).
    std::vector<std::uint32_t> lowest_copy_;
    std::vector<std::uint32_t> copy_begin_;
    std::vector<std::uint32_t> copies_;
    std::vector<float> rest_;     // x y z per vertex, the current rest pose
    std::vector<float> display_;  // what is drawn
    bool display_changed_ = false;
    OrbitCamera camera_;
    std::uint32_t flags_ = 0;

    Stage stage_ = Stage::pick_first;
    std::uint32_t first_ = 0, last_ = 0;
    dfm_roi* roi_ = nullptr;
    std::vector<std::uint32_t> roi_vertices_;
    dfm_water_fill_diagnosis diagnosis_{};
    double handle_radius_ = 0.03;
    std::vector<std::vector<std::uint32_t>> groups_;
    std::vector<Matrix> transforms_;
    dfm_session* session_ = nullptr;
    bool transforms_dirty_ = false;
    std::uint64_t submitted_ = 0;
    std::uint64_t shown_ = 0;
    dfm_frame_info last_info_{};
    dfm_solver_settings solver_{};
    std::size_t bakes_ = 0;
    mutable std::string last_error_;

    // Pointer state: a press becomes a click unless it moves a handle group.
    bool left_down_ = false;
    bool orbiting_ = false, panning_ = false;
    int dragged_group_ = -1;
    bool rotating_ = false;
    bool moved_ = false;
    double press_x_ = 0, press_y_ = 0, last_x_ = 0, last_y_ = 0;
    bool quit_ = false;
};

}  // namespace viewer
