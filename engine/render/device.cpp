#include "render/device.hpp"

#include <string>
#include <vector>

namespace dfm::render {

namespace {

struct Candidate {
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    std::uint32_t queue_family = 0;
    int rank = -1;
};

int type_rank(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 4;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 3;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return 1;
        default: return 0;
    }
}

bool has_dynamic_rendering(VkPhysicalDevice physical) {
    VkPhysicalDeviceVulkan13Features v13{};
    v13.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES;
    VkPhysicalDeviceFeatures2 features{};
    features.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
    features.pNext = &v13;
    vkGetPhysicalDeviceFeatures2(physical, &features);
    return v13.dynamicRendering == VK_TRUE;
}

Candidate rate(VkPhysicalDevice physical, VkSurfaceKHR surface) {
    Candidate c;
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(physical, &props);
    if (props.apiVersion < VK_API_VERSION_1_3 || !has_dynamic_rendering(physical)) return c;
    std::uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(physical, &count, families.data());
    for (std::uint32_t i = 0; i < count; ++i) {
        if (!(families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT)) continue;
        if (surface != VK_NULL_HANDLE) {
            VkBool32 present = VK_FALSE;
            vkGetPhysicalDeviceSurfaceSupportKHR(physical, i, surface, &present);
            if (!present) continue;
        }
        c.physical = physical;
        c.queue_family = i;
        c.rank = type_rank(props.deviceType);
        return c;
    }
    return c;
}

}  // namespace

VkSampleCountFlagBits best_sample_count(VkPhysicalDevice physical) {
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(physical, &props);
    const VkSampleCountFlags both =
        props.limits.framebufferColorSampleCounts & props.limits.framebufferDepthSampleCounts;
    if (both & VK_SAMPLE_COUNT_4_BIT) return VK_SAMPLE_COUNT_4_BIT;
    if (both & VK_SAMPLE_COUNT_2_BIT) return VK_SAMPLE_COUNT_2_BIT;
    return VK_SAMPLE_COUNT_1_BIT;
}

Device::~Device() {
    if (gpu_.device != VK_NULL_HANDLE) vkDestroyDevice(gpu_.device, nullptr);
}

Status Device::create(VkInstance instance, VkSurfaceKHR surface, Device& out) {
    std::uint32_t count = 0;
    vkEnumeratePhysicalDevices(instance, &count, nullptr);
    std::vector<VkPhysicalDevice> physicals(count);
    vkEnumeratePhysicalDevices(instance, &count, physicals.data());
    Candidate best;
    for (VkPhysicalDevice p : physicals) {
        const Candidate c = rate(p, surface);
        if (c.rank > best.rank) best = c;
    }
    if (best.rank < 0) {
        return Status(Errc::unsupported,
                      count == 0 ? "no Vulkan device found (for software rendering "
                                   "install mesa-vulkan-drivers: lavapipe)"
                                 : "no Vulkan 1.3 device with dynamic rendering and a "
                                   "graphics queue" +
                                       std::string(surface ? " that presents to the window" : ""));
    }

    VkPhysicalDeviceFeatures available;
    vkGetPhysicalDeviceFeatures(best.physical, &available);
    VkPhysicalDeviceVulkan13Features v13{};
    v13.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES;
    v13.dynamicRendering = VK_TRUE;
    VkPhysicalDeviceFeatures2 features{};
    features.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
    features.pNext = &v13;
    features.features.fillModeNonSolid = available.fillModeNonSolid;

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queue{};
    queue.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
    queue.queueFamilyIndex = best.queue_family;
    queue.queueCount = 1;
    queue.pQueuePriorities = &priority;
    const char* swapchain_extension = VK_KHR_SWAPCHAIN_EXTENSION_NAME;
    VkDeviceCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
    info.pNext = &features;
    info.queueCreateInfoCount = 1;
    info.pQueueCreateInfos = &queue;
    if (surface != VK_NULL_HANDLE) {
        info.enabledExtensionCount = 1;
        info.ppEnabledExtensionNames = &swapchain_extension;
    }
    if (VkResult r = vkCreateDevice(best.physical, &info, nullptr, &out.gpu_.device);
        r != VK_SUCCESS) {
        out.gpu_.device = VK_NULL_HANDLE;
        return vk_failure(r, "vkCreateDevice");
    }
    out.gpu_.instance = instance;
    out.gpu_.physical = best.physical;
    out.gpu_.queue_family = best.queue_family;
    vkGetDeviceQueue(out.gpu_.device, best.queue_family, 0, &out.gpu_.queue);
    vkGetPhysicalDeviceMemoryProperties(best.physical, &out.gpu_.memory);
    out.gpu_.wireframe = available.fillModeNonSolid == VK_TRUE;
    return Status::ok();
}

Status describe_host_gpu(Gpu& gpu) {
    if (gpu.instance == VK_NULL_HANDLE || gpu.physical == VK_NULL_HANDLE ||
        gpu.device == VK_NULL_HANDLE || gpu.queue == VK_NULL_HANDLE) {
        return Status(Errc::invalid_argument,
                      "instance, physical_device, device and queue must all be given");
    }
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(gpu.physical, &props);
    if (props.apiVersion < VK_API_VERSION_1_3) {
        return Status(Errc::unsupported, "the host's physical device does not offer Vulkan 1.3");
    }
    vkGetPhysicalDeviceMemoryProperties(gpu.physical, &gpu.memory);
    return Status::ok();
}

}  // namespace dfm::render
