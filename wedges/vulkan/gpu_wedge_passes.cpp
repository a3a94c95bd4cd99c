#include "wedges/vulkan/gpu_wedge_passes.h"

#include "wedges/layer_bvh.h"

#include "core/error.h"
#include "gpu/device.h"
#include "gpu/rendering.h"
#include "gpu/shader_compiler.h"
#include "volumes/extrusion_dh.h"
#include "wedges/adjacency.h"
#include "wedges/dcs_dh.h"
#include "wedges/edge_cluster_dh.h"

#include <algorithm>
#include <cstdio>
#include <unordered_map>

namespace stsv {

namespace {

constexpr VkFormat CENTER_FORMAT = VK_FORMAT_R32_SINT;
constexpr VkPipelineStageFlags2 FRAGMENT = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
constexpr VkPipelineStageFlags2 COMPUTE = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
/// dcs_rays.comp's workgroup size.
constexpr std::uint32_t RAY_GROUP = 16u * GPU_DCS_RAY_SAMPLES_PER_GROUP;

/// `defines` plus the technique (WEDGE_PW) and whether pw folds in the STSV part (WEDGE_STSV).
std::vector<ShaderDefine> wedgeDefines(const RenderOptions& options, std::vector<ShaderDefine> defines) {
    const MethodInfo& method = methodInfo(options.method);
    const bool pw = method.wedges == WedgeVariant::Pw;
    defines.push_back({"WEDGE_PW", pw ? "1" : "0"});
    defines.push_back({"WEDGE_STSV", pw && method.stsv != StsvTriangles::None ? "1" : "0"});
    return defines;
}

/// The volume passes' common state: the depth test "behind the visible point"
/// (setBehindVisiblePointDepth), one point per primitive expanded by the geometry shader.
GraphicsPipelineDesc volumePipelineDesc(std::vector<ShaderStage> stages) {
    GraphicsPipelineDesc desc;
    desc.stages = std::move(stages);
    desc.topology = VK_PRIMITIVE_TOPOLOGY_POINT_LIST;
    setBehindVisiblePointDepth(desc);
    desc.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE; // outward faces are CCW
    return desc;
}

} // namespace

GpuEdgeTables buildGpuEdgeTables(const Scene& scene) {
    const EdgeAdjacency adj =
        buildEdgeAdjacency(scene, [&](std::size_t t) { return scene.opaqueOccluder(t); });
    return buildGpuEdgeTables(adj, edgeCarriers(adj, scene));
}

GpuEdgeTables buildGpuEdgeTables(const EdgeAdjacency& adj, const std::vector<std::uint32_t>& carriers) {
    GpuEdgeTables tables;
    std::unordered_map<std::uint32_t, std::uint32_t> carrierOf; // triangle → its index in tables.carriers
    tables.faces.reserve(adj.faces.size());
    for (const EdgeFace& f : adj.faces) tables.faces.push_back({adj.positions[f.opposite], f.triangle});
    tables.edges.reserve(adj.edges.size());
    for (const MeshEdge& e : adj.edges) {
        GpuEdge g{};
        g.v0 = adj.positions[e.v0];
        g.v1 = adj.positions[e.v1];
        g.firstFace = e.firstFace;
        g.faceCount = e.faceCount;
        // One bound per carrier face, for the up to three edges it carries (wedges/adjacency.h).
        const std::uint32_t t = carriers[tables.edges.size()];
        if (t != NO_CARRIER) {
            const auto [slot, added] = carrierOf.try_emplace(t, std::uint32_t(tables.carriers.size()));
            if (added) tables.carriers.push_back({t, GPU_NO_EDGE, GPU_NO_EDGE, GPU_NO_EDGE});
            uvec4& carrier = tables.carriers[slot->second];
            const std::uint32_t edge = std::uint32_t(tables.edges.size());
            if (carrier.y == GPU_NO_EDGE)
                carrier.y = edge;
            else if (carrier.z == GPU_NO_EDGE)
                carrier.z = edge;
            else
                carrier.w = edge;
        }
        tables.edges.push_back(g);
    }
    return tables;
}

std::vector<DescriptorBinding> WedgeResources::bindings() {
    std::vector<DescriptorBinding> bindings = {
        {GPU_BINDING_EDGES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
        {GPU_BINDING_EDGE_FACES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1},
        {GPU_BINDING_CARRIER_TEXELS, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_SHADER_STAGE_ALL, 1},
        {GPU_BINDING_EDGE_TEXELS, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_SHADER_STAGE_ALL, 1},
        {GPU_BINDING_EDGE_FACE_TEXELS, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_SHADER_STAGE_ALL, 1},
        {GPU_BINDING_CENTER, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_ALL, 1},
        {GPU_BINDING_LAYER_NODES, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_SHADER_STAGE_ALL, 1},
        {GPU_BINDING_LAYER_TRIANGLES, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, VK_SHADER_STAGE_ALL, 1},
        {GPU_BINDING_DCS_BLOCKS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_ALL, 1}};
    for (const DescriptorBinding& b : WedgeClusters::bindings()) bindings.push_back(b);
    return bindings;
}

WedgeResources::WedgeResources(const Device& device, const Scene& scene, const RenderOptions& options) {
    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    m_adjacency = buildEdgeAdjacency(scene, [&](std::size_t t) { return scene.opaqueOccluder(t); });
    m_carriers = edgeCarriers(m_adjacency, scene);
    GpuEdgeTables tables = buildGpuEdgeTables(m_adjacency, m_carriers);
    m_edgeCount = tables.edges.size();
    m_carrierCount = tables.carriers.size();
    if (tables.edges.empty()) tables.edges.push_back({});
    if (tables.faces.empty()) tables.faces.push_back({});
    if (tables.carriers.empty()) tables.carriers.push_back(uvec4(GPU_NO_EDGE));
    // The fragments of the wedge pass read edges, faces and carriers at a per-lane index: as
    // texels, a vector gather on lavapipe, where a storage-buffer load is a loop over the lanes.
    const VkBufferUsageFlags texels = VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT;
    edges = createBuffer(device, std::span<const GpuEdge>(tables.edges), storage | texels);
    faces = createBuffer(device, std::span<const GpuEdgeFace>(tables.faces), storage | texels);
    carriers = createBuffer(device, std::span<const uvec4>(tables.carriers), texels);
    edgeTexels = BufferView(device, edges, VK_FORMAT_R32G32B32A32_UINT, 16);
    faceTexels = BufferView(device, faces, VK_FORMAT_R32G32B32A32_UINT, 16);
    carrierTexels = BufferView(device, carriers, VK_FORMAT_R32G32B32A32_UINT, 16);
    center = Image(device, {static_cast<uint32_t>(options.width), static_cast<uint32_t>(options.height),
                            CENTER_FORMAT, VK_IMAGE_USAGE_STORAGE_BIT});
    // Per block of the walk its kept edges, the list of those with rays to cast (dcs_rays.comp), and
    // a bit a pixel whose segments' gaps meet a triangle (dcs_center.comp).
    const std::uint32_t blocks =
        clusterBlocksAlong(std::uint32_t(options.width)) * clusterBlocksAlong(std::uint32_t(options.height));
    const VkDeviceSize pixelWords = (VkDeviceSize(options.width) * VkDeviceSize(options.height) + 31u) / 32u;
    dcsBlocks = Buffer(device, (GPU_DCS_BLOCK_EDGES + 2u * VkDeviceSize(blocks) + pixelWords) * sizeof(uint),
                       storage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                       MemoryUsage::DeviceLocal);
    // The tree D(r) is counted through, one for every light.
    LayerBvhTables layers = buildLayerBvh(scene);
    m_layerNodeCount = layers.nodeCount();
    if (layers.nodes.empty()) layers.nodes.push_back(uvec4(0u));
    if (layers.triangles.empty()) layers.triangles.push_back(uvec4(0u));
    layerNodes = createBuffer(device, std::span<const uvec4>(layers.nodes), texels);
    layerTriangles = createBuffer(device, std::span<const uvec4>(layers.triangles), texels);
    layerNodeTexels = BufferView(device, layerNodes, VK_FORMAT_R32G32B32A32_UINT, 16);
    layerTriangleTexels = BufferView(device, layerTriangles, VK_FORMAT_R32G32B32A32_UINT, 16);
    m_clusters.emplace(device, scene, m_adjacency, m_carriers, usesWedgeClusters(options));
}

void WedgeResources::writeDescriptors(DescriptorSet& set, std::size_t light,
                                      const ClusterLists& lists) const {
    set.writeBuffer(GPU_BINDING_EDGES, edges);
    set.writeBuffer(GPU_BINDING_EDGE_FACES, faces);
    set.writeTexelBuffer(GPU_BINDING_CARRIER_TEXELS, carrierTexels.handle());
    set.writeTexelBuffer(GPU_BINDING_EDGE_TEXELS, edgeTexels.handle());
    set.writeTexelBuffer(GPU_BINDING_EDGE_FACE_TEXELS, faceTexels.handle());
    set.writeStorageImage(GPU_BINDING_CENTER, center);
    set.writeTexelBuffer(GPU_BINDING_LAYER_NODES, layerNodeTexels.handle());
    set.writeTexelBuffer(GPU_BINDING_LAYER_TRIANGLES, layerTriangleTexels.handle());
    set.writeBuffer(GPU_BINDING_DCS_BLOCKS, dcsBlocks);
    m_clusters->writeDescriptors(set, light, lists);
}

CenterCountPass::CenterCountPass(const Device& device, WedgeResources& wedges, FrameResources& frame,
                                 const FamilyDescriptors& descriptors,
                                 const std::vector<ShaderDefine>& defines, std::uint32_t width,
                                 std::uint32_t height)
    : m_wedges(&wedges), m_frame(&frame), m_descriptors(&descriptors), m_width(width), m_height(height) {
    const ShaderCompiler compiler;
    m_pipeline = createComputePipeline(device, descriptors.pipelineLayout(),
                                       compiler.compileFile("wedges/shaders/dcs_center.comp", defines));
}

PassAccesses CenterCountPass::accesses(std::size_t) const {
    PassAccesses accesses;
    accesses.use(m_frame->gbuffer.triangleId, ResourceUse::storageRead(COMPUTE))
        .use(m_frame->gbuffer.position, ResourceUse::storageRead(COMPUTE))
        .use(m_wedges->center, ResourceUse::storageReadWrite(COMPUTE))
        .use(m_wedges->dcsBlocks, ResourceUse::storageReadWrite(COMPUTE))
        .use(m_descriptors->stats(), ResourceUse::storageReadWrite(COMPUTE));
    return accesses;
}

void CenterCountPass::record(VkCommandBuffer cmd, std::size_t light) const {
    m_pipeline.bind(cmd);
    m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, light);
    m_descriptors->push(cmd, GpuPush{uint(light), 0u, 0u, 0u});
    dispatchPerPixel(cmd, m_width, m_height);
}

ShaderDefine dcsRayEdgesDefine(const RenderOptions& options) {
    // A float literal of the knob's float value, as the CPU mirror compares with (9 digits: exact).
    std::array<char, 32> text{};
    std::snprintf(text.data(), text.size(), "%.9g", double(float(methodKnob(options, "ray_edges"))));
    std::string literal = text.data();
    if (literal.find_first_of(".e") == std::string::npos) literal += ".0";
    return {"DCS_RAY_EDGES", literal};
}

DcsRaysPass::DcsRaysPass(const Device& device, const RenderOptions& options, WedgeResources& wedges,
                         FrameResources& frame, const FamilyDescriptors& descriptors,
                         const std::vector<ShaderDefine>& defines, std::uint32_t stage)
    : m_wedges(&wedges), m_frame(&frame), m_descriptors(&descriptors), m_stage(stage),
      m_blocks(clusterBlocksAlong(std::uint32_t(options.width)) *
               clusterBlocksAlong(std::uint32_t(options.height))) {
    std::vector<ShaderDefine> stageDefines = defines;
    stageDefines.push_back(dcsRayEdgesDefine(options));
    stageDefines.push_back({"DCS_RAYS_STAGE", std::to_string(stage)});
    const ShaderCompiler compiler;
    m_pipeline = createComputePipeline(device, descriptors.pipelineLayout(),
                                       compiler.compileFile("wedges/shaders/dcs_rays.comp", stageDefines));
}

PassAccesses DcsRaysPass::accesses(std::size_t light) const {
    PassAccesses accesses;
    accesses.use(m_wedges->dcsBlocks, ResourceUse::storageReadWrite(COMPUTE));
    if (m_stage == 0) return accesses;
    accesses.use(m_wedges->dcsBlocks, ResourceUse::indirectRead())
        .use(m_frame->gbuffer.position, ResourceUse::storageRead(COMPUTE))
        .use(m_frame->gbuffer.triangleId, ResourceUse::storageRead(COMPUTE))
        .use(m_wedges->center, ResourceUse::storageRead(COMPUTE))
        .use(m_descriptors->stats(), ResourceUse::storageReadWrite(COMPUTE))
        .use(m_frame->samples.counters[light], ResourceUse::storageReadWrite(COMPUTE));
    return accesses;
}

void DcsRaysPass::record(VkCommandBuffer cmd, std::size_t light) const {
    m_pipeline.bind(cmd);
    m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, light);
    m_descriptors->push(cmd, GpuPush{uint(light), 0u, 0u, 0u});
    if (m_stage == 0)
        vkCmdDispatch(cmd, (m_blocks + RAY_GROUP - 1u) / RAY_GROUP, 1, 1); // a block an invocation
    else
        vkCmdDispatchIndirect(cmd, m_wedges->dcsBlocks.handle(), GPU_DCS_RAY_DISPATCH * sizeof(uint));
}

WedgePass::WedgePass(const Device& device, const RenderOptions& options, WedgeResources& wedges,
                     FrameResources& frame, const FamilyDescriptors& descriptors,
                     const std::vector<ShaderDefine>& defines, VolumeGeometry geometry,
                     const HullResources& hulls, DeferredFragments& deferred)
    : m_wedges(&wedges), m_frame(&frame), m_descriptors(&descriptors), m_device(&device),
      m_geometry(geometry), m_hulls(&hulls), m_deferred(&deferred),
      m_pw(methodInfo(options.method).wedges == WedgeVariant::Pw) {
    VkFormatProperties coverageFormat{};
    vkGetPhysicalDeviceFormatProperties(device.physicalDevice(), VCOEF_FORMAT, &coverageFormat);
    if (m_pw && !(coverageFormat.optimalTilingFeatures & VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BLEND_BIT))
        throw UsageError("Vulkan device " + device.info().name +
                         " cannot blend into R32_SFLOAT attachments (penumbra-wedge coverage)");
    const ShaderCompiler compiler;
    // The back faces of the bound behind the visible point, as the STSV pass.
    std::vector<ShaderDefine> fragmentDefines = wedgeDefines(options, defines);
    GraphicsPipelineDesc desc;
    switch (m_geometry) {
    case VolumeGeometry::ComputeHull:
        fragmentDefines.push_back({"WEDGE_HULL_PATH", "1"});
        desc = volumePipelineDesc(
            {{VK_SHADER_STAGE_VERTEX_BIT, compiler.compileFile("render/shaders/hull.vert", defines)},
             {VK_SHADER_STAGE_FRAGMENT_BIT,
              compiler.compileFile("wedges/shaders/wedge.frag", fragmentDefines)}});
        desc.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
        break;
    case VolumeGeometry::MeshShaderHull: {
        fragmentDefines.push_back({"WEDGE_MESH_PATH", "1"});
        std::vector<ShaderStage> stages = meshHullStages(device, "wedges/shaders/wedge", defines);
        stages.push_back({VK_SHADER_STAGE_FRAGMENT_BIT,
                          compiler.compileFile("wedges/shaders/wedge.frag", fragmentDefines)});
        desc = volumePipelineDesc(std::move(stages)); // no input assembly: the topology is unused
        break;
    }
    case VolumeGeometry::GeometryShaderPrism:
        desc = volumePipelineDesc(
            {{VK_SHADER_STAGE_VERTEX_BIT, compiler.compileFile("volumes/shaders/stsv.vert", defines)},
             {VK_SHADER_STAGE_GEOMETRY_BIT, compiler.compileFile("wedges/shaders/wedge.geom", defines)},
             {VK_SHADER_STAGE_FRAGMENT_BIT,
              compiler.compileFile("wedges/shaders/wedge.frag", fragmentDefines)}});
        break;
    }
    if (m_pw) {
        desc.colorFormats = {VCOEF_FORMAT};
        desc.blend = {additiveBlend()};
    }
    desc.cullMode = VK_CULL_MODE_FRONT_BIT;
    m_pipeline = createGraphicsPipeline(device, descriptors.pipelineLayout(), desc);
}

PassAccesses WedgePass::accesses(std::size_t) const {
    PassAccesses accesses;
    accesses.use(m_frame->gbuffer.position, ResourceUse::storageRead(FRAGMENT))
        .use(m_frame->gbuffer.triangleId, ResourceUse::storageRead(FRAGMENT))
        .use(m_frame->gbuffer.depth, ResourceUse::depthTest())
        .use(m_descriptors->stats(), ResourceUse::storageReadWrite(volumeStatsStages(m_geometry)));
    if (m_geometry == VolumeGeometry::ComputeHull) m_hulls->declareDrawReads(accesses);
    if (m_pw)
        accesses.use(m_frame->samples.vcoef, ResourceUse::colorAttachment());
    else
        accesses.use(m_deferred->count, ResourceUse::storageReadWrite(FRAGMENT))
            .use(m_deferred->fragments, ResourceUse::storageReadWrite(FRAGMENT));
    return accesses;
}

void WedgePass::record(VkCommandBuffer cmd, std::size_t light) const {
    std::vector<ColorTarget> targets;
    if (m_pw) targets.push_back({&m_frame->samples.vcoef, true, {}});
    beginRendering(cmd, targets, DepthTarget{&m_frame->gbuffer.depth, false, GPU_DEPTH_CLEAR, true});
    m_pipeline.bind(cmd);
    m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, light);
    m_descriptors->push(cmd, GpuPush{uint(light), 0u, 0u, 0u});
    const auto carriers = static_cast<uint32_t>(m_wedges->carrierCount());
    switch (m_geometry) {
    case VolumeGeometry::ComputeHull:
        m_hulls->recordDraw(cmd);
        break;
    case VolumeGeometry::MeshShaderHull:
        recordMeshHullDraw(*m_device, cmd, carriers);
        break;
    case VolumeGeometry::GeometryShaderPrism:
        if (carriers > 0) vkCmdDraw(cmd, carriers, 1, 0, 0);
        break;
    }
    endRendering(cmd);
}

WedgeSamplesPass::WedgeSamplesPass(const Device& device, const Scene& scene, const RenderOptions& options,
                                   WedgeResources& wedges, FrameResources& frame, DeferredFragments& deferred,
                                   const FamilyDescriptors& descriptors,
                                   const std::vector<ShaderDefine>& defines)
    : m_device(&device), m_scene(&scene), m_wedges(&wedges), m_frame(&frame), m_deferred(&deferred),
      m_descriptors(&descriptors), m_samples(options.samples),
      m_pipelines(lightTypeComputePipelines(device, descriptors.pipelineLayout(), lightTypesIn(scene),
                                            "wedges/shaders/wedge_samples.comp", defines)) {}

PassAccesses WedgeSamplesPass::accesses(std::size_t light) const {
    PassAccesses accesses;
    accesses.use(m_deferred->count, ResourceUse::storageRead(COMPUTE))
        .use(m_deferred->fragments, ResourceUse::storageRead(COMPUTE))
        .use(m_deferred->terms, ResourceUse::storageRead(COMPUTE))
        .use(m_wedges->dcsBlocks, ResourceUse::storageRead(COMPUTE))
        .use(m_frame->gbuffer.position, ResourceUse::storageRead(COMPUTE))
        .use(m_frame->gbuffer.triangleId, ResourceUse::storageRead(COMPUTE))
        .use(m_descriptors->stats(), ResourceUse::storageReadWrite(COMPUTE))
        .use(m_frame->samples.counters[light], ResourceUse::storageReadWrite(COMPUTE));
    return accesses;
}

void WedgeSamplesPass::record(VkCommandBuffer cmd, std::size_t light) const {
    m_pipelines.at(m_scene->lights.at(light).type).bind(cmd);
    m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, light);
    m_descriptors->push(cmd, GpuPush{uint(light), 0u, 0u, 0u});
    vkCmdDispatch(cmd, deferredSampleGroups(*m_device, m_deferred->capacity(), m_samples), 1, 1);
}

FoldPass::FoldPass(const Device& device, const RenderOptions& options, WedgeResources& wedges,
                   FrameResources& frame, const FamilyDescriptors& descriptors,
                   const std::vector<ShaderDefine>& defines)
    : m_wedges(&wedges), m_frame(&frame), m_descriptors(&descriptors),
      m_pw(methodInfo(options.method).wedges == WedgeVariant::Pw), m_counters(frameCountsLayers(options)),
      m_stsvDepths(m_pw && methodInfo(options.method).stsv != StsvTriangles::None &&
                   options.buffer == BufferKind::Transmittance),
      m_width(static_cast<uint32_t>(options.width)), m_height(static_cast<uint32_t>(options.height)) {
    const ShaderCompiler compiler;
    m_pipeline = createComputePipeline(
        device, descriptors.pipelineLayout(),
        compiler.compileFile("wedges/shaders/wedge_fold.comp", wedgeDefines(options, defines)));
}

PassAccesses FoldPass::accesses(std::size_t light) const {
    PassAccesses accesses;
    accesses.use(m_frame->gbuffer.triangleId, ResourceUse::storageRead(COMPUTE))
        .use(m_wedges->center, ResourceUse::storageRead(COMPUTE))
        .use(m_frame->samples.vcoef,
             m_pw ? ResourceUse::storageReadWrite(COMPUTE) : ResourceUse::storageRead(COMPUTE));
    // DCS folds into the counters; pw+stsv reads the STSV part from the light's sample buffer.
    // wedge_fold.comp declares the mask array in every variant.
    if (m_counters)
        accesses.use(m_frame->samples.counters[light],
                     m_pw ? ResourceUse::storageRead(COMPUTE) : ResourceUse::storageReadWrite(COMPUTE));
    for (std::size_t i = 0; i < GPU_MAX_MASK_IMAGES; ++i)
        accesses.use(m_frame->samples.mask(light, i), ResourceUse::storageRead(COMPUTE));
    if (m_stsvDepths) accesses.use(m_frame->samples.depths[light], ResourceUse::storageRead(COMPUTE));
    return accesses;
}

void FoldPass::record(VkCommandBuffer cmd, std::size_t light) const {
    m_pipeline.bind(cmd);
    m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, light);
    m_descriptors->push(cmd, GpuPush{uint(light), 0u, 0u, 0u});
    // wedge_fold.comp works on 16 × 16 tiles.
    dispatchPerPixel(cmd, m_width, m_height);
}

} // namespace stsv
