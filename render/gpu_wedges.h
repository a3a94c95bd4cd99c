// The Vulkan passes of the opaque occluders (issue 4, DESIGN §4.5, STSV paper Algorithm 2):
// per light, the z-fail counting shadow volume at the light centre (dcs_center.*), the wedge
// pass over the potential silhouette edges (wedge.*; DCS counters or PW coverage) and the fold
// that combines them (wedge_fold.comp). Owned by VulkanRenderer, which provides the descriptor
// set (render/gpu_frame_dh.h bindings), the G-buffer depth and the light-sample buffers.
#pragma once

#include "gpu/buffer.h"
#include "gpu/descriptors.h"
#include "gpu/image.h"
#include "gpu/pipeline.h"
#include "gpu/shader_compiler.h"
#include "gpu/timer.h"
#include "render/gpu_frame_dh.h"
#include "render/options.h"
#include "scene/scene.h"

#include <vulkan/vulkan.h>

#include <cstddef>
#include <string>
#include <vector>

namespace stsv {

class Device;

/// The welded edges of the opaque triangles (wedges/adjacency.h) as the GPU reads them: edge
/// endpoints, incident faces with their third vertices, and the carrier face whose STSV volume
/// bounds the edge's wedge (the first non-degenerate face, as render/cpu_wedges.cpp).
struct GpuEdgeTables {
    std::vector<GpuEdge> edges;
    std::vector<GpuEdgeFace> faces;
};

GpuEdgeTables buildGpuEdgeTables(const Scene& scene);

class GpuWedgePasses {
  public:
    GpuWedgePasses() = default;
    /// Uploads the edge tables (for a wedge method) and builds the pipelines; otherwise only
    /// the 1×1 stand-ins that the shared descriptor set needs.
    GpuWedgePasses(const Device& device, const Scene& scene, const RenderOptions& options,
                   const PipelineLayout& layout, const std::vector<ShaderDefine>& defines);

    /// The bindings these passes add to the frame's descriptor set layout.
    static std::vector<DescriptorBinding> bindings();
    void writeDescriptors(DescriptorSet& set) const;

    bool enabled() const { return m_enabled; }
    std::size_t edgeCount() const { return m_edgeCount; }

    /// Records, for light `light` (its set bound by the caller with `layout`'s push constants
    /// set): clear, centre count, wedge pass. `depth` is the G-buffer depth (read only).
    /// GPU timer scopes `prefix`center and `prefix`wedges (per-pass timings in the stats).
    void recordOcclusion(VkCommandBuffer cmd, Image& depth, uint32_t triangleCount, GpuTimer& timer,
                         const std::string& prefix);
    /// Records the fold (after the STSV pass of the perforated triangles, before the resolve).
    void recordFold(VkCommandBuffer cmd);
    /// Puts the images in GENERAL once per frame (before the first pass that uses them).
    void prepare(VkCommandBuffer cmd);

  private:
    bool m_enabled = false;
    bool m_pw = false;
    std::size_t m_edgeCount = 0;
    uint32_t m_width = 0, m_height = 0;
    Buffer m_edges, m_faces;
    Image m_center, m_coverage;
    Pipeline m_centerPipeline, m_wedgePipeline, m_foldPipeline;
};

} // namespace stsv
