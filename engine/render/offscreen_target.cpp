#include "render/offscreen_target.hpp"

#include "render/attachment_commands.hpp"

namespace dfm::render {

namespace {

constexpr VkPipelineStageFlags attachment_stages = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                                                   VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                                                   VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;

}  // namespace

Status OffscreenTarget::create(const Gpu& gpu, const AttachmentFormats& formats, VkExtent2D extent,
                               OffscreenTarget& out) {
    OffscreenTarget made;
    made.extent_ = extent;
    made.multisampled_ = formats.samples != VK_SAMPLE_COUNT_1_BIT;
    const VkImageUsageFlags picture_usage =
        VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    if (made.multisampled_) {
        if (Status s = GpuImage::create(
                gpu, extent, formats.color, formats.samples,
                VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSIENT_ATTACHMENT_BIT,
                VK_IMAGE_ASPECT_COLOR_BIT, made.color_);
            !s) {
            return s;
        }
        if (Status s = GpuImage::create(gpu, extent, formats.color, VK_SAMPLE_COUNT_1_BIT,
                                        picture_usage, VK_IMAGE_ASPECT_COLOR_BIT, made.resolve_);
            !s) {
            return s;
        }
    } else if (Status s = GpuImage::create(gpu, extent, formats.color, VK_SAMPLE_COUNT_1_BIT,
                                           picture_usage, VK_IMAGE_ASPECT_COLOR_BIT, made.color_);
               !s) {
        return s;
    }
    if (Status s = GpuImage::create(gpu, extent, formats.depth, formats.samples,
                                    VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                                    VK_IMAGE_ASPECT_DEPTH_BIT, made.depth_);
        !s) {
        return s;
    }
    if (Status s = GpuBuffer::create(gpu, VkDeviceSize{extent.width} * extent.height * 4,
                                     VK_BUFFER_USAGE_TRANSFER_DST_BIT, true, made.readback_);
        !s) {
        return s;
    }
    out = std::move(made);
    return Status::ok();
}

void OffscreenTarget::record_begin(VkCommandBuffer cmd, const float background[4]) const {
    // From UNDEFINED every frame: the previous picture is not needed, and the
    // source stages order this frame after the last one's writes and copy.
    const VkPipelineStageFlags previous_use = attachment_stages | VK_PIPELINE_STAGE_TRANSFER_BIT;
    for (const GpuImage* image : {&color_, &resolve_}) {
        if (image->handle() == VK_NULL_HANDLE) continue;
        transition_image(
            cmd, image->handle(), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
            VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, previous_use,
            VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
            VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_READ_BIT);
    }
    transition_image(
        cmd, depth_.handle(), VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
        VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, attachment_stages,
        VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, attachment_stages,
        VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
    begin_clear_rendering(cmd, extent_, color_.view(),
                          multisampled_ ? resolve_.view() : VK_NULL_HANDLE, depth_.view(),
                          background);
}

void OffscreenTarget::record_end_and_copy(VkCommandBuffer cmd) const {
    vkCmdEndRendering(cmd);
    copy_to_host(cmd, multisampled_ ? resolve_.handle() : color_.handle(), extent_,
                 readback_.handle());
}

std::span<const std::uint8_t> OffscreenTarget::pixels() const {
    return {static_cast<const std::uint8_t*>(readback_.mapped()),
            static_cast<std::size_t>(extent_.width) * extent_.height * 4};
}

}  // namespace dfm::render
