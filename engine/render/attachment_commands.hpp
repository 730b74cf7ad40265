#pragma once

// Layout transitions and the start of clearing rendering, shared by the
// offscreen target and the swapchain.

#include <vulkan/vulkan.h>

namespace dfm::render {

// A layout transition of a whole single-level colour or depth image.
void transition_image(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect,
                      VkImageLayout from, VkImageLayout to, VkPipelineStageFlags src_stage,
                      VkAccessFlags src_access, VkPipelineStageFlags dst_stage,
                      VkAccessFlags dst_access);

// Begins dynamic rendering that clears `color` (resolving into `resolve` when
// given) and `depth` (when given) over `extent`.
void begin_clear_rendering(VkCommandBuffer cmd, VkExtent2D extent, VkImageView color,
                           VkImageView resolve, VkImageView depth, const float background[4]);

}  // namespace dfm::render
