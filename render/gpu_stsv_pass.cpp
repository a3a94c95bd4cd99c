#include "render/gpu_stsv_pass.h"

#include "core/error.h"
#include "gpu/device.h"
#include "gpu/rendering.h"
#include "gpu/shader_compiler.h"

#include <algorithm>
#include <string>

namespace stsv {

namespace {

constexpr VkPipelineStageFlags2 COMPUTE = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr VkPipelineStageFlags2 VERTEX = VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT;
constexpr VkPipelineStageFlags2 FRAGMENT = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
constexpr VkBufferUsageFlags STORAGE = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
/// Threads of stsv_hull.comp's workgroups; one thread per (triangle, side).
constexpr std::uint32_t HULL_GROUP = 64;

} // namespace

const char* toString(StsvGeometry geometry) {
    switch (geometry) {
    case StsvGeometry::GeometryShaderPrism:
        return "geometry shader";
    case StsvGeometry::MeshShaderPrism:
        return "mesh shader";
    case StsvGeometry::Hull:
        return "hull (compute)";
    }
    return "?";
}

StsvHullResources::StsvHullResources(const Device& device) : m_device(&device) {
    draw = Buffer(device, sizeof(GpuStsvDraw), STORAGE | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                  MemoryUsage::DeviceLocal);
    resize(1, 1);
}

std::vector<DescriptorBinding> StsvHullResources::bindings() {
    return {{GPU_BINDING_STSV_DRAW, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_STSV_RECORDS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_STSV_HULL, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_STSV_RECORD_TEXELS, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_STSV_HULL_TEXELS, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_SHADER_STAGE_ALL, 1}};
}

void StsvHullResources::writeDescriptors(DescriptorSet& set) const {
    set.writeBuffer(GPU_BINDING_STSV_DRAW, draw);
    set.writeBuffer(GPU_BINDING_STSV_RECORDS, records);
    set.writeBuffer(GPU_BINDING_STSV_HULL, vertices);
    set.writeTexelBuffer(GPU_BINDING_STSV_RECORD_TEXELS, recordTexels.handle());
    set.writeTexelBuffer(GPU_BINDING_STSV_HULL_TEXELS, vertexTexels.handle());
}

void StsvHullResources::resize(std::uint64_t volumes, std::uint64_t triangles) {
    m_volumeCapacity = std::max<std::uint64_t>(volumes, 1);
    m_triangleCapacity = std::max<std::uint64_t>(triangles, 1);
    // uvec4 lengths in the shaders are 32-bit: 2^32 / 16 vertices at most.
    if (3 * m_triangleCapacity > 0xffffffffull / 16 ||
        m_volumeCapacity > 0xffffffffull / sizeof(GpuStsvRecord))
        throw UsageError("the STSV hulls need " + std::to_string(m_triangleCapacity) + " triangles of " +
                         std::to_string(m_volumeCapacity) +
                         " volumes, more than one buffer holds; use --extrusion geometry");
    constexpr VkBufferUsageFlags TEXELS = STORAGE | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT;
    records = Buffer(*m_device, m_volumeCapacity * sizeof(GpuStsvRecord), TEXELS, MemoryUsage::DeviceLocal);
    vertices = Buffer(*m_device, 3 * m_triangleCapacity * 16, TEXELS, MemoryUsage::DeviceLocal);
    recordTexels = BufferView(*m_device, records, VK_FORMAT_R32G32B32A32_UINT, 16);
    vertexTexels = BufferView(*m_device, vertices, VK_FORMAT_R32G32B32A32_UINT, 16);
}

StsvHullPass::StsvHullPass(const Device& device, const Scene& scene, const RenderOptions& options,
                           FrameResources& resources, StsvHullResources& hulls,
                           const FrameDescriptors& descriptors)
    : m_resources(&resources), m_hulls(&hulls), m_descriptors(&descriptors),
      m_perforatedOnly(methodInfo(options.method).stsv == StsvTriangles::Perforated),
      m_triangleCount(static_cast<std::uint32_t>(scene.triangleCount())) {
    const ShaderCompiler compiler;
    m_pipeline =
        createComputePipeline(device, descriptors.pipelineLayout(),
                              compiler.compileFile("stsv_hull.comp", layoutDefines(resources.tables.layout)));
}

PassAccesses StsvHullPass::accesses(std::size_t) const {
    PassAccesses accesses;
    accesses.use(m_hulls->draw, ResourceUse::storageReadWrite(COMPUTE))
        .use(m_hulls->records, ResourceUse::storageReadWrite(COMPUTE))
        .use(m_hulls->vertices, ResourceUse::storageReadWrite(COMPUTE))
        .use(m_resources->stats, ResourceUse::storageReadWrite(COMPUTE));
    return accesses;
}

void StsvHullPass::record(VkCommandBuffer cmd, std::size_t light) const {
    m_pipeline.bind(cmd);
    m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, light);
    m_descriptors->push(cmd, GpuPush{uint(light), 0u, m_perforatedOnly ? GPU_PUSH_PERFORATED_ONLY : 0u, 0u});
    const std::uint64_t threads = 2ull * m_triangleCount; // side-major (stsv_hull.comp)
    const auto groups = static_cast<std::uint32_t>((threads + HULL_GROUP - 1) / HULL_GROUP);
    // Rows of at most 65535 workgroups (the minimum maxComputeWorkGroupCount[0]); the shader
    // numbers its threads by gl_GlobalInvocationID.x only, so a dispatch holds at most one row.
    if (groups > 65535)
        throw UsageError("the STSV hull pass takes at most " + std::to_string(65535 * HULL_GROUP / 2) +
                         " triangles; use --extrusion geometry");
    if (groups > 0) vkCmdDispatch(cmd, groups, 1, 1);
}

StsvPass::StsvPass(const Device& device, const Scene& scene, const RenderOptions& options,
                   FrameResources& resources, StsvHullResources& hulls, const FrameDescriptors& descriptors,
                   StsvGeometry geometry)
    : m_device(&device), m_scene(&scene), m_resources(&resources), m_hulls(&hulls),
      m_descriptors(&descriptors), m_geometry(geometry), m_counters(options.buffer == BufferKind::Counters),
      m_perforatedOnly(methodInfo(options.method).stsv == StsvTriangles::Perforated),
      m_triangleCount(static_cast<std::uint32_t>(scene.triangleCount())) {
    const ShaderCompiler compiler;
    const std::vector<ShaderDefine> common = layoutDefines(resources.tables.layout);
    std::vector<ShaderDefine> fragmentDefines = sampleDefines(options, resources.tables.layout);
    // Back faces of the convex volume behind the visible point, no depth write, depth clamp (the
    // far extrusion may pass the far plane): one fragment per pixel and volume.
    GraphicsPipelineDesc desc;
    switch (m_geometry) {
    case StsvGeometry::MeshShaderPrism:
        fragmentDefines.push_back({"STSV_MESH_PATH", "1"});
        desc.stages = {{VK_SHADER_STAGE_MESH_BIT_EXT, compiler.compileFile("stsv.mesh", common)}};
        break;
    case StsvGeometry::GeometryShaderPrism:
        desc.stages = {{VK_SHADER_STAGE_VERTEX_BIT, compiler.compileFile("stsv.vert", common)},
                       {VK_SHADER_STAGE_GEOMETRY_BIT, compiler.compileFile("stsv.geom", common)}};
        break;
    case StsvGeometry::Hull:
        fragmentDefines.push_back({"STSV_HULL_PATH", "1"});
        desc.stages = {{VK_SHADER_STAGE_VERTEX_BIT, compiler.compileFile("stsv_hull.vert", common)}};
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
    std::array<bool, 4> used{};
    for (const Light& light : scene.lights) used.at(light.type) = true;
    for (uint type = 0; type < used.size(); ++type) {
        if (!used[type]) continue;
        desc.stages.back().spirv = compiler.compileFile("stsv.frag", lightTypeDefines(fragmentDefines, type));
        m_pipelines[type] = createGraphicsPipeline(device, descriptors.pipelineLayout(), desc);
    }
}

PassAccesses StsvPass::accesses(std::size_t light) const {
    PassAccesses accesses;
    accesses.use(m_resources->gbuffer.position, ResourceUse::storageRead(FRAGMENT))
        .use(m_resources->gbuffer.triangleId, ResourceUse::storageRead(FRAGMENT))
        .use(m_resources->gbuffer.depth, ResourceUse::depthTest())
        .use(m_resources->stats, ResourceUse::storageReadWrite(FRAGMENT));
    if (m_geometry == StsvGeometry::Hull)
        accesses.use(m_hulls->draw, ResourceUse::indirectRead())
            .use(m_hulls->vertices, ResourceUse::sampledRead(VERTEX))
            .use(m_hulls->records, ResourceUse::sampledRead(FRAGMENT));
    if (m_counters)
        accesses.use(m_resources->samples.counters[light], ResourceUse::storageReadWrite(FRAGMENT));
    for (Image& mask : m_resources->samples.masks[light]) accesses.use(mask, ResourceUse::colorAttachment());
    return accesses;
}

void StsvPass::record(VkCommandBuffer cmd, std::size_t light) const {
    std::vector<ColorTarget> targets; // bitmask attachments, cleared by the pass
    for (Image& image : m_resources->samples.masks[light]) targets.push_back({&image, true, {}});
    beginRendering(cmd, targets, DepthTarget{&m_resources->gbuffer.depth, false, 1.0f, true});
    m_pipelines.at(m_scene->lights[light].type).bind(cmd);
    m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, light);
    m_descriptors->push(cmd, GpuPush{uint(light), 0u, m_perforatedOnly ? GPU_PUSH_PERFORATED_ONLY : 0u, 0u});
    if (m_triangleCount > 0) {
        switch (m_geometry) {
        case StsvGeometry::MeshShaderPrism: {
            // Workgroups in rows of at most 65535 (the minimum maxMeshWorkGroupCount[0]).
            const uint32_t rowLength = std::min<uint32_t>(m_triangleCount, 65535u);
            m_device->cmdDrawMeshTasks()(cmd, rowLength, (m_triangleCount + rowLength - 1) / rowLength, 1);
            break;
        }
        case StsvGeometry::GeometryShaderPrism:
            vkCmdDraw(cmd, 3 * m_triangleCount, 1, 0, 0);
            break;
        case StsvGeometry::Hull:
            vkCmdDrawIndirect(cmd, m_hulls->draw.handle(), 0, 1, sizeof(VkDrawIndirectCommand));
            break;
        }
    }
    endRendering(cmd);
}

} // namespace stsv
