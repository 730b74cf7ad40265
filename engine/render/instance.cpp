#include "render/instance.hpp"

#include <cstring>
#include <string>

namespace dfm::render {

namespace {

constexpr const char* validation_layer = "VK_LAYER_KHRONOS_validation";

bool layer_available(const char* name) {
    std::uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> layers(count);
    vkEnumerateInstanceLayerProperties(&count, layers.data());
    for (const VkLayerProperties& layer : layers) {
        if (std::strcmp(layer.layerName, name) == 0) return true;
    }
    return false;
}

}  // namespace

Instance::~Instance() {
    if (messenger_ != VK_NULL_HANDLE) {
        auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
        if (destroy) destroy(instance_, messenger_, nullptr);
    }
    if (instance_ != VK_NULL_HANDLE) vkDestroyInstance(instance_, nullptr);
}

Status Instance::create(const std::vector<const char*>& extensions, bool validation,
                        ValidationCounter& counter, Instance& out) {
    std::uint32_t version = 0;
    if (vkEnumerateInstanceVersion(&version) != VK_SUCCESS || version < VK_API_VERSION_1_3) {
        return Status(Errc::unsupported, "the Vulkan loader does not offer Vulkan 1.3");
    }
    if (validation && !layer_available(validation_layer)) {
        return Status(Errc::unsupported,
                      "validation was asked for, but VK_LAYER_KHRONOS_validation is "
                      "not installed (Debian: vulkan-validationlayers)");
    }
    VkApplicationInfo app{};
    app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
    app.pApplicationName = "dualform";
    app.pEngineName = "dualform";
    app.apiVersion = VK_API_VERSION_1_3;

    std::vector<const char*> enabled = extensions;
    const VkDebugUtilsMessengerCreateInfoEXT messenger_info = counter.messenger_info();
    VkInstanceCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
    info.pApplicationInfo = &app;
    if (validation) {
        enabled.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
        info.enabledLayerCount = 1;
        info.ppEnabledLayerNames = &validation_layer;
        info.pNext = &messenger_info;
    }
    info.enabledExtensionCount = static_cast<std::uint32_t>(enabled.size());
    info.ppEnabledExtensionNames = enabled.data();
    if (VkResult r = vkCreateInstance(&info, nullptr, &out.instance_); r != VK_SUCCESS) {
        out.instance_ = VK_NULL_HANDLE;
        return vk_failure(r, "vkCreateInstance");
    }
    if (validation) {
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(out.instance_, "vkCreateDebugUtilsMessengerEXT"));
        if (!create) {
            return Status(Errc::unsupported, "vkCreateDebugUtilsMessengerEXT is missing");
        }
        if (VkResult r = create(out.instance_, &messenger_info, nullptr, &out.messenger_);
            r != VK_SUCCESS) {
            out.messenger_ = VK_NULL_HANDLE;
            return vk_failure(r, "vkCreateDebugUtilsMessengerEXT");
        }
    }
    return Status::ok();
}

}  // namespace dfm::render
