// The cluster walk of the volume families on Vulkan (DESIGN §4.5; render/shaders/cluster_walk.glsl):
// a tree over a family's occluders, built on the CPU and uploaded as texel tables, walked per
// 16 × 16 tile of pixels down to the leaves, then per 4 × 4 block, level by level over lists of
// pairs; the family's pixel stages then list
// the (pixel, item) pairs its sample pass reads, in place of drawing volumes. DCS walks each
// light's potential silhouettes (gpu_wedge_clusters.h), STSV the balls of its triangles
// (gpu_stsv_clusters.h); both share the frame's lists, one pass after the other.
#pragma once

#include "gpu/buffer.h"
#include "gpu/descriptors.h"
#include "gpu/pass_recorder.h"
#include "gpu/pipeline.h"
#include "render/options.h"
#include "render/vulkan/gpu_deferred.h"
#include "render/vulkan/gpu_frame_resources.h"
#include "render/vulkan/gpu_pass.h"
#include "render/vulkan/gpu_volumes_dh.h"

#include "gpu/vulkan.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace stsv {

class Device;

/// A tree's texel tables (GPU_BINDING_CLUSTER_NODES, _ITEMS): GPU_CLUSTER_TEXELS rgba32ui per node
/// and per item.
struct ClusterTables {
    Buffer nodes, items;
    BufferView nodeTexels, itemTexels;
    /// Levels of the tree (a lone root: 1; none: 0).
    std::size_t depth = 0;
};
/// Uploads a tree's tables (fewer texels than a node: no tree); an Error when it is deeper than
/// the walk takes.
ClusterTables uploadClusterTables(const Device& device, std::vector<uvec4> nodes, std::vector<uvec4> items,
                                  std::size_t depth, const std::string& source);
/// An rgba32ui texel buffer of `texels` (one zero texel when empty).
void uploadTexels(const Device& device, std::vector<uvec4> texels, Buffer& buffer, BufferView& view);
/// A vec4's bits as a texel of a table.
uvec4 texelBits(vec4 v);
/// Levels of the subtree at `index` of a tree whose nodes are leaves (`count` > 0) or have their
/// children at `first` and first + 1.
template <class Node> std::size_t treeDepth(const std::vector<Node>& nodes, std::uint32_t index) {
    const Node& node = nodes[index];
    if (node.count > 0) return 1;
    return 1 + std::max(treeDepth(nodes, node.first), treeDepth(nodes, node.first + 1));
}

/// The frame's lists of the walk (GPU_BINDING_CLUSTER_COUNTS, _PAIRS, _BLOCKS, _DISPATCH): 1-element
/// stand-ins until a family uses them.
class ClusterLists {
  public:
    /// `listLimit`: the pairs a list holds at most (0: what a storage buffer binding addresses).
    ClusterLists(const Device& device, const RenderOptions& options, std::uint64_t listLimit);

    /// The bindings of the lists and the tables in a volume family's set.
    static std::vector<DescriptorBinding> bindings();
    /// The lists and `tables` (stand-ins when null) into a family's set.
    void writeDescriptors(DescriptorSet& set, const ClusterTables* tables) const;
    /// A family walks: the lists get room for 64 pairs a block. The descriptors must be written after.
    void use();

    /// After a frame whose lists needed `needed` pairs (the most of any light's and part's, 0
    /// when every list held its pairs): grows them to twice that, or past what a storage buffer
    /// holds takes the tiles in more parts (past one 16 × 16 tile a part, tiles of one 4 × 4
    /// block), and returns true, and the caller renders the frame again (the descriptors must be
    /// written again). An Error when one block needs more than a list holds.
    bool growFor(std::uint64_t needed);
    /// After a frame whose walk listed `listed` (pixel, item) pairs for the sample passes in its
    /// worst part, more than the `limit` the deferred list holds: takes the tiles in more parts
    /// (each part's pairs are sampled before the next part lists its own), and the caller renders
    /// the frame again. An Error when one 4 × 4 block lists more.
    void splitFor(std::uint64_t listed, std::uint64_t limit);
    /// Whether a family walks in this frame.
    bool used() const { return m_used; }
    std::uint64_t capacity() const { return m_capacity; }
    /// Parts of the frame's tiles (row by row) the walk takes one after the other (1 unless a list
    /// needed more than a storage buffer holds, or the sample list more than it holds).
    std::uint32_t parts() const { return m_parts; }
    /// A tile's side in 4 × 4 blocks: 4, or 1 once one 16 × 16 tile a part was still too much for
    /// a list.
    std::uint32_t tileBlocks() const { return m_tileBlocks; }
    std::uint32_t tileCount() const {
        return ((m_blocksAcross + m_tileBlocks - 1) / m_tileBlocks) *
               ((m_blocksDown + m_tileBlocks - 1) / m_tileBlocks);
    }

    Buffer listCounts; ///< GPU_CLUSTER_COUNT_SLOTS uints
    Buffer pairs;      ///< GPU_CLUSTER_LISTS lists of capacity() uvec2 each
    Buffer blocks;     ///< two vec4 (lo, hi) per 4 × 4 block of the frame, then per 16 × 16 tile
    Buffer dispatch;   ///< the indirect dispatch of the next pass (3 uints)

  private:
    void resize(std::uint64_t capacity);
    /// More parts, so that the worst one's `needed` entries of a list holding `limit` shrink
    /// about as its share of the tiles, with twice the room; `what` names the list for the
    /// error, with `advice`, when the parts are single blocks already.
    void split(std::uint64_t needed, std::uint64_t limit, const std::string& what, const std::string& advice);

    const Device* m_device;
    ClusterTables m_empty; ///< the stand-ins
    std::uint64_t m_capacity = 0;
    std::uint64_t m_maxCapacity = 0; ///< what a storage buffer binding of the lists may address
    std::uint32_t m_blockCount = 1;
    std::uint32_t m_blocksAcross = 1;
    std::uint32_t m_blocksDown = 1;
    std::uint32_t m_tileBlocks = 4;
    std::uint32_t m_parts = 1;
    bool m_used = false;
};

/// A family's walk (its shader's CLUSTER_STAGE 0 … stages − 1; render/shaders/cluster_walk.glsl): the
/// tiles' and blocks' boxes, a dispatch per level of the walk, then the family's stages over the
/// kept pairs (3) and over the candidates (4, where it has one), each sized from its list by the
/// args stage. The last stage lists (pixel, item) pairs in the deferred list.
class ClusterWalkPasses {
  public:
    /// `reads`: the family's buffers its stages after the blocks' read (texels or storage),
    /// which earlier passes of the frame write.
    ClusterWalkPasses(const Device& device, const std::string& shader, std::uint32_t stages,
                      FrameResources& frame, DeferredFragments& deferred, ClusterLists& lists,
                      const FamilyDescriptors& descriptors, const std::vector<ShaderDefine>& defines,
                      std::vector<std::pair<const Buffer*, ResourceUse>> reads = {});

    /// Light `light`'s passes over a tree `depth` levels deep, part by part, each part's inside
    /// the timer scope `scope`, then `samples` over the pairs the part listed, in the scope
    /// `samplesScope` (the scopes of a name add up); the deferred list's count is cleared between
    /// parts (the caller clears it before the first).
    void record(PassRecorder& recorder, VkCommandBuffer cmd, std::size_t light, std::size_t depth,
                const std::string& scope, const GpuPass& samples, const std::string& samplesScope) const;

  private:
    /// One dispatch of a stage (CLUSTER_STAGE) at a step (GpuPush::step; the boxes' stage: the
    /// part's first tile, `end` its end).
    class Stage final : public GpuPass {
      public:
        Stage(const ClusterWalkPasses& passes, std::uint32_t stage, std::uint32_t step, std::uint32_t end = 0)
            : m_passes(&passes), m_stage(stage), m_step(step), m_end(end) {}
        PassAccesses accesses(std::size_t light) const override;
        void record(VkCommandBuffer cmd, std::size_t light) const override;

      private:
        const ClusterWalkPasses* m_passes;
        std::uint32_t m_stage;
        std::uint32_t m_step;
        std::uint32_t m_end;
    };

    FrameResources* m_frame;
    DeferredFragments* m_deferred;
    ClusterLists* m_lists;
    const FamilyDescriptors* m_descriptors;
    std::vector<std::pair<const Buffer*, ResourceUse>> m_reads;
    std::vector<Pipeline> m_pipelines; ///< per stage
};

} // namespace stsv
