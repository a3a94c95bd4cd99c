// The resolve of one light (STSV paper Algorithm 2 line 14; DESIGN §4.4): v_coef = visible
// samples / N (or the v_coef image of a visibility-only method) and Monte-Carlo direct lighting, accumulated
// into the colour and visibility images (render/shaders/resolve.comp). The first light's dispatch writes the
// ambient term (or the background) first; a scene without lights gets that dispatch alone.
#pragma once

#include "gpu/pipeline.h"
#include "render/vulkan/gpu_frame_resources.h"
#include "render/vulkan/gpu_pass.h"
#include "sampling/pattern.h"

#include <array>
#include <cstddef>
#include <cstdint>

namespace stsv {

class ResolvePass final : public GpuPass {
  public:
    /// The `light` of the ambient-only dispatch of a scene without lights.
    static constexpr std::size_t AMBIENT_ONLY = SIZE_MAX;

    ResolvePass(const Device& device, const Scene& scene, const RenderOptions& options,
                const SamplePlan& plan, FrameResources& resources, const FrameDescriptors& descriptors);

    /// Its set (GPU_SET_FAMILY): the colour and visibility images it alone writes.
    void writeDescriptors();

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    const Scene* m_scene;
    FrameResources* m_resources;
    FamilyDescriptors m_set;
    bool m_counters;     ///< counters buffer only, else bitmask images
    bool m_countsLayers; ///< counters too (frameCountsLayers)
    bool m_vcoef;        ///< MethodOutput::Visibility: v_coef from the v_coef image
    bool m_depths;       ///< each sample weighed by its optical depth (transmittance, not v_coef)
    uint32_t m_width, m_height;
    /// Per light type (LIGHT_*) the scene has; [0] also for the ambient-only dispatch.
    std::array<Pipeline, 4> m_pipelines;
};

} // namespace stsv
