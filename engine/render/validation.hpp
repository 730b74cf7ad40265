#pragma once

#include <atomic>
#include <cstdint>

#include <vulkan/vulkan.h>

namespace dfm::render {

// Whether the environment asks for the Khronos validation layer
// (DUALFORM_VALIDATION=1; tests always set it).
bool validation_requested();

// Counts every warning or error the validation layer reports, and prints it,
// so a test can assert that a whole run produced none. Lives at a fixed
// address for as long as the messenger that points at it.
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
