#include "volumes/vulkan/gpu_stsv_pass.h"

#include "core/error.h"
#include "gpu/device.h"
#include "gpu/rendering.h"
#include "gpu/shader_compiler.h"

#include <algorithm>
#include <string>

namespace stsv {

namespace {

constexpr VkPipelineStageFlags2 FRAGMENT = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
constexpr VkPipelineStageFlags2 COMPUTE = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
} // namespace

StsvSamplesPass::StsvSamplesPass(const Device& device, const Scene& scene, const RenderOptions& options,
                                 FrameResources& resources, HullResources& hulls, DeferredFragments& deferred,
                                 const FamilyDescriptors& descriptors)
    : m_scene(&scene), m_resources(&resources), m_hulls(&hulls), m_deferred(&deferred),
      m_descriptors(&descriptors), m_counters(options.buffer == BufferKind::Counters),
      m_transmittance(options.buffer == BufferKind::Transmittance), m_device(&device),
      m_samples(options.samples),
      m_pipelines(lightTypeComputePipelines(device, descriptors.pipelineLayout(), lightTypesIn(scene),
                                            "volumes/shaders/stsv_samples.comp",
                                            sampleDefines(options, resources.tables.layout))) {}

PassAccesses StsvSamplesPass::accesses(std::size_t light) const {
    PassAccesses accesses;
    accesses.use(m_deferred->count, ResourceUse::storageRead(COMPUTE))
        .use(m_deferred->fragments, ResourceUse::storageRead(COMPUTE))
        .use(m_hulls->records, ResourceUse::sampledRead(COMPUTE))
        .use(m_resources->gbuffer.position, ResourceUse::storageRead(COMPUTE))
        .use(m_descriptors->stats(), ResourceUse::storageReadWrite(COMPUTE));
    if (m_counters)
        accesses.use(m_resources->samples.counters[light], ResourceUse::storageReadWrite(COMPUTE));
    else
        accesses.use(m_deferred->maskWords, ResourceUse::storageReadWrite(COMPUTE));
    if (m_transmittance)
        accesses.use(m_resources->samples.depths[light], ResourceUse::storageReadWrite(COMPUTE));
    return accesses;
}

void StsvSamplesPass::record(VkCommandBuffer cmd, std::size_t light) const {
    m_pipelines.at(m_scene->lights[light].type).bind(cmd);
    m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, light);
    m_descriptors->push(cmd, GpuPush{uint(light), 0u, 0u, 0u});
    vkCmdDispatch(cmd, deferredSampleGroups(*m_device, m_deferred->capacity(), m_samples), 1, 1);
}

StsvMergePass::StsvMergePass(const Device& device, const RenderOptions& options, FrameResources& resources,
                             DeferredFragments& deferred, const FamilyDescriptors& descriptors)
    : m_resources(&resources), m_deferred(&deferred), m_descriptors(&descriptors),
      m_width(static_cast<std::uint32_t>(options.width)),
      m_height(static_cast<std::uint32_t>(options.height)) {
    const ShaderCompiler compiler;
    m_pipeline = createComputePipeline(device, descriptors.pipelineLayout(),
                                       compiler.compileFile("volumes/shaders/stsv_merge.comp",
                                                            sampleDefines(options, resources.tables.layout)));
}

PassAccesses StsvMergePass::accesses(std::size_t light) const {
    PassAccesses accesses;
    accesses.use(m_deferred->maskWords, ResourceUse::storageRead(COMPUTE));
    // The whole image array is bound (its unused elements a stand-in) and indexed by a loop
    // counter, so the validator counts every element as written.
    for (std::size_t i = 0; i < GPU_MAX_MASK_IMAGES; ++i)
        accesses.use(m_resources->samples.mask(light, i), ResourceUse::storageReadWrite(COMPUTE));
    return accesses;
}

void StsvMergePass::record(VkCommandBuffer cmd, std::size_t light) const {
    m_pipeline.bind(cmd);
    m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, light);
    m_descriptors->push(cmd, GpuPush{uint(light), 0u, 0u, 0u});
    dispatchPerPixel(cmd, m_width, m_height);
}

StsvPass::StsvPass(const Device& device, const Scene& scene, const RenderOptions& options,
                   FrameResources& resources, HullResources& hulls, DeferredFragments& deferred,
                   const FamilyDescriptors& descriptors, VolumeGeometry geometry)
    : m_device(&device), m_scene(&scene), m_resources(&resources), m_hulls(&hulls), m_deferred(&deferred),
      m_descriptors(&descriptors), m_geometry(geometry), m_counters(options.buffer == BufferKind::Counters),
      m_transmittance(options.buffer == BufferKind::Transmittance),
      m_perforatedOnly(methodInfo(options.method).stsv == StsvTriangles::Perforated),
      m_triangleCount(static_cast<std::uint32_t>(scene.triangleCount())) {
    const ShaderCompiler compiler;
    const std::vector<ShaderDefine> common = layoutDefines(resources.tables.layout);
    std::vector<ShaderDefine> fragmentDefines = sampleDefines(options, resources.tables.layout);
    // Back faces of the convex volume behind the visible point, no depth write, depth clamp (the
    // far extrusion may pass the far plane): one fragment per pixel and volume.
    GraphicsPipelineDesc desc;
    switch (m_geometry) {
    case VolumeGeometry::MeshShaderHull:
        fragmentDefines.push_back({"STSV_MESH_PATH", "1"});
        desc.stages = meshHullStages(device, "volumes/shaders/stsv", common);
        break;
    case VolumeGeometry::GeometryShaderPrism:
        desc.stages = {
            {VK_SHADER_STAGE_VERTEX_BIT, compiler.compileFile("volumes/shaders/stsv.vert", common)},
            {VK_SHADER_STAGE_GEOMETRY_BIT, compiler.compileFile("volumes/shaders/stsv.geom", common)}};
        break;
    case VolumeGeometry::ComputeHull:
        fragmentDefines.push_back({"STSV_HULL_PATH", "1"});
        desc.stages = {
            {VK_SHADER_STAGE_VERTEX_BIT, compiler.compileFile("render/shaders/hull.vert", common)}};
        break;
    }
    desc.stages.push_back({VK_SHADER_STAGE_FRAGMENT_BIT, {}});
    if (!m_counters) {
        desc.colorFormats.assign(std::size_t(maskAttachmentCount(options.samples)), MASK_FORMAT);
        desc.logicOpEnable = true;
        desc.logicOp = VK_LOGIC_OP_OR;
    }
    setBehindVisiblePointDepth(desc);
    // The strip and the hull face outward (counter-clockwise seen from outside, extrusion_dh.h,
    // clip_box_dh.h); the y-down clip space keeps that orientation in framebuffer coordinates, so
    // the back faces are the clockwise ones.
    desc.cullMode = VK_CULL_MODE_FRONT_BIT;
    desc.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    const std::array<bool, 4> used = lightTypesIn(scene);
    for (uint type = 0; type < used.size(); ++type) {
        if (!used[type]) continue;
        desc.stages.back().spirv =
            compiler.compileFile("volumes/shaders/stsv.frag", lightTypeDefines(fragmentDefines, type));
        m_pipelines[type] = createGraphicsPipeline(device, descriptors.pipelineLayout(), desc);
    }
}

PassAccesses StsvPass::accesses(std::size_t light) const {
    PassAccesses accesses;
    accesses.use(m_resources->gbuffer.position, ResourceUse::storageRead(FRAGMENT))
        .use(m_resources->gbuffer.triangleId, ResourceUse::storageRead(FRAGMENT))
        .use(m_resources->gbuffer.depth, ResourceUse::depthTest())
        .use(m_descriptors->stats(), ResourceUse::storageReadWrite(volumeStatsStages(m_geometry)));
    if (m_geometry == VolumeGeometry::ComputeHull) {
        m_hulls->declareDrawReads(accesses);
        accesses.use(m_deferred->count, ResourceUse::storageReadWrite(FRAGMENT))
            .use(m_deferred->fragments, ResourceUse::storageReadWrite(FRAGMENT));
    }
    if (m_counters)
        accesses.use(m_resources->samples.counters[light], ResourceUse::storageReadWrite(FRAGMENT));
    if (m_transmittance)
        accesses.use(m_resources->samples.depths[light], ResourceUse::storageReadWrite(FRAGMENT));
    for (Image& mask : m_resources->samples.masks[light]) accesses.use(mask, ResourceUse::colorAttachment());
    return accesses;
}

void StsvPass::record(VkCommandBuffer cmd, std::size_t light) const {
    std::vector<ColorTarget> targets; // bitmask attachments, cleared by the pass
    for (Image& image : m_resources->samples.masks[light]) targets.push_back({&image, true, {}});
    beginRendering(cmd, targets, DepthTarget{&m_resources->gbuffer.depth, false, GPU_DEPTH_CLEAR, true});
    m_pipelines.at(m_scene->lights[light].type).bind(cmd);
    m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, light);
    m_descriptors->push(cmd, GpuPush{uint(light), 0u, m_perforatedOnly ? GPU_PUSH_PERFORATED_ONLY : 0u, 0u});
    if (m_triangleCount > 0) {
        switch (m_geometry) {
        case VolumeGeometry::MeshShaderHull:
            recordMeshHullDraw(*m_device, cmd, m_triangleCount);
            break;
        case VolumeGeometry::GeometryShaderPrism:
            vkCmdDraw(cmd, 3 * m_triangleCount, 1, 0, 0);
            break;
        case VolumeGeometry::ComputeHull:
            m_hulls->recordDraw(cmd);
            break;
        }
    }
    endRendering(cmd);
}

} // namespace stsv
