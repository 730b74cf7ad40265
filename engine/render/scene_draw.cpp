#include "render/scene_draw.hpp"

#include "render/view_transform.hpp"

namespace dfm::render {

namespace {

// Depth pulled towards the eye (in clip z / w) so the wireframe and lines win
// the depth test against the surface they lie on.
constexpr float wireframe_pull = 2e-4f;
constexpr float line_pull = 1e-3f;

}  // namespace

void record_scene_draw(VkCommandBuffer cmd, const Pipelines& pipelines, const DrawBuffers& buffers,
                       const ViewSettings& view, const mesh::Bounds& scene, VkExtent2D extent) {
    pick::Camera camera = view.camera;
    camera.width = extent.width;
    camera.height = extent.height;
    const glm::mat4 clip = clip_from_world(camera, scene);

    const VkViewport viewport{
        0.0f, 0.0f, static_cast<float>(extent.width), static_cast<float>(extent.height),
        0.0f, 1.0f};
    const VkRect2D scissor{{0, 0}, extent};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    const VkDeviceSize zero = 0;
    const VkShaderStageFlags stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;

    if (buffers.index_count > 0) {
        MeshPush push{};
        push.clip_from_world = clip;
        push.eye = glm::vec4(glm::vec3(camera.eye), 1.0f);
        push.line_color = glm::vec4(0.05f, 0.05f, 0.08f, 1.0f);
        push.flags = view.flat ? mesh_flag_flat : 0u;
        vkCmdBindVertexBuffers(cmd, 0, 1, &buffers.mesh_vertices, &zero);
        vkCmdBindIndexBuffer(cmd, buffers.indices, 0, VK_INDEX_TYPE_UINT32);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelines.surface());
        vkCmdPushConstants(cmd, pipelines.mesh_layout(), stages, 0, sizeof push, &push);
        vkCmdDrawIndexed(cmd, buffers.index_count, 1, 0, 0, 0);
        if (view.wireframe && pipelines.wireframe() != VK_NULL_HANDLE) {
            push.flags |= mesh_flag_wireframe_pass;
            push.depth_pull = wireframe_pull;
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelines.wireframe());
            vkCmdPushConstants(cmd, pipelines.mesh_layout(), stages, 0, sizeof push, &push);
            vkCmdDrawIndexed(cmd, buffers.index_count, 1, 0, 0, 0);
        }
    }
    if (buffers.line_vertex_count > 0) {
        LinePush push{};
        push.clip_from_world = clip;
        push.depth_pull = line_pull;
        vkCmdBindVertexBuffers(cmd, 0, 1, &buffers.line_vertices, &zero);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelines.lines());
        vkCmdPushConstants(cmd, pipelines.line_layout(), stages, 0, sizeof push, &push);
        vkCmdDraw(cmd, buffers.line_vertex_count, 1, 0, 0);
    }
}

}  // namespace dfm::render
