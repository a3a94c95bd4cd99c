#include "render/vulkan/gpu_shadowmap_passes.h"

#include "core/error.h"
#include "gpu/device.h"
#include "gpu/rendering.h"
#include "gpu/shader_compiler.h"
#include "render/options.h"
#include "shadowmaps/shadow_fit.h"

#include <cstring>
#include <string>

namespace stsv {

namespace {

constexpr VkPipelineStageFlags2 FRAGMENT = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
constexpr VkPipelineStageFlags2 COMPUTE = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr VkBufferUsageFlags STORAGE = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;

} // namespace

std::vector<DescriptorBinding> ShadowMapResources::bindings() {
    return {{GPU_BINDING_SHADOW_MAP, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_SHADOW_VIEWS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_SHADOW_TAPS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1}};
}

ShadowMapResources::ShadowMapResources(const Device& device, const Scene& scene, const RenderOptions& options)
    : m_settings(shadowMapSettings(options)) {
    if (scene.lights.empty()) throw Error("internal error: shadow maps of a scene without lights");
    const ShadowFilterParams params = shadowFilterParams(m_settings);
    const Bounds receivers = m_settings.fit == 0
                                 ? Bounds{}
                                 : shadowReceiverBounds(scene, float(options.width) / float(options.height));
    for (const Light& light : scene.lights) {
        m_views.push_back(fitFrameShadowMap(scene, light, receivers, m_settings));
        depth.emplace_back(device, shadowMapBytes(m_views.back()), STORAGE, MemoryUsage::DeviceLocal);
    }
    const std::vector<vec2> tapPoints = shadowFilterTaps(m_settings);
    std::vector<std::byte> table(sizeof(ShadowFilterParams) + sizeof(ShadowMapView) * m_views.size());
    std::memcpy(table.data(), &params, sizeof params);
    std::memcpy(table.data() + sizeof params, m_views.data(), sizeof(ShadowMapView) * m_views.size());
    views = createBuffer(device, std::span<const std::byte>(table), STORAGE);
    taps = createBuffer(device, std::span<const vec2>(tapPoints), STORAGE);
}

ShadowMap ShadowMapResources::download(std::size_t light) const {
    ShadowMap map;
    map.view = m_views.at(light);
    const std::vector<uint> words = depth.at(light).download<uint>();
    map.depth.resize(words.size());
    for (std::size_t i = 0; i < words.size(); ++i) map.depth[i] = gpuShadowDepthOf(words[i]);
    return map;
}

void ShadowMapResources::writeDescriptors(DescriptorSet& set, std::size_t light) const {
    set.writeBuffer(GPU_BINDING_SHADOW_MAP, depth[light]);
    set.writeBuffer(GPU_BINDING_SHADOW_VIEWS, views);
    set.writeBuffer(GPU_BINDING_SHADOW_TAPS, taps);
}

ShadowMapPass::ShadowMapPass(const Device& device, const Scene& scene, ShadowMapResources& maps,
                             const FamilyDescriptors& descriptors, const std::vector<ShaderDefine>& defines)
    : m_maps(&maps), m_descriptors(&descriptors),
      m_triangleCount(static_cast<std::uint32_t>(scene.triangleCount())) {
    const ShaderCompiler compiler;
    GraphicsPipelineDesc desc;
    desc.stages = {
        {VK_SHADER_STAGE_VERTEX_BIT, compiler.compileFile("shadowmaps/shadowmap.vert", defines)},
        {VK_SHADER_STAGE_FRAGMENT_BIT, compiler.compileFile("shadowmaps/shadowmap.frag", defines)}};
    // A triangle blocks light whichever face the light sees: no culling.
    desc.cullMode = VK_CULL_MODE_NONE;
    m_pipeline = createGraphicsPipeline(device, descriptors.pipelineLayout(), desc);
}

PassAccesses ShadowMapPass::accesses(std::size_t light) const {
    PassAccesses accesses;
    accesses.use(m_maps->depth[light], ResourceUse::storageReadWrite(FRAGMENT));
    return accesses;
}

void ShadowMapPass::record(VkCommandBuffer cmd, std::size_t light) const {
    const ShadowMapView& view = m_maps->view(light);
    beginRendering(cmd, VkExtent2D{view.size, view.size});
    m_pipeline.bind(cmd);
    m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, light);
    m_descriptors->push(cmd, GpuPush{uint(light), 0u, 0u, 0u});
    if (m_triangleCount > 0) vkCmdDraw(cmd, 3 * m_triangleCount, view.faces, 0, 0);
    endRendering(cmd);
}

ShadowFilterPass::ShadowFilterPass(const Device& device, const RenderOptions& options, Step step,
                                   ShadowMapResources& maps, FrameResources& frame,
                                   const FamilyDescriptors& descriptors,
                                   const std::vector<ShaderDefine>& defines)
    : m_maps(&maps), m_frame(&frame), m_descriptors(&descriptors), m_step(step),
      m_width(static_cast<uint32_t>(options.width)), m_height(static_cast<uint32_t>(options.height)) {
    const ShaderCompiler compiler;
    std::vector<ShaderDefine> withStep = defines;
    withStep.push_back({"SHADOW_FILTER_STEP", std::to_string(int(step))});
    m_pipeline = createComputePipeline(device, descriptors.pipelineLayout(),
                                       compiler.compileFile("shadowmaps/shadow_filter.comp", withStep));
}

PassAccesses ShadowFilterPass::accesses(std::size_t light) const {
    PassAccesses accesses;
    accesses.use(m_frame->gbuffer.position, ResourceUse::storageRead(COMPUTE))
        .use(m_frame->gbuffer.triangleId, ResourceUse::storageRead(COMPUTE))
        .use(m_maps->depth[light], ResourceUse::storageRead(COMPUTE))
        .use(m_frame->samples.vcoef, ResourceUse::storageReadWrite(COMPUTE))
        .use(m_descriptors->stats(), ResourceUse::storageReadWrite(COMPUTE));
    return accesses;
}

void ShadowFilterPass::record(VkCommandBuffer cmd, std::size_t light) const {
    m_pipeline.bind(cmd);
    m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, light);
    m_descriptors->push(cmd, GpuPush{uint(light), 0u, 0u, 0u});
    // shadow_filter.comp works on 16 × 16 tiles.
    dispatchPerPixel(cmd, m_width, m_height);
}

} // namespace stsv
