// viewer: Dualform's interactive editor. Two clicks select a region by
// Water-Filling, clicks add handles, dragging them deforms the region, the
// solve following asynchronously every frame; a Dear ImGui panel shows the
// edit and the solver and holds the commands. See README.md or --help.
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
#include "imgui_layer.hpp"
#include "input_router.hpp"
#include "input_script.hpp"
#include "key_help.hpp"
#include "panel.hpp"
#include "script_player.hpp"

namespace {

// Input while the window's session runs; none after it.
viewer::InputRouter* router_of(GLFWwindow* window) {
    return static_cast<viewer::InputRouter*>(glfwGetWindowUserPointer(window));
}

void install_callbacks(GLFWwindow* window) {
    glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int mods) {
        double x = 0, y = 0;
        glfwGetCursorPos(w, &x, &y);
        if (viewer::InputRouter* r = router_of(w)) r->button(button, action, mods, x, y);
    });
    glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) {
        if (viewer::InputRouter* r = router_of(w)) r->cursor(x, y);
    });
    glfwSetScrollCallback(window, [](GLFWwindow* w, double dx, double dy) {
        if (viewer::InputRouter* r = router_of(w)) r->scroll(dx, dy);
    });
    glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int mods) {
        if (viewer::InputRouter* r = router_of(w)) r->key(key, action, mods);
    });
    glfwSetCharCallback(window, [](GLFWwindow* w, unsigned int c) {
        if (viewer::InputRouter* r = router_of(w)) r->character(c);
    });
    glfwSetFramebufferSizeCallback(window, [](GLFWwindow* w, int width, int height) {
        if (viewer::InputRouter* r = router_of(w)) r->resize(width, height);
    });
}

// Presents one frame; with `screenshot` set it also reads the presented
// picture back and writes it there (false when that fails).
bool present(dfm_vk_renderer* renderer, GLFWwindow* window, const dfm_vk_frame& frame,
             viewer::ScriptPlayer* player) {
    if (player == nullptr || player->pending_screenshot().empty()) {
        if (dfm_vk_renderer_present(renderer, &frame, nullptr) == DFM_OK) return true;
        std::fprintf(stderr, "viewer: %s\n", dfm_last_error_message());
        return false;
    }
    int width = 0, height = 0;
    glfwGetFramebufferSize(window, &width, &height);
    std::vector<std::uint8_t> rgba(std::size_t(width) * std::size_t(height) * 4);
    bool presented = false;
    if (dfm_vk_renderer_present_and_read(renderer, &frame, rgba.data(), rgba.size(), &presented) !=
            DFM_OK ||
        (presented &&
         dfm_vk_write_png(player->pending_screenshot().c_str(), rgba.data(), rgba.size(),
                          std::uint32_t(width), std::uint32_t(height)) != DFM_OK)) {
        std::fprintf(stderr, "viewer: %s\n", dfm_last_error_message());
        return false;
    }
    // Nothing shown (the swapchain was rebuilt): the next frame tries again.
    if (presented) player->screenshot_taken();
    return true;
}

// The window's session: panel, input and the frame loop. The status.
int run(GLFWwindow* window, dfm_context* context, dfm_vk_renderer* renderer,
        const std::string& mesh, const std::string& out_mesh,
        std::vector<viewer::ScriptEvent> events, bool scripted) {
    viewer::Editor editor(context, renderer);
    int fb_width = 0, fb_height = 0;
    glfwGetFramebufferSize(window, &fb_width, &fb_height);
    if (!out_mesh.empty()) editor.set_mesh_output(out_mesh);
    if (!editor.open(mesh, fb_width, fb_height)) return 1;
    viewer::ImGuiLayer imgui;
    if (!imgui.create(window, renderer)) return 1;
    viewer::Panel panel(editor);
    viewer::InputRouter router(window, editor, panel);
    glfwSetWindowUserPointer(window, &router);
    install_callbacks(window);
    viewer::ScriptPlayer player(std::move(events), router, editor, panel);
    const auto start = std::chrono::steady_clock::now();
    auto last = start;
    double frame_ms = 0.0;
    std::string title;
    int status = 0;
    while (!glfwWindowShouldClose(window) && !editor.quit_requested()) {
        glfwPollEvents();
        const auto now = std::chrono::steady_clock::now();
        frame_ms = std::chrono::duration<double, std::milli>(now - last).count();
        last = now;
        const double now_ms = std::chrono::duration<double, std::milli>(now - start).count();
        if (scripted && !player.step(now_ms)) {
            status = 1;
            break;
        }
        imgui.begin_frame(scripted ? &player.pointer() : nullptr);
        panel.draw(frame_ms);
        imgui.end_frame();
        if (!editor.update() ||
            !present(renderer, window, editor.frame(), scripted ? &player : nullptr)) {
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
    // The router dies with this function; the window lives on a little.
    glfwSetWindowUserPointer(window, nullptr);
    return status;
}

}  // namespace

int main(int argc, char** argv) {
    std::string mesh = "model:cow", script_path, out_mesh;
    int width = 960, height = 640;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        const bool value = i + 1 < argc;
        if (arg == "--help" || arg == "-h") {
            std::fputs(viewer::usage_text().c_str(), stdout);
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
            std::fputs(viewer::usage_text().c_str(), stderr);
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
        status =
            run(window, context, renderer, mesh, out_mesh, std::move(events), !script_path.empty());
    }
    dfm_vk_renderer_destroy(renderer);
    dfm_context_destroy(context);
    if (window != nullptr) glfwDestroyWindow(window);
    glfwTerminate();
    return status;
}
