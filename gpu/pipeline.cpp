#include "gpu/pipeline.h"

#include "gpu/check.h"
#include "gpu/device.h"

#include <deque>
#include <utility>

namespace stsv {
namespace {

/// Owns a temporary VkShaderModule for pipeline creation.
class ShaderModule {
  public:
    ShaderModule(const Device& device, std::span<const uint32_t> spirv) : m_device(device.handle()) {
        if (spirv.empty()) throw UsageError("empty SPIR-V module");
        VkShaderModuleCreateInfo info{};
        info.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
        info.codeSize = spirv.size_bytes();
        info.pCode = spirv.data();
        STSV_VK_CHECK(vkCreateShaderModule(m_device, &info, nullptr, &m_module));
    }
    ~ShaderModule() { vkDestroyShaderModule(m_device, m_module, nullptr); }
    ShaderModule(const ShaderModule&) = delete;
    ShaderModule& operator=(const ShaderModule&) = delete;
    VkShaderModule handle() const { return m_module; }

  private:
    VkDevice m_device;
    VkShaderModule m_module = VK_NULL_HANDLE;
};

} // namespace

PipelineLayout::PipelineLayout(const Device& device, std::vector<VkDescriptorSetLayout> setLayouts,
                               uint32_t pushConstantBytes, VkShaderStageFlags pushStages)
    : m_device(&device), m_pushStages(pushConstantBytes > 0 ? pushStages : 0) {
    VkPushConstantRange range{pushStages, 0, pushConstantBytes};
    VkPipelineLayoutCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
    info.setLayoutCount = uint32_t(setLayouts.size());
    info.pSetLayouts = setLayouts.data();
    info.pushConstantRangeCount = pushConstantBytes > 0 ? 1 : 0;
    info.pPushConstantRanges = &range;
    STSV_VK_CHECK(vkCreatePipelineLayout(device.handle(), &info, nullptr, &m_layout));
}

PipelineLayout::~PipelineLayout() {
    destroy();
}

PipelineLayout::PipelineLayout(PipelineLayout&& other) noexcept
    : m_device(std::exchange(other.m_device, nullptr)),
      m_layout(std::exchange(other.m_layout, VK_NULL_HANDLE)),
      m_pushStages(std::exchange(other.m_pushStages, 0)) {}

PipelineLayout& PipelineLayout::operator=(PipelineLayout&& other) noexcept {
    if (this != &other) {
        destroy();
        m_device = std::exchange(other.m_device, nullptr);
        m_layout = std::exchange(other.m_layout, VK_NULL_HANDLE);
        m_pushStages = std::exchange(other.m_pushStages, 0);
    }
    return *this;
}

void PipelineLayout::destroy() noexcept {
    if (m_device != nullptr && m_layout != VK_NULL_HANDLE)
        vkDestroyPipelineLayout(m_device->handle(), m_layout, nullptr);
    m_layout = VK_NULL_HANDLE;
    m_device = nullptr;
}

void PipelineLayout::push(VkCommandBuffer cmd, const void* data, uint32_t bytes) const {
    vkCmdPushConstants(cmd, m_layout, m_pushStages, 0, bytes, data);
}

Pipeline::Pipeline(const Device& device, VkPipeline pipeline, VkPipelineBindPoint bindPoint)
    : m_device(&device), m_pipeline(pipeline), m_bindPoint(bindPoint) {}

Pipeline::~Pipeline() {
    destroy();
}

Pipeline::Pipeline(Pipeline&& other) noexcept
    : m_device(std::exchange(other.m_device, nullptr)),
      m_pipeline(std::exchange(other.m_pipeline, VK_NULL_HANDLE)), m_bindPoint(other.m_bindPoint) {}

Pipeline& Pipeline::operator=(Pipeline&& other) noexcept {
    if (this != &other) {
        destroy();
        m_device = std::exchange(other.m_device, nullptr);
        m_pipeline = std::exchange(other.m_pipeline, VK_NULL_HANDLE);
        m_bindPoint = other.m_bindPoint;
    }
    return *this;
}

void Pipeline::destroy() noexcept {
    if (m_device != nullptr && m_pipeline != VK_NULL_HANDLE)
        vkDestroyPipeline(m_device->handle(), m_pipeline, nullptr);
    m_pipeline = VK_NULL_HANDLE;
    m_device = nullptr;
}

Pipeline createComputePipeline(const Device& device, const PipelineLayout& layout,
                               std::span<const uint32_t> spirv) {
    ShaderModule module(device, spirv);
    VkComputePipelineCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO;
    info.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    info.stage.module = module.handle();
    info.stage.pName = "main";
    info.layout = layout.handle();
    VkPipeline pipeline = VK_NULL_HANDLE;
    STSV_VK_CHECK(vkCreateComputePipelines(device.handle(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline));
    return Pipeline(device, pipeline, VK_PIPELINE_BIND_POINT_COMPUTE);
}

VkPipelineColorBlendAttachmentState additiveBlend() {
    VkPipelineColorBlendAttachmentState state{};
    state.blendEnable = VK_TRUE;
    state.srcColorBlendFactor = VK_BLEND_FACTOR_ONE;
    state.dstColorBlendFactor = VK_BLEND_FACTOR_ONE;
    state.colorBlendOp = VK_BLEND_OP_ADD;
    state.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
    state.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
    state.alphaBlendOp = VK_BLEND_OP_ADD;
    state.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT |
                           VK_COLOR_COMPONENT_A_BIT;
    return state;
}

Pipeline createGraphicsPipeline(const Device& device, const PipelineLayout& layout,
                                const GraphicsPipelineDesc& desc) {
    if (desc.depthClamp && !device.info().depthClamp)
        throw UsageError(device.info().name + " lacks depthClamp");
    if (desc.logicOpEnable && !device.info().logicOp) throw UsageError(device.info().name + " lacks logicOp");

    std::deque<ShaderModule> modules; // stable addresses, no moves
    std::vector<VkPipelineShaderStageCreateInfo> stages;
    bool meshPipeline = false;
    for (const ShaderStage& s : desc.stages) {
        modules.emplace_back(device, s.spirv);
        VkPipelineShaderStageCreateInfo stage{};
        stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
        stage.stage = s.stage;
        stage.module = modules.back().handle();
        stage.pName = "main";
        stages.push_back(stage);
        if (s.stage == VK_SHADER_STAGE_MESH_BIT_EXT) meshPipeline = true;
    }

    VkPipelineVertexInputStateCreateInfo vertexInput{};

    vertexInput.sType = VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO;
    vertexInput.vertexBindingDescriptionCount = uint32_t(desc.vertexBindings.size());
    vertexInput.pVertexBindingDescriptions = desc.vertexBindings.data();
    vertexInput.vertexAttributeDescriptionCount = uint32_t(desc.vertexAttributes.size());
    vertexInput.pVertexAttributeDescriptions = desc.vertexAttributes.data();

    VkPipelineInputAssemblyStateCreateInfo inputAssembly{};

    inputAssembly.sType = VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO;
    inputAssembly.topology = desc.topology;

    VkPipelineViewportStateCreateInfo viewport{};

    viewport.sType = VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO;
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;

    VkPipelineRasterizationStateCreateInfo raster{};

    raster.sType = VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO;
    raster.depthClampEnable = desc.depthClamp ? VK_TRUE : VK_FALSE;
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = desc.cullMode;
    raster.frontFace = desc.frontFace;
    raster.lineWidth = 1.0f;
    raster.depthBiasEnable =
        desc.depthBiasConstant != 0.0f || desc.depthBiasSlope != 0.0f ? VK_TRUE : VK_FALSE;
    raster.depthBiasConstantFactor = desc.depthBiasConstant;
    raster.depthBiasSlopeFactor = desc.depthBiasSlope;

    VkPipelineMultisampleStateCreateInfo multisample{};

    multisample.sType = VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO;
    multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;

    VkPipelineDepthStencilStateCreateInfo depth{};

    depth.sType = VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO;
    depth.depthTestEnable = desc.depthTest ? VK_TRUE : VK_FALSE;
    depth.depthWriteEnable = desc.depthWrite ? VK_TRUE : VK_FALSE;
    depth.depthCompareOp = desc.depthCompare;
    depth.minDepthBounds = 0.0f;
    depth.maxDepthBounds = 1.0f;

    std::vector<VkPipelineColorBlendAttachmentState> blend = desc.blend;
    if (blend.empty()) {
        VkPipelineColorBlendAttachmentState writeAll{};
        writeAll.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                                  VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
        blend.assign(desc.colorFormats.size(), writeAll);
    }
    if (blend.size() != desc.colorFormats.size())
        throw UsageError("graphics pipeline: " + std::to_string(blend.size()) + " blend states for " +
                         std::to_string(desc.colorFormats.size()) + " color attachments");
    VkPipelineColorBlendStateCreateInfo colorBlend{};
    colorBlend.sType = VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO;
    colorBlend.logicOpEnable = desc.logicOpEnable ? VK_TRUE : VK_FALSE;
    colorBlend.logicOp = desc.logicOp;
    colorBlend.attachmentCount = uint32_t(blend.size());
    colorBlend.pAttachments = blend.data();

    const VkDynamicState dynamicStates[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dynamic{};
    dynamic.sType = VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO;
    dynamic.dynamicStateCount = 2;
    dynamic.pDynamicStates = dynamicStates;

    VkPipelineRenderingCreateInfo rendering{};

    rendering.sType = VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO;
    rendering.colorAttachmentCount = uint32_t(desc.colorFormats.size());
    rendering.pColorAttachmentFormats = desc.colorFormats.data();
    rendering.depthAttachmentFormat = desc.depthFormat;

    VkGraphicsPipelineCreateInfo info{};

    info.sType = VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO;
    info.pNext = &rendering;
    info.stageCount = uint32_t(stages.size());
    info.pStages = stages.data();
    // Mesh pipelines have no vertex input or input assembly state.
    info.pVertexInputState = meshPipeline ? nullptr : &vertexInput;
    info.pInputAssemblyState = meshPipeline ? nullptr : &inputAssembly;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = desc.depthFormat != VK_FORMAT_UNDEFINED ? &depth : nullptr;
    info.pColorBlendState = &colorBlend;
    info.pDynamicState = &dynamic;
    info.layout = layout.handle();
    VkPipeline pipeline = VK_NULL_HANDLE;
    STSV_VK_CHECK(vkCreateGraphicsPipelines(device.handle(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline));
    return Pipeline(device, pipeline, VK_PIPELINE_BIND_POINT_GRAPHICS);
}

} // namespace stsv
