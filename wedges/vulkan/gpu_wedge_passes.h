// The Vulkan passes of the wedge family (the opaque occluders) (DESIGN §4.5, STSV paper Algorithm 2 lines 4–7
// and 11), per light: the layer count at the light centre (dcs_center.comp), the wedge pass over the
// potential silhouette edges (wedge.*; DCS counters or PW coverage) and, after the STSV pass of the
// perforated triangles, the fold that combines them (wedge_fold.comp).
#pragma once

#include "gpu/buffer.h"
#include "gpu/descriptors.h"
#include "gpu/image.h"
#include "gpu/pipeline.h"
#include "render/options.h"
#include "render/vulkan/gpu_deferred.h"
#include "render/vulkan/gpu_frame_resources.h"
#include "render/vulkan/gpu_hulls.h"
#include "render/vulkan/gpu_pass.h"
#include "scene/scene.h"
#include "wedges/adjacency.h"
#include "wedges/vulkan/gpu_wedge_clusters.h"
#include "wedges/vulkan/gpu_wedges_dh.h"

#include "gpu/vulkan.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace stsv {

class Device;

/// The welded edges of the opaque triangles (wedges/adjacency.h) as the GPU reads them: edge
/// endpoints, incident faces with their third vertices, and the carrier face whose STSV volume
/// bounds the edge's wedge (the first non-degenerate face, as wedges/cpu/cpu_wedges.cpp). The
/// carriers, each with the edges it carries (at most its three, GPU_NO_EDGE in the free slots),
/// are what the wedge passes draw: one bound for all of a face's edges.
struct GpuEdgeTables {
    std::vector<GpuEdge> edges;
    std::vector<GpuEdgeFace> faces;
    std::vector<uvec4> carriers; ///< triangle, edges
};

GpuEdgeTables buildGpuEdgeTables(const Scene& scene);
/// The tables of an adjacency and its edges' carriers (edgeCarriers).
GpuEdgeTables buildGpuEdgeTables(const EdgeAdjacency& adjacency, const std::vector<std::uint32_t>& carriers);

/// What the wedge passes share: the edge tables (uploaded once; 1-element stand-ins for a scene
/// without opaque edges), for the cluster pass each light's silhouette tables, and the
/// centre-count image. Only a frame with the wedge technique has them.
class WedgeResources {
  public:
    WedgeResources(const Device& device, const Scene& scene, const RenderOptions& options);

    /// The bindings these resources add to the wedge family's set (gpu_wedges_dh.h).
    static std::vector<DescriptorBinding> bindings();
    /// Into light `light`'s set, with the frame's cluster lists.
    void writeDescriptors(DescriptorSet& set, std::size_t light, const ClusterLists& lists) const;

    std::size_t edgeCount() const { return m_edgeCount; }
    /// Nodes of the tree D(r) is counted through (0: no opaque triangle).
    std::uint32_t layerNodeCount() const { return m_layerNodeCount; }
    WedgeClusters& clusters() { return *m_clusters; }
    const WedgeClusters& clusters() const { return *m_clusters; }
    std::size_t carrierCount() const { return m_carrierCount; }

    Buffer edges;    ///< GpuEdge[], read as storage and as texels
    Buffer faces;    ///< GpuEdgeFace[], read as storage and as texels
    Buffer carriers; ///< uvec4[]: triangle, carried edges, read as texels
    BufferView edgeTexels;
    BufferView faceTexels;
    BufferView carrierTexels;
    Image center;          ///< r32i layer count D(r) at the light centre
    Buffer dcsBlocks;      ///< DCS's choice per block of the walk (GPU_BINDING_DCS_BLOCKS)
    Buffer layerNodes;     ///< the tree's nodes (wedges/layer_bvh_dh.h), read as texels
    Buffer layerTriangles; ///< its triangles, read as texels
    BufferView layerNodeTexels;
    BufferView layerTriangleTexels;

  private:
    std::size_t m_edgeCount = 0;
    std::size_t m_carrierCount = 0;
    std::uint32_t m_layerNodeCount = 0;
    EdgeAdjacency m_adjacency;
    std::vector<std::uint32_t> m_carriers;
    std::optional<WedgeClusters> m_clusters;
};

/// D(r) into `center`: per pixel, the opaque triangles the segment from its visible point to the
/// light centre crosses, counted through the tree of wedges/layer_bvh.h (dcs_center.comp).
class CenterCountPass final : public GpuPass {
  public:
    CenterCountPass(const Device& device, WedgeResources& wedges, FrameResources& frame,
                    const FamilyDescriptors& descriptors, const std::vector<ShaderDefine>& defines,
                    std::uint32_t width, std::uint32_t height);

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    WedgeResources* m_wedges;
    FrameResources* m_frame;
    const FamilyDescriptors* m_descriptors;
    std::uint32_t m_width, m_height;
    Pipeline m_pipeline;
};

/// DCS's blocks that cast rays (dcs_rays.comp), after the walk has added up each block's kept
/// edges: stage 0 lists the blocks whose edges exceed the ray_edges knob per sample
/// (dcsBlockCastsRays) and sets the indirect dispatch of stage 1, which counts each of their
/// (pixel, sample) segments through the layer tree into the light's counters.
class DcsRaysPass final : public GpuPass {
  public:
    DcsRaysPass(const Device& device, const RenderOptions& options, WedgeResources& wedges,
                FrameResources& frame, const FamilyDescriptors& descriptors,
                const std::vector<ShaderDefine>& defines, std::uint32_t stage);

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    WedgeResources* m_wedges;
    FrameResources* m_frame;
    const FamilyDescriptors* m_descriptors;
    std::uint32_t m_stage;
    std::uint32_t m_blocks; ///< of the frame
    Pipeline m_pipeline;
};

/// The define that carries the ray_edges knob of a DCS frame into its shaders (DCS_RAY_EDGES).
ShaderDefine dcsRayEdgesDefine(const RenderOptions& options);

/// Per potential silhouette edge, the wedge bounded by its carrier's STSV volume and light
/// planes: DCS lists the fragments with the edge a silhouette seen from p in `deferred` (for
/// WedgeSamplesPass), PW adds the analytic wedge coverage to the v_coef image (an attachment here, summing
/// the terms). The bounds are drawn as the carrier's prism (wedge.geom), as the hulls of wedge_hull.comp
/// from `hulls` (render/vulkan/gpu_hulls.h), or as the hulls wedge.task and wedge.mesh emit.
class WedgePass final : public GpuPass {
  public:
    WedgePass(const Device& device, const RenderOptions& options, WedgeResources& wedges,
              FrameResources& frame, const FamilyDescriptors& descriptors,
              const std::vector<ShaderDefine>& defines, VolumeGeometry geometry, const HullResources& hulls,
              DeferredFragments& deferred);

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    WedgeResources* m_wedges;
    FrameResources* m_frame;
    const FamilyDescriptors* m_descriptors;
    const Device* m_device;
    VolumeGeometry m_geometry;
    const HullResources* m_hulls; ///< read by the draw of ComputeHull
    DeferredFragments* m_deferred;
    bool m_pw;
    Pipeline m_pipeline;
};

/// DCS after WedgePass: wedge_samples.comp runs the edge term and the sample loop of every listed
/// fragment, adding the crossings to the light's counters; it also stores how many fragments the
/// draw tried to list (GpuWedgeStats::listed), so that the host can grow a list that was short.
class WedgeSamplesPass final : public GpuPass {
  public:
    /// One pipeline per light type of the scene (FIXED_LIGHT_TYPE): the sample loop's domain map
    /// folds at compile time.
    /// Reads `wedges.dcsBlocks`: the pairs of a block that casts rays add nothing.
    WedgeSamplesPass(const Device& device, const Scene& scene, const RenderOptions& options,
                     WedgeResources& wedges, FrameResources& frame, DeferredFragments& deferred,
                     const FamilyDescriptors& descriptors, const std::vector<ShaderDefine>& defines);

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    const Device* m_device;
    const Scene* m_scene;
    WedgeResources* m_wedges;
    FrameResources* m_frame;
    DeferredFragments* m_deferred;
    const FamilyDescriptors* m_descriptors;
    int m_samples;
    std::array<Pipeline, 4> m_pipelines; ///< per light type
};

/// D(r) plus the wedge terms: DCS counters D(x) = D(r) + Σ crossings (+ STSV increments), or
/// the PW v_coef in the v_coef image (minus the STSV occluded fraction for pw+stsv).
class FoldPass final : public GpuPass {
  public:
    FoldPass(const Device& device, const RenderOptions& options, WedgeResources& wedges,
             FrameResources& frame, const FamilyDescriptors& descriptors,
             const std::vector<ShaderDefine>& defines);

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    WedgeResources* m_wedges;
    FrameResources* m_frame;
    const FamilyDescriptors* m_descriptors;
    bool m_pw;
    bool m_counters;   ///< the frame counts layers (frameCountsLayers)
    bool m_stsvDepths; ///< pw+stsv with transmittance: the STSV samples' optical depths
    uint32_t m_width, m_height;
    Pipeline m_pipeline;
};

} // namespace stsv
