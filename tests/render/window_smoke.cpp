// Opens a GLFW window (run under Xvfb by CTest), presents frames through the
// renderer's swapchain path, resizes, presents again and exits; exit code 0
// only when every call succeeded and validation reported nothing.
#include <GLFW/glfw3.h>

#include <cstdio>
#include <vector>

#include "dualform/dualform_vulkan.h"
#include "dualform/dualform_vulkan_glfw.h"
#include "support/procedural_meshes.hpp"

namespace {

int fail(const char* what) {
    std::fprintf(stderr, "window smoke: %s: %s\n", what, dfm_last_error_message());
    return 1;
}

}  // namespace

int main() {
    if (glfwInit() != GLFW_TRUE) {
        std::fprintf(stderr, "window smoke: glfwInit failed (no display?)\n");
        return 1;
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    GLFWwindow* window = glfwCreateWindow(320, 240, "dualform window smoke", nullptr, nullptr);
    if (window == nullptr) {
        std::fprintf(stderr, "window smoke: glfwCreateWindow failed\n");
        glfwTerminate();
        return 1;
    }
    int status = 0;
    dfm_vk_renderer* renderer = nullptr;
    const dfm::mesh::Mesh sphere = dfm::test::make_icosphere(3);
    dfm_vec3_input positions = {};
    positions.data = sphere.positions.data();
    positions.count = sphere.positions.size();
    positions.type = DFM_SCALAR_FLOAT64;
    dfm_vk_frame frame = {};
    int presented_count = 0;
    dfm_vk_renderer_desc desc = {};
    desc.validation = true;
    if (dfm_vk_renderer_create_window(&desc, window, &renderer) != DFM_OK) {
        status = fail("create_window");
    } else if (dfm_vk_renderer_set_mesh(renderer, &positions, sphere.triangles.front().data(),
                                        sphere.triangles.size()) != DFM_OK) {
        status = fail("set_mesh");
    } else if (dfm_vk_framing_camera(&positions, 320, 240, &frame.camera) != DFM_OK) {
        status = fail("framing_camera");
    }
    for (int i = 0; status == 0 && i < 12; ++i) {
        if (i == 5) glfwSetWindowSize(window, 400, 180);
        glfwPollEvents();
        frame.flags = (i % 2) ? DFM_VK_FLAG_WIREFRAME : 0;
        bool presented = false;
        if (dfm_vk_renderer_present(renderer, &frame, &presented) != DFM_OK) {
            status = fail("present");
        }
        presented_count += presented ? 1 : 0;
    }
    int width = 0;
    int height = 0;
    glfwGetFramebufferSize(window, &width, &height);
    if (status == 0 && (width != 400 || height != 180)) {
        std::fprintf(stderr, "window smoke: the window was not resized (%dx%d)\n", width, height);
        status = 1;
    }
    std::uint64_t messages = 0;
    if (status == 0 && dfm_vk_renderer_validation_message_count(renderer, &messages) != DFM_OK) {
        status = fail("validation_message_count");
    }
    dfm_vk_renderer_destroy(renderer);
    glfwDestroyWindow(window);
    glfwTerminate();
    std::printf("window smoke: %d frames presented, %llu validation messages\n", presented_count,
                static_cast<unsigned long long>(messages));
    if (status == 0 && (messages != 0 || presented_count < 8)) status = 1;
    return status;
}
