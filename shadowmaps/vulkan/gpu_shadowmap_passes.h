// The Vulkan passes of the image-based methods (DESIGN §4.6), per light: the light-space map
// rasterised into a buffer (shadowmap.vert/frag, one instance per face), then PCF or PCSS's
// blocker search and filter into the v_coef image (shadow_filter.comp), which the resolve
// reads as v_coef; or the filtered representations built from the map, `peel`'s depth grid and
// march, and the transmittance functions of `avsm` and `vpcss` from per-texel fragment lists.
#pragma once

#include "gpu/buffer.h"
#include "gpu/descriptors.h"
#include "gpu/pipeline.h"
#include "render/options.h"
#include "render/vulkan/gpu_frame_resources.h"
#include "render/vulkan/gpu_pass.h"
#include "scene/scene.h"
#include "shadowmaps/avsm.h"
#include "shadowmaps/depth_grid.h"
#include "shadowmaps/shadow_map.h"
#include "shadowmaps/vulkan/gpu_shadowmaps_dh.h"

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

    /// The bindings of the shadow-map family's set for a row's filter (gpu_shadowmaps_dh.h).
    static std::vector<DescriptorBinding> bindings(ShadowMapMethod filter);
    /// Light `light`'s map, the views and the taps into its family set.
    void writeDescriptors(DescriptorSet& set, std::size_t light) const;

    /// Light `light`'s map as the last frame left it (call after the frame's submit has finished).
    ShadowMap download(std::size_t light) const;
    /// Light `light`'s depth grid (`peel`) as the last frame left it.
    DepthGrid downloadGrid(std::size_t light) const;
    /// Light `light`'s transmittance functions (`avsm`, `vpcss`) as the last frame left them.
    AvsmMap downloadAvsm(std::size_t light) const;
    /// The fragments the lists hold (`avsm`, `vpcss`).
    std::uint64_t avsmCapacity() const { return m_avsmCapacity; }
    /// After a frame whose fragment passes listed `listed` fragments (for one light, at most):
    /// when the lists had less room, fragments were lost, so they grow to what the frame needed
    /// (a quarter more) and the caller renders the frame again (true; the descriptors must be
    /// written again). A UsageError past what the device can bind.
    bool growAvsmFragments(std::uint64_t listed);
    const ShadowMapSettings& settings() const { return m_settings; }
    const ShadowMapView& view(std::size_t light) const { return m_views.at(light); }

    /// [light]: gpuShadowDepthWord per texel, faces × size²; a stand-in for rows that do not read it
    std::vector<Buffer> depth;
    /// [light], filtered rows only: filteredMapBytes of planes, read and written by device
    /// address (ShadowMapView::representationLow/High)
    std::vector<Buffer> filtered;
    /// [light], `peel` only: depthGridBytes of grid words, read and written by device address
    /// (ShadowMapView::representationLow/High)
    std::vector<Buffer> grid;
    /// [light], `avsm` and `vpcss`: the transmittance functions (avsmBytes; gpuAvsmNodeWord),
    /// built by avsm_build.comp, read by device address (ShadowMapView::representationLow/High)
    std::vector<Buffer> avsm;
    std::vector<Buffer> avsmHeads; ///< [light], `avsm` and `vpcss`: per texel its list's head
    /// `avsm` and `vpcss`: the lists' fragments, uvec4 each, every light's in turn, read and
    /// written by device address (GpuAvsmLists in `avsmLists`)
    Buffer avsmFragments;
    Buffer avsmLists;
    Buffer views; ///< ShadowFilterParams, then ShadowMapView per light
    Buffer taps;  ///< vec2: blocker taps, then filter taps

  private:
    /// The most fragments the lists may hold: AVSM_FRAGMENT_BYTES each within one allocation.
    std::uint64_t maxAvsmFragments() const;
    /// Room for `capacity` fragments (the old ones dropped) and its GpuAvsmLists.
    void allocateAvsmFragments(std::uint64_t capacity);
    const Device* m_device;
    std::uint64_t m_avsmCapacity = 0;
    ShadowMapSettings m_settings;
    std::vector<ShadowMapView> m_views;
};

/// The transmittance functions' fragment lists (`avsm`, `vpcss`): a head a texel, 16 bytes a
/// listed fragment, and room for four fragments a texel of the largest map at first; a frame that
/// lists more grows the lists and runs again (ShadowMapResources::growAvsmFragments).
inline constexpr std::uint64_t AVSM_HEAD_BYTES = 4;
inline constexpr std::uint64_t AVSM_FRAGMENT_BYTES = 16;
inline constexpr std::uint64_t AVSM_INITIAL_FRAGMENTS_PER_TEXEL = 4;
/// What a map of `texels` texels adds to the lists at first (the frame memory estimate's term).
inline std::uint64_t avsmInitialListBytes(std::uint64_t texels) {
    return texels * (AVSM_HEAD_BYTES + AVSM_INITIAL_FRAGMENTS_PER_TEXEL * AVSM_FRAGMENT_BYTES);
}

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

/// Invocations of peel_march.comp that share a pixel, a power of two: enough that none marches
/// more samples than SAMPLE_LOOP_BUDGET allows at up to peel_max_steps·(peel_bins + 1) + 1 loop
/// iterations a sample (lavapipe ends an invocation's loops after 65 535; one sample's march
/// stays under that at every peel_max_steps and peel_bins the parameters accept).
std::uint32_t peelMarchLanes(int samples, int steps, int bins);

/// `peel`'s march (peel_march.comp): every covered pixel's light-sample rays through the light's
/// grid into its bitmask images (or counters), peelMarchLanes invocations a pixel.
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
    uint32_t m_pixelsPerGroup; ///< a workgroup's pixels, of one row
    Pipeline m_pipeline;
};

/// The fragment lists of one light's transmittance functions (avsm_fragments.frag, drawn as the
/// map is): every fragment that takes light, with its depth and optical-depth units, pushed onto
/// its texel's list (heads cleared first).
class AvsmListPass final : public GpuPass {
  public:
    AvsmListPass(const Device& device, const Scene& scene, ShadowMapResources& maps,
                 const FamilyDescriptors& descriptors, const std::vector<ShaderDefine>& defines);

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    ShadowMapResources* m_maps;
    const FamilyDescriptors* m_descriptors;
    std::uint32_t m_triangleCount;
    Pipeline m_pipeline;
};

/// One light's transmittance functions from its lists (avsm_build.comp): per texel the fragments
/// in (depth, triangle) order appended into at most avsm_nodes nodes, as the CPU backend builds
/// them from its rays, so the result does not depend on the order the rasteriser listed them in.
class AvsmBuildPass final : public GpuPass {
  public:
    AvsmBuildPass(const Device& device, ShadowMapResources& maps, const FamilyDescriptors& descriptors,
                  const std::vector<ShaderDefine>& defines);

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    ShadowMapResources* m_maps;
    const FamilyDescriptors* m_descriptors;
    Pipeline m_pipeline;
};

/// One filter step per pixel into the v_coef image: a fixed kernel over the depth map (PCF), PCSS's blocker
/// search (the kernel radius), PCSS's filter (v_coef), a filtered representation's lookup (v_coef), or on the
/// transmittance functions `avsm`'s lookup, `vpcss`'s blocker search and its filter.
class ShadowFilterPass final : public GpuPass {
  public:
    enum Step {
        DepthKernel = 0,
        PcssBlocker = 1,
        PcssFilter = 2,
        FilteredLookup = 3,
        AvsmLookup = 4,
        VpcssBlocker = 5,
        VpcssFilter = 6
    };

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
