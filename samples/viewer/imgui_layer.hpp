#pragma once

#include <cstdint>
#include <vector>

#include "dualform/dualform_vulkan.h"

struct GLFWwindow;

namespace viewer {

// A pointer that a script drives instead of the system's: what ImGui sees
// in scripted mode.
struct ScriptedPointer {
    double x = -1e9, y = -1e9;
    bool down[3] = {false, false, false};
};

// Dear ImGui in the viewer's window: the GLFW backend for input (the
// viewer's own callbacks forward to it) and the Vulkan backend drawing into
// the renderer's frame through dualform_vulkan.h's overlay, after the mesh,
// in a render pass of its own on the swapchain image.
class ImGuiLayer {
public:
    ImGuiLayer() = default;
    ImGuiLayer(const ImGuiLayer&) = delete;
    ImGuiLayer& operator=(const ImGuiLayer&) = delete;
    ~ImGuiLayer();

    // False with the reason on stderr.
    bool create(GLFWwindow* window, dfm_vk_renderer* renderer);

    // Starts an ImGui frame; `pointer` (scripted mode) replaces the system's.
    void begin_frame(const ScriptedPointer* pointer);
    // Ends it: what the next present draws.
    void end_frame();

private:
    static dfm_result record(void* user, const dfm_vk_overlay_target* target);
    dfm_result record(const dfm_vk_overlay_target& target);
    bool create_vulkan(const dfm_vk_overlay_target& target);
    void destroy_framebuffers();

    dfm_vk_renderer* renderer_ = nullptr;
    dfm_vk_device_info device_{};
    bool glfw_ready_ = false;
    bool vulkan_ready_ = false;
    bool frame_ended_ = false;
    VkFormat format_ = VK_FORMAT_UNDEFINED;
    VkRenderPass render_pass_ = VK_NULL_HANDLE;
    VkDescriptorPool pool_ = VK_NULL_HANDLE;
    std::uint64_t generation_ = 0;
    std::vector<VkFramebuffer> framebuffers_;
    // Frames recorded since the font upload: its staging buffer goes once
    // the GPU is certainly past it.
    std::uint32_t since_font_upload_ = 0;
    bool font_staging_alive_ = false;
};

}  // namespace viewer
