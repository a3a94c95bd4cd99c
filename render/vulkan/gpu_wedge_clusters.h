// DCS through the cluster tree on Vulkan (DESIGN §4.5): each light's potential silhouettes,
// their tree and their carriers' bounds, built on the CPU when the renderer starts
// (wedges/silhouette_edges.h, the tables the CPU mirror walks) and uploaded as texel buffers; the
// lists of the walk; and its passes (shaders/wedges/dcs_clusters.comp), which list the (pixel,
// edge) pairs that add to the light's counters for wedge_samples.comp. They take the place of the
// wedge hulls and their draw.
#pragma once

#include "gpu/buffer.h"
#include "gpu/descriptors.h"
#include "gpu/pass_recorder.h"
#include "gpu/pipeline.h"
#include "render/options.h"
#include "render/vulkan/gpu_deferred.h"
#include "render/vulkan/gpu_frame_resources.h"
#include "render/vulkan/gpu_pass.h"
#include "scene/scene.h"
#include "wedges/adjacency.h"

#include "gpu/vulkan.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace stsv {

class Device;

/// Whether a frame's opaque occluders take the cluster passes: DCS with the extrusion stage left to
/// the renderer (--extrusion auto). PW sums float coverage and keeps its wedge draw.
bool usesWedgeClusters(const RenderOptions& options);

/// Per light, the tables of dcs_clusters.comp (gpu_wedges_dh.h GPU_BINDING_CLUSTER_*), and the
/// frame's lists of its walk; 1-element stand-ins for a light without potential silhouettes, or
/// for everything when not `build`.
class WedgeClusters {
  public:
    /// `listLimit`: the pairs a list holds at most (0: what a storage buffer binding addresses).
    WedgeClusters(const Device& device, const Scene& scene, const RenderOptions& options,
                  const EdgeAdjacency& adjacency, const std::vector<std::uint32_t>& carriers, bool build,
                  std::uint64_t listLimit = 0);

    static std::vector<DescriptorBinding> bindings();
    /// Light `light`'s tables and the lists into its set (a set past the lights gets the
    /// stand-in tables).
    void writeDescriptors(DescriptorSet& set, std::size_t light) const;

    /// What one light's tables hold.
    struct Counts {
        std::size_t potentialSilhouettes = 0; ///< potential silhouette edges of the light
        std::size_t leaves = 0;
        std::size_t carriers = 0; ///< bounds
        std::size_t depth = 0;    ///< levels of the tree (a lone root: 1; none: 0)
    };
    /// Per light; empty when not built.
    const std::vector<Counts>& counts() const { return m_counts; }

    /// After a frame whose lists needed `needed` pairs (the most of any light's and band's, 0
    /// when every list held its pairs): grows them to twice that, or past what a
    /// storage buffer holds takes the blocks in more parts, and returns true, and the caller
    /// renders the frame again (the descriptors must be written again). An Error when one block
    /// needs more than a list holds.
    bool growFor(std::uint64_t needed);
    std::uint64_t capacity() const { return m_capacity; }
    /// Parts of the frame's 4 × 4 blocks (row by row) the walk takes one after the other (1
    /// unless a list needed more than a storage buffer holds).
    std::uint32_t parts() const { return m_parts; }

    Buffer listCounts; ///< GPU_CLUSTER_COUNT_SLOTS uints
    Buffer pairs;      ///< GPU_CLUSTER_LISTS lists of capacity() uvec2 each
    Buffer blocks;     ///< vec4 per 4 × 4 block of the frame
    Buffer dispatch;   ///< the indirect dispatch of the next pass (3 uints)

  private:
    struct Tables {
        Buffer nodes, items, bounds;
        BufferView nodeTexels, itemTexels, boundTexels;
    };
    void resize(std::uint64_t capacity);

    const Device* m_device;
    Tables m_empty; ///< the stand-ins
    std::vector<Tables> m_lights;
    std::vector<Counts> m_counts;
    std::uint64_t m_capacity = 0;
    std::uint64_t m_maxCapacity = 0; ///< what a storage buffer binding of the lists may address
    std::uint32_t m_blockCount = 1;
    std::uint32_t m_parts = 1;
};

/// DCS's silhouette edges per 4 × 4 block of pixels through the cluster tree (dcs_clusters.comp):
/// the blocks' balls, a dispatch per level of the walk, the pixels of the kept (block, edge)
/// pairs, then the candidates among them, which list the (pixel, edge) pairs for
/// wedge_samples.comp.
class DcsClusterPasses {
  public:
    DcsClusterPasses(const Device& device, const RenderOptions& options, FrameResources& frame,
                     DeferredFragments& deferred, WedgeClusters& clusters,
                     const FamilyDescriptors& descriptors, const std::vector<ShaderDefine>& defines);

    /// Light `light`'s passes inside the timer scope `scope`; the lists' counts must be cleared.
    void record(PassRecorder& recorder, VkCommandBuffer cmd, std::size_t light,
                const std::string& scope) const;

  private:
    /// One dispatch of a stage (DCS_CLUSTER_STAGE) at a step (GpuPush::step; the blocks stage:
    /// the part's first block, `end` its end).
    class Stage final : public GpuPass {
      public:
        Stage(const DcsClusterPasses& passes, std::uint32_t stage, std::uint32_t step, std::uint32_t end = 0)
            : m_passes(&passes), m_stage(stage), m_step(step), m_end(end) {}
        PassAccesses accesses(std::size_t light) const override;
        void record(VkCommandBuffer cmd, std::size_t light) const override;

      private:
        const DcsClusterPasses* m_passes;
        std::uint32_t m_stage;
        std::uint32_t m_step;
        std::uint32_t m_end;
    };

    FrameResources* m_frame;
    DeferredFragments* m_deferred;
    WedgeClusters* m_clusters;
    const FamilyDescriptors* m_descriptors;
    Pipeline m_pipelines[5]; ///< per stage
    std::uint32_t m_blocksAcross;
    std::uint32_t m_blocksDown;
};

} // namespace stsv
