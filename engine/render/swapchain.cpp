#include "render/swapchain.hpp"

#include <algorithm>

#include "render/attachment_commands.hpp"

namespace dfm::render {

namespace {

constexpr VkPipelineStageFlags attachment_stages = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                                                   VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                                                   VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;

VkPresentModeKHR choose_present_mode(const Gpu& gpu, VkSurfaceKHR surface, bool vsync) {
    if (vsync) return VK_PRESENT_MODE_FIFO_KHR;
    std::uint32_t count = 0;
    vkGetPhysicalDeviceSurfacePresentModesKHR(gpu.physical, surface, &count, nullptr);
    std::vector<VkPresentModeKHR> modes(count);
    vkGetPhysicalDeviceSurfacePresentModesKHR(gpu.physical, surface, &count, modes.data());
    for (VkPresentModeKHR wanted : {VK_PRESENT_MODE_MAILBOX_KHR, VK_PRESENT_MODE_IMMEDIATE_KHR}) {
        if (std::find(modes.begin(), modes.end(), wanted) != modes.end()) return wanted;
    }
    return VK_PRESENT_MODE_FIFO_KHR;
}

}  // namespace

Swapchain::~Swapchain() {
    for (VkSemaphore s : rendered_) vkDestroySemaphore(device_, s, nullptr);
    for (VkImageView v : views_) vkDestroyImageView(device_, v, nullptr);
    if (swapchain_ != VK_NULL_HANDLE) vkDestroySwapchainKHR(device_, swapchain_, nullptr);
}

Status Swapchain::choose_format(const Gpu& gpu, VkSurfaceKHR surface, VkSurfaceFormatKHR& out) {
    std::uint32_t count = 0;
    vkGetPhysicalDeviceSurfaceFormatsKHR(gpu.physical, surface, &count, nullptr);
    std::vector<VkSurfaceFormatKHR> formats(count);
    vkGetPhysicalDeviceSurfaceFormatsKHR(gpu.physical, surface, &count, formats.data());
    if (formats.empty()) return Status(Errc::device, "the window surface has no formats");
    for (VkFormat wanted : {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM}) {
        for (const VkSurfaceFormatKHR& f : formats) {
            if (f.format == wanted && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR) {
                out = f;
                return Status::ok();
            }
        }
    }
    out = formats.front();
    return Status::ok();
}

Status Swapchain::create(const Gpu& gpu, VkSurfaceKHR surface, const AttachmentFormats& formats,
                         VkSurfaceFormatKHR format, VkExtent2D extent, bool vsync, Swapchain& out) {
    VkSurfaceCapabilitiesKHR caps;
    if (VkResult r = vkGetPhysicalDeviceSurfaceCapabilitiesKHR(gpu.physical, surface, &caps);
        r != VK_SUCCESS) {
        return vk_failure(r, "vkGetPhysicalDeviceSurfaceCapabilitiesKHR");
    }
    if (caps.currentExtent.width != UINT32_MAX) extent = caps.currentExtent;
    extent.width = std::clamp(extent.width, caps.minImageExtent.width, caps.maxImageExtent.width);
    extent.height =
        std::clamp(extent.height, caps.minImageExtent.height, caps.maxImageExtent.height);
    std::uint32_t image_count = caps.minImageCount + 1;
    if (caps.maxImageCount > 0) image_count = std::min(image_count, caps.maxImageCount);

    out.device_ = gpu.device;
    out.extent_ = extent;
    out.format_ = format.format;
    out.multisampled_ = formats.samples != VK_SAMPLE_COUNT_1_BIT;
    out.readable_ = (caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT) != 0;
    VkSwapchainCreateInfoKHR info{};
    info.sType = VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR;
    info.surface = surface;
    info.minImageCount = image_count;
    info.imageFormat = format.format;
    info.imageColorSpace = format.colorSpace;
    info.imageExtent = extent;
    info.imageArrayLayers = 1;
    info.imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    if (out.readable_) info.imageUsage |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.preTransform = caps.currentTransform;
    info.compositeAlpha = (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR)
                              ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
                              : VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR;
    info.presentMode = choose_present_mode(gpu, surface, vsync);
    info.clipped = VK_TRUE;
    if (VkResult r = vkCreateSwapchainKHR(gpu.device, &info, nullptr, &out.swapchain_);
        r != VK_SUCCESS) {
        out.swapchain_ = VK_NULL_HANDLE;
        return vk_failure(r, "vkCreateSwapchainKHR");
    }
    std::uint32_t count = 0;
    vkGetSwapchainImagesKHR(gpu.device, out.swapchain_, &count, nullptr);
    out.images_.resize(count);
    vkGetSwapchainImagesKHR(gpu.device, out.swapchain_, &count, out.images_.data());
    for (VkImage image : out.images_) {
        VkImageViewCreateInfo view{};
        view.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO;
        view.image = image;
        view.viewType = VK_IMAGE_VIEW_TYPE_2D;
        view.format = format.format;
        view.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        VkImageView v = VK_NULL_HANDLE;
        if (VkResult r = vkCreateImageView(gpu.device, &view, nullptr, &v); r != VK_SUCCESS) {
            return vk_failure(r, "vkCreateImageView");
        }
        out.views_.push_back(v);
        VkSemaphoreCreateInfo semaphore{};
        semaphore.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO;
        VkSemaphore s = VK_NULL_HANDLE;
        if (VkResult r = vkCreateSemaphore(gpu.device, &semaphore, nullptr, &s); r != VK_SUCCESS) {
            return vk_failure(r, "vkCreateSemaphore");
        }
        out.rendered_.push_back(s);
    }
    if (out.multisampled_) {
        if (Status s = GpuImage::create(
                gpu, extent, format.format, formats.samples,
                VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSIENT_ATTACHMENT_BIT,
                VK_IMAGE_ASPECT_COLOR_BIT, out.color_);
            !s) {
            return s;
        }
    }
    return GpuImage::create(gpu, extent, formats.depth, formats.samples,
                            VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, VK_IMAGE_ASPECT_DEPTH_BIT,
                            out.depth_);
}

void Swapchain::record_begin(VkCommandBuffer cmd, std::uint32_t image,
                             const float background[4]) const {
    transition_image(
        cmd, images_[image], VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
        VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, 0,
        VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT);
    if (multisampled_) {
        transition_image(
            cmd, color_.handle(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
            VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
            VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
            VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_READ_BIT);
    }
    transition_image(
        cmd, depth_.handle(), VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
        VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, attachment_stages,
        VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, attachment_stages,
        VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
    if (multisampled_) {
        begin_clear_rendering(cmd, extent_, color_.view(), views_[image], depth_.view(),
                              background);
    } else {
        begin_clear_rendering(cmd, extent_, views_[image], VK_NULL_HANDLE, depth_.view(),
                              background);
    }
}

void Swapchain::record_end_rendering(VkCommandBuffer cmd, std::uint32_t image) const {
    vkCmdEndRendering(cmd);
    transition_image(
        cmd, images_[image], VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
        VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
        VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
        VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT);
}

void Swapchain::record_copy(VkCommandBuffer cmd, std::uint32_t image, VkBuffer readback) const {
    copy_to_host(cmd, images_[image], extent_, readback);
}

void Swapchain::record_present_ready(VkCommandBuffer cmd, std::uint32_t image, bool copied) const {
    if (copied) {
        transition_image(cmd, images_[image], VK_IMAGE_ASPECT_COLOR_BIT,
                         VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                         VK_PIPELINE_STAGE_TRANSFER_BIT, 0, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT,
                         0);
        return;
    }
    transition_image(cmd, images_[image], VK_IMAGE_ASPECT_COLOR_BIT,
                     VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                     VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                     VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0);
}

}  // namespace dfm::render
