#pragma once

#include <vulkan/vulkan.h>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "render/vulkan_result.hpp"

namespace dfm::render {

// What the pipelines render into (dynamic rendering: formats, no render pass).
struct AttachmentFormats {
    VkFormat color = VK_FORMAT_R8G8B8A8_UNORM;
    VkFormat depth = VK_FORMAT_D32_SFLOAT;  // VK_FORMAT_UNDEFINED: no depth
    VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT;
};

// mesh.vert / mesh.frag push constants.
struct MeshPush {
    glm::mat4 clip_from_world;
    glm::vec4 eye;
    glm::vec4 line_color;
    std::uint32_t flags;
    float depth_pull;
};
inline constexpr std::uint32_t mesh_flag_flat = 1;
inline constexpr std::uint32_t mesh_flag_wireframe_pass = 2;

// line.vert push constants.
struct LinePush {
    glm::mat4 clip_from_world;
    float depth_pull;
};

// The surface, wireframe and line pipelines for one set of attachment
// formats; the wireframe one only where the device fills polygons as lines.
// Viewport and scissor are dynamic. Move-only; destroys its objects.
class Pipelines {
public:
    Pipelines() = default;
    Pipelines(const Pipelines&) = delete;
    Pipelines& operator=(const Pipelines&) = delete;
    ~Pipelines();

    Status create(VkDevice device, const AttachmentFormats& formats, bool wireframe);

    VkPipelineLayout mesh_layout() const { return mesh_layout_; }
    VkPipelineLayout line_layout() const { return line_layout_; }
    VkPipeline surface() const { return surface_; }
    VkPipeline wireframe() const { return wireframe_; }
    VkPipeline lines() const { return lines_; }

private:
    VkDevice device_ = VK_NULL_HANDLE;
    VkPipelineLayout mesh_layout_ = VK_NULL_HANDLE;
    VkPipelineLayout line_layout_ = VK_NULL_HANDLE;
    VkPipeline surface_ = VK_NULL_HANDLE;
    VkPipeline wireframe_ = VK_NULL_HANDLE;
    VkPipeline lines_ = VK_NULL_HANDLE;
};

}  // namespace dfm::render
