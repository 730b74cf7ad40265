#include <doctest/doctest.h>

#include <atomic>
#include <cstring>
#include <vector>

#include "render/render_helpers.hpp"
#include "support/procedural_meshes.hpp"

using namespace dfm;
using namespace dfm::test;

namespace {

std::atomic<int> host_messages{0};

VKAPI_ATTR VkBool32 VKAPI_CALL count_message(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                             VkDebugUtilsMessageTypeFlagsEXT,
                                             const VkDebugUtilsMessengerCallbackDataEXT* data,
                                             void*) {
    ++host_messages;
    MESSAGE("validation: " << (data && data->pMessage ? data->pMessage : ""));
    return VK_FALSE;
}

std::uint32_t memory_type(VkPhysicalDevice physical, std::uint32_t bits,
                          VkMemoryPropertyFlags flags) {
    VkPhysicalDeviceMemoryProperties props;
    vkGetPhysicalDeviceMemoryProperties(physical, &props);
    for (std::uint32_t i = 0; i < props.memoryTypeCount; ++i) {
        if ((bits & (1u << i)) && (props.memoryTypes[i].propertyFlags & flags) == flags) return i;
    }
    FAIL("no memory type");
    return 0;
}

// What a host application has: its own instance (validation on, its own
// messenger), device, queue, attachments and command buffer.
struct Host {
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    std::uint32_t family = 0;
    VkCommandPool pool = VK_NULL_HANDLE;
    struct Image {
        VkImage image = VK_NULL_HANDLE;
        VkDeviceMemory memory = VK_NULL_HANDLE;
        VkImageView view = VK_NULL_HANDLE;
    } color, depth;
    VkBuffer readback = VK_NULL_HANDLE;
    VkDeviceMemory readback_memory = VK_NULL_HANDLE;

    Host() {
        VkApplicationInfo app{};
        app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
        app.apiVersion = VK_API_VERSION_1_3;
        VkDebugUtilsMessengerCreateInfoEXT messenger_info{};
        messenger_info.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT;
        messenger_info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                         VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        messenger_info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                                     VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                     VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
        messenger_info.pfnUserCallback = count_message;
        const char* layer = "VK_LAYER_KHRONOS_validation";
        const char* extension = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
        VkInstanceCreateInfo info{};
        info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
        info.pNext = &messenger_info;
        info.pApplicationInfo = &app;
        info.enabledLayerCount = 1;
        info.ppEnabledLayerNames = &layer;
        info.enabledExtensionCount = 1;
        info.ppEnabledExtensionNames = &extension;
        REQUIRE(vkCreateInstance(&info, nullptr, &instance) == VK_SUCCESS);
        auto create_messenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
        REQUIRE(create_messenger(instance, &messenger_info, nullptr, &messenger) == VK_SUCCESS);

        std::uint32_t count = 1;
        REQUIRE(vkEnumeratePhysicalDevices(instance, &count, &physical) !=
                VK_ERROR_INITIALIZATION_FAILED);
        REQUIRE(count == 1);
        std::uint32_t families = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(physical, &families, nullptr);
        std::vector<VkQueueFamilyProperties> family_props(families);
        vkGetPhysicalDeviceQueueFamilyProperties(physical, &families, family_props.data());
        while (family < families && !(family_props[family].queueFlags & VK_QUEUE_GRAPHICS_BIT)) {
            ++family;
        }
        REQUIRE(family < families);
        VkPhysicalDeviceVulkan13Features v13{};
        v13.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES;
        v13.dynamicRendering = VK_TRUE;
        const float priority = 1.0f;
        VkDeviceQueueCreateInfo queue_info{};
        queue_info.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
        queue_info.queueFamilyIndex = family;
        queue_info.queueCount = 1;
        queue_info.pQueuePriorities = &priority;
        VkDeviceCreateInfo device_info{};
        device_info.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
        device_info.pNext = &v13;
        device_info.queueCreateInfoCount = 1;
        device_info.pQueueCreateInfos = &queue_info;
        REQUIRE(vkCreateDevice(physical, &device_info, nullptr, &device) == VK_SUCCESS);
        vkGetDeviceQueue(device, family, 0, &queue);
        VkCommandPoolCreateInfo pool_info{};
        pool_info.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
        pool_info.queueFamilyIndex = family;
        REQUIRE(vkCreateCommandPool(device, &pool_info, nullptr, &pool) == VK_SUCCESS);
    }

    void make_image(Image& out, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage,
                    VkImageAspectFlags aspect) {
        VkImageCreateInfo info{};
        info.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO;
        info.imageType = VK_IMAGE_TYPE_2D;
        info.format = format;
        info.extent = {extent.width, extent.height, 1};
        info.mipLevels = 1;
        info.arrayLayers = 1;
        info.samples = VK_SAMPLE_COUNT_1_BIT;
        info.usage = usage;
        REQUIRE(vkCreateImage(device, &info, nullptr, &out.image) == VK_SUCCESS);
        VkMemoryRequirements needs;
        vkGetImageMemoryRequirements(device, out.image, &needs);
        VkMemoryAllocateInfo allocate{};
        allocate.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
        allocate.allocationSize = needs.size;
        allocate.memoryTypeIndex = memory_type(physical, needs.memoryTypeBits, 0);
        REQUIRE(vkAllocateMemory(device, &allocate, nullptr, &out.memory) == VK_SUCCESS);
        REQUIRE(vkBindImageMemory(device, out.image, out.memory, 0) == VK_SUCCESS);
        VkImageViewCreateInfo view{};
        view.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO;
        view.image = out.image;
        view.viewType = VK_IMAGE_VIEW_TYPE_2D;
        view.format = format;
        view.subresourceRange = {aspect, 0, 1, 0, 1};
        REQUIRE(vkCreateImageView(device, &view, nullptr, &out.view) == VK_SUCCESS);
    }

    void make_readback(VkDeviceSize size) {
        VkBufferCreateInfo info{};
        info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
        info.size = size;
        info.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
        REQUIRE(vkCreateBuffer(device, &info, nullptr, &readback) == VK_SUCCESS);
        VkMemoryRequirements needs;
        vkGetBufferMemoryRequirements(device, readback, &needs);
        VkMemoryAllocateInfo allocate{};
        allocate.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
        allocate.allocationSize = needs.size;
        allocate.memoryTypeIndex =
            memory_type(physical, needs.memoryTypeBits,
                        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
        REQUIRE(vkAllocateMemory(device, &allocate, nullptr, &readback_memory) == VK_SUCCESS);
        REQUIRE(vkBindBufferMemory(device, readback, readback_memory, 0) == VK_SUCCESS);
    }

    ~Host() {
        vkDeviceWaitIdle(device);
        vkDestroyBuffer(device, readback, nullptr);
        vkFreeMemory(device, readback_memory, nullptr);
        for (Image* i : {&color, &depth}) {
            vkDestroyImageView(device, i->view, nullptr);
            vkDestroyImage(device, i->image, nullptr);
            vkFreeMemory(device, i->memory, nullptr);
        }
        vkDestroyCommandPool(device, pool, nullptr);
        vkDestroyDevice(device, nullptr);
        auto destroy_messenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
        destroy_messenger(instance, messenger, nullptr);
        vkDestroyInstance(instance, nullptr);
    }
};

void barrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from,
             VkImageLayout to, VkPipelineStageFlags src, VkAccessFlags src_access,
             VkPipelineStageFlags dst, VkAccessFlags dst_access) {
    VkImageMemoryBarrier b{};
    b.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER;
    b.srcAccessMask = src_access;
    b.dstAccessMask = dst_access;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {aspect, 0, 1, 0, 1};
    vkCmdPipelineBarrier(cmd, src, dst, 0, 0, nullptr, 0, nullptr, 1, &b);
}

}  // namespace

TEST_CASE("render: a host's device records our draw into its own command buffer") {
    const mesh::Mesh sphere = make_icosphere(3);
    pick::Camera view;
    view.eye = {0.5, 0.8, 4.0};
    view.up = {0.0, 1.0, 0.0};
    view.fov_y_degrees = 60.0;
    view.width = 96;
    view.height = 64;
    const dfm_camera camera = to_c_camera(view);
    const VkExtent2D extent{view.width, view.height};

    std::vector<std::uint8_t> host_picture(std::size_t{extent.width} * extent.height * 4);
    {
        Host host;
        host.make_image(host.color, extent, VK_FORMAT_R8G8B8A8_UNORM,
                        VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                        VK_IMAGE_ASPECT_COLOR_BIT);
        host.make_image(host.depth, extent, VK_FORMAT_D32_SFLOAT,
                        VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, VK_IMAGE_ASPECT_DEPTH_BIT);
        host.make_readback(host_picture.size());

        dfm_vk_host_desc desc = {};
        desc.instance = host.instance;
        desc.physical_device = host.physical;
        desc.device = host.device;
        desc.queue_family = host.family;
        desc.queue = host.queue;
        desc.color_format = VK_FORMAT_R8G8B8A8_UNORM;
        desc.depth_format = VK_FORMAT_D32_SFLOAT;
        dfm_vk_renderer* renderer = nullptr;
        REQUIRE_MESSAGE(dfm_vk_renderer_create_host(&desc, &renderer) == DFM_OK,
                        dfm_last_error_message());
        const dfm_vec3_input positions = positions_of(sphere);
        REQUIRE(dfm_vk_renderer_set_mesh(renderer, &positions, sphere.triangles.front().data(),
                                         sphere.triangles.size()) == DFM_OK);
        dfm_vk_frame frame = {};
        frame.camera = camera;
        std::uint8_t none[4];
        CHECK(dfm_vk_renderer_render_offscreen(renderer, &frame, none, 4) ==
              DFM_ERROR_INVALID_ARGUMENT);
        CHECK(dfm_vk_renderer_render_offscreen(renderer, &frame, nullptr, 0) ==
              DFM_ERROR_UNSUPPORTED);

        VkCommandBufferAllocateInfo allocate{};
        allocate.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
        allocate.commandPool = host.pool;
        allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        allocate.commandBufferCount = 1;
        VkCommandBuffer cmd = VK_NULL_HANDLE;
        REQUIRE(vkAllocateCommandBuffers(host.device, &allocate, &cmd) == VK_SUCCESS);
        VkCommandBufferBeginInfo begin{};
        begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
        REQUIRE(vkBeginCommandBuffer(cmd, &begin) == VK_SUCCESS);

        REQUIRE(dfm_vk_renderer_record_upload(renderer, cmd) == DFM_OK);
        barrier(cmd, host.color.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
                VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT);
        barrier(
            cmd, host.depth.image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
            VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
            VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT,
            VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
                VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT);
        VkRenderingAttachmentInfo color{};
        color.sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO;
        color.imageView = host.color.view;
        color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        color.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        // The renderer's default background, so the two pictures compare.
        color.clearValue.color = {{0.16f, 0.18f, 0.22f, 1.0f}};
        VkRenderingAttachmentInfo depth{};
        depth.sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO;
        depth.imageView = host.depth.view;
        depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
        depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        depth.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
        depth.clearValue.depthStencil = {1.0f, 0};
        VkRenderingInfo rendering{};
        rendering.sType = VK_STRUCTURE_TYPE_RENDERING_INFO;
        rendering.renderArea = {{0, 0}, extent};
        rendering.layerCount = 1;
        rendering.colorAttachmentCount = 1;
        rendering.pColorAttachments = &color;
        rendering.pDepthAttachment = &depth;
        vkCmdBeginRendering(cmd, &rendering);
        REQUIRE(dfm_vk_renderer_record_draw(renderer, cmd, &frame, extent.width, extent.height) ==
                DFM_OK);
        vkCmdEndRendering(cmd);
        // A new mesh while the recorded draw is not even submitted: the
        // renderer waits on nothing of the host's and keeps the buffers that
        // draw reads alive (the validation layer would see a destroyed one).
        REQUIRE(dfm_vk_renderer_set_mesh(renderer, &positions, sphere.triangles.front().data(),
                                         sphere.triangles.size()) == DFM_OK);
        barrier(cmd, host.color.image, VK_IMAGE_ASPECT_COLOR_BIT,
                VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {extent.width, extent.height, 1};
        vkCmdCopyImageToBuffer(cmd, host.color.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                               host.readback, 1, &region);
        REQUIRE(vkEndCommandBuffer(cmd) == VK_SUCCESS);
        VkSubmitInfo submit{};
        submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
        submit.commandBufferCount = 1;
        submit.pCommandBuffers = &cmd;
        REQUIRE(vkQueueSubmit(host.queue, 1, &submit, VK_NULL_HANDLE) == VK_SUCCESS);
        REQUIRE(vkQueueWaitIdle(host.queue) == VK_SUCCESS);
        void* mapped = nullptr;
        REQUIRE(vkMapMemory(host.device, host.readback_memory, 0, VK_WHOLE_SIZE, 0, &mapped) ==
                VK_SUCCESS);
        std::memcpy(host_picture.data(), mapped, host_picture.size());
        vkUnmapMemory(host.device, host.readback_memory);

        dfm_vk_renderer_destroy(renderer);
    }
    CHECK(host_messages.load() == 0);

    // The same scene through a headless renderer without MSAA: the same pixels.
    HeadlessScene headless(sphere, 1);
    const std::vector<std::uint8_t> headless_picture = headless.render(camera);
    const std::size_t covered = host_picture.size() / 4 - count_pixels(host_picture, is_background);
    CHECK(covered > host_picture.size() / 4 / 20);
    CHECK(host_picture == headless_picture);
    CHECK(headless.messages() == 0);
}
