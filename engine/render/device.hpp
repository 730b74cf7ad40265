#pragma once

#include <cstdint>

#include <vulkan/vulkan.h>

#include "render/vulkan_result.hpp"

namespace dfm::render {

// The device handles the renderer works with, whoever created them.
struct Gpu {
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    std::uint32_t queue_family = 0;
    VkQueue queue = VK_NULL_HANDLE;
    VkPhysicalDeviceMemoryProperties memory{};
    bool wireframe = false;  // fillModeNonSolid enabled
};

// The largest sample count up to 4 that colour and depth attachments both
// support (1 when the device has no MSAA).
VkSampleCountFlagBits best_sample_count(VkPhysicalDevice physical);

// A logical device the renderer owns: the first suitable physical device
// (Vulkan 1.3 with dynamic rendering, a graphics queue, presenting to
// `surface` when there is one; discrete GPUs first). Move-only.
class Device {
public:
    Device() = default;
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;
    ~Device();

    static Status create(VkInstance instance, VkSurfaceKHR surface, Device& out);

    const Gpu& gpu() const { return gpu_; }

private:
    Gpu gpu_;
};

// Fills in the properties of handles a host created (memory types, features
// in use); fails when the device cannot run the renderer.
Status describe_host_gpu(Gpu& gpu);

}  // namespace dfm::render
