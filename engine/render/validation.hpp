#pragma once

#include <atomic>
#include <cstdint>

#include <vulkan/vulkan.h>

namespace dfm::render {

// Counts every warning or error the validation layer reports, and prints it,
// so a test can assert that a whole run produced none. Only messages of the
// validation type are heard: the loader's general notices (for instance
// that VK_INSTANCE_LAYERS is set, the standard way a user turns the layer
// on) say nothing about our use of Vulkan. Lives at a fixed address for as
// long as the messenger that points at it.
class ValidationCounter {
public:
    std::uint64_t count() const { return count_.load(); }
    void add() { count_.fetch_add(1); }

    // Chained into VkInstanceCreateInfo too, so messages from instance
    // creation and destruction count as well.
    VkDebugUtilsMessengerCreateInfoEXT messenger_info();

private:
    std::atomic<std::uint64_t> count_{0};
};

}  // namespace dfm::render
