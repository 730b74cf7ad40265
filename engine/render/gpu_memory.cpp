#include "render/gpu_memory.hpp"

#include <cstdint>
#include <utility>

namespace dfm::render {

namespace {

// The first memory type allowed by `bits` with all of `wanted`, else the
// first with all of `needed`; UINT32_MAX when there is none.
std::uint32_t find_memory_type(const VkPhysicalDeviceMemoryProperties& memory, std::uint32_t bits,
                               VkMemoryPropertyFlags wanted, VkMemoryPropertyFlags needed) {
    for (VkMemoryPropertyFlags flags : {wanted, needed}) {
        for (std::uint32_t i = 0; i < memory.memoryTypeCount; ++i) {
            if ((bits & (1u << i)) && (memory.memoryTypes[i].propertyFlags & flags) == flags) {
                return i;
            }
        }
    }
    return UINT32_MAX;
}

Status allocate(const Gpu& gpu, const VkMemoryRequirements& needs, VkMemoryPropertyFlags wanted,
                VkMemoryPropertyFlags needed, VkDeviceMemory& out) {
    const std::uint32_t type = find_memory_type(gpu.memory, needs.memoryTypeBits, wanted, needed);
    if (type == UINT32_MAX) {
        return Status(Errc::unsupported, "no suitable Vulkan memory type");
    }
    VkMemoryAllocateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
    info.allocationSize = needs.size;
    info.memoryTypeIndex = type;
    if (VkResult r = vkAllocateMemory(gpu.device, &info, nullptr, &out); r != VK_SUCCESS) {
        out = VK_NULL_HANDLE;
        return vk_failure(r, "vkAllocateMemory");
    }
    return Status::ok();
}

}  // namespace

GpuBuffer::~GpuBuffer() {
    if (buffer_ != VK_NULL_HANDLE) vkDestroyBuffer(device_, buffer_, nullptr);
    if (memory_ != VK_NULL_HANDLE) vkFreeMemory(device_, memory_, nullptr);
}

void GpuBuffer::swap(GpuBuffer& other) noexcept {
    std::swap(device_, other.device_);
    std::swap(buffer_, other.buffer_);
    std::swap(memory_, other.memory_);
    std::swap(size_, other.size_);
    std::swap(mapped_, other.mapped_);
}

Status GpuBuffer::create(const Gpu& gpu, VkDeviceSize size, VkBufferUsageFlags usage,
                         bool host_visible, GpuBuffer& out) {
    GpuBuffer made;
    made.device_ = gpu.device;
    made.size_ = size;
    VkBufferCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
    info.size = size;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    if (VkResult r = vkCreateBuffer(gpu.device, &info, nullptr, &made.buffer_); r != VK_SUCCESS) {
        made.buffer_ = VK_NULL_HANDLE;
        return vk_failure(r, "vkCreateBuffer");
    }
    VkMemoryRequirements needs;
    vkGetBufferMemoryRequirements(gpu.device, made.buffer_, &needs);
    const VkMemoryPropertyFlags host =
        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    if (Status s = host_visible
                       ? allocate(gpu, needs, host, host, made.memory_)
                       : allocate(gpu, needs, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0, made.memory_);
        !s) {
        return s;
    }
    if (VkResult r = vkBindBufferMemory(gpu.device, made.buffer_, made.memory_, 0);
        r != VK_SUCCESS) {
        return vk_failure(r, "vkBindBufferMemory");
    }
    if (host_visible) {
        if (VkResult r = vkMapMemory(gpu.device, made.memory_, 0, VK_WHOLE_SIZE, 0, &made.mapped_);
            r != VK_SUCCESS) {
            return vk_failure(r, "vkMapMemory");
        }
    }
    out = std::move(made);
    return Status::ok();
}

GpuImage::~GpuImage() {
    if (view_ != VK_NULL_HANDLE) vkDestroyImageView(device_, view_, nullptr);
    if (image_ != VK_NULL_HANDLE) vkDestroyImage(device_, image_, nullptr);
    if (memory_ != VK_NULL_HANDLE) vkFreeMemory(device_, memory_, nullptr);
}

void GpuImage::swap(GpuImage& other) noexcept {
    std::swap(device_, other.device_);
    std::swap(image_, other.image_);
    std::swap(memory_, other.memory_);
    std::swap(view_, other.view_);
}

Status GpuImage::create(const Gpu& gpu, VkExtent2D extent, VkFormat format,
                        VkSampleCountFlagBits samples, VkImageUsageFlags usage,
                        VkImageAspectFlags aspect, GpuImage& out) {
    GpuImage made;
    made.device_ = gpu.device;
    VkImageCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO;
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {extent.width, extent.height, 1};
    info.mipLevels = 1;
    info.arrayLayers = 1;
    info.samples = samples;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    if (VkResult r = vkCreateImage(gpu.device, &info, nullptr, &made.image_); r != VK_SUCCESS) {
        made.image_ = VK_NULL_HANDLE;
        return vk_failure(r, "vkCreateImage");
    }
    VkMemoryRequirements needs;
    vkGetImageMemoryRequirements(gpu.device, made.image_, &needs);
    if (Status s = allocate(gpu, needs, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0, made.memory_); !s) {
        return s;
    }
    if (VkResult r = vkBindImageMemory(gpu.device, made.image_, made.memory_, 0); r != VK_SUCCESS) {
        return vk_failure(r, "vkBindImageMemory");
    }
    VkImageViewCreateInfo view{};
    view.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO;
    view.image = made.image_;
    view.viewType = VK_IMAGE_VIEW_TYPE_2D;
    view.format = format;
    view.subresourceRange = {aspect, 0, 1, 0, 1};
    if (VkResult r = vkCreateImageView(gpu.device, &view, nullptr, &made.view_); r != VK_SUCCESS) {
        made.view_ = VK_NULL_HANDLE;
        return vk_failure(r, "vkCreateImageView");
    }
    out = std::move(made);
    return Status::ok();
}

}  // namespace dfm::render
