#include "render/frame_uploader.hpp"

#include <algorithm>
#include <cstring>

#include "render/attachment_commands.hpp"

namespace dfm::render {

namespace {

// Grows by half again, so a mesh growing a little each frame reallocates rarely.
Status ensure(const Gpu& gpu, GpuBuffer& buffer, VkDeviceSize needed, VkBufferUsageFlags usage,
              bool host_visible) {
    if (buffer.handle() != VK_NULL_HANDLE && buffer.size() >= needed) return Status::ok();
    return GpuBuffer::create(gpu, needed + needed / 2, usage, host_visible, buffer);
}

}  // namespace

Status FrameUploader::stage(const Gpu& gpu, std::size_t slot_index, const SceneData& scene) {
    Slot& slot = slots_[slot_index];
    slot.mesh_bytes = scene.vertex_count() * sizeof(MeshVertex);
    slot.line_bytes = scene.line_vertices().size_bytes();
    // Zero-sized buffers are invalid; a scene without lines still gets one.
    const VkDeviceSize mesh_size = std::max<VkDeviceSize>(slot.mesh_bytes, sizeof(MeshVertex));
    const VkDeviceSize line_size = std::max<VkDeviceSize>(slot.line_bytes, sizeof(LineVertex));
    const VkBufferUsageFlags vertex_usage =
        VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    if (Status s = ensure(gpu, slot.staging, mesh_size + line_size,
                          VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
        !s) {
        return s;
    }
    if (Status s = ensure(gpu, slot.mesh, mesh_size, vertex_usage, false); !s) return s;
    if (Status s = ensure(gpu, slot.lines, line_size, vertex_usage, false); !s) return s;
    auto* staging = static_cast<unsigned char*>(slot.staging.mapped());
    scene.pack_vertices(reinterpret_cast<MeshVertex*>(staging));
    if (slot.line_bytes > 0) {
        std::memcpy(staging + slot.mesh_bytes, scene.line_vertices().data(), slot.line_bytes);
    }
    return Status::ok();
}

void FrameUploader::record_copy(VkCommandBuffer cmd, std::size_t slot_index) const {
    const Slot& slot = slots_[slot_index];
    if (slot.mesh_bytes > 0) {
        const VkBufferCopy region{0, 0, slot.mesh_bytes};
        vkCmdCopyBuffer(cmd, slot.staging.handle(), slot.mesh.handle(), 1, &region);
    }
    if (slot.line_bytes > 0) {
        const VkBufferCopy region{slot.mesh_bytes, 0, slot.line_bytes};
        vkCmdCopyBuffer(cmd, slot.staging.handle(), slot.lines.handle(), 1, &region);
    }
    memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                   VK_PIPELINE_STAGE_VERTEX_INPUT_BIT, VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT);
}

}  // namespace dfm::render
