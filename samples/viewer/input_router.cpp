#include "input_router.hpp"

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <imgui.h>

#include <utility>

namespace viewer {

namespace {

constexpr std::pair<int, const char*> named_keys[] = {
    {GLFW_KEY_ENTER, "enter"},    {GLFW_KEY_ESCAPE, "escape"},   {GLFW_KEY_BACKSPACE, "backspace"},
    {GLFW_KEY_LEFT_BRACKET, "["}, {GLFW_KEY_RIGHT_BRACKET, "]"}, {GLFW_KEY_F1, "f1"},
};

Editor::Button editor_button(int button) {
    if (button == GLFW_MOUSE_BUTTON_RIGHT) return Editor::Button::right;
    if (button == GLFW_MOUSE_BUTTON_MIDDLE) return Editor::Button::middle;
    return Editor::Button::left;
}

}  // namespace

std::string key_name(int key, int mods) {
    char letter[2] = {0, 0};
    const char* base = nullptr;
    if (key >= GLFW_KEY_A && key <= GLFW_KEY_Z) {
        letter[0] = static_cast<char>('a' + (key - GLFW_KEY_A));
        base = letter;
    }
    for (const auto& [code, text] : named_keys) {
        if (key == code) base = text;
    }
    if (base == nullptr) return {};
    std::string name = (mods & GLFW_MOD_CONTROL) != 0 ? "ctrl+" : "";
    name.append(base);
    return name;
}

bool parse_key_name(const std::string& name, int& key, int& mods) {
    std::string base = name;
    mods = 0;
    if (base.rfind("ctrl+", 0) == 0) {
        mods = GLFW_MOD_CONTROL;
        base.erase(0, 5);
    }
    if (base.size() == 1 && base[0] >= 'a' && base[0] <= 'z') {
        key = GLFW_KEY_A + (base[0] - 'a');
        return true;
    }
    for (const auto& [code, text] : named_keys) {
        if (base == text) {
            key = code;
            return true;
        }
    }
    return false;
}

void InputRouter::button(int button, int action, int mods, double x, double y) {
    ImGui_ImplGlfw_MouseButtonCallback(window_, button, action, mods);
    if (button < 0 || button > 2) return;
    bool& panel_has = panel_has_button_[button];
    if (action == GLFW_PRESS) {
        panel_has = ImGui::GetIO().WantCaptureMouse;
        if (!panel_has) {
            editor_.press(editor_button(button), x, y, (mods & GLFW_MOD_SHIFT) != 0);
        }
    } else if (action == GLFW_RELEASE) {
        if (!panel_has) editor_.release(editor_button(button), x, y);
        panel_has = false;
    }
}

void InputRouter::cursor(double x, double y) {
    editor_.move(x, y);
}

void InputRouter::scroll(double dx, double dy) {
    ImGui_ImplGlfw_ScrollCallback(window_, dx, dy);
    if (!ImGui::GetIO().WantCaptureMouse) editor_.scroll(dy);
}

void InputRouter::key(int key, int action, int mods) {
    ImGui_ImplGlfw_KeyCallback(window_, key, 0, action, mods);
    if (action != GLFW_PRESS || ImGui::GetIO().WantCaptureKeyboard) return;
    const std::string name = key_name(key, mods);
    if (name == "h" || name == "f1") {
        panel_.toggle_help();
    } else if (name == "s") {
        editor_.save_mesh(panel_.path(), panel_.morph_target());
    } else if (!name.empty()) {
        editor_.key(name);
    }
}

void InputRouter::character(unsigned int codepoint) {
    ImGui_ImplGlfw_CharCallback(window_, codepoint);
}

}  // namespace viewer
