#include "render/vulkan/gpu_resolve_pass.h"

namespace stsv {

ResolvePass::ResolvePass(const Device& device, const Scene& scene, const RenderOptions& options,
                         const SamplePlan& plan, FrameResources& resources,
                         const FrameDescriptors& descriptors)
    : m_scene(&scene), m_resources(&resources),
      m_set(device, descriptors,
            {{GPU_BINDING_RESOLVE_COLOR, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_ALL, 1},
             {GPU_BINDING_RESOLVE_VISIBILITY, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_ALL, 1}},
            0),
      m_counters(options.buffer == BufferKind::Counters), m_countsLayers(frameCountsLayers(options)),
      m_vcoef(methodInfo(options.method).output == MethodOutput::Visibility),
      m_depths(options.buffer == BufferKind::Transmittance && !m_vcoef),
      m_width(static_cast<uint32_t>(options.width)), m_height(static_cast<uint32_t>(options.height)) {
    std::vector<ShaderDefine> defines =
        withPatternDefine(sampleDefines(options, resources.tables.layout), plan);
    defines.push_back({"RESOLVE_VCOEF", m_vcoef ? "1" : "0"});
    // The ambient-only pass of a scene without lights binds the first type's.
    std::array<bool, 4> used = lightTypesIn(scene);
    if (scene.lights.empty()) used[0] = true;
    m_pipelines = lightTypeComputePipelines(device, m_set.pipelineLayout(), used,
                                            "render/shaders/resolve.comp", defines);
}

void ResolvePass::writeDescriptors() {
    for (std::size_t l = 0; l < m_set.setCount(); ++l) {
        m_set.set(l).writeStorageImage(GPU_BINDING_RESOLVE_COLOR, m_resources->color);
        m_set.set(l).writeStorageImage(GPU_BINDING_RESOLVE_VISIBILITY, m_resources->visibility);
    }
}

PassAccesses ResolvePass::accesses(std::size_t light) const {
    constexpr VkPipelineStageFlags2 COMPUTE = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    const std::size_t set = light == AMBIENT_ONLY ? 0 : light;
    PassAccesses accesses;
    accesses.use(m_resources->gbuffer.position, ResourceUse::storageRead(COMPUTE))
        .use(m_resources->gbuffer.triangleId, ResourceUse::storageRead(COMPUTE))
        .use(m_resources->color, ResourceUse::storageReadWrite(COMPUTE))
        .use(m_resources->visibility, ResourceUse::storageReadWrite(COMPUTE));
    if (m_countsLayers) accesses.use(m_resources->samples.counters[set], ResourceUse::storageRead(COMPUTE));
    if (!m_counters)
        for (std::size_t i = 0; i < GPU_MAX_MASK_IMAGES; ++i)
            accesses.use(m_resources->samples.mask(set, i), ResourceUse::storageRead(COMPUTE));
    if (m_depths) accesses.use(m_resources->samples.depths[set], ResourceUse::storageRead(COMPUTE));
    if (m_vcoef) accesses.use(m_resources->samples.vcoef, ResourceUse::storageRead(COMPUTE));
    return accesses;
}

void ResolvePass::record(VkCommandBuffer cmd, std::size_t light) const {
    const bool ambientOnly = light == AMBIENT_ONLY;
    const std::size_t set = ambientOnly ? 0 : light;
    m_pipelines.at(ambientOnly ? 0u : m_scene->lights[light].type).bind(cmd);
    m_set.bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, set);
    m_set.push(cmd, GpuPush{ambientOnly ? 0xffffffffu : uint(light), set == 0 ? 1u : 0u, 0u, 0u});
    // resolve.comp works on 16 × 16 tiles (fewer, larger workgroups: lavapipe pays per workgroup).
    dispatchPerPixel(cmd, m_width, m_height);
}

} // namespace stsv
