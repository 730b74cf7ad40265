// The window path's host hooks under Xvfb (CTest runs it through xvfb-run):
// an overlay the host records after the mesh (dfm_vk_renderer_set_overlay)
// shows in the picture dfm_vk_renderer_present_and_read reads back, where
// the host drew it; its failure is the present's result; a resize starts a
// new swapchain generation; removing it leaves the mesh alone. Exit code 0
// only when every check held and validation reported nothing.
#include <GLFW/glfw3.h>

#include <cstdio>
#include <vector>

#include "dualform/dualform_vulkan.h"
#include "dualform/dualform_vulkan_glfw.h"
#include "support/procedural_meshes.hpp"

namespace {

int failures = 0;

void check(bool ok, const char* what) {
    if (ok) return;
    std::fprintf(stderr, "window overlay: FAILED: %s (last error: %s)\n", what,
                 dfm_last_error_message());
    ++failures;
}

// The host's overlay: a magenta rectangle in the top-left corner, drawn with
// the host's own dynamic rendering on the image it is handed.
struct Host {
    dfm_result result = DFM_OK;
    int calls = 0;
    dfm_vk_overlay_target last = {};
};

dfm_result draw_corner(void* user, const dfm_vk_overlay_target* target) {
    Host& host = *static_cast<Host*>(user);
    ++host.calls;
    host.last = *target;
    VkRenderingAttachmentInfo color = {};
    color.sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO;
    color.imageView = target->image_view;
    color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    VkRenderingInfo rendering = {};
    rendering.sType = VK_STRUCTURE_TYPE_RENDERING_INFO;
    rendering.renderArea.extent = {target->width, target->height};
    rendering.layerCount = 1;
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachments = &color;
    vkCmdBeginRendering(target->command_buffer, &rendering);
    VkClearAttachment clear = {};
    clear.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT;
    clear.clearValue.color = {{1.0f, 0.0f, 1.0f, 1.0f}};
    VkClearRect rect = {};
    rect.rect.extent = {40, 30};
    rect.layerCount = 1;
    vkCmdClearAttachments(target->command_buffer, 1, &clear, 1, &rect);
    vkCmdEndRendering(target->command_buffer);
    return host.result;
}

bool magenta(const std::vector<std::uint8_t>& rgba, int width, int x, int y) {
    const std::uint8_t* p = &rgba[(std::size_t(y) * width + x) * 4];
    return p[0] == 255 && p[1] == 0 && p[2] == 255;
}

std::size_t magenta_count(const std::vector<std::uint8_t>& rgba) {
    std::size_t n = 0;
    for (std::size_t i = 0; i + 3 < rgba.size(); i += 4) {
        n += rgba[i] == 255 && rgba[i + 1] == 0 && rgba[i + 2] == 255;
    }
    return n;
}

// Presents until a frame is shown (a new swapchain shows nothing at first).
bool read_window(dfm_vk_renderer* renderer, const dfm_vk_frame& frame,
                 std::vector<std::uint8_t>& rgba) {
    for (int tries = 0; tries < 4; ++tries) {
        glfwPollEvents();
        bool presented = false;
        if (dfm_vk_renderer_present_and_read(renderer, &frame, rgba.data(), rgba.size(),
                                             &presented) != DFM_OK) {
            return false;
        }
        if (presented) return true;
    }
    return false;
}

}  // namespace

int main() {
    if (glfwInit() != GLFW_TRUE) {
        std::fprintf(stderr, "window overlay: glfwInit failed (no display?)\n");
        return 1;
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    const int width = 200, height = 150;
    GLFWwindow* window = glfwCreateWindow(width, height, "dualform overlay", nullptr, nullptr);
    if (window == nullptr) {
        std::fprintf(stderr, "window overlay: glfwCreateWindow failed\n");
        glfwTerminate();
        return 1;
    }
    dfm_vk_renderer* renderer = nullptr;
    dfm_vk_renderer* headless = nullptr;
    dfm_vk_renderer_desc desc = {};
    desc.validation = true;
    const dfm::mesh::Mesh sphere = dfm::test::make_icosphere(3);
    dfm_vec3_input positions = {};
    positions.data = sphere.positions.data();
    positions.count = sphere.positions.size();
    positions.type = DFM_SCALAR_FLOAT64;
    dfm_vk_frame frame = {};
    Host host;
    dfm_vk_overlay_desc overlay = {};
    overlay.struct_size = sizeof overlay;
    overlay.record = draw_corner;
    overlay.user = &host;
    if (dfm_vk_renderer_create_window(&desc, window, &renderer) != DFM_OK ||
        dfm_vk_renderer_set_mesh(renderer, &positions, sphere.triangles.front().data(),
                                 sphere.triangles.size()) != DFM_OK ||
        dfm_vk_framing_camera(&positions, width, height, &frame.camera) != DFM_OK) {
        check(false, "a window renderer with a mesh");
    } else {
        dfm_vk_device_info device = {};
        device.struct_size = sizeof device;
        check(dfm_vk_renderer_get_device(renderer, &device) == DFM_OK, "get_device");
        check(device.device != VK_NULL_HANDLE && device.queue != VK_NULL_HANDLE &&
                  device.instance != VK_NULL_HANDLE && device.physical_device != VK_NULL_HANDLE,
              "get_device gives the renderer's handles");
        check(device.frames_in_flight == 2 && device.samples >= 1, "get_device's figures");
        check(dfm_vk_renderer_set_overlay(renderer, nullptr) == DFM_ERROR_INVALID_ARGUMENT,
              "set_overlay refuses a NULL desc");
        check(dfm_vk_renderer_set_overlay(renderer, &overlay) == DFM_OK, "set_overlay");

        std::vector<std::uint8_t> rgba(std::size_t(width) * height * 4);
        std::vector<std::uint8_t> small(16);
        bool presented = true;
        check(dfm_vk_renderer_present_and_read(renderer, &frame, small.data(), small.size(),
                                               &presented) == DFM_ERROR_INVALID_ARGUMENT &&
                  !presented,
              "present_and_read refuses a buffer of another size");
        check(read_window(renderer, frame, rgba), "present_and_read");
        check(host.calls >= 1, "the overlay was called");
        check(host.last.struct_size == sizeof(dfm_vk_overlay_target) &&
                  host.last.width == unsigned(width) && host.last.height == unsigned(height) &&
                  host.last.image_index < host.last.image_count,
              "the overlay's target describes the window's image");
        check(magenta(rgba, width, 0, 0) && magenta(rgba, width, 39, 29) &&
                  !magenta(rgba, width, 40, 29) && !magenta(rgba, width, 39, 30),
              "the overlay's rectangle is in the picture, where it was drawn");
        check(magenta_count(rgba) == 40 * 30, "nothing else is magenta");
        const std::uint8_t* centre = &rgba[(std::size_t(height / 2) * width + width / 2) * 4];
        const std::uint8_t* corner = &rgba[(std::size_t(height - 1) * width + width - 1) * 4];
        check(centre[0] != corner[0] || centre[1] != corner[1] || centre[2] != corner[2],
              "the mesh is drawn under the overlay");

        host.result = DFM_ERROR_IO;
        check(dfm_vk_renderer_present(renderer, &frame, &presented) == DFM_ERROR_IO,
              "the overlay's failure is the present's result");
        host.result = DFM_OK;

        const std::uint64_t generation = host.last.swapchain_generation;
        glfwSetWindowSize(window, 240, 160);
        std::vector<std::uint8_t> resized(std::size_t(240) * 160 * 4);
        for (int i = 0; i < 20 && host.last.width != 240; ++i) {
            glfwPollEvents();
            dfm_vk_renderer_present(renderer, &frame, nullptr);
        }
        check(read_window(renderer, frame, resized), "present_and_read after a resize");
        check(host.last.swapchain_generation > generation,
              "a resize starts a new swapchain generation");
        check(magenta_count(resized) == 40 * 30, "the overlay follows the new swapchain");

        dfm_vk_overlay_desc none = {};
        check(dfm_vk_renderer_set_overlay(renderer, &none) == DFM_OK, "removing the overlay");
        const int calls = host.calls;
        check(read_window(renderer, frame, resized) && magenta_count(resized) == 0 &&
                  host.calls == calls,
              "without the overlay the picture is the mesh alone");
    }
    check(dfm_vk_renderer_create_headless(&desc, &headless) == DFM_OK, "a headless renderer");
    check(dfm_vk_renderer_set_overlay(headless, &overlay) == DFM_ERROR_UNSUPPORTED,
          "a headless renderer has no overlay");
    std::uint64_t messages = 0;
    dfm_vk_renderer_validation_message_count(renderer, &messages);
    check(messages == 0, "no validation messages");
    dfm_vk_renderer_destroy(headless);
    dfm_vk_renderer_destroy(renderer);
    glfwDestroyWindow(window);
    glfwTerminate();
    std::printf("window overlay: %d failures, %llu validation messages\n", failures,
                static_cast<unsigned long long>(messages));
    return failures == 0 ? 0 : 1;
}
