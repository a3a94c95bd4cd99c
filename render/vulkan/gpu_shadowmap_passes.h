// The Vulkan passes of the image-based methods (DESIGN §4.6), per light: the light-space map
// rasterised into a buffer (shadowmap.vert/frag, one instance per face), then PCF or PCSS's
// blocker search and filter into the v_coef image (shadow_filter.comp), which the resolve
// reads as v_coef.
#pragma once

#include "gpu/buffer.h"
#include "gpu/descriptors.h"
#include "gpu/pipeline.h"
#include "render/options.h"
#include "render/vulkan/gpu_frame_resources.h"
#include "render/vulkan/gpu_pass.h"
#include "render/vulkan/gpu_shadowmaps_dh.h"
#include "scene/scene.h"
#include "shadowmaps/depth_grid.h"
#include "shadowmaps/shadow_map.h"

#include "gpu/vulkan.h"

#include <cstddef>
#include <vector>

namespace stsv {

class Device;

/// Each light's map buffer, the views and filter knobs, the taps (a scene with lights; only a
/// frame with the shadow-map technique has them).
class ShadowMapResources {
  public:
    ShadowMapResources(const Device& device, const Scene& scene, const RenderOptions& options);

    /// The bindings of the shadow-map family's set (gpu_shadowmaps_dh.h).
    static std::vector<DescriptorBinding> bindings();
    /// Light `light`'s map, the views and the taps into its family set.
    void writeDescriptors(DescriptorSet& set, std::size_t light) const;

    /// Light `light`'s map as the last frame left it (call after the frame's submit has finished).
    ShadowMap download(std::size_t light) const;
    /// Light `light`'s depth grid (`peel`) as the last frame left it.
    DepthGrid downloadGrid(std::size_t light) const;
    const ShadowMapSettings& settings() const { return m_settings; }
    const ShadowMapView& view(std::size_t light) const { return m_views.at(light); }

    std::vector<Buffer> depth; ///< [light]: gpuShadowDepthWord per texel, faces × size²
    /// [light], filtered rows only: filteredMapBytes of planes, read and written by device
    /// address (ShadowMapView::filteredLow/High)
    std::vector<Buffer> filtered;
    /// [light], `peel` only: depthGridBytes of grid words, read and written by device address
    /// (ShadowMapView::filteredLow/High)
    std::vector<Buffer> grid;
    Buffer views; ///< ShadowFilterParams, then ShadowMapView per light
    Buffer taps;  ///< vec2: blocker taps, then filter taps

  private:
    ShadowMapSettings m_settings;
    std::vector<ShadowMapView> m_views;
};

/// The map of one light: every triangle drawn once per face, alpha-tested, nearest depth per
/// texel centre by atomicMax into the light's (cleared) map buffer.
class ShadowMapPass final : public GpuPass {
  public:
    ShadowMapPass(const Device& device, const Scene& scene, ShadowMapResources& maps,
                  const FamilyDescriptors& descriptors, const std::vector<ShaderDefine>& defines);

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    ShadowMapResources* m_maps;
    const FamilyDescriptors* m_descriptors;
    std::uint32_t m_triangleCount;
    Pipeline m_pipeline;
};

/// A light's filtered representation from its map (filtered_map.comp): summed-area rows then
/// columns, or mip level 0 then each level from the one below, with the barriers between them.
class FilteredMapPass final : public GpuPass {
  public:
    FilteredMapPass(const Device& device, ShadowMapResources& maps, const FamilyDescriptors& descriptors,
                    const std::vector<ShaderDefine>& defines);

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    ShadowMapResources* m_maps;
    const FamilyDescriptors* m_descriptors;
    bool m_mip;
    std::uint32_t m_channels;
    std::vector<Pipeline> m_steps; ///< rows, columns; or level 0, the levels above
};

/// `peel`'s depth grid of one light (depth_grid.frag, drawn as the map is): the depth range of
/// each texel, then the subintervals' farthest front and back faces, into the light's cleared grid.
class DepthGridPass final : public GpuPass {
  public:
    DepthGridPass(const Device& device, const Scene& scene, ShadowMapResources& maps,
                  const FamilyDescriptors& descriptors, const std::vector<ShaderDefine>& defines);

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    ShadowMapResources* m_maps;
    const FamilyDescriptors* m_descriptors;
    std::uint32_t m_triangleCount;
    Pipeline m_range;
    Pipeline m_bins;
};

/// `peel`'s march (peel_march.comp): every covered pixel's light-sample rays through the light's
/// grid into its bitmask images (or counters).
class PeelMarchPass final : public GpuPass {
  public:
    PeelMarchPass(const Device& device, const RenderOptions& options, ShadowMapResources& maps,
                  FrameResources& frame, const FamilyDescriptors& descriptors,
                  const std::vector<ShaderDefine>& defines);

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    ShadowMapResources* m_maps;
    FrameResources* m_frame;
    const FamilyDescriptors* m_descriptors;
    bool m_counters;
    uint32_t m_width, m_height;
    Pipeline m_pipeline;
};

/// One filter step per pixel into the v_coef image: PCF, PCSS's blocker search (the kernel
/// radius), PCSS's filter (v_coef), or a filtered representation's lookup (v_coef).
class ShadowFilterPass final : public GpuPass {
  public:
    enum Step { Pcf = 0, PcssBlocker = 1, PcssFilter = 2, FilteredLookup = 3 };

    ShadowFilterPass(const Device& device, const RenderOptions& options, Step step, ShadowMapResources& maps,
                     FrameResources& frame, const FamilyDescriptors& descriptors,
                     const std::vector<ShaderDefine>& defines);

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    ShadowMapResources* m_maps;
    FrameResources* m_frame;
    const FamilyDescriptors* m_descriptors;
    Step m_step;
    uint32_t m_width, m_height;
    Pipeline m_pipeline;
};

} // namespace stsv
