#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <vulkan/vulkan.h>

#include "render/device.hpp"
#include "render/vulkan_result.hpp"

namespace dfm::render {

// The per-frame-in-flight command buffers, fences and image-acquired
// semaphores of a renderer that owns its device, cycled in order. Move-only.
class CommandFrames {
public:
    CommandFrames() = default;
    CommandFrames(const CommandFrames&) = delete;
    CommandFrames& operator=(const CommandFrames&) = delete;
    ~CommandFrames();

    Status create(const Gpu& gpu, std::size_t count);

    std::size_t current() const { return current_; }
    VkCommandBuffer command_buffer() const { return commands_[current_]; }
    VkFence fence() const { return fences_[current_]; }
    VkSemaphore acquired() const { return acquired_[current_]; }

    // Waits until the current slot's last submission has finished.
    Status wait_current() const;
    // Resets the current slot's fence and command buffer and begins recording.
    Status begin_current() const;
    // Ends recording and submits, signalling the slot's fence; the semaphores
    // are optional (window path).
    Status submit_current(VkSemaphore wait, VkSemaphore signal) const;
    void advance() { current_ = (current_ + 1) % commands_.size(); }

private:
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    std::vector<VkCommandBuffer> commands_;
    std::vector<VkFence> fences_;
    std::vector<VkSemaphore> acquired_;
    std::size_t current_ = 0;
};

}  // namespace dfm::render
