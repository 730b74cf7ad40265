#include "render/pipelines.hpp"

#include <cstddef>
#include <cstdint>
#include <span>

#include "dualform_shaders/line_frag.h"
#include "dualform_shaders/line_vert.h"
#include "dualform_shaders/mesh_frag.h"
#include "dualform_shaders/mesh_vert.h"
#include "render/scene_data.hpp"

namespace dfm::render {

namespace {

// Modules live only while the pipelines are built.
class ShaderModule {
public:
    ShaderModule(VkDevice device, std::span<const std::uint32_t> code) : device_(device) {
        VkShaderModuleCreateInfo info{};
        info.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
        info.codeSize = code.size_bytes();
        info.pCode = code.data();
        result_ = vkCreateShaderModule(device, &info, nullptr, &module_);
    }
    ShaderModule(const ShaderModule&) = delete;
    ShaderModule& operator=(const ShaderModule&) = delete;
    ~ShaderModule() {
        if (module_ != VK_NULL_HANDLE) vkDestroyShaderModule(device_, module_, nullptr);
    }
    VkResult result() const { return result_; }
    VkShaderModule handle() const { return module_; }

private:
    VkDevice device_;
    VkShaderModule module_ = VK_NULL_HANDLE;
    VkResult result_;
};

struct PipelineSpec {
    VkShaderModule vertex;
    VkShaderModule fragment;
    VkPipelineLayout layout;
    std::span<const VkVertexInputAttributeDescription> attributes;
    std::uint32_t stride;
    VkPrimitiveTopology topology;
    VkPolygonMode polygon_mode;
    bool depth_write;
};

Status build(VkDevice device, const AttachmentFormats& formats, const PipelineSpec& spec,
             VkPipeline& out) {
    const VkPipelineShaderStageCreateInfo stages[2] = {
        {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0,
         VK_SHADER_STAGE_VERTEX_BIT, spec.vertex, "main", nullptr},
        {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0,
         VK_SHADER_STAGE_FRAGMENT_BIT, spec.fragment, "main", nullptr}};
    const VkVertexInputBindingDescription binding{0, spec.stride, VK_VERTEX_INPUT_RATE_VERTEX};
    VkPipelineVertexInputStateCreateInfo vertex_input{};
    vertex_input.sType = VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO;
    vertex_input.vertexBindingDescriptionCount = 1;
    vertex_input.pVertexBindingDescriptions = &binding;
    vertex_input.vertexAttributeDescriptionCount =
        static_cast<std::uint32_t>(spec.attributes.size());
    vertex_input.pVertexAttributeDescriptions = spec.attributes.data();
    VkPipelineInputAssemblyStateCreateInfo assembly{};
    assembly.sType = VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO;
    assembly.topology = spec.topology;
    VkPipelineViewportStateCreateInfo viewport{};
    viewport.sType = VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO;
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo raster{};
    raster.sType = VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO;
    raster.polygonMode = spec.polygon_mode;
    // Both sides are drawn and lit: hosts hand meshes of either orientation.
    raster.cullMode = VK_CULL_MODE_NONE;
    raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    raster.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo multisample{};
    multisample.sType = VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO;
    multisample.rasterizationSamples = formats.samples;
    VkPipelineDepthStencilStateCreateInfo depth{};
    depth.sType = VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO;
    depth.depthTestEnable = formats.depth != VK_FORMAT_UNDEFINED;
    depth.depthWriteEnable = spec.depth_write && formats.depth != VK_FORMAT_UNDEFINED;
    depth.depthCompareOp = VK_COMPARE_OP_LESS_OR_EQUAL;
    VkPipelineColorBlendAttachmentState blend_attachment{};
    blend_attachment.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                                      VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
    VkPipelineColorBlendStateCreateInfo blend{};
    blend.sType = VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO;
    blend.attachmentCount = 1;
    blend.pAttachments = &blend_attachment;
    const VkDynamicState dynamic_states[2] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dynamic{};
    dynamic.sType = VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO;
    dynamic.dynamicStateCount = 2;
    dynamic.pDynamicStates = dynamic_states;
    VkPipelineRenderingCreateInfo rendering{};
    rendering.sType = VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO;
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachmentFormats = &formats.color;
    rendering.depthAttachmentFormat = formats.depth;

    VkGraphicsPipelineCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO;
    info.pNext = &rendering;
    info.stageCount = 2;
    info.pStages = stages;
    info.pVertexInputState = &vertex_input;
    info.pInputAssemblyState = &assembly;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &depth;
    info.pColorBlendState = &blend;
    info.pDynamicState = &dynamic;
    info.layout = spec.layout;
    if (VkResult r = vkCreateGraphicsPipelines(device, VK_NULL_HANDLE, 1, &info, nullptr, &out);
        r != VK_SUCCESS) {
        out = VK_NULL_HANDLE;
        return vk_failure(r, "vkCreateGraphicsPipelines");
    }
    return Status::ok();
}

Status make_layout(VkDevice device, std::uint32_t push_size, VkPipelineLayout& out) {
    const VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                                    push_size};
    VkPipelineLayoutCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
    info.pushConstantRangeCount = 1;
    info.pPushConstantRanges = &range;
    if (VkResult r = vkCreatePipelineLayout(device, &info, nullptr, &out); r != VK_SUCCESS) {
        out = VK_NULL_HANDLE;
        return vk_failure(r, "vkCreatePipelineLayout");
    }
    return Status::ok();
}

}  // namespace

Pipelines::~Pipelines() {
    for (VkPipeline p : {surface_, wireframe_, lines_}) {
        if (p != VK_NULL_HANDLE) vkDestroyPipeline(device_, p, nullptr);
    }
    for (VkPipelineLayout l : {mesh_layout_, line_layout_}) {
        if (l != VK_NULL_HANDLE) vkDestroyPipelineLayout(device_, l, nullptr);
    }
}

Status Pipelines::create(VkDevice device, const AttachmentFormats& formats, bool wireframe) {
    device_ = device;
    const ShaderModule mesh_vert(device, mesh_vert_spv);
    const ShaderModule mesh_frag(device, mesh_frag_spv);
    const ShaderModule line_vert(device, line_vert_spv);
    const ShaderModule line_frag(device, line_frag_spv);
    for (const ShaderModule* m : {&mesh_vert, &mesh_frag, &line_vert, &line_frag}) {
        if (m->result() != VK_SUCCESS) return vk_failure(m->result(), "vkCreateShaderModule");
    }
    if (Status s = make_layout(device, sizeof(MeshPush), mesh_layout_); !s) return s;
    if (Status s = make_layout(device, sizeof(LinePush), line_layout_); !s) return s;

    const VkVertexInputAttributeDescription mesh_attributes[3] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(MeshVertex, position)},
        {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(MeshVertex, normal)},
        {2, 0, VK_FORMAT_R32_UINT, offsetof(MeshVertex, mark)}};
    const VkVertexInputAttributeDescription line_attributes[2] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(LineVertex, position)},
        {1, 0, VK_FORMAT_R32G32B32A32_SFLOAT, offsetof(LineVertex, color)}};

    PipelineSpec surface{mesh_vert.handle(),   mesh_frag.handle(),
                         mesh_layout_,         mesh_attributes,
                         sizeof(MeshVertex),   VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST,
                         VK_POLYGON_MODE_FILL, true};
    if (Status s = build(device, formats, surface, surface_); !s) return s;
    if (wireframe) {
        PipelineSpec wire = surface;
        wire.polygon_mode = VK_POLYGON_MODE_LINE;
        wire.depth_write = false;
        if (Status s = build(device, formats, wire, wireframe_); !s) return s;
    }
    PipelineSpec lines{line_vert.handle(),   line_frag.handle(),
                       line_layout_,         line_attributes,
                       sizeof(LineVertex),   VK_PRIMITIVE_TOPOLOGY_LINE_LIST,
                       VK_POLYGON_MODE_FILL, false};
    return build(device, formats, lines, lines_);
}

}  // namespace dfm::render
