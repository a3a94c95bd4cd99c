// Pipeline layouts, compute and graphics pipelines (dynamic rendering: no render passes).
#pragma once

#include "gpu/vulkan.h"

#include <cstdint>
#include <span>
#include <vector>

namespace stsv {

class Device;

/// Move-only VkPipelineLayout: descriptor set layouts (set = position) and one push-constant
/// range visible to all stages.
class PipelineLayout {
  public:
    PipelineLayout() = default;
    PipelineLayout(const Device& device, std::vector<VkDescriptorSetLayout> setLayouts,
                   uint32_t pushConstantBytes = 0, VkShaderStageFlags pushStages = VK_SHADER_STAGE_ALL);
    ~PipelineLayout();
    PipelineLayout(PipelineLayout&& other) noexcept;
    PipelineLayout& operator=(PipelineLayout&& other) noexcept;

    VkPipelineLayout handle() const { return m_layout; }
    VkShaderStageFlags pushStages() const { return m_pushStages; }
    /// vkCmdPushConstants over the whole range this layout declares, from offset 0.
    void push(VkCommandBuffer cmd, const void* data, uint32_t bytes) const;

  private:
    const Device* m_device = nullptr;
    VkPipelineLayout m_layout = VK_NULL_HANDLE;
    VkShaderStageFlags m_pushStages = 0;

    void destroy() noexcept;
};

/// Move-only VkPipeline with its bind point.
class Pipeline {
  public:
    Pipeline() = default;
    Pipeline(const Device& device, VkPipeline pipeline, VkPipelineBindPoint bindPoint);
    ~Pipeline();
    Pipeline(Pipeline&& other) noexcept;
    Pipeline& operator=(Pipeline&& other) noexcept;

    VkPipeline handle() const { return m_pipeline; }
    VkPipelineBindPoint bindPoint() const { return m_bindPoint; }
    void bind(VkCommandBuffer cmd) const { vkCmdBindPipeline(cmd, m_bindPoint, m_pipeline); }

  private:
    const Device* m_device = nullptr;
    VkPipeline m_pipeline = VK_NULL_HANDLE;
    VkPipelineBindPoint m_bindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;

    void destroy() noexcept;
};

/// A compiled shader stage (SPIR-V words, e.g. from ShaderCompiler).
struct ShaderStage {
    VkShaderStageFlagBits stage = VK_SHADER_STAGE_COMPUTE_BIT;
    std::vector<uint32_t> spirv;
};

Pipeline createComputePipeline(const Device& device, const PipelineLayout& layout,
                               std::span<const uint32_t> spirv);

/// Fixed-function state of a graphics pipeline. Viewport and scissor are dynamic (set by
/// beginRendering); attachments are described by format only (dynamic rendering).
struct GraphicsPipelineDesc {
    std::vector<ShaderStage> stages; ///< vertex+fragment, optionally geometry; or mesh(+task)+fragment
    std::vector<VkFormat> colorFormats;
    VkFormat depthFormat = VK_FORMAT_UNDEFINED;
    VkPrimitiveTopology topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    std::vector<VkVertexInputBindingDescription> vertexBindings;
    std::vector<VkVertexInputAttributeDescription> vertexAttributes;
    VkCullModeFlags cullMode = VK_CULL_MODE_NONE;
    VkFrontFace frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    bool depthTest = false;
    bool depthWrite = false;
    VkCompareOp depthCompare = VK_COMPARE_OP_LESS_OR_EQUAL;
    bool depthClamp = false; ///< needs DeviceInfo::depthClamp
    /// Depth bias (Vulkan's o = m·slope + r·constant, r the depth format's resolution at the
    /// primitive): a positive value moves fragments farther before the depth test.
    float depthBiasConstant = 0.0f;
    float depthBiasSlope = 0.0f;
    bool logicOpEnable = false; ///< needs DeviceInfo::logicOp; applies to every (integer) attachment
    VkLogicOp logicOp = VK_LOGIC_OP_COPY;
    /// One per color attachment; empty: no blending, all channels written.
    std::vector<VkPipelineColorBlendAttachmentState> blend;
};

Pipeline createGraphicsPipeline(const Device& device, const PipelineLayout& layout,
                                const GraphicsPipelineDesc& desc);

/// A blend state that adds source to destination (exact for small integers in float targets).
VkPipelineColorBlendAttachmentState additiveBlend();

} // namespace stsv
