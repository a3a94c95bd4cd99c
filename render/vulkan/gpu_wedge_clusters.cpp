#include "render/vulkan/gpu_wedge_clusters.h"

#include "core/error.h"
#include "core/parallel.h"
#include "gpu/shader_compiler.h"
#include "render/methods.h"
#include "render/vulkan/gpu_wedges_dh.h"
#include "sampling/light_bounds.h"
#include "wedges/silhouette_edges.h"

#include <algorithm>
#include <bit>
#include <span>
#include <string>

namespace stsv {

namespace {

constexpr VkPipelineStageFlags2 COMPUTE = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;

uvec4 bitsOf(vec4 v) {
    return uvec4(std::bit_cast<uint>(v.x), std::bit_cast<uint>(v.y), std::bit_cast<uint>(v.z),
                 std::bit_cast<uint>(v.w));
}

/// Levels of the subtree at `index` (nodes' children at first and first + 1).
std::size_t treeDepth(const EdgeClusterTree& tree, std::uint32_t index) {
    const EdgeClusterNode& node = tree.nodes[index];
    if (node.count > 0) return 1;
    return 1 + std::max(treeDepth(tree, node.first), treeDepth(tree, node.first + 1));
}

} // namespace

bool usesWedgeClusters(const RenderOptions& options) {
    return methodInfo(options.method).opaque == OpaqueTechnique::Dcs &&
           options.extrusion == ExtrusionStage::Auto;
}

WedgeClusterTables::WedgeClusterTables(const Device& device, const Scene& scene, const EdgeAdjacency& adj,
                                       const std::vector<std::uint32_t>& carriers, bool build) {
    const VkBufferUsageFlags usage = VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT;
    const auto upload = [&](std::vector<uvec4> texels, Buffer& buffer, BufferView& view) {
        if (texels.empty()) texels.push_back(uvec4(0u)); // fewer texels than a node: no tree
        buffer = createBuffer(device, std::span<const uvec4>(texels), usage);
        view = BufferView(device, buffer, VK_FORMAT_R32G32B32A32_UINT, 16);
    };
    upload({}, m_empty.nodes, m_empty.nodeTexels);
    upload({}, m_empty.items, m_empty.itemTexels);
    upload({}, m_empty.bounds, m_empty.boundTexels);
    if (!build) return;
    const float farDistance = farDistanceFor(scene.bounds());
    for (const Light& light : scene.lights) {
        const SilhouetteEdges sil(scene, adj, carriers, light, farDistance);
        const EdgeClusterTree& tree = sil.tree();
        Counts counts;
        counts.potentialSilhouettes = sil.potentialCount();
        counts.edges = tree.items.size();
        counts.leaves = tree.leaves;
        counts.nodes = tree.nodes.size();
        counts.carriers = sil.carrierCount();
        counts.depth = tree.nodes.empty() ? 0 : treeDepth(tree, 0);
        // The walk's stack holds one node per level and the second child of each above.
        if (counts.depth >= GPU_CLUSTER_STACK)
            throw UsageError("the cluster tree of " + scene.source + " is " + std::to_string(counts.depth) +
                             " levels deep, more than the cluster pass's stack holds (" +
                             std::to_string(GPU_CLUSTER_STACK - 1) + "); use --extrusion hull");
        std::vector<uvec4> nodes;
        nodes.reserve(tree.nodes.size() * GPU_CLUSTER_NODE_TEXELS);
        for (const EdgeClusterNode& node : tree.nodes) {
            nodes.push_back(bitsOf(node.ball));
            nodes.push_back(bitsOf(node.cone));
            nodes.push_back(uvec4(node.first, node.count, std::bit_cast<uint>(node.inverseNormal),
                                  std::bit_cast<uint>(node.faceReach)));
        }
        std::vector<uvec4> items(tree.items.size());
        for (std::size_t k = 0; k < items.size(); ++k)
            items[k] = uvec4(sil.edge(tree.items[k]), sil.carrier(tree.items[k]), 0u, 0u);
        std::vector<uvec4> bounds(sil.carrierCount() * GPU_CLUSTER_BOUND_TEXELS);
        parallelForChunks(sil.carrierCount(), [&](std::size_t begin, std::size_t end) {
            for (std::size_t c = begin; c < end; ++c) {
                const FaceBound& b = sil.carrierBound(std::uint32_t(c));
                uvec4* t = bounds.data() + c * GPU_CLUSTER_BOUND_TEXELS;
                t[0] = uvec4(b.volumeCount, b.volumeCount > 0 ? b.volumes[0].planeCount : 0u,
                             b.volumeCount > 1 ? b.volumes[1].planeCount : 0u, b.lightPlanes.count);
                for (uint v = 0; v < 2; ++v)
                    for (uint i = 0; i < STSV_VOLUME_MAX_PLANES; ++i)
                        t[1 + v * STSV_VOLUME_MAX_PLANES + i] =
                            v < b.volumeCount ? bitsOf(b.volumes[v].planes[i]) : uvec4(0u);
                for (uint i = 0; i < STSV_LIGHT_PLANES_MAX; ++i)
                    t[1 + 2 * STSV_VOLUME_MAX_PLANES + i] = bitsOf(b.lightPlanes.planes[i]);
            }
        });
        Tables tables;
        upload(std::move(nodes), tables.nodes, tables.nodeTexels);
        upload(std::move(items), tables.items, tables.itemTexels);
        upload(std::move(bounds), tables.bounds, tables.boundTexels);
        m_lights.push_back(std::move(tables));
        m_counts.push_back(counts);
    }
}

std::vector<DescriptorBinding> WedgeClusterTables::bindings() {
    const VkDescriptorType texels = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    return {{GPU_BINDING_CLUSTER_NODES, texels, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_CLUSTER_ITEMS, texels, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_CLUSTER_BOUNDS, texels, VK_SHADER_STAGE_ALL, 1}};
}

void WedgeClusterTables::writeDescriptors(DescriptorSet& set, std::size_t light) const {
    const Tables& t = light < m_lights.size() ? m_lights[light] : m_empty;
    set.writeTexelBuffer(GPU_BINDING_CLUSTER_NODES, t.nodeTexels.handle());
    set.writeTexelBuffer(GPU_BINDING_CLUSTER_ITEMS, t.itemTexels.handle());
    set.writeTexelBuffer(GPU_BINDING_CLUSTER_BOUNDS, t.boundTexels.handle());
}

DcsClusterPass::DcsClusterPass(const Device& device, const RenderOptions& options, FrameResources& frame,
                               const FamilyDescriptors& descriptors, const std::vector<ShaderDefine>& defines)
    : m_frame(&frame), m_descriptors(&descriptors), m_width(static_cast<std::uint32_t>(options.width)),
      m_height(static_cast<std::uint32_t>(options.height)) {
    m_pipeline = createComputePipeline(device, descriptors.pipelineLayout(),
                                       ShaderCompiler().compileFile("wedges/dcs_clusters.comp", defines));
}

PassAccesses DcsClusterPass::accesses(std::size_t light) const {
    PassAccesses accesses;
    accesses.use(m_frame->gbuffer.position, ResourceUse::storageRead(COMPUTE))
        .use(m_frame->gbuffer.triangleId, ResourceUse::storageRead(COMPUTE))
        .use(m_descriptors->stats(), ResourceUse::storageReadWrite(COMPUTE))
        .use(m_frame->samples.counters[light], ResourceUse::storageReadWrite(COMPUTE));
    return accesses;
}

void DcsClusterPass::record(VkCommandBuffer cmd, std::size_t light) const {
    m_pipeline.bind(cmd);
    m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, light);
    m_descriptors->push(cmd, GpuPush{uint(light), 0u, 0u, 0u});
    // dcs_clusters.comp works on 16 × 16 tiles.
    dispatchPerPixel(cmd, m_width, m_height);
}

} // namespace stsv
