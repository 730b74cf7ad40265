// viewer: Dualform's interactive editor. Two clicks select a region by
// Water-Filling, clicks add handles, dragging them deforms the region, the
// solve following asynchronously every frame. See README.md or --help.
#include <GLFW/glfw3.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "../common/sample_environment.h"
#include "dualform/dualform.h"
#include "dualform/dualform_vulkan.h"
#include "dualform/dualform_vulkan_glfw.h"
#include "editor.hpp"
#include "input_script.hpp"

namespace {

constexpr const char* help_text =
    "usage: viewer [MESH] [--script FILE] [--width W] [--height H] [--out MESH_FILE]\n"
    "\n"
    "MESH: an .off, .obj or .ply file, or model:NAME (default model:cow)\n"
    "\n"
    "mouse\n"
    "  left click          1st: the limb's tip; 2nd: where the region ends (Water-Filling);\n"
    "                      then: add a handle (a ball of vertices around the click)\n"
    "  left drag           move the handle group nearest the pointer in the view plane\n"
    "  shift + left drag   rotate it about the view axis\n"
    "  right drag          orbit          middle drag   pan          wheel   zoom\n"
    "keys\n"
    "  Enter   keep a region marked SUSPECT     Escape  cancel the selection\n"
    "  B       bake the edit into the mesh      Ctrl+Z  undo a bake     Ctrl+Y  redo\n"
    "  R       reset the handles (also Backspace)\n"
    "  [ ]     smaller / larger handle balls    W  wireframe    F  flat shading\n"
    "  S       bake and save the mesh (--out, default viewer_mesh.off)\n"
    "  E       save the edit as a scenario (viewer_edit.json)\n"
    "  Q       quit\n"
    "The window title shows the ROI size, the solver's iterations and time.\n"
    "--script FILE replays timed input (see README.md) through the same code.\n";

struct App {
    viewer::Editor* editor = nullptr;
    bool shift = false;
};

App& app_of(GLFWwindow* window) {
    return *static_cast<App*>(glfwGetWindowUserPointer(window));
}

std::string key_name(int key, int mods) {
    static const std::pair<int, const char*> named[] = {
        {GLFW_KEY_ENTER, "enter"},         {GLFW_KEY_ESCAPE, "escape"},
        {GLFW_KEY_BACKSPACE, "backspace"}, {GLFW_KEY_LEFT_BRACKET, "["},
        {GLFW_KEY_RIGHT_BRACKET, "]"},
    };
    char letter[2] = {0, 0};
    const char* base = nullptr;
    if (key >= GLFW_KEY_A && key <= GLFW_KEY_Z) {
        letter[0] = static_cast<char>('a' + (key - GLFW_KEY_A));
        base = letter;
    }
    for (const auto& [code, text] : named) {
        if (key == code) base = text;
    }
    if (base == nullptr) return {};
    std::string name = (mods & GLFW_MOD_CONTROL) != 0 ? "ctrl+" : "";
    name.append(base);
    return name;
}

viewer::Editor::Button button_of(int button) {
    if (button == GLFW_MOUSE_BUTTON_RIGHT) return viewer::Editor::Button::right;
    if (button == GLFW_MOUSE_BUTTON_MIDDLE) return viewer::Editor::Button::middle;
    return viewer::Editor::Button::left;
}

void install_callbacks(GLFWwindow* window) {
    glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int mods) {
        double x = 0, y = 0;
        glfwGetCursorPos(w, &x, &y);
        if (action == GLFW_PRESS) {
            app_of(w).editor->press(button_of(button), x, y, (mods & GLFW_MOD_SHIFT) != 0);
        } else if (action == GLFW_RELEASE) {
            app_of(w).editor->release(button_of(button), x, y);
        }
    });
    glfwSetCursorPosCallback(
        window, [](GLFWwindow* w, double x, double y) { app_of(w).editor->move(x, y); });
    glfwSetScrollCallback(window,
                          [](GLFWwindow* w, double, double dy) { app_of(w).editor->scroll(dy); });
    glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int mods) {
        if (action != GLFW_PRESS) return;
        const std::string name = key_name(key, mods);
        if (!name.empty()) app_of(w).editor->key(name);
    });
    glfwSetFramebufferSizeCallback(window, [](GLFWwindow* w, int width, int height) {
        app_of(w).editor->resize(width, height);
    });
}

// Replays a script through the editor's input methods, one step per frame.
class ScriptPlayer {
public:
    explicit ScriptPlayer(std::vector<viewer::ScriptEvent> events) : events_(std::move(events)) {}

    bool active() const { return next_ < events_.size() || drag_left_ > 0; }

    // False when an event failed (a screenshot or save that could not be written).
    bool step(viewer::Editor& editor, double now_ms) {
        if (drag_left_ > 0) {
            --drag_left_;
            const double t = 1.0 - double(drag_left_) / drag_frames_;
            editor.move(drag_[0] + t * (drag_[2] - drag_[0]), drag_[1] + t * (drag_[3] - drag_[1]));
            if (drag_left_ == 0) editor.release(viewer::Editor::Button::left, drag_[2], drag_[3]);
            return true;
        }
        if (waiting_) {
            if (!editor.settled()) return true;
            waiting_ = false;
            paused_ms_ += now_ms - wait_started_;
        }
        while (next_ < events_.size() && events_[next_].time_ms <= now_ms - paused_ms_) {
            const viewer::ScriptEvent& e = events_[next_++];
            const auto number = [&](std::size_t i) { return std::atof(e.args[i].c_str()); };
            if (e.name == "click") {
                editor.move(number(0), number(1));
                editor.press(viewer::Editor::Button::left, number(0), number(1), false);
                editor.release(viewer::Editor::Button::left, number(0), number(1));
            } else if (e.name == "drag") {
                for (int i = 0; i < 4; ++i) drag_[i] = number(i);
                drag_frames_ = drag_left_ = std::max(1, std::atoi(e.args[4].c_str()));
                editor.move(drag_[0], drag_[1]);
                editor.press(viewer::Editor::Button::left, drag_[0], drag_[1],
                             e.args.size() > 5 && e.args[5] == "shift");
                return true;
            } else if (e.name == "key") {
                editor.key(e.args[0]);
            } else if (e.name == "wait") {
                waiting_ = true;
                wait_started_ = now_ms;
                return true;
            } else if (e.name == "screenshot") {
                if (!editor.write_screenshot(e.args[0])) return false;
            } else if (e.name == "save-scenario") {
                if (!editor.save_scenario(e.args[0])) return false;
            } else if (e.name == "save-camera") {
                if (!editor.save_camera(e.args[0])) return false;
            } else if (e.name == "quit") {
                editor.key("q");
            }
        }
        return true;
    }

private:
    std::vector<viewer::ScriptEvent> events_;
    std::size_t next_ = 0;
    double drag_[4] = {};
    int drag_frames_ = 0, drag_left_ = 0;
    bool waiting_ = false;
    double wait_started_ = 0, paused_ms_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
    std::string mesh = "model:cow", script_path, out_mesh;
    int width = 960, height = 640;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        const bool value = i + 1 < argc;
        if (arg == "--help" || arg == "-h") {
            std::fputs(help_text, stdout);
            return 0;
        } else if (arg == "--script" && value) {
            script_path = argv[++i];
        } else if (arg == "--width" && value) {
            width = std::atoi(argv[++i]);
        } else if (arg == "--height" && value) {
            height = std::atoi(argv[++i]);
        } else if (arg == "--out" && value) {
            out_mesh = argv[++i];
        } else if (!arg.empty() && arg[0] != '-') {
            mesh = arg;
        } else {
            std::fputs(help_text, stderr);
            return 2;
        }
    }
    if (width < 16 || height < 16) {
        std::fprintf(stderr, "viewer: the window needs at least 16 x 16 pixels\n");
        return 2;
    }
    std::vector<viewer::ScriptEvent> events;
    if (!script_path.empty()) {
        std::string error;
        if (!viewer::load_script(script_path, events, error)) {
            std::fprintf(stderr, "viewer: %s\n", error.c_str());
            return 2;
        }
    }
    if (glfwInit() != GLFW_TRUE) {
        std::fprintf(stderr, "viewer: GLFW could not start (is there a display?)\n");
        return 1;
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    GLFWwindow* window = glfwCreateWindow(width, height, "Dualform", nullptr, nullptr);
    dfm_context* context = nullptr;
    dfm_vk_renderer* renderer = nullptr;
    char models[4096];
    dfm_context_desc context_desc = {};
    context_desc.models_directory = sample_models_folder(models, sizeof models);
    dfm_vk_renderer_desc renderer_desc = {};
    renderer_desc.validation = sample_validation();
    int status = 1;
    if (window == nullptr) {
        std::fprintf(stderr, "viewer: GLFW could not open a window\n");
    } else if (dfm_context_create(&context_desc, &context) != DFM_OK ||
               dfm_vk_renderer_create_window(&renderer_desc, window, &renderer) != DFM_OK) {
        std::fprintf(stderr, "viewer: %s\n", dfm_last_error_message());
    } else {
        viewer::Editor editor(context, renderer);
        App app;
        app.editor = &editor;
        glfwSetWindowUserPointer(window, &app);
        int fb_width = 0, fb_height = 0;
        glfwGetFramebufferSize(window, &fb_width, &fb_height);
        if (!out_mesh.empty()) editor.set_mesh_output(out_mesh);
        if (editor.open(mesh, fb_width, fb_height)) {
            install_callbacks(window);
            ScriptPlayer player(std::move(events));
            const bool scripted = !script_path.empty();
            const auto start = std::chrono::steady_clock::now();
            std::string title;
            status = 0;
            while (!glfwWindowShouldClose(window) && !editor.quit_requested()) {
                glfwPollEvents();
                const double now_ms = std::chrono::duration<double, std::milli>(
                                          std::chrono::steady_clock::now() - start)
                                          .count();
                if (scripted && !player.step(editor, now_ms)) {
                    status = 1;
                    break;
                }
                if (!editor.update()) {
                    status = 1;
                    break;
                }
                const dfm_vk_frame frame = editor.frame();
                if (dfm_vk_renderer_present(renderer, &frame, nullptr) != DFM_OK) {
                    std::fprintf(stderr, "viewer: %s\n", dfm_last_error_message());
                    status = 1;
                    break;
                }
                if (const std::string line = editor.status_line(); line != title) {
                    title = line;
                    glfwSetWindowTitle(window, title.c_str());
                }
                if (scripted && !player.active()) break;
            }
            std::uint64_t messages = 0;
            dfm_vk_renderer_validation_message_count(renderer, &messages);
            if (messages > 0) {
                std::fprintf(stderr, "viewer: %llu Vulkan validation messages\n",
                             static_cast<unsigned long long>(messages));
                status = 1;
            }
            std::printf("%s\n", title.c_str());
        }
    }
    dfm_vk_renderer_destroy(renderer);
    dfm_context_destroy(context);
    if (window != nullptr) glfwDestroyWindow(window);
    glfwTerminate();
    return status;
}
