// The resources the passes of the Vulkan frame share (DESIGN §5): the scene as the shaders read
// it, the G-buffer, the output images, the per-light sample buffers, bound in set GPU_SET_FRAME
// (render/vulkan/gpu_frame_dh.h) with a set per light; and each family's own set GPU_SET_FAMILY
// with its stats (FamilyDescriptors). The passes own only their pipelines and the resources no
// other pass touches.
#pragma once

#include "gpu/buffer.h"
#include "gpu/descriptors.h"
#include "gpu/image.h"
#include "gpu/pipeline.h"
#include "render/options.h"
#include "render/vulkan/gpu_frame_dh.h"
#include "render/vulkan/gpu_shader_defines.h"
#include "scene/scene.h"

#include "gpu/vulkan.h"

#include <cstddef>
#include <vector>

namespace stsv {

class Device;

constexpr VkFormat POSITION_FORMAT = VK_FORMAT_R32G32B32A32_SFLOAT; ///< world units, w = 1
constexpr VkFormat TRIANGLE_FORMAT = VK_FORMAT_R32_UINT;
constexpr VkFormat DEPTH_FORMAT = VK_FORMAT_D32_SFLOAT;

/// The G-buffer's depth where no surface is seen: reversed depth (gpuClipFromWorld) puts infinity at 0.
constexpr float GPU_DEPTH_CLEAR = 0.0f;

/// Depth state of the shadow-volume passes (STSV, wedges): a face's fragment
/// runs only where the face lies behind the G-buffer's visible point p (LESS under reversed
/// depth, early tests, no writes, depth clamp for faces in front of the near plane). Every volume
/// pass decides in world space whether p is inside (a point-in-volume or plane test on p), so the
/// depth test only prunes; its bias, toward the eye, lets through every face the depth buffer
/// cannot place on either side of p. Reversed float depth resolves about 2^-23 of the distance
/// at any distance (1.2e-7·z), while a volume face can lie 1e-4 m from p (the near cap of a thin
/// box's near side, seen from its far side). 256 units of the format's resolution cover the
/// G-buffer's rounding and the snapping of both triangles to the sub-pixel grid; one pixel of the
/// face's depth slope covers faces seen edge-on. Faces let through in front of p fail the world
/// test.
void setBehindVisiblePointDepth(GraphicsPipelineDesc& desc);
constexpr VkFormat MASK_FORMAT = VK_FORMAT_R32G32_UINT;          ///< 64 sample bits
constexpr VkFormat COLOR_FORMAT = VK_FORMAT_R32G32B32A32_SFLOAT; ///< linear RGB
constexpr VkFormat VISIBILITY_FORMAT = VK_FORMAT_R32_SFLOAT;     ///< v_coef
constexpr VkFormat VCOEF_FORMAT = VK_FORMAT_R32_SFLOAT;          ///< PW occlusion sum, then v_coef

/// RG32UI attachments of a bitmask of N samples: 64 samples each.
int maskAttachmentCount(int samples);

/// The scene tables of render/vulkan/gpu_frame_dh.h, uploaded once and constant afterwards (no pass
/// declares them: nothing on the GPU writes them).
struct GpuSceneTables {
    Buffer triangles; ///< GpuTriangle[]
    Buffer alpha;     ///< alpha bits (uniform) or bytes (storage) of every texture
    Buffer textures;  ///< GpuTexture[]
    Buffer pattern;   ///< SamplePlan::points, whole vec4s
    Buffer frame;     ///< GpuFrame then GpuLight[]
    /// 256 optical-depth units per material (transmittance frames, avsm and vpcss), else 256 zeros
    Buffer depthTables;
    FrameTableLayout layout;

    GpuSceneTables(const Device& device, const Scene& scene, const RenderOptions& options,
                   const SamplePlan& plan);
};

/// G-buffer images (pass 0).
struct GBufferImages {
    Image position;   ///< POSITION_FORMAT
    Image triangleId; ///< GPU_NO_TRIANGLE on the background
    Image depth;
};

/// What the method writes per light (MethodInfo::output): bitmask attachments, counters, or for
/// transmittance the bits with per-sample optical depths (and DCS's counters, frameCountsLayers);
/// the v_coef image of visibility methods. Buffers of kinds the frame does not write are small
/// stand-ins the descriptor sets bind.
struct LightSampleBuffers {
    std::vector<std::vector<Image>> masks; ///< [light][attachment], bitmask and transmittance frames
    std::vector<Buffer> counters;          ///< [light] where frameCountsLayers; else stand-ins
    std::vector<Buffer> depths;            ///< [light] uint per sample, transmittance frames; else stand-ins
    Image unusedMask;                      ///< 1×1: the mask array elements no light fills
    Image vcoef;                           ///< v_coef (MethodOutput::Visibility); else 1×1

    /// Element `i` of light `light`'s GPU_BINDING_MASKS array.
    Image& mask(std::size_t light, std::size_t i);
};

class FrameResources {
  public:
    /// `options.buffer` is the kind the frame writes (MethodInfo::bufferKind).
    FrameResources(const Device& device, const Scene& scene, const RenderOptions& options,
                   const SamplePlan& plan);

    /// The bindings of these resources in set GPU_SET_FRAME.
    std::vector<DescriptorBinding> bindings() const;
    /// Light `light`'s resources into its descriptor set.
    void writeDescriptors(DescriptorSet& set, std::size_t light);

    GpuSceneTables tables;
    GBufferImages gbuffer;
    Image color;      ///< linear RGB, ambient + Σ lights
    Image visibility; ///< v_coef averaged over the lights
    LightSampleBuffers samples;
};

/// Set GPU_SET_FRAME: its layout, one set per light (at least one), and the pipeline layout of the
/// passes that bind nothing else (G-buffer, resolve) with the GpuPush constants.
class FrameDescriptors {
  public:
    FrameDescriptors(const Device& device, std::vector<DescriptorBinding> bindings, std::size_t setCount);

    const DescriptorSetLayout& setLayout() const { return m_setLayout; }
    const PipelineLayout& pipelineLayout() const { return m_pipelineLayout; }
    DescriptorSet& set(std::size_t light) { return m_sets.at(light); }
    const DescriptorSet& set(std::size_t light) const { return m_sets.at(light); }
    std::size_t setCount() const { return m_sets.size(); }

    void bind(VkCommandBuffer cmd, VkPipelineBindPoint point, std::size_t light) const;
    void push(VkCommandBuffer cmd, const GpuPush& constants) const;

  private:
    DescriptorSetLayout m_setLayout;
    PipelineLayout m_pipelineLayout;
    std::vector<DescriptorSet> m_sets;
};

/// One family's GPU interface (or the resolve's, which keeps no stats): set GPU_SET_FAMILY with
/// the bindings only its passes declare, one per light; the pipeline layout of its passes (the frame's set,
/// then this one, and the GpuPush constants); and its stats buffer, `statsBytes` per light at
/// GPU_BINDING_FAMILY_STATS, which the frame clears before each frame and reads back after it.
class FamilyDescriptors {
  public:
    /// `bindings`: the family's, without its stats (this adds them; none when `statsBytes` is 0,
    /// as for the resolve's set).
    FamilyDescriptors(const Device& device, const FrameDescriptors& frame,
                      std::vector<DescriptorBinding> bindings, std::size_t statsBytes);

    const PipelineLayout& pipelineLayout() const { return m_pipelineLayout; }
    DescriptorSet& set(std::size_t light) { return m_sets.at(light); }
    std::size_t setCount() const { return m_sets.size(); }
    /// The family's stats, `statsStride()` bytes per light (an empty buffer without stats).
    const Buffer& stats() const { return m_stats; }
    std::size_t statsStride() const { return m_statsStride; }

    /// Binds light `light`'s frame set and family set.
    void bind(VkCommandBuffer cmd, VkPipelineBindPoint point, std::size_t light) const;
    void push(VkCommandBuffer cmd, const GpuPush& constants) const;

  private:
    const FrameDescriptors* m_frame;
    DescriptorSetLayout m_setLayout;
    PipelineLayout m_pipelineLayout;
    std::vector<DescriptorSet> m_sets;
    std::size_t m_statsStride;
    Buffer m_stats;
};

} // namespace stsv
