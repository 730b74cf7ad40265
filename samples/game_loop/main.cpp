// game_loop: a fixed-timestep 60 Hz loop in which gameplay code animates
// handles while rendering goes on, and deformation runs asynchronously: the
// loop submits new targets every frame and shows whatever result is newest,
// never waiting on the solver.
//
// usage: game_loop [--frames N] [--model NAME] [--window] [--png OUT]
//
// Headless by default (offscreen rendering, nothing read back); --window
// opens a GLFW window. The last line printed is one JSON object with the
// host's frame times, the age of the results on screen, and how many rigs'
// last targets were solved after the loop.
#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "../common/sample_environment.h"
#include "dualform/dualform.h"
#include "dualform/dualform_vulkan.h"
#include "dualform/dualform_vulkan_glfw.h"
#include "rig.hpp"

namespace {

using Clock = std::chrono::steady_clock;

struct Options {
    int frames = 600;
    std::string model = "model:cow";
    bool window = false;
    std::string png;
};

bool parse(int argc, char** argv, Options& o) {
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        const bool has_value = i + 1 < argc;
        if (arg == "--frames" && has_value) {
            o.frames = std::atoi(argv[++i]);
        } else if (arg == "--model" && has_value) {
            o.model = argv[++i];
        } else if (arg == "--png" && has_value) {
            o.png = argv[++i];
        } else if (arg == "--window") {
            o.window = true;
        } else {
            return false;
        }
    }
    return o.frames > 0;
}

bool ok(dfm_result result, const char* call) {
    if (result == DFM_OK) return true;
    std::fprintf(stderr, "game_loop: %s: %s: %s\n", call, dfm_result_name(result),
                 dfm_last_error_message());
    return false;
}

double percentile(std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, static_cast<std::size_t>(q * v.size()))];
}

// The state the host keeps for drawing: positions of every vertex (float,
// as a GPU wants them) and each vertex's mark.
struct Scene {
    std::vector<float> positions;
    std::vector<std::uint8_t> marks;
    std::vector<std::uint32_t> indices;
};

}  // namespace

int main(int argc, char** argv) {
    Options options;
    if (!parse(argc, argv, options)) {
        std::fprintf(stderr,
                     "usage: game_loop [--frames N] [--model NAME] [--window] [--png OUT]\n");
        return 2;
    }
    dfm_context* context = nullptr;
    dfm_mesh* mesh = nullptr;
    dfm_vk_renderer* renderer = nullptr;
    GLFWwindow* window = nullptr;
    std::vector<game::Rig> rigs;
    int status = 1;
    dfm_mesh_info info = {};
    Scene scene;
    dfm_vk_frame frame = {};

    char models[4096];
    dfm_context_desc context_desc = {};
    context_desc.models_directory = sample_models_folder(models, sizeof models);
    if (!ok(dfm_context_create(&context_desc, &context), "dfm_context_create") ||
        !ok(dfm_mesh_load(context, options.model.c_str(), &mesh), "dfm_mesh_load") ||
        !ok(dfm_mesh_get_info(mesh, &info), "dfm_mesh_get_info") ||
        !game::make_rigs(mesh, options.model, rigs)) {
        game::destroy_rigs(rigs);
        dfm_mesh_destroy(mesh);
        dfm_context_destroy(context);
        return 1;
    }
    scene.positions.resize(3 * info.vertex_count);
    scene.marks.assign(info.vertex_count, DFM_VK_MARK_SURFACE);
    scene.indices.resize(3 * info.triangle_count);
    const dfm_vec3_output rest = {scene.positions.data(), info.vertex_count, 0, DFM_SCALAR_FLOAT32};
    dfm_mesh_read_positions(mesh, &rest);
    dfm_mesh_read_indices(mesh, scene.indices.data(), scene.indices.size());
    for (const game::Rig& rig : rigs) {
        std::size_t n = 0;
        dfm_roi_count(rig.roi, &n);
        std::vector<std::uint32_t> roi(n);
        dfm_roi_read(rig.roi, roi.data(), n);
        for (std::uint32_t v : roi) scene.marks[v] = DFM_VK_MARK_ROI;
    }
    const dfm_vec3_input scene_positions = {scene.positions.data(), info.vertex_count, 0,
                                            DFM_SCALAR_FLOAT32};

    // Headless, the picture is small and single-sampled: lavapipe draws on
    // the same CPU cores as the game and the solver.
    const int width = options.window ? 640 : 320;
    const int height = options.window ? 360 : 180;
    if (options.window) {
        if (glfwInit() != GLFW_TRUE) {
            std::fprintf(stderr, "game_loop: GLFW could not start (no display?)\n");
            goto done;
        }
        glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
        window = glfwCreateWindow(width, height, "Dualform game loop", nullptr, nullptr);
        if (window == nullptr) {
            std::fprintf(stderr, "game_loop: GLFW could not open a window\n");
            goto done;
        }
        dfm_vk_renderer_desc desc = {};
        desc.validation = sample_validation();
        if (!ok(dfm_vk_renderer_create_window(&desc, window, &renderer), "create_window")) {
            goto done;
        }
    } else {
        dfm_vk_renderer_desc desc = {};
        desc.max_samples = 1;
        desc.validation = sample_validation();
        if (!ok(dfm_vk_renderer_create_headless(&desc, &renderer), "create_headless")) goto done;
    }
    if (!ok(dfm_vk_renderer_set_mesh(renderer, &scene_positions, scene.indices.data(),
                                     info.triangle_count),
            "set_mesh") ||
        !ok(dfm_vk_renderer_set_marks(renderer, scene.marks.data(), scene.marks.size()),
            "set_marks") ||
        !ok(dfm_vk_framing_camera(&scene_positions, width, height, &frame.camera),
            "framing_camera")) {
        goto done;
    }

    {
        // The host's own frame work (gameplay, the SDK's calls, handing the
        // positions to the renderer) apart from drawing, which on lavapipe is
        // CPU work on the same cores and waits for free frames in flight.
        std::vector<double> host_ms, render_ms, age_frames;
        int received = 0;
        const auto start = Clock::now();
        for (int f = 0; f < options.frames; ++f) {
            const auto frame_start = Clock::now();
            const double t = f / 60.0;
            // Gameplay: move every rig's handles, hand the targets over.
            for (game::Rig& rig : rigs) {
                double m[16];
                game::transform_at(rig.motion, t, info.diagonal, m);
                std::uint64_t generation = 0;
                if (!ok(dfm_session_set_group_transform(rig.session, 0, m), "set_transform") ||
                    !ok(dfm_session_submit(rig.session, &generation), "submit")) {
                    goto done;
                }
                rig.submitted_at.resize(generation + 1, f);
            }
            // Show the newest results: borrow each frame, copy its region.
            bool changed = false;
            int oldest = 0;
            for (game::Rig& rig : rigs) {
                dfm_frame_info polled = {};
                bool is_new = false;
                dfm_session_poll(rig.session, rig.shown, &polled, &is_new);
                if (is_new) {
                    dfm_frame_view view = {};
                    if (dfm_session_acquire_frame(rig.session, &view, &polled) == DFM_OK) {
                        for (std::size_t i = 0; i < view.roi_count; ++i) {
                            std::memcpy(&scene.positions[3 * view.roi_vertices[i]],
                                        &view.roi_positions[3 * i], 3 * sizeof(float));
                        }
                        dfm_session_release_frame(rig.session);
                        rig.shown = polled.generation;
                        changed = true;
                        ++received;
                    }
                }
                // Generation 0 is the rest pose, on screen since before frame 0.
                const int shown_at = rig.shown == 0 ? -1 : rig.submitted_at[rig.shown];
                oldest = std::max(oldest, f - shown_at);
            }
            if (changed && !ok(dfm_vk_renderer_update_positions(renderer, &scene_positions),
                               "update_positions")) {
                goto done;
            }
            const auto render_start = Clock::now();
            host_ms.push_back(
                std::chrono::duration<double, std::milli>(render_start - frame_start).count());
            age_frames.push_back(oldest);
            if (window != nullptr) {
                glfwPollEvents();
                if (glfwWindowShouldClose(window)) break;
                if (!ok(dfm_vk_renderer_present(renderer, &frame, nullptr), "present")) goto done;
            } else if (!ok(dfm_vk_renderer_render_offscreen(renderer, &frame, nullptr, 0),
                           "render_offscreen")) {
                goto done;
            }
            render_ms.push_back(
                std::chrono::duration<double, std::milli>(Clock::now() - render_start).count());
            std::this_thread::sleep_until(start + std::chrono::microseconds(16667) * (f + 1));
        }
        // The newest targets win: each rig's last ones are solved, whatever
        // the loop skipped on the way.
        int last_targets_solved = 0;
        for (const game::Rig& rig : rigs) {
            const std::uint64_t last = rig.submitted_at.size() - 1;
            dfm_frame_info solved = {};
            if (!ok(dfm_session_wait(rig.session, last, -1, &solved), "wait")) goto done;
            if (solved.generation == last && solved.status == DFM_OK) ++last_targets_solved;
        }
        if (!options.png.empty()) {
            std::vector<std::uint8_t> rgba(static_cast<std::size_t>(width) * height * 4);
            if (!ok(dfm_vk_renderer_render_offscreen(renderer, &frame, rgba.data(), rgba.size()),
                    "render_offscreen") ||
                !ok(dfm_vk_write_png(options.png.c_str(), rgba.data(), rgba.size(), width, height),
                    "write_png")) {
                goto done;
            }
        }
        std::uint64_t messages = 0;
        dfm_vk_renderer_validation_message_count(renderer, &messages);
        if (messages > 0) {
            std::fprintf(stderr, "game_loop: %llu Vulkan validation messages\n",
                         static_cast<unsigned long long>(messages));
            goto done;
        }
        std::printf(
            "{\"frames\": %zu, \"host_frame_ms\": {\"p50\": %.3f, \"p99\": %.3f, \"max\": %.3f}, "
            "\"render_ms\": {\"p50\": %.3f, \"p99\": %.3f}, "
            "\"result_age_frames\": {\"p50\": %.0f, \"max\": %.0f}, \"results_received\": %d, "
            "\"rigs\": %zu, \"last_targets_solved\": %d}\n",
            host_ms.size(), percentile(host_ms, 0.5), percentile(host_ms, 0.99),
            percentile(host_ms, 1.0), percentile(render_ms, 0.5), percentile(render_ms, 0.99),
            percentile(age_frames, 0.5), percentile(age_frames, 1.0), received, rigs.size(),
            last_targets_solved);
        status = 0;
    }

done:
    dfm_vk_renderer_destroy(renderer);
    if (window != nullptr) glfwDestroyWindow(window);
    if (options.window) glfwTerminate();
    game::destroy_rigs(rigs);
    dfm_mesh_destroy(mesh);
    dfm_context_destroy(context);
    return status;
}
