// Pass 0 of the Vulkan frame (DESIGN §5): world position and triangle id of the visible surface
// (render/shaders/gbuffer.*), perforated triangles alpha-tested, into the G-buffer and its depth.
#pragma once

#include "gpu/pipeline.h"
#include "render/vulkan/gpu_frame_resources.h"
#include "render/vulkan/gpu_pass.h"

#include <cstdint>
#include <vector>

namespace stsv {

class GBufferPass final : public GpuPass {
  public:
    GBufferPass(const Device& device, FrameResources& resources, const FrameDescriptors& descriptors,
                const std::vector<ShaderDefine>& layoutDefines, std::uint32_t triangleCount);

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    GBufferImages* m_gbuffer;
    const FrameDescriptors* m_descriptors;
    std::uint32_t m_triangleCount;
    Pipeline m_pipeline;
};

} // namespace stsv
