// The STSV pass of one light (DESIGN §4.2–4.4, STSV paper Algorithm 2 lines 8–10): one draw of
// the S-triangles' convex penumbra volumes; the fragments behind the visible point run the
// projective transmittance test per light sample (Eq. 1–5) into the light's sample buffer. The
// volumes are drawn as the paper's ten-vertex prisms (geometry shader, or mesh shader where the
// device has VK_EXT_mesh_shader), or as their hulls (render/vulkan/gpu_hulls.h, stsv_hull.comp).
#pragma once

#include "gpu/pipeline.h"
#include "render/vulkan/gpu_deferred.h"
#include "render/vulkan/gpu_frame_resources.h"
#include "render/vulkan/gpu_hulls.h"
#include "render/vulkan/gpu_pass.h"
#include "volumes/vulkan/gpu_stsv_dh.h"

#include <array>
#include <cstdint>
#include <vector>

namespace stsv {

/// stsv_samples.comp for one light: the deferred fragments' samples, into the mask words or the
/// counters.
class StsvSamplesPass final : public GpuPass {
  public:
    StsvSamplesPass(const Device& device, const Scene& scene, const RenderOptions& options,
                    FrameResources& resources, HullResources& hulls, DeferredFragments& deferred,
                    const FamilyDescriptors& descriptors);

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    const Scene* m_scene;
    FrameResources* m_resources;
    HullResources* m_hulls;
    DeferredFragments* m_deferred;
    const FamilyDescriptors* m_descriptors;
    bool m_counters;
    bool m_transmittance; ///< translucent triangles add optical depths
    const Device* m_device;
    int m_samples;
    std::array<Pipeline, 4> m_pipelines; ///< per light type (LIGHT_*) the scene has
};

/// stsv_merge.comp for one light of a bitmask frame: the mask words ORed into its images.
class StsvMergePass final : public GpuPass {
  public:
    StsvMergePass(const Device& device, const RenderOptions& options, FrameResources& resources,
                  DeferredFragments& deferred, const FamilyDescriptors& descriptors);

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    FrameResources* m_resources;
    DeferredFragments* m_deferred;
    const FamilyDescriptors* m_descriptors;
    std::uint32_t m_width;
    std::uint32_t m_height;
    Pipeline m_pipeline;
};

class StsvPass final : public GpuPass {
  public:
    /// With hulls, `deferred` receives the fragments whose samples StsvSamplesPass tests.
    StsvPass(const Device& device, const Scene& scene, const RenderOptions& options,
             FrameResources& resources, HullResources& hulls, DeferredFragments& deferred,
             const FamilyDescriptors& descriptors, VolumeGeometry geometry);

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    const Device* m_device;
    const Scene* m_scene;
    FrameResources* m_resources;
    HullResources* m_hulls;
    DeferredFragments* m_deferred;
    const FamilyDescriptors* m_descriptors;
    VolumeGeometry m_geometry;
    bool m_counters;       ///< counters buffer, else bitmask attachments
    bool m_transmittance;  ///< translucent triangles add optical depths
    bool m_perforatedOnly; ///< StsvTriangles::Perforated
    std::uint32_t m_triangleCount;
    std::array<Pipeline, 4> m_pipelines; ///< per light type (LIGHT_*) the scene has
};

} // namespace stsv
