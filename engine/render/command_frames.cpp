#include "render/command_frames.hpp"

#include <cstdint>

namespace dfm::render {

CommandFrames::~CommandFrames() {
    for (VkFence f : fences_) vkDestroyFence(device_, f, nullptr);
    for (VkSemaphore s : acquired_) vkDestroySemaphore(device_, s, nullptr);
    if (pool_ != VK_NULL_HANDLE) vkDestroyCommandPool(device_, pool_, nullptr);
}

Status CommandFrames::create(const Gpu& gpu, std::size_t count) {
    device_ = gpu.device;
    queue_ = gpu.queue;
    VkCommandPoolCreateInfo pool{};
    pool.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = gpu.queue_family;
    if (VkResult r = vkCreateCommandPool(device_, &pool, nullptr, &pool_); r != VK_SUCCESS) {
        pool_ = VK_NULL_HANDLE;
        return vk_failure(r, "vkCreateCommandPool");
    }
    commands_.resize(count);
    VkCommandBufferAllocateInfo allocate{};
    allocate.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    allocate.commandPool = pool_;
    allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    allocate.commandBufferCount = static_cast<std::uint32_t>(count);
    if (VkResult r = vkAllocateCommandBuffers(device_, &allocate, commands_.data());
        r != VK_SUCCESS) {
        commands_.clear();
        return vk_failure(r, "vkAllocateCommandBuffers");
    }
    for (std::size_t i = 0; i < count; ++i) {
        VkFenceCreateInfo fence{};
        fence.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
        fence.flags = VK_FENCE_CREATE_SIGNALED_BIT;
        VkFence f = VK_NULL_HANDLE;
        if (VkResult r = vkCreateFence(device_, &fence, nullptr, &f); r != VK_SUCCESS) {
            return vk_failure(r, "vkCreateFence");
        }
        fences_.push_back(f);
        VkSemaphoreCreateInfo semaphore{};
        semaphore.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO;
        VkSemaphore s = VK_NULL_HANDLE;
        if (VkResult r = vkCreateSemaphore(device_, &semaphore, nullptr, &s); r != VK_SUCCESS) {
            return vk_failure(r, "vkCreateSemaphore");
        }
        acquired_.push_back(s);
    }
    return Status::ok();
}

Status CommandFrames::wait_current() const {
    if (VkResult r = vkWaitForFences(device_, 1, &fences_[current_], VK_TRUE, UINT64_MAX);
        r != VK_SUCCESS) {
        return vk_failure(r, "vkWaitForFences");
    }
    return Status::ok();
}

Status CommandFrames::begin_current() const {
    if (VkResult r = vkResetFences(device_, 1, &fences_[current_]); r != VK_SUCCESS) {
        return vk_failure(r, "vkResetFences");
    }
    if (VkResult r = vkResetCommandBuffer(commands_[current_], 0); r != VK_SUCCESS) {
        return vk_failure(r, "vkResetCommandBuffer");
    }
    VkCommandBufferBeginInfo begin{};
    begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    if (VkResult r = vkBeginCommandBuffer(commands_[current_], &begin); r != VK_SUCCESS) {
        return vk_failure(r, "vkBeginCommandBuffer");
    }
    return Status::ok();
}

Status CommandFrames::submit_current(VkSemaphore wait, VkSemaphore signal) const {
    if (VkResult r = vkEndCommandBuffer(commands_[current_]); r != VK_SUCCESS) {
        return vk_failure(r, "vkEndCommandBuffer");
    }
    const VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    VkSubmitInfo submit{};
    submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &commands_[current_];
    if (wait != VK_NULL_HANDLE) {
        submit.waitSemaphoreCount = 1;
        submit.pWaitSemaphores = &wait;
        submit.pWaitDstStageMask = &wait_stage;
    }
    if (signal != VK_NULL_HANDLE) {
        submit.signalSemaphoreCount = 1;
        submit.pSignalSemaphores = &signal;
    }
    if (VkResult r = vkQueueSubmit(queue_, 1, &submit, fences_[current_]); r != VK_SUCCESS) {
        return vk_failure(r, "vkQueueSubmit");
    }
    return Status::ok();
}

}  // namespace dfm::render
