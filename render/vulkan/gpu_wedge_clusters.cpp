#include "render/vulkan/gpu_wedge_clusters.h"

#include "core/error.h"
#include "core/parallel.h"
#include "gpu/device.h"
#include "gpu/shader_compiler.h"
#include "render/methods.h"
#include "render/vulkan/gpu_deferred.h"
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

WedgeClusters::WedgeClusters(const Device& device, const Scene& scene, const RenderOptions& options,
                             const EdgeAdjacency& adj, const std::vector<std::uint32_t>& carriers, bool build,
                             std::uint64_t listLimit)
    : m_device(&device) {
    const VkBufferUsageFlags usage = VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT;
    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    listCounts = Buffer(device, GPU_CLUSTER_COUNT_SLOTS * sizeof(uint), storage, MemoryUsage::DeviceLocal);
    dispatch = Buffer(device, 4 * sizeof(uint), storage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                      MemoryUsage::DeviceLocal);
    m_blockCount = static_cast<std::uint32_t>(((options.width + 3) / 4) * ((options.height + 3) / 4));
    const std::uint64_t blockCount = build ? m_blockCount : 1;
    blocks = Buffer(device, blockCount * sizeof(vec4), storage, MemoryUsage::DeviceLocal);
    // One buffer holds the lists: each at most what a storage buffer binding may address.
    m_maxCapacity =
        std::min<std::uint64_t>(kMaxDeferredFragments, device.limits().maxStorageBufferRange /
                                                           (GPU_CLUSTER_LISTS * 2 * sizeof(uint)));
    if (listLimit > 0) m_maxCapacity = std::min(m_maxCapacity, listLimit);
    // Room for 64 pairs a block to start with (the 184 k-triangle knot needs 840 candidates a
    // block at 256², the 11.5 k one 75); a frame that needs more grows the lists, or walks the
    // blocks in parts. Each growth renders the frame again, and a short list shortens the ones
    // after it, so the lists grow to twice what the frame asked for.
    resize(build ? std::min(std::max<std::uint64_t>(blockCount * 64, 4096), m_maxCapacity) : 1);
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
        counts.leaves = tree.leaves;
        counts.carriers = sil.carrierCount();
        counts.depth = tree.nodes.empty() ? 0 : treeDepth(tree, 0);
        if (counts.depth >= GPU_CLUSTER_MAX_DEPTH)
            throw UsageError("the cluster tree of " + scene.source + " is " + std::to_string(counts.depth) +
                             " levels deep, more than the cluster passes take (" +
                             std::to_string(GPU_CLUSTER_MAX_DEPTH - 1) + "); use --extrusion hull");
        std::vector<uvec4> nodes;
        nodes.reserve(tree.nodes.size() * GPU_CLUSTER_TEXELS);
        for (const EdgeClusterNode& node : tree.nodes) {
            nodes.push_back(bitsOf(node.ball));
            nodes.push_back(bitsOf(node.cone));
            nodes.push_back(uvec4(node.first, node.count, std::bit_cast<uint>(node.inverseNormal),
                                  std::bit_cast<uint>(node.faceReach)));
        }
        std::vector<uvec4> items(tree.items.size() * GPU_CLUSTER_TEXELS);
        parallelForChunks(tree.items.size(), [&](std::size_t begin, std::size_t end) {
            for (std::size_t k = begin; k < end; ++k) {
                const std::uint32_t item = tree.items[k];
                const EdgeClusterNode own = edgeCluster(adj, sil.edge(item), sil.carrierNormal(item));
                uvec4* t = items.data() + k * GPU_CLUSTER_TEXELS;
                t[0] = bitsOf(own.ball);
                t[1] = bitsOf(own.cone);
                t[2] = uvec4(sil.edge(item), sil.carrier(item), std::bit_cast<uint>(own.inverseNormal),
                             std::bit_cast<uint>(own.faceReach));
            }
        });
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

void WedgeClusters::resize(std::uint64_t capacity) {
    m_capacity = capacity;
    pairs = Buffer(*m_device, GPU_CLUSTER_LISTS * capacity * 2 * sizeof(uint),
                   VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUsage::DeviceLocal);
}

bool WedgeClusters::growFor(std::uint64_t needed) {
    if (needed <= m_capacity) return false;
    if (needed <= m_maxCapacity) {
        resize(std::min(2 * needed, m_maxCapacity));
        return true;
    }
    // More than a list can hold: the walk takes the blocks in more parts, each with the lists
    // to itself.
    if (m_parts >= m_blockCount)
        throw Error("the cluster walk needs " + std::to_string(needed) + " pairs in one list for one 4x4 " +
                    "block, more than the " + std::to_string(m_maxCapacity) +
                    " a storage buffer holds; use --extrusion hull");
    // The worst part's list shrinks about as its share of the blocks (twice the room).
    const std::uint64_t wanted = std::uint64_t(m_parts) * 2 * needed / m_maxCapacity + 1;
    m_parts = static_cast<std::uint32_t>(
        std::min<std::uint64_t>(m_blockCount, std::max<std::uint64_t>(wanted, m_parts + 1)));
    if (m_capacity < m_maxCapacity) resize(m_maxCapacity);
    return true;
}

std::vector<DescriptorBinding> WedgeClusters::bindings() {
    const VkDescriptorType texels = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    const VkDescriptorType storage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    return {{GPU_BINDING_CLUSTER_NODES, texels, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_CLUSTER_ITEMS, texels, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_CLUSTER_BOUNDS, texels, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_CLUSTER_COUNTS, storage, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_CLUSTER_PAIRS, storage, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_CLUSTER_BLOCKS, storage, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_CLUSTER_DISPATCH, storage, VK_SHADER_STAGE_ALL, 1}};
}

void WedgeClusters::writeDescriptors(DescriptorSet& set, std::size_t light) const {
    const Tables& t = light < m_lights.size() ? m_lights[light] : m_empty;
    set.writeTexelBuffer(GPU_BINDING_CLUSTER_NODES, t.nodeTexels.handle());
    set.writeTexelBuffer(GPU_BINDING_CLUSTER_ITEMS, t.itemTexels.handle());
    set.writeTexelBuffer(GPU_BINDING_CLUSTER_BOUNDS, t.boundTexels.handle());
    set.writeBuffer(GPU_BINDING_CLUSTER_COUNTS, listCounts);
    set.writeBuffer(GPU_BINDING_CLUSTER_PAIRS, pairs);
    set.writeBuffer(GPU_BINDING_CLUSTER_BLOCKS, blocks);
    set.writeBuffer(GPU_BINDING_CLUSTER_DISPATCH, dispatch);
}

DcsClusterPasses::DcsClusterPasses(const Device& device, const RenderOptions& options, FrameResources& frame,
                                   DeferredFragments& deferred, WedgeClusters& clusters,
                                   const FamilyDescriptors& descriptors,
                                   const std::vector<ShaderDefine>& defines)
    : m_frame(&frame), m_deferred(&deferred), m_clusters(&clusters), m_descriptors(&descriptors),
      m_blocksAcross(static_cast<std::uint32_t>((options.width + 3) / 4)),
      m_blocksDown(static_cast<std::uint32_t>((options.height + 3) / 4)) {
    const ShaderCompiler compiler;
    for (std::uint32_t stage = 0; stage < 5; ++stage) {
        std::vector<ShaderDefine> stageDefines = defines;
        stageDefines.push_back({"DCS_CLUSTER_STAGE", std::to_string(stage)});
        m_pipelines[stage] =
            createComputePipeline(device, descriptors.pipelineLayout(),
                                  compiler.compileFile("wedges/dcs_clusters.comp", stageDefines));
    }
}

void DcsClusterPasses::record(PassRecorder& recorder, VkCommandBuffer cmd, std::size_t light,
                              const std::string& scope) const {
    const std::size_t depth = light < m_clusters->counts().size() ? m_clusters->counts()[light].depth : 0;
    const ClearPass clearCounts({}, {&m_clusters->listCounts});
    const std::uint32_t parts = m_clusters->parts();
    const std::uint32_t blocks = m_blocksAcross * m_blocksDown;
    recorder.beginScope(cmd, scope);
    for (std::uint32_t part = 0; part < parts; ++part) {
        // Blocks [first, end), row by row, with the lists to themselves.
        const auto first = static_cast<std::uint32_t>(std::uint64_t(blocks) * part / parts);
        const auto end = static_cast<std::uint32_t>(std::uint64_t(blocks) * (part + 1) / parts);
        if (first == end) continue;
        runPass(recorder, cmd, "", clearCounts, light);
        runPass(recorder, cmd, "", Stage(*this, 0, first, end), light);
        for (std::uint32_t level = 0; level < depth; ++level) {
            runPass(recorder, cmd, "", Stage(*this, 1, level), light);
            runPass(recorder, cmd, "", Stage(*this, 2, level), light);
        }
        runPass(recorder, cmd, "", Stage(*this, 1, GPU_CLUSTER_KEPT), light);
        runPass(recorder, cmd, "", Stage(*this, 3, 0), light);
        runPass(recorder, cmd, "", Stage(*this, 1, GPU_CLUSTER_CANDIDATES), light);
        runPass(recorder, cmd, "", Stage(*this, 4, 0), light);
    }
    recorder.endScope(cmd);
}

PassAccesses DcsClusterPasses::Stage::accesses(std::size_t) const {
    const DcsClusterPasses& p = *m_passes;
    const WedgeClusters& c = *p.m_clusters;
    PassAccesses accesses;
    if (m_stage == 1) {
        accesses.use(c.listCounts, ResourceUse::storageRead(COMPUTE))
            .use(c.dispatch, ResourceUse::storageReadWrite(COMPUTE));
        return accesses;
    }
    accesses.use(c.listCounts, ResourceUse::storageReadWrite(COMPUTE))
        .use(c.pairs, ResourceUse::storageReadWrite(COMPUTE))
        .use(c.blocks, ResourceUse::storageReadWrite(COMPUTE))
        .use(p.m_descriptors->stats(), ResourceUse::storageReadWrite(COMPUTE));
    if (m_stage != 0) accesses.use(c.dispatch, ResourceUse::indirectRead());
    if (m_stage != 2)
        accesses.use(p.m_frame->gbuffer.position, ResourceUse::storageRead(COMPUTE))
            .use(p.m_frame->gbuffer.triangleId, ResourceUse::storageRead(COMPUTE));
    if (m_stage == 4)
        accesses.use(p.m_deferred->count, ResourceUse::storageReadWrite(COMPUTE))
            .use(p.m_deferred->fragments, ResourceUse::storageReadWrite(COMPUTE));
    return accesses;
}

void DcsClusterPasses::Stage::record(VkCommandBuffer cmd, std::size_t light) const {
    const DcsClusterPasses& p = *m_passes;
    p.m_pipelines[m_stage].bind(cmd);
    p.m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, light);
    p.m_descriptors->push(cmd, GpuPush{uint(light), m_end, 0u, m_step});
    if (m_stage == 0)
        vkCmdDispatch(cmd, (m_end - m_step + 63) / 64, 1, 1);
    else if (m_stage == 1)
        vkCmdDispatch(cmd, 1, 1, 1);
    else
        vkCmdDispatchIndirect(cmd, p.m_clusters->dispatch.handle(), 0);
}

} // namespace stsv
