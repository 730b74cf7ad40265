#pragma once

#include <cstddef>
#include <vector>

#include <vulkan/vulkan.h>

#include "render/gpu_memory.hpp"
#include "render/scene_data.hpp"

namespace dfm::render {

// Streams the scene's vertices to the GPU every frame without stalling it:
// each frame in flight has its own host-visible staging buffer and its own
// device-local vertex buffers, so writing frame N's vertices never touches
// buffers frame N-1 is still reading. The caller guarantees that the GPU has
// finished the slot's previous frame before stage() reuses it.
class FrameUploader {
public:
    explicit FrameUploader(std::size_t frames_in_flight) : slots_(frames_in_flight) {}

    std::size_t slot_count() const { return slots_.size(); }

    // Writes the scene's vertices into the slot's staging buffer, growing the
    // slot's buffers when the scene outgrew them.
    Status stage(const Gpu& gpu, std::size_t slot, const SceneData& scene);

    // Records the staging-to-vertex-buffer copies and the barrier that makes
    // them visible to vertex input. Outside any rendering.
    void record_copy(VkCommandBuffer cmd, std::size_t slot) const;

    VkBuffer mesh_vertices(std::size_t slot) const { return slots_[slot].mesh.handle(); }
    VkBuffer line_vertices(std::size_t slot) const { return slots_[slot].lines.handle(); }

private:
    struct Slot {
        GpuBuffer staging;
        GpuBuffer mesh;
        GpuBuffer lines;
        VkDeviceSize mesh_bytes = 0;
        VkDeviceSize line_bytes = 0;
    };

    std::vector<Slot> slots_;
};

}  // namespace dfm::render
