#pragma once

// The renderer's barriers (every vkCmdPipelineBarrier of engine/render is
// here) and the start of clearing rendering, shared by the offscreen target,
// the swapchain and the frame uploader.

#include <vulkan/vulkan.h>

namespace dfm::render {

// A layout transition of a whole single-level colour or depth image.
void transition_image(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect,
                      VkImageLayout from, VkImageLayout to, VkPipelineStageFlags src_stage,
                      VkAccessFlags src_access, VkPipelineStageFlags dst_stage,
                      VkAccessFlags dst_access);

// A global memory barrier: `src_access` writes of `src_stage` made visible
// to `dst_access` of `dst_stage`.
void memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags src_stage, VkAccessFlags src_access,
                    VkPipelineStageFlags dst_stage, VkAccessFlags dst_access);

// Copies a rendered colour image (left in COLOR_ATTACHMENT_OPTIMAL by the
// rendering) into `readback`, tightly packed, and makes the copy visible to
// the host once the command buffer's fence has signalled. The image is
// left in TRANSFER_SRC_OPTIMAL.
void copy_to_host(VkCommandBuffer cmd, VkImage image, VkExtent2D extent, VkBuffer readback);

// Begins dynamic rendering that clears `color` (resolving into `resolve` when
// given) and `depth` (when given) over `extent`.
void begin_clear_rendering(VkCommandBuffer cmd, VkExtent2D extent, VkImageView color,
                           VkImageView resolve, VkImageView depth, const float background[4]);

}  // namespace dfm::render
