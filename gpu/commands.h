// Command recording and submission, and the barriers passes need (synchronization2).
#pragma once

#include "gpu/vulkan.h"

#include <functional>

namespace stsv {

class Device;

/// A primary command buffer with its own pool and fence: begin(), record, submitAndWait(),
/// and again. Move-only.
class CommandBuffer {
  public:
    CommandBuffer() = default;
    explicit CommandBuffer(const Device& device);
    ~CommandBuffer();
    CommandBuffer(CommandBuffer&& other) noexcept;
    CommandBuffer& operator=(CommandBuffer&& other) noexcept;

    VkCommandBuffer handle() const { return m_buffer; }
    /// Resets the buffer and starts recording (one-time submit).
    VkCommandBuffer begin();
    /// Ends recording, submits to the device's queue and blocks until the GPU is done.
    void submitAndWait();

  private:
    const Device* m_device = nullptr;
    VkCommandPool m_pool = VK_NULL_HANDLE;
    VkCommandBuffer m_buffer = VK_NULL_HANDLE;
    VkFence m_fence = VK_NULL_HANDLE;

    void destroy() noexcept;
};

/// Records `record` into a fresh command buffer, submits it and waits.
void submitOnce(const Device& device, const std::function<void(VkCommandBuffer)>& record);

/// A global memory dependency (vkCmdPipelineBarrier2).
void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                   VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess);

/// Makes all prior GPU writes visible to host reads of mapped memory after the fence wait;
/// end a command buffer with it before reading a host-visible buffer the GPU wrote.
void hostReadBarrier(VkCommandBuffer cmd);

} // namespace stsv
