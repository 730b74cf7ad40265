#pragma once

#include <cstdint>
#include <vector>

#include <vulkan/vulkan.h>

#include "render/gpu_memory.hpp"
#include "render/pipelines.hpp"

namespace dfm::render {

// The window's swapchain with what drawing into it needs: a view and a
// "rendering done" semaphore per image (a present may still wait on an
// image's semaphore when the next frame slot comes round), and the shared
// multisampled colour and depth images. Rebuilt whole on resize.
class Swapchain {
public:
    Swapchain() = default;
    Swapchain(const Swapchain&) = delete;
    Swapchain& operator=(const Swapchain&) = delete;
    ~Swapchain();

    // The surface format the pipelines must target (BGRA8/RGBA8 UNORM first).
    static Status choose_format(const Gpu& gpu, VkSurfaceKHR surface, VkSurfaceFormatKHR& out);

    // `extent`: the window's framebuffer size, clamped to what the surface
    // allows. `vsync`: FIFO; otherwise MAILBOX or IMMEDIATE where offered.
    static Status create(const Gpu& gpu, VkSurfaceKHR surface, const AttachmentFormats& formats,
                         VkSurfaceFormatKHR format, VkExtent2D extent, bool vsync, Swapchain& out);

    VkSwapchainKHR handle() const { return swapchain_; }
    VkExtent2D extent() const { return extent_; }
    VkFormat format() const { return format_; }
    std::uint32_t image_count() const { return static_cast<std::uint32_t>(images_.size()); }
    VkImage image(std::uint32_t i) const { return images_[i]; }
    VkImageView view(std::uint32_t i) const { return views_[i]; }
    VkSemaphore rendered(std::uint32_t i) const { return rendered_[i]; }
    // Whether the surface lets its images be copied from (a window picture).
    bool readable() const { return readable_; }

    // Transitions the acquired image for drawing and begins clearing rendering.
    void record_begin(VkCommandBuffer cmd, std::uint32_t image, const float background[4]) const;
    // Ends rendering; the image stays a colour attachment, our writes made
    // visible to later colour-attachment reads and writes (a host overlay).
    void record_end_rendering(VkCommandBuffer cmd, std::uint32_t image) const;
    // Copies the finished image into `readback` (width x height x 4 bytes,
    // host-visible); only on a readable() swapchain.
    void record_copy(VkCommandBuffer cmd, std::uint32_t image, VkBuffer readback) const;
    // Readies the image for presenting (from the layout the steps above left).
    void record_present_ready(VkCommandBuffer cmd, std::uint32_t image, bool copied) const;

private:
    VkDevice device_ = VK_NULL_HANDLE;
    VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
    VkExtent2D extent_{};
    VkFormat format_ = VK_FORMAT_UNDEFINED;
    bool multisampled_ = false;
    bool readable_ = false;
    std::vector<VkImage> images_;
    std::vector<VkImageView> views_;
    std::vector<VkSemaphore> rendered_;
    GpuImage color_;
    GpuImage depth_;
};

}  // namespace dfm::render
