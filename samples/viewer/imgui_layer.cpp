#include "imgui_layer.hpp"

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>
#include <imgui.h>

#include <algorithm>
#include <cstdio>

namespace viewer {

namespace {

void check_vk(VkResult result) {
    if (result != VK_SUCCESS) std::fprintf(stderr, "viewer: ImGui's Vulkan backend: %d\n", result);
}

}  // namespace

ImGuiLayer::~ImGuiLayer() {
    if (renderer_ != nullptr) {
        dfm_vk_overlay_desc none = {};
        none.struct_size = sizeof none;
        dfm_vk_renderer_set_overlay(renderer_, &none);
    }
    if (vulkan_ready_) {
        // Our objects live on the renderer's device and die before it.
        vkDeviceWaitIdle(device_.device);
        if (font_staging_alive_) ImGui_ImplVulkan_DestroyFontUploadObjects();
        ImGui_ImplVulkan_Shutdown();
        destroy_framebuffers();
        vkDestroyRenderPass(device_.device, render_pass_, nullptr);
        vkDestroyDescriptorPool(device_.device, pool_, nullptr);
    }
    if (glfw_ready_) ImGui_ImplGlfw_Shutdown();
    if (ImGui::GetCurrentContext() != nullptr) ImGui::DestroyContext();
}

bool ImGuiLayer::create(GLFWwindow* window, dfm_vk_renderer* renderer) {
    device_.struct_size = sizeof device_;
    if (dfm_vk_renderer_get_device(renderer, &device_) != DFM_OK) {
        std::fprintf(stderr, "viewer: %s\n", dfm_last_error_message());
        return false;
    }
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    // No imgui.ini: the panel's layout is the viewer's, the same every run.
    io.IniFilename = nullptr;
    ImGui::StyleColorsDark();
    // Compact: the whole panel fits a 640 x 480 window.
    ImGuiStyle& style = ImGui::GetStyle();
    style.ItemSpacing.y = 3.0f;
    style.FramePadding.y = 2.0f;
    style.WindowRounding = 0.0f;
    // The atlas is built now, its texture uploaded with the first frame
    // (create_vulkan): the swapchain's format is known only then.
    unsigned char* pixels = nullptr;
    int atlas_width = 0, atlas_height = 0;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &atlas_width, &atlas_height);
    // The viewer's callbacks forward to the backend's (input reaches the
    // panel first, and the editor only what the panel does not want).
    if (!ImGui_ImplGlfw_InitForVulkan(window, false)) {
        std::fprintf(stderr, "viewer: ImGui's GLFW backend did not start\n");
        return false;
    }
    glfw_ready_ = true;
    dfm_vk_overlay_desc overlay = {};
    overlay.struct_size = sizeof overlay;
    overlay.record = &ImGuiLayer::record;
    overlay.user = this;
    if (dfm_vk_renderer_set_overlay(renderer, &overlay) != DFM_OK) {
        std::fprintf(stderr, "viewer: %s\n", dfm_last_error_message());
        return false;
    }
    renderer_ = renderer;
    return true;
}

void ImGuiLayer::begin_frame(const ScriptedPointer* pointer) {
    if (vulkan_ready_) ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    if (pointer != nullptr) {
        ImGuiIO& io = ImGui::GetIO();
        io.MousePos = ImVec2(static_cast<float>(pointer->x), static_cast<float>(pointer->y));
        for (int i = 0; i < 3; ++i) io.MouseDown[i] = pointer->down[i];
    }
    ImGui::NewFrame();
    frame_ended_ = false;
}

void ImGuiLayer::end_frame() {
    ImGui::Render();
    frame_ended_ = true;
}

dfm_result ImGuiLayer::record(void* user, const dfm_vk_overlay_target* target) {
    return static_cast<ImGuiLayer*>(user)->record(*target);
}

bool ImGuiLayer::create_vulkan(const dfm_vk_overlay_target& target) {
    format_ = target.format;
    VkAttachmentDescription color{};
    color.format = target.format;
    color.samples = VK_SAMPLE_COUNT_1_BIT;
    // Over the mesh the renderer drew, and left as the renderer wants it.
    color.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    color.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    color.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    color.initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.finalLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    VkAttachmentReference reference{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass{};
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    subpass.colorAttachmentCount = 1;
    subpass.pColorAttachments = &reference;
    VkSubpassDependency dependency{};
    dependency.srcSubpass = VK_SUBPASS_EXTERNAL;
    dependency.dstSubpass = 0;
    dependency.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    dependency.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    dependency.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    dependency.dstAccessMask =
        VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    VkRenderPassCreateInfo pass{};
    pass.sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO;
    pass.attachmentCount = 1;
    pass.pAttachments = &color;
    pass.subpassCount = 1;
    pass.pSubpasses = &subpass;
    pass.dependencyCount = 1;
    pass.pDependencies = &dependency;
    if (VkResult r = vkCreateRenderPass(device_.device, &pass, nullptr, &render_pass_);
        r != VK_SUCCESS) {
        std::fprintf(stderr, "viewer: vkCreateRenderPass: %d\n", r);
        return false;
    }
    // One combined image sampler: the font atlas.
    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1};
    VkDescriptorPoolCreateInfo pool{};
    pool.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
    pool.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
    pool.maxSets = 1;
    pool.poolSizeCount = 1;
    pool.pPoolSizes = &size;
    if (VkResult r = vkCreateDescriptorPool(device_.device, &pool, nullptr, &pool_);
        r != VK_SUCCESS) {
        std::fprintf(stderr, "viewer: vkCreateDescriptorPool: %d\n", r);
        return false;
    }
    ImGui_ImplVulkan_InitInfo info = {};
    info.Instance = device_.instance;
    info.PhysicalDevice = device_.physical_device;
    info.Device = device_.device;
    info.QueueFamily = device_.queue_family;
    info.Queue = device_.queue;
    info.DescriptorPool = pool_;
    // ImageCount sets how many vertex buffers the backend cycles through:
    // more than the renderer's frames in flight, so none is still read.
    info.ImageCount = std::max(target.image_count, device_.frames_in_flight + 1);
    info.MinImageCount = std::max(2u, std::min(target.image_count, info.ImageCount));
    info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
    info.CheckVkResultFn = check_vk;
    if (!ImGui_ImplVulkan_Init(&info, render_pass_)) {
        std::fprintf(stderr, "viewer: ImGui's Vulkan backend did not start\n");
        return false;
    }
    vulkan_ready_ = true;
    // The font atlas uploads inside this frame's command buffer.
    ImGui_ImplVulkan_CreateFontsTexture(target.command_buffer);
    font_staging_alive_ = true;
    since_font_upload_ = 0;
    return true;
}

void ImGuiLayer::destroy_framebuffers() {
    for (VkFramebuffer f : framebuffers_) vkDestroyFramebuffer(device_.device, f, nullptr);
    framebuffers_.clear();
}

dfm_result ImGuiLayer::record(const dfm_vk_overlay_target& target) {
    if (!frame_ended_) return DFM_OK;
    if (!vulkan_ready_ && !create_vulkan(target)) return DFM_ERROR_DEVICE;
    if (target.format != format_) return DFM_ERROR_UNSUPPORTED;
    if (font_staging_alive_ && ++since_font_upload_ > device_.frames_in_flight) {
        // The frame fences have covered the upload's command buffer.
        ImGui_ImplVulkan_DestroyFontUploadObjects();
        font_staging_alive_ = false;
    }
    // A rebuilt swapchain: the renderer waited for its device, so the old
    // framebuffers are no longer in use.
    if (target.swapchain_generation != generation_ || framebuffers_.size() != target.image_count) {
        destroy_framebuffers();
        framebuffers_.assign(target.image_count, VK_NULL_HANDLE);
        generation_ = target.swapchain_generation;
    }
    VkFramebuffer& framebuffer = framebuffers_[target.image_index];
    if (framebuffer == VK_NULL_HANDLE) {
        VkFramebufferCreateInfo info{};
        info.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO;
        info.renderPass = render_pass_;
        info.attachmentCount = 1;
        info.pAttachments = &target.image_view;
        info.width = target.width;
        info.height = target.height;
        info.layers = 1;
        if (vkCreateFramebuffer(device_.device, &info, nullptr, &framebuffer) != VK_SUCCESS) {
            framebuffer = VK_NULL_HANDLE;
            return DFM_ERROR_DEVICE;
        }
    }
    VkRenderPassBeginInfo begin{};
    begin.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO;
    begin.renderPass = render_pass_;
    begin.framebuffer = framebuffer;
    begin.renderArea.extent = {target.width, target.height};
    vkCmdBeginRenderPass(target.command_buffer, &begin, VK_SUBPASS_CONTENTS_INLINE);
    ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), target.command_buffer);
    vkCmdEndRenderPass(target.command_buffer);
    return DFM_OK;
}

}  // namespace viewer
