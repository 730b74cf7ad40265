#pragma once

#include <utility>

#include <vulkan/vulkan.h>

#include "render/device.hpp"
#include "render/vulkan_result.hpp"

namespace dfm::render {

// A buffer with its own memory; host-visible ones stay mapped for their whole
// life. Move-only; frees itself.
class GpuBuffer {
public:
    GpuBuffer() = default;
    GpuBuffer(GpuBuffer&& other) noexcept { swap(other); }
    GpuBuffer& operator=(GpuBuffer&& other) noexcept {
        GpuBuffer gone(std::move(*this));
        swap(other);
        return *this;
    }
    ~GpuBuffer();

    // `host_visible`: mapped, coherent memory; otherwise device-local where the
    // device has it.
    static Status create(const Gpu& gpu, VkDeviceSize size, VkBufferUsageFlags usage,
                         bool host_visible, GpuBuffer& out);

    VkBuffer handle() const { return buffer_; }
    VkDeviceSize size() const { return size_; }
    void* mapped() const { return mapped_; }

private:
    void swap(GpuBuffer& other) noexcept;

    VkDevice device_ = VK_NULL_HANDLE;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkDeviceSize size_ = 0;
    void* mapped_ = nullptr;
};

// A 2D attachment image in device-local memory with one view. Move-only.
class GpuImage {
public:
    GpuImage() = default;
    GpuImage(GpuImage&& other) noexcept { swap(other); }
    GpuImage& operator=(GpuImage&& other) noexcept {
        GpuImage gone(std::move(*this));
        swap(other);
        return *this;
    }
    ~GpuImage();

    static Status create(const Gpu& gpu, VkExtent2D extent, VkFormat format,
                         VkSampleCountFlagBits samples, VkImageUsageFlags usage,
                         VkImageAspectFlags aspect, GpuImage& out);

    VkImage handle() const { return image_; }
    VkImageView view() const { return view_; }

private:
    void swap(GpuImage& other) noexcept;

    VkDevice device_ = VK_NULL_HANDLE;
    VkImage image_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkImageView view_ = VK_NULL_HANDLE;
};

}  // namespace dfm::render
