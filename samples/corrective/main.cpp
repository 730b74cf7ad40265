// corrective: a skinned arm plays its animation twice side by side, on the
// left as linear blend skinning alone shows it (the elbow thins and pinches
// as it bends), on the right with a corrective edited on it in Dualform at
// the bent pose and driven by the elbow's angle (pose-space deformation):
// off while the arm is straight, fully on at the edited bend.
//
// usage: corrective [--frames N] [--png OUT] [--meshes DIR] [--window]
//
// The host skins both copies itself, as an engine does: the corrected copy's
// bind positions plus weight x corrective (a morph target, applied before
// skinning), the weight a function of the elbow's angle (driver_weight).
// Headless by default: N frames (one bend and back, 120) offscreen.
// --window plays in a GLFW window until it is closed (or for N frames).
// --png writes three frames (straight, half bent, at the edited bend) one
// above the other; --meshes writes both copies at those poses, and the
// edited pose as Dualform shows it, as OFF files. The last line printed is
// one JSON object of figures (README.md).
#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "../common/sample_environment.h"
#include "arm.hpp"
#include "corrective_edit.hpp"
#include "dualform/dualform.h"
#include "dualform/dualform_vulkan.h"
#include "dualform/dualform_vulkan_glfw.h"
#include "scene.hpp"

namespace {

using Clock = std::chrono::steady_clock;

struct Options {
    int frames = 120;
    bool frames_given = false;
    std::string png;
    std::string meshes;
    bool window = false;
};

bool parse(int argc, char** argv, Options& o) {
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        const bool has_value = i + 1 < argc;
        if (arg == "--frames" && has_value) {
            o.frames = std::atoi(argv[++i]);
            o.frames_given = true;
        } else if (arg == "--png" && has_value) {
            o.png = argv[++i];
        } else if (arg == "--meshes" && has_value) {
            o.meshes = argv[++i];
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
    std::fprintf(stderr, "corrective: %s: %s: %s\n", call, dfm_result_name(result),
                 dfm_last_error_message());
    return false;
}

double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, static_cast<std::size_t>(q * v.size()))];
}

// The largest distance between vertex pairs of two x y z arrays.
double largest_distance(const std::vector<double>& a, const std::vector<double>& b) {
    double worst = 0.0;
    for (std::size_t v = 0; v < a.size() / 3; ++v) {
        const double dx = a[3 * v] - b[3 * v];
        const double dy = a[3 * v + 1] - b[3 * v + 1];
        const double dz = a[3 * v + 2] - b[3 * v + 2];
        worst = std::max(worst, std::sqrt(dx * dx + dy * dy + dz * dz));
    }
    return worst;
}

// What the naive corrective misses by: the posed displacement copied into
// bind space as it is (edited - unedited), played at the edited bend.
double naive_miss(const arm::Arm& arm, const corrective::Corrective& fix) {
    std::vector<float> naive(fix.edited.size());
    for (std::size_t i = 0; i < naive.size(); ++i) {
        naive[i] = static_cast<float>(fix.edited[i] - fix.unedited[i]);
    }
    std::vector<double> played(fix.edited.size());
    arm::skin(arm, arm::joint_matrices(arm, fix.degrees), naive, 1.0, played.data());
    return largest_distance(played, fix.edited);
}

// Writes x y z positions on the arm's triangles as a mesh file (OFF keeps
// every digit).
bool write_shape(dfm_context* context, const arm::Arm& arm, const std::vector<double>& positions,
                 const std::string& path) {
    dfm_mesh_desc desc = {};
    desc.struct_size = sizeof desc;
    desc.positions = {positions.data(), arm.vertex_count(), 0, DFM_SCALAR_FLOAT64};
    desc.indices = arm.indices.data();
    desc.triangle_count = arm.triangle_count();
    dfm_mesh* shape = nullptr;
    const bool written = ok(dfm_mesh_create(context, &desc, &shape), "dfm_mesh_create") &&
                         ok(dfm_mesh_save(shape, path.c_str()), "dfm_mesh_save");
    dfm_mesh_destroy(shape);
    return written;
}

// The skinned arm as Dualform takes it from an engine: the bind pose, the
// joints and weights per vertex, the inverse bind matrices.
bool create_mesh(dfm_context* context, const arm::Arm& arm, dfm_mesh** out) {
    double inverse_bind[16 * arm::joint_count];
    for (int j = 0; j < arm::joint_count; ++j) {
        std::memcpy(&inverse_bind[16 * j], arm.inverse_bind[j].data(), sizeof(double) * 16);
    }
    dfm_mesh_desc desc = {};
    desc.struct_size = sizeof desc;
    desc.positions = {arm.positions.data(), arm.vertex_count(), 0, DFM_SCALAR_FLOAT32};
    desc.indices = arm.indices.data();
    desc.triangle_count = arm.triangle_count();
    desc.skin.joint_count = arm::joint_count;
    desc.skin.inverse_bind_matrices = inverse_bind;
    desc.skin.influence_count = arm::influences;
    desc.skin.joints = arm.joints.data();
    desc.skin.joint_type = DFM_INDEX_UINT8;
    desc.skin.weights = arm.weights.data();
    desc.skin.weight_type = DFM_SCALAR_FLOAT32;
    return ok(dfm_mesh_create(context, &desc, out), "dfm_mesh_create");
}

}  // namespace

int main(int argc, char** argv) {
    Options options;
    if (!parse(argc, argv, options)) {
        std::fprintf(stderr,
                     "usage: corrective [--frames N] [--png OUT] [--meshes DIR] [--window]\n");
        return 2;
    }
    const arm::Arm arm = arm::make_arm();
    dfm_context* context = nullptr;
    dfm_mesh* mesh = nullptr;
    dfm_vk_renderer* renderer = nullptr;
    GLFWwindow* window = nullptr;
    corrective::Corrective fix;
    int status = 1;

    dfm_context_desc context_desc = {};
    if (!ok(dfm_context_create(&context_desc, &context), "dfm_context_create") ||
        !create_mesh(context, arm, &mesh) ||
        !corrective::make(mesh, arm, arm::max_bend_degrees, fix)) {
        dfm_mesh_destroy(mesh);
        dfm_context_destroy(context);
        return 1;
    }
    dfm_mesh_info info = {};
    dfm_mesh_get_info(mesh, &info);  // posed at the edit: the diagonal is the unit of the figures
    scene::Scene scene(arm);
    const dfm_vec3_input scene_positions = scene.input();
    dfm_vk_frame frame = {};
    const int width = options.window ? 640 : 960;
    const int height = options.window ? 360 : 280;

    if (options.window) {
        if (glfwInit() != GLFW_TRUE) {
            std::fprintf(stderr, "corrective: GLFW could not start (no display?)\n");
            goto done;
        }
        glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
        window = glfwCreateWindow(width, height, "Dualform corrective", nullptr, nullptr);
        if (window == nullptr) {
            std::fprintf(stderr, "corrective: GLFW could not open a window\n");
            goto done;
        }
        dfm_vk_renderer_desc desc = {};
        desc.validation = sample_validation();
        if (!ok(dfm_vk_renderer_create_window(&desc, window, &renderer), "create_window")) {
            goto done;
        }
    } else {
        dfm_vk_renderer_desc desc = {};
        desc.validation = sample_validation();
        if (!ok(dfm_vk_renderer_create_headless(&desc, &renderer), "create_headless")) goto done;
    }
    {
        // One camera for the whole animation: it frames both copies straight
        // and at the edited bend.
        std::vector<double> extent;
        for (double degrees : {0.0, fix.degrees}) {
            scene.pose(arm, fix, degrees);
            extent.insert(extent.end(), scene.positions.begin(), scene.positions.end());
        }
        frame.camera = scene::front_camera(extent, width, height);
        scene.pose(arm, fix, 0.0);
        if (!ok(dfm_vk_renderer_set_mesh(renderer, &scene_positions, scene.indices.data(),
                                         scene.indices.size() / 3),
                "set_mesh")) {
            goto done;
        }
    }

    {
        // Playback: each frame the host poses both copies with the same
        // joint matrices and draws them.
        std::vector<double> host_ms, render_ms;
        int played = 0;
        const bool until_closed = window != nullptr && !options.frames_given;
        for (int f = 0; until_closed || f < options.frames; ++f) {
            const auto start = Clock::now();
            scene.pose(arm, fix, arm::elbow_degrees_at(f / 60.0));
            if (!ok(dfm_vk_renderer_update_positions(renderer, &scene_positions),
                    "update_positions")) {
                goto done;
            }
            const auto render_start = Clock::now();
            host_ms.push_back(
                std::chrono::duration<double, std::milli>(render_start - start).count());
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
            ++played;
        }

        // Three frames looked at closely: straight, half bent, at the edited
        // bend. How far apart the copies are says how much corrective the
        // driver lets through.
        const double poses[3] = {0.0, 0.5 * fix.degrees, fix.degrees};
        double gaps[3] = {};
        double edited_error = 0.0;
        const std::size_t row = static_cast<std::size_t>(width) * height * 4;
        std::vector<std::uint8_t> picture(options.png.empty() ? 0 : 3 * row);
        for (int p = 0; p < 3; ++p) {
            scene.pose(arm, fix, poses[p]);
            gaps[p] = largest_distance(scene.plain, scene.corrected) / info.diagonal;
            if (p == 2)
                edited_error = largest_distance(scene.corrected, fix.edited) / info.diagonal;
            if (!options.meshes.empty()) {
                const std::string degrees = std::to_string(static_cast<int>(poses[p]));
                if (!write_shape(context, arm, scene.plain,
                                 options.meshes + "/plain-" + degrees + ".off") ||
                    !write_shape(context, arm, scene.corrected,
                                 options.meshes + "/corrected-" + degrees + ".off")) {
                    goto done;
                }
            }
            if (!options.png.empty()) {
                if (!ok(dfm_vk_renderer_update_positions(renderer, &scene_positions),
                        "update_positions") ||
                    !ok(dfm_vk_renderer_render_offscreen(renderer, &frame, &picture[p * row], row),
                        "render_offscreen")) {
                    goto done;
                }
            }
        }
        if (!options.meshes.empty()) {
            // Dualform's own posed surface at the edit (the mesh is still posed there).
            const std::string edited = options.meshes + "/edited-" +
                                       std::to_string(static_cast<int>(fix.degrees)) + ".off";
            if (!ok(dfm_mesh_save(mesh, edited.c_str()), "dfm_mesh_save")) goto done;
        }
        if (!options.png.empty() && !ok(dfm_vk_write_png(options.png.c_str(), picture.data(),
                                                         picture.size(), width, 3 * height),
                                        "write_png")) {
            goto done;
        }
        std::uint64_t messages = 0;
        dfm_vk_renderer_validation_message_count(renderer, &messages);
        if (messages > 0) {
            std::fprintf(stderr, "corrective: %llu Vulkan validation messages\n",
                         static_cast<unsigned long long>(messages));
            goto done;
        }
        double largest_delta = 0.0;
        for (std::size_t v = 0; v < arm.vertex_count(); ++v) {
            const float* d = &fix.delta[3 * v];
            largest_delta = std::max(
                largest_delta,
                std::sqrt(double(d[0]) * d[0] + double(d[1]) * d[1] + double(d[2]) * d[2]));
        }
        std::printf(
            "{\"vertices\": %zu, \"frames\": %d, \"diagonal\": %.6f, "
            "\"edit\": {\"degrees\": %.1f, \"region\": %zu, \"handles\": %zu, \"largest_drag\": "
            "%.6g, "
            "\"iterations\": %u}, "
            "\"corrective\": {\"vertices\": %zu, \"largest\": %.6g, \"worst_condition\": %.6g, "
            "\"damped\": %zu}, "
            "\"gap\": {\"straight\": %.6g, \"half\": %.6g, \"edited\": %.6g}, "
            "\"edited_pose_error\": %.3g, \"naive_error\": %.3g, "
            "\"host_frame_ms\": {\"p50\": %.3f, \"p99\": %.3f}, "
            "\"render_ms\": {\"p50\": %.3f, \"p99\": %.3f}}\n",
            arm.vertex_count(), played, info.diagonal, fix.degrees, fix.region_count,
            fix.handle_count, fix.largest_drag / info.diagonal, fix.iterations,
            fix.skin.corrective_vertex_count, largest_delta / info.diagonal,
            fix.skin.corrective_worst_condition, fix.skin.corrective_damped_count, gaps[0], gaps[1],
            gaps[2], edited_error, naive_miss(arm, fix) / info.diagonal, percentile(host_ms, 0.5),
            percentile(host_ms, 0.99), percentile(render_ms, 0.5), percentile(render_ms, 0.99));
        status = 0;
    }

done:
    dfm_vk_renderer_destroy(renderer);
    if (window != nullptr) glfwDestroyWindow(window);
    if (options.window) glfwTerminate();
    dfm_mesh_destroy(mesh);
    dfm_context_destroy(context);
    return status;
}
