#pragma once

#include <string>

#include "editor.hpp"
#include "panel.hpp"

struct GLFWwindow;

namespace viewer {

// Where input goes: to Dear ImGui first (its GLFW backend's callbacks), then
// to the editor unless the panel wants it (io.WantCaptureMouse /
// WantCaptureKeyboard), so that a click on the panel never picks the mesh
// behind it. GLFW's callbacks and a --script call the same methods.
class InputRouter {
public:
    InputRouter(GLFWwindow* window, Editor& editor, Panel& panel)
        : window_(window), editor_(editor), panel_(panel) {}

    // GLFW's codes: GLFW_MOUSE_BUTTON_*, GLFW_PRESS / GLFW_RELEASE, GLFW_MOD_*.
    void button(int button, int action, int mods, double x, double y);
    void cursor(double x, double y);
    void scroll(double dx, double dy);
    // GLFW_KEY_*, GLFW_PRESS / GLFW_RELEASE / GLFW_REPEAT.
    void key(int key, int action, int mods);
    void character(unsigned int codepoint);
    void resize(int width, int height) { editor_.resize(width, height); }

private:
    GLFWwindow* window_;
    Editor& editor_;
    Panel& panel_;
    // A press the panel took: its release (and drag) stay the panel's.
    bool panel_has_button_[3] = {false, false, false};
};

// "b", "ctrl+z", "enter", "[", "f1", ... for a key and its modifiers; empty
// for keys the viewer does not use.
std::string key_name(int key, int mods);
// The reverse, for scripts: false for a name key_name never gives.
bool parse_key_name(const std::string& name, int& key, int& mods);

}  // namespace viewer
