#pragma once

#include <cstdint>
#include <span>

#include <vulkan/vulkan.h>

#include "render/gpu_memory.hpp"
#include "render/pipelines.hpp"

namespace dfm::render {

// An offscreen RGBA8 colour image (multisampled and resolved when the
// formats ask for it), a depth image, and a host-visible buffer the resolved
// picture is copied into for reading back. Move-only.
class OffscreenTarget {
public:
    static Status create(const Gpu& gpu, const AttachmentFormats& formats, VkExtent2D extent,
                         OffscreenTarget& out);

    VkExtent2D extent() const { return extent_; }

    // Transitions the images for drawing and begins clearing rendering.
    void record_begin(VkCommandBuffer cmd, const float background[4]) const;
    // Ends rendering and copies the picture into the read-back buffer.
    void record_end_and_copy(VkCommandBuffer cmd) const;
    // The picture, rows top to bottom, 4 bytes a pixel; valid once the
    // commands of record_end_and_copy have completed.
    std::span<const std::uint8_t> pixels() const;

private:
    VkExtent2D extent_{};
    bool multisampled_ = false;
    GpuImage color_;    // multisampled when multisampled_
    GpuImage resolve_;  // the single-sample picture when multisampled_
    GpuImage depth_;
    GpuBuffer readback_;
};

}  // namespace dfm::render
