// DCS through the cluster tree on Vulkan (DESIGN §4.5): each light's potential silhouettes,
// their tree and their carriers' bounds, built on the CPU when the renderer starts
// (wedges/silhouette_edges.h, the tables the CPU mirror walks) and uploaded as texel buffers; and
// the compute pass that walks them per screen tile and adds each silhouette edge's crossings to
// the light's counters (shaders/wedges/dcs_clusters.comp). It takes the place of the wedge hulls,
// their draw and the listed fragments' samples.
#pragma once

#include "gpu/buffer.h"
#include "gpu/descriptors.h"
#include "gpu/pipeline.h"
#include "render/options.h"
#include "render/vulkan/gpu_frame_resources.h"
#include "render/vulkan/gpu_pass.h"
#include "scene/scene.h"
#include "wedges/adjacency.h"

#include "gpu/vulkan.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace stsv {

class Device;

/// Whether a frame's opaque occluders take the cluster pass: DCS with the extrusion stage left to
/// the renderer (--extrusion auto). PW sums float coverage and keeps its wedge draw.
bool usesWedgeClusters(const RenderOptions& options);

/// Per light, the tables of dcs_clusters.comp (gpu_wedges_dh.h GPU_BINDING_CLUSTER_*); 1-texel
/// stand-ins for a light without potential silhouettes, or for every light when not `build`.
class WedgeClusterTables {
  public:
    WedgeClusterTables(const Device& device, const Scene& scene, const EdgeAdjacency& adjacency,
                       const std::vector<std::uint32_t>& carriers, bool build);

    static std::vector<DescriptorBinding> bindings();
    /// Light `light`'s tables into its set (a set past the lights gets the stand-ins).
    void writeDescriptors(DescriptorSet& set, std::size_t light) const;

    /// What one light's tables hold.
    struct Counts {
        std::size_t potentialSilhouettes = 0; ///< potential silhouette edges of the light
        std::size_t edges = 0;                ///< of those, with a carrier: the tree's items
        std::size_t leaves = 0;
        std::size_t nodes = 0;
        std::size_t carriers = 0; ///< bounds
        std::size_t depth = 0;    ///< of the tree (a lone root: 1)
    };
    /// Per light; empty when not built.
    const std::vector<Counts>& counts() const { return m_counts; }

  private:
    struct Tables {
        Buffer nodes, items, bounds;
        BufferView nodeTexels, itemTexels, boundTexels;
    };
    Tables m_empty; ///< the stand-ins
    std::vector<Tables> m_lights;
    std::vector<Counts> m_counts;
};

/// DCS's silhouette edges per screen tile through the cluster tree (dcs_clusters.comp), into the
/// light's counters; wedge_fold.comp adds D(r) after it.
class DcsClusterPass final : public GpuPass {
  public:
    DcsClusterPass(const Device& device, const RenderOptions& options, FrameResources& frame,
                   const FamilyDescriptors& descriptors, const std::vector<ShaderDefine>& defines);

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    FrameResources* m_frame;
    const FamilyDescriptors* m_descriptors;
    Pipeline m_pipeline;
    std::uint32_t m_width;
    std::uint32_t m_height;
};

} // namespace stsv
