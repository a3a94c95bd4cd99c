// Readback of the Vulkan frame: every output is copied into one host-visible buffer at the end
// of the frame's command buffer (no submit per image), then unpacked into the Frame.
#pragma once

#include "gpu/buffer.h"
#include "render/frame.h"
#include "render/vulkan/gpu_frame_resources.h"
#include "render/vulkan/gpu_pass.h"

#include <cstddef>
#include <vector>

namespace stsv {

class FrameReadback final : public GpuPass {
  public:
    /// `stats`: the families' stats buffers, copied whole (stagedStats).
    FrameReadback(const Device& device, const Scene& scene, const RenderOptions& options,
                  FrameResources& resources, std::vector<const Buffer*> stats);

    /// The copies into the staging buffer.
    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;
    /// The host reads of the staging buffer after the fence (the last "pass" of a frame).
    PassAccesses hostAccesses() const;

    /// G-buffer (with shading normals), colour, visibility and every light's samples from the
    /// staging buffer.
    void unpack(Frame& frame) const;
    /// After the fence: the bytes of stats buffer `i` as the frame left them.
    const std::byte* stagedStats(std::size_t i) const { return staged<std::byte>(m_layout.stats.at(i)); }

  private:
    const Scene* m_scene;
    RenderOptions m_options;
    FrameResources* m_resources;
    std::vector<const Buffer*> m_stats;
    Buffer m_staging;
    /// Byte offsets of each part in the staging buffer.
    struct StagingLayout {
        VkDeviceSize position = 0, color = 0, triangle = 0, visibility = 0;
        std::vector<VkDeviceSize> stats;              ///< [stats buffer]
        std::vector<std::vector<VkDeviceSize>> masks; ///< [light][attachment]
        std::vector<VkDeviceSize> counters;           ///< [light], frames that count layers
        std::vector<VkDeviceSize> depths;             ///< [light], transmittance frames
    } m_layout;

    /// Light `l`'s staged bitmask attachments or counters into `buffer`.
    void unpackLightSamples(LightSampleBuffer& buffer, std::size_t l) const;
    template <class T> const T* staged(VkDeviceSize offset) const {
        return reinterpret_cast<const T*>(static_cast<const std::byte*>(m_staging.mapped()) + offset);
    }
};

} // namespace stsv
