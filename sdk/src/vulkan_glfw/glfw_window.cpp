#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <cstdint>

#include "dualform/dualform_vulkan_glfw.h"

namespace {

VkResult create_surface(void* user, VkInstance instance, VkSurfaceKHR* out) {
    return glfwCreateWindowSurface(instance, static_cast<GLFWwindow*>(user), nullptr, out);
}

void framebuffer_size(void* user, std::uint32_t* width, std::uint32_t* height) {
    int w = 0;
    int h = 0;
    glfwGetFramebufferSize(static_cast<GLFWwindow*>(user), &w, &h);
    *width = w > 0 ? static_cast<std::uint32_t>(w) : 0;
    *height = h > 0 ? static_cast<std::uint32_t>(h) : 0;
}

}  // namespace

extern "C" dfm_result dfm_vk_renderer_create_window(const dfm_vk_renderer_desc* desc,
                                                    void* glfw_window, dfm_vk_renderer** out) {
    // Every failure is reported by the renderer library, so its message lands
    // in dfm_last_error_message: a NULL window as such, a GLFW without Vulkan
    // support as the surface it cannot create.
    if (glfw_window == nullptr) return dfm_vk_renderer_create_for_window(desc, nullptr, out);
    std::uint32_t count = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&count);
    dfm_vk_window window = {};
    window.instance_extensions = names;
    window.instance_extension_count = names != nullptr ? count : 0;
    window.create_surface = create_surface;
    window.framebuffer_size = framebuffer_size;
    window.user = glfw_window;
    return dfm_vk_renderer_create_for_window(desc, &window, out);
}
