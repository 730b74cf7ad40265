#pragma once

#include <cstdint>

#include <vulkan/vulkan.h>
#include <glm/vec4.hpp>

#include "mesh/mesh.hpp"
#include "pick/camera.hpp"
#include "render/pipelines.hpp"

namespace dfm::render {

// How one frame looks.
struct ViewSettings {
    pick::Camera camera;
    bool wireframe = false;
    bool flat = false;
    glm::vec4 background{0.16f, 0.18f, 0.22f, 1.0f};
};

// The buffers one frame draws from.
struct DrawBuffers {
    VkBuffer mesh_vertices = VK_NULL_HANDLE;
    VkBuffer indices = VK_NULL_HANDLE;
    VkBuffer line_vertices = VK_NULL_HANDLE;
    std::uint32_t index_count = 0;
    std::uint32_t line_vertex_count = 0;
};

// Records the surface, the wireframe over it (when asked and available) and
// the host's lines into a command buffer inside dynamic rendering of
// `extent`. The camera's aspect is the extent's.
void record_scene_draw(VkCommandBuffer cmd, const Pipelines& pipelines, const DrawBuffers& buffers,
                       const ViewSettings& view, const mesh::Bounds& scene, VkExtent2D extent);

}  // namespace dfm::render
