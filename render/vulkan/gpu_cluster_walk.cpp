#include "render/vulkan/gpu_cluster_walk.h"

#include "core/error.h"
#include "gpu/device.h"
#include "gpu/shader_compiler.h"
#include "wedges/edge_cluster_dh.h"

#include <algorithm>
#include <bit>
#include <span>
#include <string>

namespace stsv {

namespace {

constexpr VkPipelineStageFlags2 COMPUTE = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;

} // namespace

void uploadTexels(const Device& device, std::vector<uvec4> texels, Buffer& buffer, BufferView& view) {
    if (texels.empty()) texels.push_back(uvec4(0u));
    buffer = createBuffer(device, std::span<const uvec4>(texels), VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT);
    view = BufferView(device, buffer, VK_FORMAT_R32G32B32A32_UINT, 16);
}

uvec4 texelBits(vec4 v) {
    return uvec4(std::bit_cast<uint>(v.x), std::bit_cast<uint>(v.y), std::bit_cast<uint>(v.z),
                 std::bit_cast<uint>(v.w));
}

ClusterTables uploadClusterTables(const Device& device, std::vector<uvec4> nodes, std::vector<uvec4> items,
                                  std::size_t depth, const std::string& source) {
    // The walk takes a level more than the tree has: the tiles' leaves go to their blocks.
    if (depth + 1 >= GPU_CLUSTER_MAX_DEPTH)
        throw UsageError("the cluster tree of " + source + " is " + std::to_string(depth) +
                         " levels deep, more than the cluster passes take (" +
                         std::to_string(GPU_CLUSTER_MAX_DEPTH - 2) + "); use --extrusion hull");
    ClusterTables tables;
    uploadTexels(device, std::move(nodes), tables.nodes, tables.nodeTexels);
    uploadTexels(device, std::move(items), tables.items, tables.itemTexels);
    tables.depth = depth;
    return tables;
}

ClusterLists::ClusterLists(const Device& device, const RenderOptions& options, std::uint64_t listLimit)
    : m_device(&device) {
    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    listCounts = Buffer(device, GPU_CLUSTER_COUNT_SLOTS * sizeof(uint), storage, MemoryUsage::DeviceLocal);
    dispatch = Buffer(device, 4 * sizeof(uint), storage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                      MemoryUsage::DeviceLocal);
    m_blocksAcross = clusterBlocksAlong(std::uint32_t(options.width));
    m_blocksDown = clusterBlocksAlong(std::uint32_t(options.height));
    m_blockCount = m_blocksAcross * m_blocksDown;
    blocks = Buffer(device, 2 * sizeof(vec4), storage, MemoryUsage::DeviceLocal);
    // One buffer holds the lists: each at most what a storage buffer binding may address.
    m_maxCapacity =
        std::min<std::uint64_t>(MAX_DEFERRED_FRAGMENTS, device.limits().maxStorageBufferRange /
                                                            (GPU_CLUSTER_LISTS * 2 * sizeof(uint)));
    if (listLimit > 0) m_maxCapacity = std::min(m_maxCapacity, listLimit);
    resize(1);
    uploadTexels(device, {}, m_empty.nodes, m_empty.nodeTexels);
    uploadTexels(device, {}, m_empty.items, m_empty.itemTexels);
}

void ClusterLists::use() {
    if (m_used) return;
    m_used = true;
    // The blocks' boxes, then the tiles' (at most one a block).
    blocks = Buffer(*m_device, std::uint64_t(m_blockCount) * 4 * sizeof(vec4),
                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUsage::DeviceLocal);
    // Room for 64 pairs a block to start with (the 184 k-triangle knot needs 840 DCS candidates
    // a block at 256², the 11.5 k one 75); a frame that needs more grows the lists, or walks the
    // tiles in parts. Each growth renders the frame again, and a short list shortens the ones
    // after it, so the lists grow to twice what the frame asked for.
    resize(std::min(std::max<std::uint64_t>(std::uint64_t(m_blockCount) * 64, 4096), m_maxCapacity));
}

void ClusterLists::resize(std::uint64_t capacity) {
    m_capacity = capacity;
    pairs = Buffer(*m_device, GPU_CLUSTER_LISTS * capacity * 2 * sizeof(uint),
                   VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUsage::DeviceLocal);
}

bool ClusterLists::growFor(std::uint64_t needed) {
    if (needed <= m_capacity) return false;
    if (needed <= m_maxCapacity) {
        resize(std::min(2 * needed, m_maxCapacity));
        return true;
    }
    // More than a list can hold: the walk takes the tiles in more parts, each with the lists
    // to itself.
    split(needed, m_maxCapacity,
          "pairs in one list, more than the " + std::to_string(m_maxCapacity) + " a storage buffer holds",
          "use --extrusion hull");
    if (m_capacity < m_maxCapacity) resize(m_maxCapacity);
    return true;
}

void ClusterLists::splitFor(std::uint64_t listed, std::uint64_t limit) {
    split(listed, limit,
          "fragments for the sample passes, more than the " + std::to_string(limit) + " their list holds",
          "the scene is too dense for the walk's sample list");
}

void ClusterLists::split(std::uint64_t needed, std::uint64_t limit, const std::string& what,
                         const std::string& advice) {
    // Past one 16 × 16 tile a part, 4 × 4 tiles (a block each).
    if (m_parts >= tileCount()) {
        if (m_tileBlocks == 1)
            throw Error("the cluster walk lists " + std::to_string(needed) + " " + what +
                        ", for one 4x4 block; " + advice);
        m_tileBlocks = 1; // the same parts, each now a row of blocks as long as its tiles were
    }
    // The worst part's list shrinks about as its share of the tiles (twice the room).
    const std::uint64_t wanted = std::uint64_t(m_parts) * 2 * needed / limit + 1;
    m_parts = static_cast<std::uint32_t>(
        std::min<std::uint64_t>(tileCount(), std::max<std::uint64_t>(wanted, m_parts + 1)));
}

std::vector<DescriptorBinding> ClusterLists::bindings() {
    const VkDescriptorType texels = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    const VkDescriptorType storage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    return {{GPU_BINDING_CLUSTER_COUNTS, storage, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_CLUSTER_PAIRS, storage, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_CLUSTER_BLOCKS, storage, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_CLUSTER_DISPATCH, storage, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_CLUSTER_NODES, texels, VK_SHADER_STAGE_ALL, 1},
            {GPU_BINDING_CLUSTER_ITEMS, texels, VK_SHADER_STAGE_ALL, 1}};
}

void ClusterLists::writeDescriptors(DescriptorSet& set, const ClusterTables* tables) const {
    const ClusterTables& t = tables ? *tables : m_empty;
    set.writeBuffer(GPU_BINDING_CLUSTER_COUNTS, listCounts);
    set.writeBuffer(GPU_BINDING_CLUSTER_PAIRS, pairs);
    set.writeBuffer(GPU_BINDING_CLUSTER_BLOCKS, blocks);
    set.writeBuffer(GPU_BINDING_CLUSTER_DISPATCH, dispatch);
    set.writeTexelBuffer(GPU_BINDING_CLUSTER_NODES, t.nodeTexels.handle());
    set.writeTexelBuffer(GPU_BINDING_CLUSTER_ITEMS, t.itemTexels.handle());
}

ClusterWalkPasses::ClusterWalkPasses(const Device& device, const std::string& shader, std::uint32_t stages,
                                     FrameResources& frame, DeferredFragments& deferred, ClusterLists& lists,
                                     const FamilyDescriptors& descriptors,
                                     const std::vector<ShaderDefine>& defines,
                                     std::vector<std::pair<const Buffer*, ResourceUse>> reads)
    : m_frame(&frame), m_deferred(&deferred), m_lists(&lists), m_descriptors(&descriptors),
      m_reads(std::move(reads)) {
    const ShaderCompiler compiler;
    for (std::uint32_t stage = 0; stage < stages; ++stage) {
        std::vector<ShaderDefine> stageDefines = defines;
        stageDefines.push_back({"CLUSTER_STAGE", std::to_string(stage)});
        m_pipelines.push_back(createComputePipeline(device, descriptors.pipelineLayout(),
                                                    compiler.compileFile(shader, stageDefines)));
    }
}

void ClusterWalkPasses::record(PassRecorder& recorder, VkCommandBuffer cmd, std::size_t light,
                               std::size_t depth, const std::string& scope, const GpuPass& samples,
                               const std::string& samplesScope) const {
    const ClearPass clearCounts({}, {&m_lists->listCounts});
    const ClearPass clearListed({}, {&m_deferred->count});
    const std::uint32_t parts = m_lists->parts();
    const auto stages = static_cast<std::uint32_t>(m_pipelines.size());
    const std::uint32_t tiles = m_lists->tileCount();
    for (std::uint32_t part = 0; part < parts; ++part) {
        // Tiles [first, end), row by row, with the lists to themselves.
        const auto first = static_cast<std::uint32_t>(std::uint64_t(tiles) * part / parts);
        const auto end = static_cast<std::uint32_t>(std::uint64_t(tiles) * (part + 1) / parts);
        if (first == end) continue;
        // Each part's pairs are sampled before the next part lists its own.
        if (part > 0) runPass(recorder, cmd, "", clearListed, light);
        recorder.beginScope(cmd, scope);
        runPass(recorder, cmd, "", clearCounts, light);
        runPass(recorder, cmd, "", Stage(*this, 0, first, end), light);
        // A level more than the tree has: the tiles' leaves go to their blocks (a family that
        // tests a tile's leaf with its blocks at once, CLUSTER_KEEP_TILE_BLOCKS, lists none there).
        for (std::uint32_t level = 0; level < (depth > 0 ? depth + 1 : 0); ++level) {
            runPass(recorder, cmd, "", Stage(*this, 1, level), light);
            runPass(recorder, cmd, "", Stage(*this, 2, level), light);
        }
        // The family's stages over the kept pairs (3: STSV's volume tests, DCS's pixels), then
        // over the candidates (4: STSV's pixels, DCS's other tests).
        for (std::uint32_t stage = 3; stage < stages; ++stage) {
            runPass(recorder, cmd, "",
                    Stage(*this, 1, stage == 3 ? GPU_CLUSTER_KEPT : GPU_CLUSTER_CANDIDATES), light);
            runPass(recorder, cmd, "", Stage(*this, stage, 0), light);
        }
        recorder.endScope(cmd);
        runPass(recorder, cmd, samplesScope, samples, light);
    }
}

PassAccesses ClusterWalkPasses::Stage::accesses(std::size_t) const {
    const ClusterWalkPasses& p = *m_passes;
    const ClusterLists& c = *p.m_lists;
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
    if (m_stage != 0) {
        accesses.use(c.dispatch, ResourceUse::indirectRead());
        for (const auto& [buffer, use] : p.m_reads) accesses.use(*buffer, use);
    }
    if (m_stage != 2)
        accesses.use(p.m_frame->gbuffer.position, ResourceUse::storageRead(COMPUTE))
            .use(p.m_frame->gbuffer.triangleId, ResourceUse::storageRead(COMPUTE));
    // Every stage that appends can write the deferred list (render/shaders/cluster_walk.glsl groupFlush),
    // though only the last one does.
    if (m_stage >= 2)
        accesses.use(p.m_deferred->count, ResourceUse::storageReadWrite(COMPUTE))
            .use(p.m_deferred->fragments, ResourceUse::storageReadWrite(COMPUTE))
            .use(p.m_deferred->terms, ResourceUse::storageReadWrite(COMPUTE));
    return accesses;
}

void ClusterWalkPasses::Stage::record(VkCommandBuffer cmd, std::size_t light) const {
    const ClusterWalkPasses& p = *m_passes;
    p.m_pipelines[m_stage].bind(cmd);
    p.m_descriptors->bind(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, light);
    p.m_descriptors->push(cmd, GpuPush{uint(light), m_end, p.m_lists->tileBlocks(), m_step});
    if (m_stage == 0) // 64 tiles a workgroup, whatever its size
        vkCmdDispatch(cmd, (m_end - m_step + 63) / 64, 1, 1);
    else if (m_stage == 1)
        vkCmdDispatch(cmd, 1, 1, 1);
    else
        vkCmdDispatchIndirect(cmd, p.m_lists->dispatch.handle(), 0);
}

} // namespace stsv
