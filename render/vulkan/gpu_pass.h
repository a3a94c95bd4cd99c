// A pass of the Vulkan frame (DESIGN §2, §5): a type that owns its pipelines, declares what it
// reads and writes for one light (gpu/pass_recorder.h derives the barriers from that), and records
// itself. A method's frame is a sequence of these per light (STSV paper Algorithm 2).
#pragma once

#include "gpu/pass_recorder.h"

#include "gpu/vulkan.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace stsv {

class Buffer;
class Image;

class GpuPass {
  public:
    virtual ~GpuPass() = default;
    /// Every image and buffer the pass's commands for light `light` touch, with how.
    virtual PassAccesses accesses(std::size_t light) const = 0;
    virtual void record(VkCommandBuffer cmd, std::size_t light) const = 0;
};

/// Zeroes images (vkCmdClearColorImage) and buffers (vkCmdFillBuffer); the same for every light.
class ClearPass final : public GpuPass {
  public:
    ClearPass(std::vector<Image*> images, std::vector<const Buffer*> buffers)
        : m_images(std::move(images)), m_buffers(std::move(buffers)) {}

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    std::vector<Image*> m_images;
    std::vector<const Buffer*> m_buffers;
};

/// One workgroup per 16 × 16 pixels of a width × height frame: the dispatch of the per-pixel
/// compute shaders (local size 16 × 16: resolve, fold, shadow filter, STSV merge).
inline void dispatchPerPixel(VkCommandBuffer cmd, std::uint32_t width, std::uint32_t height) {
    vkCmdDispatch(cmd, (width + 15) / 16, (height + 15) / 16, 1);
}

/// Runs `pass` for `light` through `recorder`: its barriers, then its commands in the timer scope
/// `scope` ("" = untimed).
inline void runPass(PassRecorder& recorder, VkCommandBuffer cmd, const std::string& scope,
                    const GpuPass& pass, std::size_t light = 0) {
    recorder.addPass(cmd, scope, pass.accesses(light), [&](VkCommandBuffer c) { pass.record(c, light); });
}

} // namespace stsv
