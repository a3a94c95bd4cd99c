// The STSV pass of one light (DESIGN §4.2–4.4, STSV paper Algorithm 2 lines 8–10): one draw of
// the S-triangles, each extruded into its convex penumbra volume (geometry shader, or mesh shader
// where the device has VK_EXT_mesh_shader); the fragments behind the visible point run the
// projective transmittance test per light sample (Eq. 1–5) into the light's sample buffer.
#pragma once

#include "gpu/pipeline.h"
#include "render/gpu_frame_resources.h"
#include "render/gpu_pass.h"

#include <array>
#include <cstdint>
#include <vector>

namespace stsv {

class StsvPass final : public GpuPass {
  public:
    /// `meshShader`: extrude in stsv.mesh instead of stsv.vert + stsv.geom.
    StsvPass(const Device& device, const Scene& scene, const RenderOptions& options,
             FrameResources& resources, const FrameDescriptors& descriptors, bool meshShader);

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    const Device* m_device;
    const Scene* m_scene;
    FrameResources* m_resources;
    const FrameDescriptors* m_descriptors;
    bool m_mesh;
    bool m_counters;       ///< counters buffer, else bitmask attachments
    bool m_perforatedOnly; ///< StsvTriangles::Perforated
    std::uint32_t m_triangleCount;
    std::array<Pipeline, 4> m_pipelines; ///< per light type (LIGHT_*) the scene has
};

} // namespace stsv
