#pragma once

#include <vector>

#include <vulkan/vulkan.h>

#include "render/validation.hpp"
#include "render/vulkan_result.hpp"

namespace dfm::render {

// A Vulkan 1.3 instance the renderer owns, with the validation layer and a
// messenger feeding `counter` when validation is on. Move-only.
class Instance {
public:
    Instance() = default;
    Instance(const Instance&) = delete;
    Instance& operator=(const Instance&) = delete;
    ~Instance();

    // `extensions`: what the window's surface needs, empty when headless.
    // `counter` must outlive the instance.
    static Status create(const std::vector<const char*>& extensions, bool validation,
                         ValidationCounter& counter, Instance& out);

    VkInstance handle() const { return instance_; }

private:
    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
};

}  // namespace dfm::render
