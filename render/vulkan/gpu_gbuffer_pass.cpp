#include "render/vulkan/gpu_gbuffer_pass.h"

#include "gpu/rendering.h"
#include "gpu/shader_compiler.h"

namespace stsv {

GBufferPass::GBufferPass(const Device& device, FrameResources& resources, const FrameDescriptors& descriptors,
                         const std::vector<ShaderDefine>& layoutDefines, std::uint32_t triangleCount)
    : m_gbuffer(&resources.gbuffer), m_descriptors(&descriptors), m_triangleCount(triangleCount) {
    const ShaderCompiler compiler;
    GraphicsPipelineDesc desc;
    desc.stages = {
        {VK_SHADER_STAGE_VERTEX_BIT, compiler.compileFile("render/shaders/gbuffer.vert", layoutDefines)},
        {VK_SHADER_STAGE_FRAGMENT_BIT, compiler.compileFile("render/shaders/gbuffer.frag", layoutDefines)}};
    desc.colorFormats = {POSITION_FORMAT, TRIANGLE_FORMAT};
    desc.depthFormat = DEPTH_FORMAT;
    desc.depthTest = true;
    desc.depthWrite = true;
    desc.depthCompare = VK_COMPARE_OP_GREATER; // reversed depth: nearer is larger
    m_pipeline = createGraphicsPipeline(device, descriptors.pipelineLayout(), desc);
}

PassAccesses GBufferPass::accesses(std::size_t) const {
    PassAccesses accesses;
    accesses.use(m_gbuffer->position, ResourceUse::colorAttachment())
        .use(m_gbuffer->triangleId, ResourceUse::colorAttachment())
        .use(m_gbuffer->depth, ResourceUse::depthAttachment());
    return accesses;
}

void GBufferPass::record(VkCommandBuffer cmd, std::size_t) const {
    VkClearColorValue noTriangle{};
    noTriangle.uint32[0] = GPU_NO_TRIANGLE;
    const ColorTarget targets[] = {{&m_gbuffer->position, true, {}},
                                   {&m_gbuffer->triangleId, true, noTriangle}};
    beginRendering(cmd, targets, DepthTarget{&m_gbuffer->depth, true, GPU_DEPTH_CLEAR, false});
    m_pipeline.bind(cmd);
    m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, 0);
    m_descriptors->push(cmd, GpuPush{0u, 0u, 0u, 0u});
    if (m_triangleCount > 0) vkCmdDraw(cmd, 3 * m_triangleCount, 1, 0, 0);
    endRendering(cmd);
}

} // namespace stsv
