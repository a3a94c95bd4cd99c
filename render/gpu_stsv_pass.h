// The STSV pass of one light (DESIGN §4.2–4.4, STSV paper Algorithm 2 lines 8–10): one draw of
// the S-triangles' convex penumbra volumes; the fragments behind the visible point run the
// projective transmittance test per light sample (Eq. 1–5) into the light's sample buffer. The
// volumes are drawn as the paper's ten-vertex prisms (geometry shader, or mesh shader where the
// device has VK_EXT_mesh_shader), or as their hulls: a compute pass (StsvHullPass) clips the
// scene box by each volume's planes and the light's (volumes/clip_box_dh.h) and the draw is
// indirect.
#pragma once

#include "gpu/buffer.h"
#include "gpu/pipeline.h"
#include "render/gpu_frame_resources.h"
#include "render/gpu_pass.h"

#include <array>
#include <cstdint>
#include <vector>

namespace stsv {

/// What builds the volumes the STSV pass rasterises (ExtrusionStage, resolved for the device).
enum class StsvGeometry {
    GeometryShaderPrism, ///< stsv.vert + stsv.geom
    MeshShaderPrism,     ///< stsv.mesh
    Hull,                ///< stsv_hull.comp, then stsv_hull.vert
};

const char* toString(StsvGeometry geometry);

/// The hull pass's output, read by the draw: the indirect arguments and counts, the volumes'
/// records and the hulls' triangles. Sized at start-up by a run of the hull pass (sizeFor), so
/// a frame's exact needs; 1-element stand-ins before that and without hulls.
class StsvHullResources {
  public:
    explicit StsvHullResources(const Device& device);

    /// The bindings these resources add to the frame's descriptor set layout.
    static std::vector<DescriptorBinding> bindings();
    void writeDescriptors(DescriptorSet& set) const;
    /// Room for `volumes` records and `triangles` hull triangles (at least one of each).
    void resize(std::uint64_t volumes, std::uint64_t triangles);

    std::uint64_t volumeCapacity() const { return m_volumeCapacity; }
    std::uint64_t triangleCapacity() const { return m_triangleCapacity; }

    Buffer draw;     ///< GpuStsvDraw
    Buffer records;  ///< GpuStsvRecord[], written as storage, read as texels
    Buffer vertices; ///< uvec4 per hull vertex, written as storage, read as texels
    BufferView recordTexels;
    BufferView vertexTexels;

  private:
    const Device* m_device;
    std::uint64_t m_volumeCapacity = 0;
    std::uint64_t m_triangleCapacity = 0;
};

/// stsv_hull.comp for one light: appends the hulls of the volumes and their records
/// (StsvHullResources::draw must be zeroed before).
class StsvHullPass final : public GpuPass {
  public:
    StsvHullPass(const Device& device, const Scene& scene, const RenderOptions& options,
                 FrameResources& resources, StsvHullResources& hulls, const FrameDescriptors& descriptors);

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    FrameResources* m_resources;
    StsvHullResources* m_hulls;
    const FrameDescriptors* m_descriptors;
    bool m_perforatedOnly; ///< StsvTriangles::Perforated
    std::uint32_t m_triangleCount;
    Pipeline m_pipeline;
};

class StsvPass final : public GpuPass {
  public:
    StsvPass(const Device& device, const Scene& scene, const RenderOptions& options,
             FrameResources& resources, StsvHullResources& hulls, const FrameDescriptors& descriptors,
             StsvGeometry geometry);

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

    StsvGeometry geometry() const { return m_geometry; }

  private:
    const Device* m_device;
    const Scene* m_scene;
    FrameResources* m_resources;
    StsvHullResources* m_hulls;
    const FrameDescriptors* m_descriptors;
    StsvGeometry m_geometry;
    bool m_counters;       ///< counters buffer, else bitmask attachments
    bool m_perforatedOnly; ///< StsvTriangles::Perforated
    std::uint32_t m_triangleCount;
    std::array<Pipeline, 4> m_pipelines; ///< per light type (LIGHT_*) the scene has
};

} // namespace stsv
