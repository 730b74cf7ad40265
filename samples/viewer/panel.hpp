#pragma once

#include <map>
#include <string>

#include "editor.hpp"

namespace viewer {

// A control's rectangle in window pixels, as the panel last drew it.
struct ControlRect {
    float x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

// The viewer's Dear ImGui interface: a panel docked on the left with the
// region, the handle groups, the solver's settings and figures, bake /
// undo / redo, open / save; and the help overlay with the keys. Its
// controls act on the Editor through the same methods the keys call.
class Panel {
public:
    explicit Panel(Editor& editor) : editor_(editor) {}

    // Draws this frame's panel (between ImGui's NewFrame and Render);
    // `frame_ms` is the viewer's last frame time.
    void draw(double frame_ms);

    void toggle_help() { help_open_ = !help_open_; }
    void set_path(const std::string& path);
    // The File section's path: what Open reads and Save (and the S key) writes.
    std::string path() const { return path_[0] != '\0' ? path_ : editor_.mesh_output(); }
    std::string morph_target() const { return morph_target_; }

    // Where the control a script names (its script name, README.md) was
    // drawn last frame; false when it was not drawn.
    bool find_control(const std::string& name, ControlRect& out) const;

    // The panel's width in pixels at the window's left edge.
    static constexpr float width = 272.0f;

private:
    void remember(const char* name);
    void draw_region();
    void draw_handles();
    void draw_solver(double frame_ms);
    void draw_edit();
    void draw_file();
    void draw_help();

    Editor& editor_;
    bool help_open_ = false;
    char path_[1024] = {};
    char morph_target_[128] = {};
    std::string file_message_;
    std::map<std::string, ControlRect> controls_;
};

}  // namespace viewer
